//! Scenes built in code, with no asset files, addressed by name (`--scene NAME`).

use glam::{Mat4, Quat, Vec3};

use super::camera::{Camera, Light};
use super::character;
use super::layout::{ground_plane, with_ground};
use super::lights::parse_light_spec;
use super::open_casters;
// Re-exported for callers of the path it had before it moved to `layout`.
use super::objects::Scene;
use crate::error::{Error, Result};
use crate::mesh::{shapes, MeshData};

/// Names of the built-in scenes and what each shows. Every one of them is swept by the
/// shadow-volume proofs (emulated == reference); heavier scenes live in `OTHER_SCENES`.
pub const BUILTIN_SCENES: &[(&str, &str)] = &[
    ("default", "ground plane, torus, box and torus knot under a directional light"),
    ("overlap", "stacked casters whose volumes overlap, a torus lying in the light, a sphere"),
    ("point-light", "the default shapes under a point light"),
    ("inside", "camera under a floating slab, inside its shadow volume"),
    ("box", "one box over the ground under a directional light (analytic shadow)"),
    ("outline", "overlapping box, sphere and torus knot with a torus in front: selection outlines"),
    ("duck", "a duck made of ellipsoids (seed 002's figure): toon shading and ink lines"),
    ("open-quad", "one one-sided quad over the ground, its back to the light: it casts two-sided"),
    ("open-box", "a box without its top, the camera looking in through the hole"),
    ("non-manifold", "three quads sharing one edge (a non-manifold fan) and a box with a flipped triangle"),
    ("touching", "boxes touching along an edge (non-manifold) and at a corner, one mesh each"),
    ("lights", "a warm sun, a red point lamp and a blue spot whose shadows overlap on a box, a torus and a pillar"),
];

/// Scenes outside the shadow-volume sweep (too heavy to render dozens of times in tests, or
/// made for one technique).
pub const OTHER_SCENES: &[(&str, &str)] = &[
    (
        "slope",
        "the character and a box over ground tilted to normal (0, 3, 1): planar shadows with --plane-normal 0,3,1",
    ),
    ("atlas-one", "seed 004, Table 1 row 1: one 257x257 geometry image (131,072 faces)"),
    ("atlas-125", "seed 004, Table 1 row 2: 125 models of 64x64 geometry images"),
];

pub fn builtin_scene(name: &str) -> Result<Scene> {
    builtin_scene_at(name, 0.0)
}

/// A built-in scene with its animated parts (the skinned character) posed at `time` seconds.
pub fn builtin_scene_at(name: &str, time: f32) -> Result<Scene> {
    match name {
        "default" => default_scene_at(time),
        "character" => character_scene(time, Light::Directional { direction: CHARACTER_LIGHT }),
        "character-point" => character_scene(time, Light::Point { position: Vec3::new(-1.2, 3.2, 0.9) }),
        "overlap" => overlap_scene(),
        "point-light" => point_light_scene(time),
        "inside" => inside_scene(),
        "box" => Ok(box_scene()),
        "outline" => outline_scene(),
        "duck" => duck_scene(),
        "open-quad" => Ok(open_casters::open_quad_scene()),
        "open-box" => Ok(open_casters::open_box_scene()),
        "non-manifold" => Ok(open_casters::non_manifold_scene()),
        "touching" => Ok(open_casters::touching_scene()),
        "lights" => lights_scene(),
        "slope" => slope_scene(time),
        "atlas-one" => atlas_one_scene(),
        "atlas-125" => atlas_125_scene(),
        _ => Err(Error::InvalidInput(format!(
            "unknown scene '{name}'; built-in scenes: {}",
            BUILTIN_SCENES.iter().chain(OTHER_SCENES).map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
        ))),
    }
}

/// Where the character stands in the default scene.
pub const DEFAULT_CHARACTER_PLACEMENT: Vec3 = Vec3::new(1.1, 0.0, 2.0);

/// The light of the character scenes: from the character's left, so that the shadow of its right
/// arm falls across the torso's.
pub const CHARACTER_LIGHT: Vec3 = Vec3::new(-0.62, -1.0, -0.25);

/// The default scene: three closed shapes floating over a ground plane and the skinned
/// character walking in place in front of them (at animation time `time`), lit from above-left.
pub fn default_scene_at(time: f32) -> Result<Scene> {
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
    let placement = Mat4::from_rotation_translation(Quat::from_rotation_y(-0.3), DEFAULT_CHARACTER_PLACEMENT);
    character::add_character(&mut scene, placement, time, CHARACTER_COLOUR)?;
    Ok(scene)
}

const CHARACTER_COLOUR: Vec3 = Vec3::new(0.93, 0.72, 0.30);

/// The character alone over the ground, framed close (`character`, or `character-point` under a
/// point light). Kept out of BUILTIN_SCENES, which every sweep renders: the default scene
/// already holds the character, and it casts shadow volumes like any closed mesh.
fn character_scene(time: f32, light: Light) -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(1.0, 3.3, 3.4), Vec3::new(-0.5, 0.5, -0.2));
    let mut scene = with_ground("character", camera, light);
    light_the_origin_as_the_sun_would(&mut scene);
    character::add_character(&mut scene, Mat4::IDENTITY, time, CHARACTER_COLOUR)?;
    Ok(scene)
}

/// A built-in point light falls off with distance squared (KHR_lights_punctual): its intensity
/// is set so that at the scene's origin, where its objects stand, it is as bright as the
/// built-in sun.
fn light_the_origin_as_the_sun_would(scene: &mut Scene) {
    for light in &mut scene.lights {
        if light.kind != super::model::LightKind::Directional {
            light.intensity = super::lights::DEFAULT_INTENSITY * light.position.length_squared();
        }
    }
}

/// The normal of the `slope` scene's ground: typed exactly as `--plane-normal 0,3,1`.
pub const SLOPE_NORMAL: Vec3 = Vec3::new(0.0, 3.0, 1.0);

/// The character and a floating box over a ground tilted about x to `SLOPE_NORMAL` (through the
/// origin), under a directional light: no horizontal ground, so planar shadows need the plane
/// given (`--plane-normal 0,3,1`).
fn slope_scene(time: f32) -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(1.5, 3.6, 4.2), Vec3::new(-0.3, 0.3, -0.3));
    let mut scene = Scene::empty("slope", camera, Light::Directional { direction: CHARACTER_LIGHT });
    let ground = scene.add_mesh("ground", ground_plane(14.0));
    let tilt = Quat::from_rotation_arc(Vec3::Y, SLOPE_NORMAL.normalize());
    scene.add_object("ground", ground, Mat4::from_quat(tilt), Vec3::new(0.82, 0.80, 0.74), false);
    // The character stands on the slope where it crosses the y axis (the origin).
    character::add_character(&mut scene, Mat4::IDENTITY, time, CHARACTER_COLOUR)?;
    let cube = scene.add_mesh("box", shapes::cube(0.5));
    let transform = Mat4::from_rotation_translation(Quat::from_rotation_y(0.4), Vec3::new(-1.0, 1.4, 0.6));
    scene.add_object("box", cube, transform, Vec3::new(0.30, 0.55, 0.85), true);
    Ok(scene)
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

fn point_light_scene(time: f32) -> Result<Scene> {
    let mut scene = default_scene_at(time)?;
    scene.name = "point-light".into();
    scene.set_light(Light::Point { position: Vec3::new(-1.0, 6.0, 2.0) });
    light_the_origin_as_the_sun_would(&mut scene);
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

/// Three lights of the three KHR_lights_punctual kinds, coloured, over casters each of them
/// reaches, so that their shadows overlap: the additive loop's scene (docs/shadow-volumes.md).
pub fn lights_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(0.3, 3.6, 5.2), Vec3::new(0.0, 0.5, 0.2));
    let sun = Light::Directional { direction: Vec3::new(0.5, -1.0, -0.3).normalize() };
    let mut scene = with_ground("lights", camera, sun);
    scene.lights[0].colour = Vec3::new(1.0, 0.85, 0.6);
    scene.lights[0].intensity = 0.45;
    let add = |spec: &str, scene: &mut Scene| -> Result<()> {
        let light = parse_light_spec(spec)?;
        scene.lights.push(light);
        Ok(())
    };
    add("point:name=lamp:at=-2.2,2.4,1.4:colour=1,0.3,0.2:intensity=6:range=7", &mut scene)?;
    add(
        "spot:name=spot:at=2.4,4.2,1.6:aim=0.4,0,-0.2:colour=0.3,0.5,1:intensity=14:range=9:inner=20:outer=32",
        &mut scene,
    )?;

    let cube = scene.add_mesh("box", shapes::cube(1.1));
    scene.add_object(
        "box",
        cube,
        Mat4::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::new(0.0, 0.8, -0.3)),
        Vec3::new(0.75, 0.75, 0.72),
        true,
    );
    let torus = scene.add_mesh("torus", shapes::torus(0.6, 0.22, 40, 20)?);
    scene.add_object(
        "torus",
        torus,
        Mat4::from_rotation_translation(Quat::from_rotation_x(1.2), Vec3::new(-1.3, 1.2, 0.9)),
        Vec3::new(0.8, 0.8, 0.8),
        true,
    );
    let pillar = scene.add_mesh("pillar", shapes::cube(1.0));
    scene.add_object(
        "pillar",
        pillar,
        Mat4::from_scale_rotation_translation(Vec3::new(0.35, 2.2, 0.35), Quat::IDENTITY, Vec3::new(1.4, 1.1, 0.8)),
        Vec3::new(0.75, 0.75, 0.78),
        true,
    );
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

/// Objects that overlap on screen, to outline one or several: a box and a sphere that
/// intersect, a torus knot behind them, and a torus in front of the box.
pub fn outline_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(0.5, 3.2, 7.0), Vec3::new(0.0, 1.0, 0.0));
    let light = Light::Directional { direction: Vec3::new(-0.4, -1.0, -0.5).normalize() };
    let mut scene = with_ground("outline", camera, light);
    let cube = scene.add_mesh("box", shapes::cube(1.4));
    scene.add_object(
        "box",
        cube,
        Mat4::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::new(-0.8, 0.9, 0.0)),
        Vec3::new(0.30, 0.55, 0.85),
        true,
    );
    let sphere = scene.add_mesh("sphere", shapes::uv_sphere(16, 32)?);
    scene.add_object(
        "sphere",
        sphere,
        Mat4::from_scale_rotation_translation(Vec3::splat(0.8), Quat::IDENTITY, Vec3::new(0.3, 1.1, 0.3)),
        Vec3::new(0.42, 0.75, 0.36),
        true,
    );
    let knot = scene.add_mesh("torus knot", shapes::torus_knot(2, 3, 0.9, 0.15, 128, 12)?);
    scene.add_object(
        "torus knot",
        knot,
        Mat4::from_translation(Vec3::new(1.6, 1.5, -1.6)),
        Vec3::new(0.75, 0.45, 0.80),
        true,
    );
    let torus = scene.add_mesh("torus", shapes::torus(0.5, 0.18, 32, 16)?);
    scene.add_object(
        "torus",
        torus,
        Mat4::from_rotation_translation(Quat::from_rotation_x(1.3), Vec3::new(-0.6, 0.9, 1.6)),
        Vec3::new(0.86, 0.36, 0.24),
        true,
    );
    Ok(scene)
}

/// A yellow duck of ellipsoids (body, head, tail, beak, eyes) on a pond-blue ground: the
/// subject of seed 002's figure 5.1.1.
pub fn duck_scene() -> Result<Scene> {
    let camera = Camera::look_at(Vec3::new(2.6, 3.0, 5.4), Vec3::new(0.3, 1.2, 0.0));
    let light = Light::Directional { direction: Vec3::new(-0.5, -1.0, -0.6).normalize() };
    let mut scene = Scene::empty("duck", camera, light);
    scene.background = Vec3::new(0.93, 0.93, 0.90);
    let ground = scene.add_mesh("ground", ground_plane(10.0));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::new(0.45, 0.68, 0.85), false);
    let sphere = scene.add_mesh("sphere", shapes::uv_sphere(20, 40)?);
    let yellow = Vec3::new(1.0, 0.82, 0.18);
    let mut part = |name: &str, scale: Vec3, rotation: Quat, at: Vec3, colour: Vec3| {
        scene.add_object(name, sphere, Mat4::from_scale_rotation_translation(scale, rotation, at), colour, true);
    };
    part("body", Vec3::new(1.25, 0.75, 0.9), Quat::from_rotation_z(-0.12), Vec3::new(0.0, 0.85, 0.0), yellow);
    part("tail", Vec3::new(0.45, 0.22, 0.35), Quat::from_rotation_z(0.7), Vec3::new(-1.15, 1.25, 0.0), yellow);
    part("head", Vec3::splat(0.55), Quat::IDENTITY, Vec3::new(0.95, 1.95, 0.0), yellow);
    let orange = Vec3::new(0.98, 0.45, 0.08);
    part("beak", Vec3::new(0.42, 0.1, 0.26), Quat::from_rotation_z(-0.1), Vec3::new(1.52, 1.82, 0.0), orange);
    let black = Vec3::new(0.05, 0.05, 0.05);
    for (name, z) in [("left eye", 0.3), ("right eye", -0.3)] {
        part(name, Vec3::splat(0.08), Quat::IDENTITY, Vec3::new(1.32, 2.12, z), black);
    }
    Ok(scene)
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
    use crate::mesh::geometry_image::{geometry_image, horned_radius};
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
