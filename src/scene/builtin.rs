//! Scenes built in code, with no asset files, addressed by name (`--scene NAME`).

use glam::{Mat4, Quat, Vec2, Vec3};

use super::camera::{Camera, Light};
use super::objects::Scene;
use crate::error::{Error, Result};
use crate::mesh::{shapes, MeshData};

/// Names of the built-in scenes and what each shows.
///
/// (Like the shadow-volume test scenes, the seed-004 scenes `atlas-one` and `atlas-125` are not
/// listed: `tests/shadow_volume.rs` runs every listed scene through 28 shadow-volume frames, and
/// their 131,072 and 992,250 caster faces would make that suite minutes long.)
pub const BUILTIN_SCENES: &[(&str, &str)] =
    &[("default", "ground plane, torus, box and torus knot under a directional light")];

pub fn builtin_scene(name: &str) -> Result<Scene> {
    match name {
        "default" => default_scene(),
        "overlap" => overlap_scene(),
        "point-light" => point_light_scene(),
        "inside" => inside_scene(),
        "box" => Ok(box_scene()),
        "atlas-one" => atlas_one_scene(),
        "atlas-125" => atlas_125_scene(),
        _ => Err(Error::InvalidInput(format!(
            "unknown scene '{name}'; built-in scenes: {}",
            BUILTIN_SCENES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
        ))),
    }
}

pub(crate) fn empty_scene(name: &str, camera: Camera, light: Light) -> Scene {
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
    let mut scene = with_ground("default", camera, light);

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
pub(crate) fn ground_plane(size: f32) -> MeshData {
    let h = size * 0.5;
    MeshData {
        positions: vec![Vec3::new(-h, 0.0, -h), Vec3::new(-h, 0.0, h), Vec3::new(h, 0.0, h), Vec3::new(h, 0.0, -h)],
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

fn with_ground(name: &str, camera: Camera, light: Light) -> Scene {
    let mut scene = empty_scene(name, camera, light);
    let ground = scene.add_mesh("ground", ground_plane(14.0));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::new(0.82, 0.80, 0.74), false);
    scene
}

/// Casters stacked along the light so that their volumes overlap, a torus lying across the light
/// (its volume has two front and two back walls on one pixel), and a sphere.
fn overlap_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(1.5, 5.5, 8.0), Vec3::new(0.0, 0.8, 0.0));
    let light = Light::Directional { direction: Vec3::new(0.35, -1.0, -0.25).normalize() };
    let mut scene = with_ground("overlap", camera, light);
    let cube = scene.add_mesh("box", shapes::cube(1.0));
    for (i, (x, y)) in [(-2.2, 0.9), (-2.7, 2.3), (-3.2, 3.7)].into_iter().enumerate() {
        let transform = Mat4::from_rotation_translation(Quat::from_rotation_y(0.3 * i as f32), Vec3::new(x, y, -0.5));
        scene.add_object(&format!("stacked box {i}"), cube, transform, Vec3::new(0.30, 0.55, 0.85), true);
    }
    let torus = scene.add_mesh("torus", shapes::torus(0.9, 0.28, 40, 20)?);
    scene.add_object(
        "torus",
        torus,
        Mat4::from_translation(Vec3::new(0.6, 1.6, 0.4)),
        Vec3::new(0.86, 0.36, 0.24),
        true,
    );
    let sphere = scene.add_mesh("sphere", shapes::uv_sphere(16, 32)?);
    let transform = Mat4::from_scale_rotation_translation(Vec3::splat(0.7), Quat::IDENTITY, Vec3::new(2.6, 1.2, 0.8));
    scene.add_object("sphere", sphere, transform, Vec3::new(0.42, 0.75, 0.36), true);
    Ok(scene)
}

fn point_light_scene() -> Result<Scene> {
    let mut scene = default_scene()?;
    scene.name = "point-light".into();
    scene.light = Light::Point { position: Vec3::new(-1.0, 6.0, 2.0) };
    Ok(scene)
}

/// A slab floating over the ground with the camera beneath it: the camera and its near plane
/// sit inside the slab's shadow volume, where z-pass fails and z-fail does not.
fn inside_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(0.0, 1.2, 1.5), Vec3::new(0.0, 0.0, -3.0));
    let light = Light::Directional { direction: Vec3::new(0.0, -1.0, -0.3).normalize() };
    let mut scene = with_ground("inside", camera, light);
    let cube = scene.add_mesh("slab", shapes::cube(1.0));
    let slab =
        Mat4::from_scale_rotation_translation(Vec3::new(3.0, 0.3, 3.0), Quat::IDENTITY, Vec3::new(0.0, 3.0, 1.0));
    scene.add_object("slab", cube, slab, Vec3::new(0.6, 0.6, 0.65), true);
    let post = scene.add_mesh("post", shapes::cube(1.0));
    let transform =
        Mat4::from_scale_rotation_translation(Vec3::new(0.4, 1.2, 0.4), Quat::IDENTITY, Vec3::new(1.2, 0.6, -3.0));
    scene.add_object("post", post, transform, Vec3::new(0.86, 0.36, 0.24), true);
    Ok(scene)
}

/// One axis-aligned box over the ground plane under a directional light: its shadow on the
/// ground is the projection of the box, computable by hand.
pub fn box_scene() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 7.0, 6.0), Vec3::new(0.0, 0.0, 0.0));
    let light = Light::Directional { direction: Vec3::new(0.4, -1.0, -0.2).normalize() };
    let mut scene = with_ground("box", camera, light);
    let cube = scene.add_mesh("box", shapes::cube(1.0));
    scene.add_object("box", cube, Mat4::from_translation(Vec3::new(-0.5, 1.5, 0.0)), Vec3::new(0.30, 0.55, 0.85), true);
    scene
}

/// Horns of the seed-004 models: six smooth spikes, tilted off the axes, whose flanks shadow
/// the body between them.
pub const ATLAS_HORNS: [(Vec3, f32); 6] = [
    (Vec3::new(1.0, 0.3, 0.1), 0.8),
    (Vec3::new(-1.0, 0.2, -0.3), 0.7),
    (Vec3::new(0.2, 1.0, 0.3), 0.9),
    (Vec3::new(-0.1, -1.0, 0.2), 0.6),
    (Vec3::new(0.3, -0.2, 1.0), 0.8),
    (Vec3::new(-0.3, 0.4, -1.0), 0.7),
];

fn horned_geometry_image(n: u32) -> Result<MeshData> {
    use crate::technique::shadow_atlas::geometry_image::{geometry_image, horned_radius};
    geometry_image(n, horned_radius(&ATLAS_HORNS))
}

/// Seed 004, first row of Table 1: one 257x257 geometry image (its shadow texture 256x256).
fn atlas_one_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(0.0, 3.2, 6.0), Vec3::new(0.0, 1.2, 0.0));
    let light = Light::Directional { direction: Vec3::new(-0.5, -1.0, -0.4).normalize() };
    let mut scene = with_ground("atlas-one", camera, light);
    let mesh = scene.add_mesh("geometry image 257x257", horned_geometry_image(257)?);
    let transform = Mat4::from_rotation_translation(Quat::from_rotation_y(0.4), Vec3::new(0.0, 1.6, 0.0));
    scene.add_object("model", mesh, transform, Vec3::new(0.86, 0.62, 0.36), true);
    Ok(scene)
}

/// Seed 004, second row of Table 1: 125 models (5 x 5 x 5) of 64x64 geometry images, each
/// with a 64x64 shadow texture.
fn atlas_125_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(0.0, 6.5, 11.0), Vec3::new(0.0, 2.0, 0.0));
    let light = Light::Directional { direction: Vec3::new(-0.45, -1.0, -0.3).normalize() };
    let mut scene = with_ground("atlas-125", camera, light);
    let mesh = scene.add_mesh("geometry image 64x64", horned_geometry_image(64)?);
    for i in 0..125u32 {
        let (x, y, z) = ((i % 5) as f32 - 2.0, (i / 25) as f32, ((i / 5) % 5) as f32 - 2.0);
        let rotation = Quat::from_euler(glam::EulerRot::YXZ, 0.7 * i as f32, 0.3 * (i % 7) as f32, 0.0);
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::splat(0.4),
            rotation,
            Vec3::new(x * 1.5, 0.9 + y * 1.2, z * 1.5),
        );
        let tint = 0.15 * (i % 3) as f32;
        scene.add_object(&format!("model {i}"), mesh, transform, Vec3::new(0.8 - tint, 0.55, 0.35 + tint), true);
    }
    Ok(scene)
}
