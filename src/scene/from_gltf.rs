//! A glTF file as a scene: every mesh primitive posed at a chosen animation time (skins applied
//! on the CPU, so shadow volumes follow the skinned pose), placed over a ground plane that
//! receives the shadows, with a camera and light fitted to the model.

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::animation::{pose_at, rest_pose, TimeMode};
use super::camera::{Camera, Light};
use super::gltf::load_gltf;
#[cfg(test)]
use super::gltf::load_gltf_slice;
use super::layout::ground_plane;
use super::lights::{unique_name, LightNode, SceneLight, MAX_LIGHTS};
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
    scene_from_model(load_gltf(path)?, path, time)
}

/// [`scene_and_warnings_from_gltf`] for a file already in memory; `path` names it in errors and
/// anchors its relative URIs (the fuzzer loads mutated bytes this way, without writing files).
#[cfg(test)]
pub fn scene_and_warnings_from_gltf_slice(bytes: &[u8], path: &Path, time: f32) -> Result<(Scene, Vec<String>)> {
    scene_from_model(load_gltf_slice(bytes, path)?, path, time)
}

fn scene_from_model(mut model: Model, path: &Path, time: f32) -> Result<(Scene, Vec<String>)> {
    let mut warnings = std::mem::take(&mut model.warnings);
    let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
    let local = if model.animations.is_empty() { rest_pose(&model) } else { pose_at(&model, 0, time, TimeMode::Loop)? };
    let world = world_matrices(&model, &local);
    let rig = Arc::new(Rig { model, pose: RigPose::FirstAnimation });
    let model = &rig.model;

    let mut scene =
        Scene::empty(&name, Camera::look_at(Vec3::new(0.0, 2.0, 5.0), Vec3::ZERO), default_light(model, &world));
    let lights = file_lights(&rig, &world, &mut warnings);
    if !lights.is_empty() {
        scene.lights = lights;
    }
    let Some((low, high)) = add_model(&mut scene, &rig, &world)? else {
        return Err(crate::error::Error::Asset {
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

/// Every KHR_lights_punctual light on a node, placed by its node and following it when the scene
/// is re-posed: named after the light, else its node, else "light N". Lights past a frame's
/// [`MAX_LIGHTS`] are named in a warning and left out.
fn file_lights(rig: &Arc<Rig>, world: &[Mat4], warnings: &mut Vec<String>) -> Vec<SceneLight> {
    let model = &rig.model;
    let mut lights: Vec<SceneLight> = Vec::new();
    let mut left_out = Vec::new();
    for (index, node) in model.nodes.iter().enumerate() {
        let Some(light) = node.light.and_then(|l| model.lights.get(l)) else { continue };
        let base =
            light.name.clone().or_else(|| node.name.clone()).unwrap_or_else(|| format!("light {}", lights.len() + 1));
        if lights.len() == MAX_LIGHTS {
            left_out.push(base);
            continue;
        }
        let mut scene_light = SceneLight {
            name: unique_name(&lights, &base),
            kind: light.kind,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            colour: light.color,
            intensity: light.intensity,
            range: light.range,
            casts_shadow: true,
            node: Some(LightNode { rig: rig.clone(), node: index }),
        };
        scene_light.place(world.get(index).copied().unwrap_or(Mat4::IDENTITY));
        lights.push(scene_light);
    }
    if !left_out.is_empty() {
        warnings
            .push(format!("KHR_lights_punctual: a frame holds {MAX_LIGHTS} lights; left out: {}", left_out.join(", ")));
    }
    lights
}

/// A ground plane just under the model, and a camera that frames the model and its shadow.
fn fit_ground_and_camera(scene: &mut Scene, low: Vec3, high: Vec3) {
    let centre = (low + high) * 0.5;
    let radius = ((high - low).length() * 0.5).max(1e-3);
    let ground_y = low.y - radius * 0.02;
    let footprint = frame_with_shadow(low, high, ground_y, &scene.light());
    let ground = scene.add_mesh("ground", ground_plane(footprint.radius.max(radius) * 8.0));
    let below = Mat4::from_translation(Vec3::new(centre.x, ground_y, centre.z));
    scene.add_object("ground", ground, below, Vec3::new(0.82, 0.80, 0.74), false);
    scene.camera = front_camera(footprint.centre, footprint.radius);
}

/// A sphere around what a picture of the model must show.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Framing {
    centre: Vec3,
    radius: f32,
}

/// The model's box and the shadow it throws on the ground at `ground_y`: its corners projected
/// along the light (docs/design/planar-shadows.md), so that the shadow is in the picture too.
fn frame_with_shadow(low: Vec3, high: Vec3, ground_y: f32, light: &Light) -> Framing {
    let corners = (0..8).map(|i| {
        Vec3::new(
            if i & 1 == 0 { low.x } else { high.x },
            if i & 2 == 0 { low.y } else { high.y },
            if i & 4 == 0 { low.z } else { high.z },
        )
    });
    let mut points: Vec<Vec3> = corners.clone().collect();
    for p in corners {
        let on_ground = match *light {
            Light::Directional { direction } if direction.y < -1e-3 => {
                Some(p + direction * (p.y - ground_y) / -direction.y)
            }
            Light::Point { position } if position.y > p.y + 1e-3 => {
                Some(position + (p - position) * (position.y - ground_y) / (position.y - p.y))
            }
            _ => None,
        };
        // A grazing light throws a shadow to the horizon: frame at most a few model sizes of it.
        let size = (high - low).length().max(1e-3);
        if let Some(q) = on_ground.filter(|q| q.distance(p) <= size * 3.0) {
            points.push(q);
        }
    }
    let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let centre = (lo + hi) * 0.5;
    let radius = points.iter().map(|p| p.distance(centre)).fold(1e-3, f32::max);
    Framing { centre, radius }
}

/// Looking at the front of the model (glTF's front faces +Z) from 30 degrees above the ground,
/// far enough back that the framing sphere fits the vertical field of view (and so any frame at
/// least as wide as it is tall).
fn front_camera(centre: Vec3, radius: f32) -> Camera {
    let elevation = 30f32.to_radians();
    let camera = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z);
    let distance = radius / (0.5 * camera.fov_y_radians).sin() * 1.05;
    let eye = centre + Vec3::new(0.0, elevation.sin(), elevation.cos()) * distance;
    Camera { near: (distance - radius).max(distance * 0.01) * 0.5, ..Camera::look_at(eye, centre) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point of the model's box and of its shadow is inside the view frustum.
    #[test]
    fn the_camera_sees_the_model_and_its_shadow_from_the_front() {
        let (low, high) = (Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 2.0, 0.5));
        let light = Light::Directional { direction: Vec3::new(-0.45, -1.0, -0.35).normalize() };
        let framing = frame_with_shadow(low, high, 0.0, &light);
        let camera = front_camera(framing.centre, framing.radius);
        assert!(camera.eye.z > high.z && camera.eye.y > high.y * 0.5, "in front and above: {:?}", camera.eye);
        let view_proj = camera.view_projection(1.0);
        // The top of the model's shadow lands 2 / 1 * (0.45, 0.35) away from its top corner.
        let shadow_tip = Vec3::new(-0.5 - 0.9, 0.0, -0.5 - 0.7);
        for p in [low, high, Vec3::new(-0.5, 2.0, -0.5), shadow_tip] {
            let clip = view_proj * p.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            assert!(clip.w > camera.near, "{p} is in front of the camera");
            assert!(ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0, "{p} is in the frame: {ndc}");
        }
    }
}
