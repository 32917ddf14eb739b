//! A glTF file as a scene: every mesh primitive posed at a chosen animation time (skins applied
//! on the CPU, so shadow volumes follow the skinned pose), placed over a ground plane that
//! receives the shadows, with a camera and light fitted to the model.

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::animation::{pose_at, rest_pose, TimeMode};
use super::camera::{Camera, Light};
use super::gltf::load_gltf;
use super::layout::{empty_scene, ground_plane};
use super::model::{LightKind, Model};
use super::objects::Scene;
use super::place::add_model;
use super::rig::{Rig, RigPose};
use super::skinning::world_matrices;
use crate::error::Result;

/// Loads `path` and poses it at `time` seconds of its first animation (looping).
pub fn scene_from_gltf(path: &Path, time: f32) -> Result<Scene> {
    scene_and_warnings_from_gltf(path, time).map(|(scene, _)| scene)
}

/// [`scene_from_gltf`], with the loader's warnings: what it skipped or repaired.
pub fn scene_and_warnings_from_gltf(path: &Path, time: f32) -> Result<(Scene, Vec<String>)> {
    let mut model = load_gltf(path)?;
    let warnings = std::mem::take(&mut model.warnings);
    let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
    let local = if model.animations.is_empty() { rest_pose(&model) } else { pose_at(&model, 0, time, TimeMode::Loop)? };
    let world = world_matrices(&model, &local);
    let rig = Arc::new(Rig { model, pose: RigPose::FirstAnimation });
    let model = &rig.model;

    let mut scene =
        empty_scene(&name, Camera::look_at(Vec3::new(0.0, 2.0, 5.0), Vec3::ZERO), default_light(model, &world));
    let Some((low, high)) = add_model(&mut scene, &rig, &world)? else {
        return Err(crate::Error::Asset {
            path: path.to_path_buf(),
            problem: "the file has no triangle meshes to render".into(),
        });
    };
    fit_ground_and_camera(&mut scene, low, high);
    Ok((scene, warnings))
}

/// The file's first directional light (KHR_lights_punctual, shining along its node's -Z), else
/// one from above and to the side.
fn default_light(model: &Model, world: &[Mat4]) -> Light {
    model
        .nodes
        .iter()
        .enumerate()
        .find_map(|(i, node)| {
            let light = model.lights.get(node.light?)?;
            (light.kind == LightKind::Directional).then(|| Light::Directional {
                direction: world.get(i).copied().unwrap_or(Mat4::IDENTITY).transform_vector3(Vec3::NEG_Z).normalize(),
            })
        })
        .unwrap_or(Light::Directional { direction: Vec3::new(-0.45, -1.0, -0.35).normalize() })
}

/// A ground plane just under the model, and a camera that frames both.
fn fit_ground_and_camera(scene: &mut Scene, low: Vec3, high: Vec3) {
    let centre = (low + high) * 0.5;
    let radius = ((high - low).length() * 0.5).max(1e-3);
    let ground = scene.add_mesh("ground", ground_plane(radius * 8.0));
    let below = Mat4::from_translation(Vec3::new(centre.x, low.y - radius * 0.02, centre.z));
    scene.add_object("ground", ground, below, Vec3::new(0.82, 0.80, 0.74), false);
    let eye = centre + Vec3::new(0.0, 1.2, 2.6).normalize() * radius * 3.2;
    scene.camera = Camera { near: radius * 0.02, ..Camera::look_at(eye, centre) };
}
