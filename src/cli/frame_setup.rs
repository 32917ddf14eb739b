//! What every frame command starts from: the GPU, the scene and the options the command line
//! gives, and the technique's warnings on stderr. Below `commands` and `bench`, which both use it.

use std::path::Path;
use std::sync::Arc;

use super::args::{FrameArgs, GpuArgs};
use crate::error::Result;
use crate::gpu::{DeviceChoice, Gpu, GpuOptions};
use crate::scene::lights::apply_light_specs;
use crate::scene::{builtin_scene_at, scene_and_warnings_from_gltf, Scene, SceneLight};
use crate::technique::{by_name, RenderOptions};

pub(super) fn open_gpu(args: &GpuArgs) -> Result<Arc<Gpu>> {
    open_gpu_with(args, false)
}

/// `open_gpu`, optionally recording no per-pass queries (`render --no-queries`).
pub(super) fn open_gpu_with(args: &GpuArgs, without_pass_queries: bool) -> Result<Arc<Gpu>> {
    let device = args.device.as_deref().map(DeviceChoice::parse).unwrap_or_default();
    Gpu::new(&GpuOptions { validation: args.validation, device, without_pass_queries })
}

/// A built-in scene by name, or a .gltf/.glb file posed at `time` seconds; the loader's
/// warnings (what it skipped or repaired in the file) go to stderr.
/// The frame's scene: a built-in one or a glTF file, at its time, with the command line's
/// lights added (or in place of its own).
pub(super) fn load_scene(frame: &FrameArgs) -> Result<Scene> {
    let mut scene = load_named_scene(&frame.scene, frame.time, &frame.lights, frame.replace_lights)?;
    if frame.light_scale != 1.0 {
        scene.lights.iter_mut().for_each(|light| light.intensity *= frame.light_scale);
    }
    Ok(scene)
}

/// The scene `name` at `time`, with the lights `specs` added to its own (or in their place).
pub(super) fn load_named_scene(name: &str, time: f32, specs: &[SceneLight], replace: bool) -> Result<Scene> {
    let path = Path::new(name);
    let is_gltf = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"));
    let mut scene = if is_gltf || path.exists() {
        let (scene, warnings) = scene_and_warnings_from_gltf(path, time)?;
        for warning in warnings {
            eprintln!("nostencil: warning: {}: {warning}", path.display());
        }
        scene
    } else {
        builtin_scene_at(name, time)?
    };
    apply_light_specs(&mut scene.lights, specs, replace)?;
    Ok(scene)
}

/// A technique's warnings (what it could not honour in the scene), on stderr.
pub(super) fn print_warnings(technique: &str, warnings: &[String]) {
    for warning in warnings {
        eprintln!("nostencil: warning: {technique}: {warning}");
    }
}

/// The frame's options: each family's parsed flags moved in as they are, then checked.
pub(super) fn options(frame: &FrameArgs) -> Result<RenderOptions> {
    let options = RenderOptions {
        width: frame.size.0,
        height: frame.size.1,
        stencil: frame.stencil,
        samples: frame.samples,
        keep_samples: false,
        destination: Default::default(),
        frames_in_flight: 1,
        skinning: frame.skinning,
        technique: by_name(&frame.technique)?,
        shadow_volume: frame.shadow_volume,
        shadow_mode: frame.shadow_tone.shadow_mode,
        shadow_tone: frame.shadow_tone.tone(),
        shadow_atlas: frame.shadow_atlas,
        count_overdraw: false,
        cartoon: frame.cartoon.clone(),
        planar: frame.planar,
    };
    options.check()?;
    Ok(options)
}
