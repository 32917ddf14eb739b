//! Shadow volumes in alpha are proven against the real stencil, pixel for pixel, and against
//! hand-computed answers: the seed's normalisation table, a box's projected outline, a camera
//! inside a volume, and the background behind a volume. This file holds what the parts share
//! (the frames they draw and compare); the tests are in `shadow_volume/`: `sweeps.rs` (emulated
//! equals the reference over scenes and options), `counter.rs` (the counter's arithmetic),
//! `casters.rs` (what each caster casts, and how it is reported) and `reuse.rs` (volumes across
//! frames, and the shader-extruded ones).

use crate::common::{self, technique};

use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::sync::Arc;

use ash::vk;

use glam::{Mat4, Vec3};
use image::RgbaImage;
use nostencil::frame::render_pass::COLOUR_FORMAT;
use nostencil::mesh::MeshData;
use nostencil::render::plan::Scissor;
use nostencil::render::plan::{Draws, PassKinds, PlannedPass};
use nostencil::render::FrameRecorder;
use nostencil::render::Pipeline;
use nostencil::render::Renderer;
use nostencil::scene::lights::parse_light_spec;
use nostencil::technique::shadow_volume::alpha_counter;
use nostencil::technique::shadow_volume::bounds;
use nostencil::technique::shadow_volume::{self, Normalize, ShadowVolumeOptions, VolumeMethod};
use nostencil::technique::ShadowTone;
use nostencil::Gpu;
use nostencil::StencilMode;
use nostencil::{builtin_scene, Light, Scene, BUILTIN_SCENES};
use nostencil::{render_scene, RenderOptions, ShadowMode};

#[path = "shadow_volume/casters.rs"]
mod casters;
#[path = "shadow_volume/counter.rs"]
mod counter;
#[path = "shadow_volume/reuse.rs"]
mod reuse;
#[path = "shadow_volume/sweeps.rs"]
mod sweeps;

const SIZE: (u32, u32) = (128, 96);

/// The family's options for the seed's frame (Hall's apply, `--shadow-mode modulate`), what most
/// proofs here are about: `render` and its siblings draw that frame. The additive loop's own
/// proofs are `sweeps::additive_*` (`render_additive`) and in tests/inside/lights.rs.
fn seed() -> ShadowVolumeOptions {
    ShadowVolumeOptions::default()
}

/// A shadow-volume frame with the technique's statistics.
struct Frame {
    output: nostencil::FrameOutput,
    stats: nostencil::stats::ShadowVolumeStats,
}

fn render(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, options: ShadowVolumeOptions) -> Frame {
    render_sized(gpu, scene, stencil, options, SIZE)
}

/// `render` in the additive loop.
fn render_additive(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, options: ShadowVolumeOptions) -> Frame {
    try_render(gpu, scene, stencil, ShadowMode::Additive, options, SIZE, ShadowTone::default())
        .expect("shadow-volume frame")
}

/// `render` with a shadow tone other than the default.
fn render_toned(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    options: ShadowVolumeOptions,
    shadow_tone: ShadowTone,
) -> Frame {
    try_render(gpu, scene, stencil, ShadowMode::Modulate, options, SIZE, shadow_tone).expect("shadow-volume frame")
}

fn render_sized(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
) -> Frame {
    try_render(gpu, scene, stencil, ShadowMode::Modulate, options, size, ShadowTone::default())
        .expect("shadow-volume frame")
}

fn try_render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    shadow_mode: ShadowMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
    shadow_tone: ShadowTone,
) -> nostencil::Result<Frame> {
    frame_of(gpu, scene, &render_options(stencil, shadow_mode, options, size, shadow_tone))
}

fn render_options(
    stencil: StencilMode,
    shadow_mode: ShadowMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
    shadow_tone: ShadowTone,
) -> RenderOptions {
    RenderOptions {
        width: size.0,
        height: size.1,
        stencil,
        technique: technique("shadow-volume"),
        shadow_volume: options,
        shadow_mode,
        shadow_tone,
        ..Default::default()
    }
}

fn frame_of(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions) -> nostencil::Result<Frame> {
    let frame = render_scene(gpu, scene, options)?;
    let stats = frame.stats::<nostencil::stats::ShadowVolumeStats>().expect("shadow-volume statistics").clone();
    Ok(Frame { output: frame.output, stats })
}

fn lit(gpu: &Arc<Gpu>, scene: &Scene) -> RgbaImage {
    lit_sized(gpu, scene, SIZE)
}

fn lit_sized(gpu: &Arc<Gpu>, scene: &Scene, size: (u32, u32)) -> RgbaImage {
    let options = RenderOptions { width: size.0, height: size.1, technique: technique("lit"), ..Default::default() };
    render_scene(gpu, scene, &options).expect("lit frame").output.image
}

/// Pixels whose RGB differ (alpha holds each path's working state and is not the image).
fn rgb_differences(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p[..3] != q[..3]).count()
}

/// Pixels darkened by the shadow: where the shadowed frame differs from the unshadowed one.
fn shadow_mask(shadowed: &RgbaImage, lit: &RgbaImage) -> Vec<bool> {
    shadowed.chunks_exact(4).zip(lit.chunks_exact(4)).map(|(p, q)| p[..3] != q[..3]).collect()
}

/// Names of the passes a frame drew.
fn pass_names(frame: &Frame) -> Vec<&str> {
    frame.output.counters.passes.iter().map(|p| p.name.as_str()).collect()
}

/// The box scene with a roof over its box and a second, smaller box under the roof: from the
/// sun both boxes lie wholly in the roof's shadow, so they cast nothing new (the nested parts of
/// an assembly, in miniature).
fn nested_scene() -> Scene {
    let mut scene = builtin_scene("box").expect("scene");
    let cube = scene.add_mesh("roof", nostencil::mesh::shapes::cube(1.0));
    let roof = Mat4::from_scale_rotation_translation(
        Vec3::new(3.4, 0.2, 3.4),
        glam::Quat::IDENTITY,
        Vec3::new(-0.8, 3.6, 0.2),
    );
    scene.add_object("roof", cube, roof, Vec3::new(0.7, 0.7, 0.72), true);
    let small = scene.add_mesh("small box", nostencil::mesh::shapes::cube(1.0));
    let place = Mat4::from_scale_rotation_translation(Vec3::splat(0.5), glam::Quat::IDENTITY, Vec3::new(0.6, 0.6, 0.3));
    scene.add_object("small box", small, place, Vec3::new(0.85, 0.4, 0.3), true);
    scene
}

/// The volume passes' vertex invocations, clipping primitives and fragment invocations.
fn volume_work(frame: &Frame) -> [u64; 3] {
    let volumes = frame.output.counters.passes.iter().filter(|p| p.name.contains("volumes"));
    volumes.fold([0; 3], |[v, p, f], pass| {
        let count = |c: Option<u64>| c.expect("lavapipe has pipeline statistics");
        [v + count(pass.vertex_invocations), p + count(pass.clipping_primitives), f + count(pass.fragment_invocations)]
    })
}
