//! The frame every scene starts from, shared by the built-in scenes and glTF files: an empty
//! scene with the common ambient and background, and the ground plane that receives shadows.

use glam::{Mat4, Vec2, Vec3};

use super::camera::{Camera, Light};
use super::objects::Scene;
use crate::mesh::MeshData;

/// A scene with no meshes yet.
pub(crate) fn empty_scene(name: &str, camera: Camera, light: Light) -> Scene {
    Scene {
        name: name.to_owned(),
        meshes: Vec::new(),
        objects: Vec::new(),
        materials: Vec::new(),
        textures: Vec::new(),
        light,
        ambient: 0.25,
        camera,
        background: Vec3::new(0.55, 0.65, 0.78),
    }
}

/// A flat square in the XZ plane facing +Y: the receiver (scenes place it with `casts_shadow`
/// false).
pub(crate) fn ground_plane(size: f32) -> MeshData {
    let h = size * 0.5;
    MeshData {
        positions: vec![Vec3::new(-h, 0.0, -h), Vec3::new(-h, 0.0, h), Vec3::new(h, 0.0, h), Vec3::new(h, 0.0, -h)],
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// An empty scene with the common ground plane (a receiver: it casts nothing).
pub(crate) fn with_ground(name: &str, camera: Camera, light: Light) -> Scene {
    let mut scene = empty_scene(name, camera, light);
    let ground = scene.add_mesh("ground", ground_plane(14.0));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::new(0.82, 0.80, 0.74), false);
    scene
}
