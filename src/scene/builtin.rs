//! Scenes built in code, with no asset files, addressed by name (`--scene NAME`).

use glam::{Mat4, Quat, Vec2, Vec3};

use super::camera::{Camera, Light};
use super::objects::Scene;
use crate::error::{Error, Result};
use crate::mesh::{shapes, MeshData};

/// Names of the built-in scenes and what each shows.
pub const BUILTIN_SCENES: &[(&str, &str)] =
    &[("default", "ground plane, torus, box and torus knot under a directional light")];

pub fn builtin_scene(name: &str) -> Result<Scene> {
    match name {
        "default" => default_scene(),
        _ => Err(Error::InvalidInput(format!(
            "unknown scene '{name}'; built-in scenes: {}",
            BUILTIN_SCENES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
        ))),
    }
}

fn empty_scene(name: &str, camera: Camera, light: Light) -> Scene {
    Scene {
        name: name.to_owned(),
        meshes: Vec::new(),
        objects: Vec::new(),
        light,
        ambient: 0.25,
        camera,
        background: Vec3::new(0.55, 0.65, 0.78),
    }
}

/// The default scene: three closed shapes floating over a ground plane, lit from above-left.
pub fn default_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(0.0, 4.2, 8.5), Vec3::new(0.0, 0.7, 0.0));
    let light = Light::Directional { direction: Vec3::new(-0.45, -1.0, -0.35).normalize() };
    let mut scene = empty_scene("default", camera, light);

    let ground = scene.add_mesh("ground", ground_plane(14.0));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::new(0.82, 0.80, 0.74), false);

    let torus = scene.add_mesh("torus", shapes::torus(0.8, 0.3, 48, 24)?);
    scene.add_object(
        "torus",
        torus,
        Mat4::from_rotation_translation(Quat::from_rotation_x(1.1), Vec3::new(-2.6, 1.3, 0.2)),
        Vec3::new(0.86, 0.36, 0.24),
        true,
    );

    let cube = scene.add_mesh("box", shapes::cube(1.2));
    scene.add_object(
        "box",
        cube,
        Mat4::from_rotation_translation(Quat::from_rotation_y(0.6), Vec3::new(0.0, 1.0, -0.4)),
        Vec3::new(0.30, 0.55, 0.85),
        true,
    );

    let knot = scene.add_mesh("torus knot", shapes::torus_knot(2, 3, 1.0, 0.16, 160, 16)?);
    scene.add_object(
        "torus knot",
        knot,
        Mat4::from_translation(Vec3::new(2.6, 1.5, 0.3)),
        Vec3::new(0.42, 0.75, 0.36),
        true,
    );
    Ok(scene)
}

/// A flat square in the XZ plane facing +Y: a receiver only (open, so it casts nothing).
fn ground_plane(size: f32) -> MeshData {
    let h = size * 0.5;
    MeshData {
        positions: vec![Vec3::new(-h, 0.0, -h), Vec3::new(-h, 0.0, h), Vec3::new(h, 0.0, h), Vec3::new(h, 0.0, -h)],
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}
