//! The shadow-volume pipelines (docs/design/shadow-volumes.md), from the named recipes, and the frame's
//! pass plan for each path.
//!
//! Every volume is clipped to the receivers' bounds and drawn inside its own scissor, and every
//! full-screen pass after the volumes inside their union (`bounds`): the
//! same in both paths, so what clipping saves is saved in both.
//!
//! Emulated frame, one render pass:
//! 1. scene: lit objects, every pixel's alpha set to 0 (the counter);
//! 2. volumes, one pass with two pipelines: every increment (+k/255 per wall), then every
//!    decrement. All increments come first because alpha clamps at 0 where a stencil would
//!    wrap (the volumes of two-sided casters, docs/design/any-mesh-volumes.md, bring their near caps in
//!    z-pass too);
//! 3. only with `--saturation-probe`: the probe, a diagnostic full-screen pass whose occlusion
//!    query counts the pixels whose counter sits at its clamp (docs/design/saturation.md);
//! 4. normalisation, one of: `seed` (N0, n iterations, REVERSE_SUBTRACT D, ADD D), `max` (N0,
//!    n iterations, MAX D; n from k and D, `alpha_counter::seed_iterations`) or `subpass`
//!    (read the count as an input attachment, and count the clamped pixels with one atomic add
//!    each where the device has fragment atomics);
//! 5. apply: colour *= alpha (or, for `subpass`, *= the factor the shader outputs; lit pixels
//!    are discarded, so that, as under the reference's stencil test, only shadowed pixels are
//!    written).
//!
//! Reference frame, as a port would ship it: scene, volumes with a two-sided
//! INCREMENT_AND_WRAP / DECREMENT_AND_WRAP stencil cleared to 0x80 (a count of 0), and one
//! full-screen apply with stencil test `0x80 < stencil`. The bias keeps the proof bit-exact
//! with no pass of its own: a negative count (which the clamping alpha counter holds as 0)
//! wraps to below 0x80 instead of to 255, so the apply leaves it lit, as the emulated paths do.

use ash::vk;
use glam::Vec4;

use super::alpha_counter;
use super::gpu_extrusion::VOLUME_PUSH_BYTES;
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::pipeline::recipes::{self, NO_WRITE};
use crate::pipeline::{BlendState, DepthState, FixedFunction, PipelineDesc, RasterState, VertexLayout};
use crate::render::plan::{fmt_f32, DrawKind, Draws, Label, NoOwn, Only, PassKinds, PassPlan, PlannedPass, SetRole};
use crate::render::LIGHT_PUSH_BYTES;
use crate::shaders;
use crate::technique::light_loop::{self, PlannedLight};
use crate::technique::lit;
use crate::technique::material_variants::with_surface_variants;
use crate::technique::options::{Normalize, ShadowMode, ShadowVolumeOptions, VolumeExtrusion, VolumeMethod};
use crate::technique::shadow_tone::ShadowTone;

/// The subpass input that exposes the counter to full-screen passes.
/// The kinds of the shadow-volume plan: the volumes it draws itself, and the counter it reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct VolumeKinds;

impl PassKinds for VolumeKinds {
    type Draw = VolumeDraw;
    type Set = VolumeSet;
    type Target = NoOwn;
}

/// What the shadow-volume renderer draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VolumeDraw {
    /// Every caster's volume for light `light` (an index into the scene's lights), black with
    /// alpha `alpha` (the increment k/255, or 0 on the reference path), with each pipeline of
    /// the pass in turn; first, with `clear_stencil`, the stencil cleared to a count of 0 in
    /// the light's scissor (the reference's per-light clear, Doom 3's and Ogre's).
    Volumes { alpha: f32, light: u8, clear_stencil: bool },
}

impl DrawKind for VolumeDraw {
    fn describe(self) -> &'static str {
        match self {
            VolumeDraw::Volumes { .. } => "shadow volumes",
        }
    }
}

/// The shadow-volume plan's own descriptor sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VolumeSet {
    /// The colour target as an input attachment (and the saturation counter).
    CounterInput,
    /// The casters' shadow-mesh tables, which volumes extruded on the GPU read.
    ShadowMeshes,
}

impl Label for VolumeSet {
    fn label(self) -> &'static str {
        match self {
            VolumeSet::CounterInput => "counter input",
            VolumeSet::ShadowMeshes => "shadow meshes",
        }
    }
}

pub const COUNTER_INPUT: SetRole<VolumeSet> = SetRole::Own(VolumeSet::CounterInput);
pub const SHADOW_MESHES: SetRole<VolumeSet> = SetRole::Own(VolumeSet::ShadowMeshes);

/// The opt-in saturation probe's pass name (its occlusion query is the count).
pub const SATURATION_PROBE: &str = "saturation probe";

/// A volume pipeline of the CPU-chosen indices: each fragment counts the push's alpha times the
/// draw's first instance, the multiplicity of the range drawn (`shaders/shadow_volume.vert`), so
/// a draw with first instance 0 counts nothing.
fn volume_desc(name: &'static str, raster: RasterState, compare: vk::CompareOp, blend: BlendState) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: shaders::SHADOW_VOLUME_VERT,
        fragment_shader: shaders::SHADOW_VOLUME_FRAG,
        vertex_layout: VertexLayout::POSITION4,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster,
            depth: DepthState { compare: Some(compare), write: false },
            stencil: None,
            blend,
        },
        // Both forms' pipelines share one layout (the GPU form's push constants and tables),
        // so that a pass can switch between them without binding its sets again.
        push_constant_bytes: VOLUME_PUSH_BYTES,
    }
}

/// The GPU-extruded twin of a volume pipeline (`gpu_extrusion`): the same fixed function, the
/// extruding shaders, no vertex buffer.
pub fn extruded(desc: PipelineDesc) -> PipelineDesc {
    let name = match desc.name {
        "volume increment (z-pass)" => "volume increment (z-pass, extruded on the GPU)",
        "volume decrement (z-pass)" => "volume decrement (z-pass, extruded on the GPU)",
        "volume increment (z-fail)" => "volume increment (z-fail, extruded on the GPU)",
        "volume decrement (z-fail)" => "volume decrement (z-fail, extruded on the GPU)",
        "volume enter (z-pass)" => "volume enter (z-pass, extruded on the GPU)",
        "volume leave (z-pass)" => "volume leave (z-pass, extruded on the GPU)",
        "volume enter (z-fail)" => "volume enter (z-fail, extruded on the GPU)",
        "volume leave (z-fail)" => "volume leave (z-fail, extruded on the GPU)",
        "volumes (stencil, z-pass)" => "volumes (stencil, z-pass, extruded on the GPU)",
        "volumes (stencil, z-fail)" => "volumes (stencil, z-fail, extruded on the GPU)",
        _ => "volumes (extruded on the GPU)",
    };
    PipelineDesc {
        name,
        vertex_shader: shaders::SHADOW_VOLUME_EXTRUDE_VERT,
        fragment_shader: shaders::SHADOW_VOLUME_FRAG,
        vertex_layout: VertexLayout::NONE,
        ..desc
    }
}

/// Whether `desc` draws volumes extruded on the GPU.
pub fn is_extruded(desc: &PipelineDesc) -> bool {
    desc.vertex_shader == shaders::SHADOW_VOLUME_EXTRUDE_VERT
}

fn fullscreen_desc(name: &'static str, fragment_shader: shaders::Shader, blend: BlendState) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: shaders::FULLSCREEN_VERT,
        fragment_shader,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction { blend, ..FixedFunction::FULLSCREEN },
        push_constant_bytes: 16,
    }
}

/// The two pipelines of a volume pass for one counting method: entering walls blended with
/// `enter`, then leaving walls with `leave`, named `names[0]` and `names[1]` with the method.
/// z-fail counts the walls behind the visible surface (back faces enter, front faces leave),
/// z-pass those in front (front faces enter, back faces leave).
fn counting_descs(zfail: bool, names: [[&'static str; 2]; 2], [enter, leave]: [BlendState; 2]) -> [PipelineDesc; 2] {
    let [zpass_names, zfail_names] = names;
    if zfail {
        let compare = vk::CompareOp::GREATER_OR_EQUAL;
        [
            volume_desc(zfail_names[0], RasterState::CULL_FRONT, compare, enter),
            volume_desc(zfail_names[1], RasterState::CULL_BACK, compare, leave),
        ]
    } else {
        let compare = vk::CompareOp::LESS;
        [
            volume_desc(zpass_names[0], RasterState::CULL_BACK, compare, enter),
            volume_desc(zpass_names[1], RasterState::CULL_FRONT, compare, leave),
        ]
    }
}

/// Increment and decrement pipelines for one counting method (the seed's up-counter).
pub fn volume_descs(zfail: bool) -> [PipelineDesc; 2] {
    let names = [
        ["volume increment (z-pass)", "volume decrement (z-pass)"],
        ["volume increment (z-fail)", "volume decrement (z-fail)"],
    ];
    counting_descs(zfail, names, [recipes::COUNTER_INCREMENT, recipes::COUNTER_DECREMENT])
}

pub fn n0_desc() -> PipelineDesc {
    fullscreen_desc("normalise N0", shaders::SOLID_FRAG, recipes::NORMALISE_N0)
}

pub fn iteration_desc() -> PipelineDesc {
    fullscreen_desc("normalise iteration", shaders::SOLID_FRAG, recipes::NORMALISE_ITERATION)
}

pub fn darkness_descs(normalize: Normalize) -> Vec<PipelineDesc> {
    match normalize {
        Normalize::Seed => vec![
            fullscreen_desc("darkness subtract D", shaders::SOLID_FRAG, recipes::DARKNESS_SUBTRACT),
            fullscreen_desc("darkness add D", shaders::SOLID_FRAG, recipes::DARKNESS_ADD),
        ],
        Normalize::Max => vec![fullscreen_desc("darkness max D", shaders::SOLID_FRAG, recipes::DARKNESS_MAX)],
        Normalize::Subpass => vec![],
    }
}

/// The fragment shader of a subpass-reading pass: its one-sample form, or the one that reads
/// every sample of a multisampled frame.
fn counter_reader(one_sample: shaders::Shader, multisampled: shaders::Shader, samples: u32) -> shaders::Shader {
    if samples > 1 {
        multisampled
    } else {
        one_sample
    }
}

/// [`apply_desc`] for a frame of `samples` samples.
pub fn subpass_aware_apply_desc(normalize: Normalize, samples: u32) -> PipelineDesc {
    match normalize {
        // colour *= dst alpha (1 where lit, D where shadowed).
        Normalize::Seed | Normalize::Max => {
            fullscreen_desc("apply", shaders::SOLID_FRAG, recipes::MODULATE_BY_DST_ALPHA)
        }
        // colour *= the factors the shader output where the count is not 0.
        Normalize::Subpass => {
            let shader = counter_reader(shaders::SHADOW_SUBPASS_FRAG, shaders::SHADOW_SUBPASS_MS_FRAG, samples);
            fullscreen_desc("apply (subpass)", shader, recipes::MODULATE_BY_SRC_COLOUR)
        }
    }
}

/// The blend-only apply of a tinted shadow writes one group of channels at a time, those whose
/// factor the alpha mask holds at that moment (see [`tinted_darkness_and_apply`]).
fn channel_apply_desc(channels: vk::ColorComponentFlags) -> PipelineDesc {
    let name = match (channels.contains(RED), channels.contains(GREEN), channels.contains(BLUE)) {
        (true, true, true) => "apply",
        (true, true, false) => "apply (red, green)",
        (true, false, true) => "apply (red, blue)",
        (false, true, true) => "apply (green, blue)",
        (true, false, false) => "apply (red)",
        (false, true, false) => "apply (green)",
        _ => "apply (blue)",
    };
    let mut desc = fullscreen_desc(name, shaders::SOLID_FRAG, recipes::MODULATE_BY_DST_ALPHA);
    desc.fixed.blend.write_mask = channels;
    desc
}

const RED: vk::ColorComponentFlags = vk::ColorComponentFlags::R;
const GREEN: vk::ColorComponentFlags = vk::ColorComponentFlags::G;
const BLUE: vk::ColorComponentFlags = vk::ColorComponentFlags::B;

/// The blend-only paths' darkness steps and apply for the factors `rgb`. The alpha mask holds
/// one number, so each distinct factor gets its own darkness step and an apply that writes
/// only its channels, from the darkest up: the darkness steps set every shadowed pixel to
/// exactly their D (from any value <= D, which the previous, darker step left) and keep lit
/// pixels at 1. A grey shadow is one darkness step and one apply, as in the seed.
fn tinted_darkness_and_apply(normalize: Normalize, tone: ShadowTone) -> Vec<PlannedPass<VolumeKinds>> {
    let rgb = tone.rgb();
    let mut factors = rgb.to_vec();
    factors.sort_unstable();
    factors.dedup();
    let grey = factors.len() == 1;
    let mut passes = Vec::new();
    for factor in factors {
        let channels = [RED, GREEN, BLUE]
            .into_iter()
            .zip(rgb)
            .filter(|&(_, f)| f == factor)
            .fold(vk::ColorComponentFlags::empty(), |all, (channel, _)| all | channel);
        let apply = channel_apply_desc(channels);
        let suffix = if grey { String::new() } else { format!(" {}", &apply.name["apply ".len()..]) };
        for desc in darkness_descs(normalize) {
            let name = format!("{}{suffix}", desc.name);
            passes.push(PlannedPass::full_screen(name, desc, solid(ShadowTone::factor(factor))).scissored());
        }
        passes.push(PlannedPass::full_screen(apply.name, apply, solid(1.0)).scissored());
    }
    passes
}

/// The subpass apply that also counts saturated samples into a storage buffer (binding 1 of the
/// counter input set): for devices with `fragmentStoresAndAtomics`.
pub fn counting_subpass_apply_desc(samples: u32) -> PipelineDesc {
    let shader = counter_reader(shaders::SHADOW_SUBPASS_COUNTED_FRAG, shaders::SHADOW_SUBPASS_COUNTED_MS_FRAG, samples);
    fullscreen_desc("apply (subpass, counts saturation)", shader, recipes::MODULATE_BY_SRC_COLOUR)
}

pub fn saturation_probe_desc(samples: u32) -> PipelineDesc {
    let shader = counter_reader(shaders::SATURATION_PROBE_FRAG, shaders::SATURATION_PROBE_MS_FRAG, samples);
    let mut desc = fullscreen_desc("saturation probe", shader, NO_WRITE);
    desc.push_constant_bytes = 0;
    desc
}

pub fn reference_volume_desc(zfail: bool) -> PipelineDesc {
    let compare = vk::CompareOp::LESS;
    let mut desc = volume_desc(
        if zfail { "volumes (stencil, z-fail)" } else { "volumes (stencil, z-pass)" },
        RasterState::CULL_NONE,
        compare,
        NO_WRITE,
    );
    desc.fixed.stencil = Some(recipes::stencil_volume_count(zfail));
    desc
}

/// The reference's one apply: shades where the count is positive (colour *= the pushed factors). Counts below zero do occur
/// (rasterisation precision where volume walls meet their caster; a z-pass camera inside a
/// volume, whose entry wall is clipped away, leaves -1 behind the exit wall). The alpha
/// counter clamps them to 0, so they must stay lit here too: with the stencil cleared to
/// `STENCIL_COUNT_ZERO` they wrap to 0..0x7f, and the test `0x80 < stencil` fails on them. Both
/// paths then shade exactly where `increments - decrements` is in 1..=127 and agree bit for
/// bit, with no pass that a port would not ship.
pub fn reference_apply_desc() -> PipelineDesc {
    let mut desc = fullscreen_desc("apply (stencil)", shaders::SOLID_FRAG, recipes::MODULATE_BY_SRC_COLOUR);
    desc.fixed.stencil = Some(recipes::STENCIL_COUNT_POSITIVE);
    desc
}

fn solid(alpha: f32) -> Vec4 {
    Vec4::new(0.0, 0.0, 0.0, alpha)
}

/// The seed's normalisation: N0 then `iterations` iterations, each a full-screen pass writing
/// alpha only, inside the volumes' scissors (outside them every count is 0 and the apply
/// leaves the pixel alone).
pub fn seed_normalisation(iterations: usize) -> Vec<PlannedPass<VolumeKinds>> {
    let mut passes = vec![PlannedPass::full_screen("normalise N0", n0_desc(), solid(1.0)).scissored()];
    passes.extend(
        (1..=iterations)
            .map(|i| PlannedPass::full_screen(format!("normalise N{i}"), iteration_desc(), solid(1.0)).scissored()),
    );
    passes
}

/// The frame's passes for `options` in the `stencil` path, at `samples` samples per pixel, for
/// `lights` (the additive loop runs over them; the seed's modulate mode shadows the primary
/// one). `auto` is decided per scene when the renderer is built (`casters::choose_zfail`), so a
/// plan asked for without a scene must name the method.
pub fn plan(
    options: &ShadowVolumeOptions,
    mode: ShadowMode,
    tone: ShadowTone,
    stencil: StencilMode,
    samples: u32,
    lights: &[PlannedLight],
) -> Result<PassPlan<VolumeKinds>> {
    let zfail =
        match options.method {
            VolumeMethod::ZPass => false,
            VolumeMethod::ZFail => true,
            VolumeMethod::Auto => return Err(Error::InvalidInput(
                "--volume-method auto is chosen per scene: a shadow-volume plan without a scene needs zpass or zfail"
                    .into(),
            )),
        };
    let k = alpha_counter::check_increment(options.increment)?;
    match mode {
        ShadowMode::Modulate => modulate_plan(options, tone, stencil, samples, zfail, k, lights),
        ShadowMode::Additive => additive_plan(options, stencil, samples, zfail, k, lights),
    }
}

/// A pass of light `light`'s volumes, drawn with `desc`, then with `then` if given (the
/// alpha counter's decrements), each followed by its GPU-extruded twin where the extrusion is
/// `shader` (the CPU-chosen indices stay for the casters the shadow mesh does not take).
/// The coverage probe draws them without their depth test.
fn volumes_pass(
    name: impl Into<std::borrow::Cow<'static, str>>,
    (desc, then): (PipelineDesc, Option<PipelineDesc>),
    options: &ShadowVolumeOptions,
    (alpha, light, clear_stencil): (f32, u8, bool),
) -> PlannedPass<VolumeKinds> {
    let probed = |mut desc: PipelineDesc| {
        if options.coverage_probe {
            desc.fixed.depth.compare = Some(vk::CompareOp::ALWAYS);
        }
        desc
    };
    let (desc, then) = (probed(desc), then.map(probed));
    let push = format!("object transform, alpha {}", fmt_f32(alpha));
    let gpu = options.extrusion == VolumeExtrusion::Shader;
    let sets: &[SetRole<VolumeSet>] = if gpu { &[SetRole::Frame, SHADOW_MESHES] } else { &[SetRole::Frame] };
    let mut pass = PlannedPass::own(name, desc.clone(), VolumeDraw::Volumes { alpha, light, clear_stencil }, push)
        .with_sets(sets)
        .for_light(light);
    if gpu {
        pass = pass.or_pipeline(extruded(desc));
    }
    if let Some(then) = then {
        pass = pass.or_pipeline(then.clone());
        if gpu {
            pass = pass.or_pipeline(extruded(then));
        }
    }
    pass
}

/// The seed's frame (Hall): the lit scene, the primary light's volumes counted up from 0, the
/// normalisation and the apply that darkens the finished frame.
fn modulate_plan(
    options: &ShadowVolumeOptions,
    tone: ShadowTone,
    stencil: StencilMode,
    samples: u32,
    zfail: bool,
    k: u8,
    lights: &[PlannedLight],
) -> Result<PassPlan<VolumeKinds>> {
    let step = k as f32 / 255.0;
    let primary = light_loop::primary(lights).unwrap_or(0) as u8;
    // The shadowed colour's factors per channel (a grey D, or a tint).
    let factors = tone.vec3().extend(0.0);
    let mut plan = PassPlan::new();
    // The scene writes alpha 0 everywhere: the counter starts at zero.
    plan.push(lit::scene_pass(0.0));
    match stencil {
        StencilMode::Reference => {
            let desc = reference_volume_desc(zfail);
            plan.push(volumes_pass(desc.name, (desc.clone(), None), options, (0.0, primary, false)));
            plan.push(PlannedPass::full_screen("apply (stencil)", reference_apply_desc(), factors).scissored());
        }
        StencilMode::Emulated => {
            // One pass, two pipelines: every caster's increments, then every caster's
            // decrements (`renderer` draws them in that order).
            let [increment, decrement] = volume_descs(zfail);
            let name = if zfail { "volumes (alpha, z-fail)" } else { "volumes (alpha, z-pass)" };
            plan.push(volumes_pass(name, (increment, Some(decrement)), options, (step, primary, false)));
            if options.saturation_probe {
                plan.push(
                    PlannedPass::new(
                        SATURATION_PROBE,
                        saturation_probe_desc(samples),
                        Draws::FullScreen { push: None },
                    )
                    .with_sets(&[COUNTER_INPUT])
                    .reading_colour(),
                );
            }
            match options.normalize {
                Normalize::Seed | Normalize::Max => {
                    plan.extend(seed_normalisation(alpha_counter::seed_iterations(k, tone.darkest())?));
                    plan.extend(tinted_darkness_and_apply(options.normalize, tone));
                }
                Normalize::Subpass => {
                    let apply = if options.fragment_atomics {
                        counting_subpass_apply_desc(samples)
                    } else {
                        subpass_aware_apply_desc(Normalize::Subpass, samples)
                    };
                    plan.push(
                        PlannedPass::full_screen("apply (subpass)", apply, factors)
                            .with_sets(&[COUNTER_INPUT])
                            .reading_colour()
                            .scissored(),
                    );
                }
            }
        }
    }
    Ok(plan)
}

/// Down-counting volume pipelines (additive mode): entering walls take k/255 off, leaving
/// walls give it back, with the faces and depth tests of `volume_descs`.
pub fn down_volume_descs(zfail: bool) -> [PipelineDesc; 2] {
    let names =
        [["volume enter (z-pass)", "volume leave (z-pass)"], ["volume enter (z-fail)", "volume leave (z-fail)"]];
    counting_descs(zfail, names, [recipes::COUNTER_DOWN_ENTER, recipes::COUNTER_DOWN_LEAVE])
}

/// The ambient pass of the additive loop: depth, ambient x albedo and emissive, alpha 1 (every
/// light's down-counter starts at a count of 0). Blended materials wait for `transparent`.
pub fn ambient_pass() -> PlannedPass<VolumeKinds> {
    let desc = PipelineDesc {
        name: "scene (ambient)",
        fragment_shader: shaders::LIT_AMBIENT_FRAG,
        ..lit::scene_pipeline_desc()
    };
    let pass = PlannedPass::objects("scene (ambient)", desc.clone(), 1.0).only(Only::Opaque);
    with_surface_variants(pass, &desc).with_sets(&[SetRole::Frame, SetRole::Material])
}

/// One light's shading pipeline: the scene's vertex stage (invariant, so depth EQUAL meets the
/// ambient pass's depth), the light's contribution out, blended by `blend`.
fn shading_desc(name: &'static str, blend: BlendState, stencil: Option<crate::pipeline::StencilState>) -> PipelineDesc {
    let mut desc = PipelineDesc {
        name,
        fragment_shader: shaders::LIT_LIGHT_FRAG,
        push_constant_bytes: LIGHT_PUSH_BYTES,
        ..lit::scene_pipeline_desc()
    };
    desc.fixed.depth = DepthState { compare: Some(vk::CompareOp::EQUAL), write: false };
    desc.fixed.blend = blend;
    desc.fixed.stencil = stencil;
    desc
}

/// Light `light`'s shading pass: `desc` over every opaque object in the light's scissor.
fn shading_pass(name: String, desc: PipelineDesc, light: u8) -> PlannedPass<VolumeKinds> {
    let pass = PlannedPass::objects(name, desc.clone(), 1.0).only(Only::Opaque);
    with_surface_variants(pass, &desc).with_sets(&[SetRole::Frame, SetRole::Material]).for_light(light).scissored()
}

/// Doom 3's and Ogre's loop on the alpha channel (docs/shadow-volumes.md, "Several lights"):
/// ambient, then per light its volumes counted down from 1 and turned into a 0/1 mask, and its
/// contribution added through the mask by a pass whose alpha blend also resets the counter for
/// the next light. The reference clears its stencil per light instead and shades where the
/// count is not positive.
fn additive_plan(
    options: &ShadowVolumeOptions,
    stencil: StencilMode,
    samples: u32,
    zfail: bool,
    k: u8,
    lights: &[PlannedLight],
) -> Result<PassPlan<VolumeKinds>> {
    let step = k as f32 / 255.0;
    let mut plan = PassPlan::new();
    plan.push(ambient_pass());
    let mut first_shadowing = true;
    for (index, light) in lights.iter().enumerate() {
        let i = index as u8;
        if !light.shadows {
            let desc = shading_desc("shading (no shadows)", recipes::ADD_LIGHT, None);
            plan.push(shading_pass(light_loop::pass_name(light, "shading"), desc, i));
            continue;
        }
        match stencil {
            StencilMode::Reference => {
                let desc = reference_volume_desc(zfail);
                let clear = !first_shadowing;
                let name = light_loop::pass_name(light, desc.name);
                plan.push(volumes_pass(name, (desc, None), options, (0.0, i, clear)));
                let desc =
                    shading_desc("shading (stencil)", recipes::ADD_LIGHT, Some(recipes::STENCIL_COUNT_NOT_POSITIVE));
                plan.push(shading_pass(light_loop::pass_name(light, "shading (stencil)"), desc, i));
            }
            StencilMode::Emulated => {
                let [enter, leave] = down_volume_descs(zfail);
                let name = if zfail { "volumes (alpha, z-fail)" } else { "volumes (alpha, z-pass)" };
                let name = light_loop::pass_name(light, name);
                plan.push(volumes_pass(name, (enter, Some(leave)), options, (step, i, false)));
                match options.normalize {
                    // No darkness step: the mask is exactly 0 or 1, and the light's own term
                    // is what a shadow removes. `max` differed from `seed` only there.
                    Normalize::Seed | Normalize::Max => {
                        for n in 1..=alpha_counter::down_iterations(k)? {
                            let name = light_loop::pass_name(light, &format!("normalise N{n}"));
                            plan.push(
                                PlannedPass::full_screen(name, iteration_desc(), solid(1.0)).scissored().for_light(i),
                            );
                        }
                    }
                    // One sample: the shading pass reads the count itself (one invocation per
                    // pixel holds the pixel's one count), so no mask pass.
                    Normalize::Subpass if samples == 1 => {
                        let (name, shader) = if options.fragment_atomics {
                            ("shading (subpass, counts saturation)", shaders::LIT_LIGHT_SUBPASS_COUNTED_FRAG)
                        } else {
                            ("shading (subpass)", shaders::LIT_LIGHT_SUBPASS_FRAG)
                        };
                        let desc = PipelineDesc {
                            fragment_shader: shader,
                            ..shading_desc(name, recipes::ADD_LIGHT_RESET, None)
                        };
                        let pass = shading_pass(light_loop::pass_name(light, "shading"), desc, i);
                        plan.push(pass.with_sets(&[SetRole::Frame, SetRole::Material, COUNTER_INPUT]).reading_colour());
                        first_shadowing = false;
                        continue;
                    }
                    // Several samples: one invocation per pixel cannot add the light to some of
                    // its samples and only reset the others, so a mask pass writes 0 first.
                    Normalize::Subpass => {
                        let name = light_loop::pass_name(light, "mask (subpass)");
                        plan.push(
                            PlannedPass::new(
                                name,
                                mask_desc(samples, options.fragment_atomics),
                                Draws::FullScreen { push: None },
                            )
                            .with_sets(&[COUNTER_INPUT])
                            .reading_colour()
                            .scissored()
                            .for_light(i),
                        );
                    }
                }
                let desc = shading_desc("shading", recipes::ADD_LIGHT_WHERE_LIT_RESET, None);
                plan.push(shading_pass(light_loop::pass_name(light, "shading"), desc, i));
            }
        }
        first_shadowing = false;
    }
    // Blended materials after the loop, lit by every light and unshadowed, as Doom 3 and Ogre
    // draw translucent surfaces.
    let desc = lit::scene_pipeline_desc();
    let transparent = PlannedPass::objects("transparent", desc.clone(), 1.0).only(Only::Blended);
    plan.push(with_surface_variants(transparent, &desc).with_sets(&[SetRole::Frame, SetRole::Material]));
    Ok(plan)
}

/// The additive subpass mask: alpha := 0 on the light's shadowed samples.
pub fn mask_desc(samples: u32, counts_saturation: bool) -> PipelineDesc {
    let shader = match (samples > 1, counts_saturation) {
        (false, false) => shaders::SHADOW_SUBPASS_MASK_FRAG,
        (true, false) => shaders::SHADOW_SUBPASS_MASK_MS_FRAG,
        (false, true) => shaders::SHADOW_SUBPASS_MASK_COUNTED_FRAG,
        (true, true) => shaders::SHADOW_SUBPASS_MASK_COUNTED_MS_FRAG,
    };
    let name = if counts_saturation { "mask (subpass, counts saturation)" } else { "mask (subpass)" };
    let mut desc = fullscreen_desc(name, shader, recipes::MASK_SHADOWED);
    desc.push_constant_bytes = 0;
    desc
}
