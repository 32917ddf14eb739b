//! The shadow-volume pipelines (DESIGN.md section 2), from the named recipes, and the frame's
//! pass plan for each path.
//!
//! Emulated frame, one render pass:
//! 1. scene: lit objects, every pixel's alpha set to 0 (the counter);
//! 2. volume increments (+k/255 per wall), then the saturation probe, then volume decrements:
//!    all increments come first because alpha clamps at 0 where a stencil would wrap (the
//!    volumes of two-sided casters, DESIGN.md section 8, bring their near caps in z-pass too);
//! 3. normalisation, one of: `seed` (N0, n iterations, REVERSE_SUBTRACT D, ADD D), `max`
//!    (N0, n iterations, MAX D; n from k and D, `alpha_counter::seed_iterations`) or `subpass` (read the count as an input attachment);
//! 4. apply: colour *= alpha (or, for `subpass`, *= the factor the shader outputs).
//!
//! Reference frame: scene, volumes with a two-sided INCREMENT_AND_WRAP / DECREMENT_AND_WRAP
//! stencil, negative counts cleared, and a full-screen apply pass with stencil test NOT_EQUAL 0.

use ash::vk;
use glam::Vec4;

use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::pipeline::recipes::{self, NO_WRITE};
use crate::pipeline::{BlendState, DepthState, FixedFunction, PipelineDesc, RasterState, VertexLayout};
use crate::render::plan::{Draws, PassPlan, PlannedPass, Push, SetRole};
use crate::render::OBJECT_PUSH_BYTES;
use crate::technique::alpha_counter;
use crate::technique::lit;
use crate::technique::options::{Normalize, ShadowVolumeOptions, VolumeMethod};

/// The subpass input that exposes the counter to full-screen passes.
pub const COUNTER_INPUT: SetRole = SetRole::Own("counter input");

/// What the volume passes draw.
pub const VOLUMES: Draws = Draws::Geometry("shadow volumes");

fn volume_desc(name: &'static str, raster: RasterState, compare: vk::CompareOp, blend: BlendState) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: "shadow_volume.vert",
        fragment_shader: "object_colour.frag",
        vertex_layout: VertexLayout::POSITION4,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster,
            depth: DepthState { compare: Some(compare), write: false },
            stencil: None,
            blend,
        },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

fn fullscreen_desc(name: &'static str, fragment_shader: &'static str, blend: BlendState) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: "fullscreen.vert",
        fragment_shader,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction { blend, ..FixedFunction::FULLSCREEN },
        push_constant_bytes: 16,
        subpass: 0,
    }
}

/// Increment and decrement pipelines for one counting method.
pub fn volume_descs(zfail: bool) -> [PipelineDesc; 2] {
    use recipes::{COUNTER_DECREMENT, COUNTER_INCREMENT};
    const GREATER_OR_EQUAL: vk::CompareOp = vk::CompareOp::GREATER_OR_EQUAL;
    const LESS: vk::CompareOp = vk::CompareOp::LESS;
    if zfail {
        // Walls behind the visible surface count: back faces up, front faces down.
        [
            volume_desc("volume increment (z-fail)", RasterState::CULL_FRONT, GREATER_OR_EQUAL, COUNTER_INCREMENT),
            volume_desc("volume decrement (z-fail)", RasterState::CULL_BACK, GREATER_OR_EQUAL, COUNTER_DECREMENT),
        ]
    } else {
        // Walls in front of the visible surface count: front faces up, back faces down.
        [
            volume_desc("volume increment (z-pass)", RasterState::CULL_BACK, LESS, COUNTER_INCREMENT),
            volume_desc("volume decrement (z-pass)", RasterState::CULL_FRONT, LESS, COUNTER_DECREMENT),
        ]
    }
}

pub fn n0_desc() -> PipelineDesc {
    fullscreen_desc("normalise N0", "solid.frag", recipes::NORMALISE_N0)
}

pub fn iteration_desc() -> PipelineDesc {
    fullscreen_desc("normalise iteration", "solid.frag", recipes::NORMALISE_ITERATION)
}

pub fn darkness_descs(normalize: Normalize) -> Vec<PipelineDesc> {
    match normalize {
        Normalize::Seed => vec![
            fullscreen_desc("darkness subtract D", "solid.frag", recipes::DARKNESS_SUBTRACT),
            fullscreen_desc("darkness add D", "solid.frag", recipes::DARKNESS_ADD),
        ],
        Normalize::Max => vec![fullscreen_desc("darkness max D", "solid.frag", recipes::DARKNESS_MAX)],
        Normalize::Subpass => vec![],
    }
}

pub fn apply_desc(normalize: Normalize) -> PipelineDesc {
    match normalize {
        // colour *= dst alpha (1 where lit, D where shadowed).
        Normalize::Seed | Normalize::Max => fullscreen_desc("apply", "solid.frag", recipes::MODULATE_BY_DST_ALPHA),
        // colour *= the factor the shader read from the count.
        Normalize::Subpass => fullscreen_desc("apply (subpass)", "shadow_subpass.frag", recipes::MODULATE_BY_SRC_ALPHA),
    }
}

pub fn saturation_probe_desc() -> PipelineDesc {
    let mut desc = fullscreen_desc("saturation probe", "saturation_probe.frag", NO_WRITE);
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

/// Counts below zero (the stencil wraps them to 128..255) can only come from rasterisation
/// precision where volume walls meet their caster. The alpha counter clamps them to 0, so the
/// reference sets them to 0 as well before applying: both paths then shade exactly
/// `max(0, increments - decrements)`, and agree bit for bit.
pub fn reference_clear_negative_desc() -> PipelineDesc {
    let mut desc = fullscreen_desc("clear negative counts (stencil)", "solid.frag", NO_WRITE);
    desc.fixed.stencil = Some(recipes::STENCIL_NEGATIVE_TO_ZERO);
    desc
}

pub fn reference_apply_desc() -> PipelineDesc {
    let mut desc = fullscreen_desc("apply (stencil)", "solid.frag", recipes::MODULATE_BY_SRC_ALPHA);
    desc.fixed.stencil = Some(recipes::stencil_not_equal(0));
    desc
}

fn solid(alpha: f32) -> Vec4 {
    Vec4::new(0.0, 0.0, 0.0, alpha)
}

/// The seed's normalisation: N0 then `iterations` iterations, each a full-screen pass writing
/// alpha only.
pub fn seed_normalisation(iterations: usize) -> Vec<PlannedPass> {
    let mut passes = vec![PlannedPass::full_screen("normalise N0", n0_desc(), solid(1.0))];
    passes.extend(
        (1..=iterations).map(|i| PlannedPass::full_screen(format!("normalise N{i}"), iteration_desc(), solid(1.0))),
    );
    passes
}

/// The frame's passes for `options` at `stencil`, counting with z-fail or z-pass. `auto` is
/// decided per scene when the renderer is built (`casters::choose_zfail`), so a plan asked for
/// without a scene must name the method.
pub fn plan(options: &ShadowVolumeOptions, stencil: StencilMode) -> Result<PassPlan> {
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
    let step = k as f32 / 255.0;
    let factor = options.shadow_factor as f32 / 255.0;
    let volumes = |name, desc, alpha| {
        PlannedPass::new(name, desc, VOLUMES, Push::TransformAlpha(alpha)).with_sets(&[SetRole::Frame])
    };
    let mut plan = PassPlan::new();
    // The scene writes alpha 0 everywhere: the counter starts at zero.
    plan.push(lit::scene_pass(0.0));
    match stencil {
        StencilMode::Reference => {
            let desc = reference_volume_desc(zfail);
            plan.push(volumes(desc.name, desc, 0.0));
            plan.push(PlannedPass::full_screen(
                "clear negative counts (stencil)",
                reference_clear_negative_desc(),
                solid(0.0),
            ));
            plan.push(PlannedPass::full_screen("apply (stencil)", reference_apply_desc(), solid(factor)));
        }
        StencilMode::Emulated => {
            let [increment, decrement] = volume_descs(zfail);
            plan.push(volumes(increment.name, increment, step));
            plan.push(
                PlannedPass::new("saturation probe", saturation_probe_desc(), Draws::FullScreen, Push::Nothing)
                    .with_sets(&[COUNTER_INPUT])
                    .reading_colour(),
            );
            plan.push(volumes(decrement.name, decrement, step));
            match options.normalize {
                Normalize::Seed | Normalize::Max => {
                    plan.extend(seed_normalisation(alpha_counter::seed_iterations(k, options.shadow_factor)?));
                    for desc in darkness_descs(options.normalize) {
                        plan.push(PlannedPass::full_screen(desc.name, desc, solid(factor)));
                    }
                    plan.push(PlannedPass::full_screen("apply", apply_desc(options.normalize), solid(1.0)));
                }
                Normalize::Subpass => {
                    plan.push(
                        PlannedPass::full_screen(
                            "apply (subpass)",
                            apply_desc(Normalize::Subpass),
                            Vec4::new(factor, 0.0, 0.0, 0.0),
                        )
                        .with_sets(&[COUNTER_INPUT])
                        .reading_colour(),
                    );
                }
            }
        }
    }
    Ok(plan)
}
