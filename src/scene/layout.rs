//! What every scene stands on, shared by the built-in scenes and glTF files: the ground plane
//! that receives shadows (an empty scene is `Scene::empty`).

use glam::{Mat4, Vec2, Vec3};

use super::camera::{Camera, Light};
use super::objects::Scene;
use crate::mesh::MeshData;

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
    let mut scene = Scene::empty(name, camera, light);
    let ground = scene.add_mesh("ground", ground_plane(14.0));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::new(0.82, 0.80, 0.74), false);
    scene
}
