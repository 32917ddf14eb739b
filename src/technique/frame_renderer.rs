//! The renderer skeleton every technique shares, written once: build the frame renderer and
//! the plan's pipelines, then per frame check the scene, let the technique prepare its
//! geometry, record the plan (offscreen passes first, then the frame's render pass) and
//! collect the technique's statistics. A technique supplies only a [`Passes`] value: its
//! resources, its draws and its statistics.

use std::sync::Arc;

use super::interface::{check_same_scene, RenderOptions, TechniqueFrame, TechniqueRenderer};
use crate::error::{Error, Result};
use crate::frame::render_pass::FrameDestination;
use crate::frame::FrameTargets;
use crate::gpu::Gpu;
use crate::render::passes::Passes;
use crate::render::plan::{Label, PassKinds, PassPlan, SetRole, Target, When};
use crate::render::plan_execution::{record_plan, PlanPipelines};
use crate::render::PipelineTarget;
use crate::render::{FrameUniforms, Renderer, Skinning};
use crate::scene::{JointPalettes, Scene};

/// A built renderer: the frame renderer, the plan and its pipelines, and the technique's part.
pub struct FrameRenderer<'s, K: PassKinds, P> {
    technique: &'static str,
    scene: &'s Scene,
    renderer: Renderer,
    plan: PassPlan<K>,
    /// The plan by name, as `SceneRenderer::plan` hands it out to the tests.
    #[cfg(test)]
    named_plan: PassPlan,
    pipelines: PlanPipelines,
    passes: P,
    /// What the build could not honour in the scene: the technique's own warnings, and the
    /// lights it leaves unshadowed (`unit::build_unit`).
    pub warnings: Vec<String>,
}

/// Everything a technique's `Passes` is built from.
pub struct BuildContext<'a> {
    pub gpu: &'a Arc<Gpu>,
    pub renderer: &'a Renderer,
    pub options: &'a RenderOptions,
}

/// Builds the renderer of the technique called `technique` for `scene` with `plan`, from
/// options the caller has checked (`RenderOptions::check`): makes the frame renderer (with colour feedback when a pass reads the colour
/// target), lets `make` build the technique's resources, then the plan's pipelines. Written
/// once for every technique by `unit::build_unit`; `nostencil bake` calls it directly to keep
/// the technique's `Passes` type (it reads a shadow texture back).
pub fn build_typed<'s, K: PassKinds, P: Passes<K> + 's>(
    technique: &'static str,
    plan: PassPlan<K>,
    gpu: &Arc<Gpu>,
    scene: &'s Scene,
    options: &RenderOptions,
    make: impl FnOnce(BuildContext) -> Result<P>,
) -> Result<FrameRenderer<'s, K, P>> {
    let colour_feedback = plan.passes.iter().any(|p| p.reads_colour);
    let frame = (options.width, options.height, options.samples);
    let targets = match options.destination {
        // A one-sample subpass that reads its own colour needs an input attachment of the
        // renderer's own: such a frame is drawn offscreen (`SceneRenderer::presents` says so).
        FrameDestination::Swapchain { format } if !(colour_feedback && options.samples == 1) => {
            FrameTargets::presenting(gpu, frame, options.stencil, colour_feedback, format)?
        }
        _ => FrameTargets::with_samples(
            gpu,
            options.width,
            options.height,
            options.stencil,
            colour_feedback,
            options.samples,
            options.keep_samples,
        )?,
    };
    // Room for the palettes of GPU-skinned objects in every slot's frame set.
    let mut renderer = Renderer::with_palettes(gpu, targets, JointPalettes::of(scene).joints)?;
    renderer.count_overdraw = options.count_overdraw;
    let passes = make(BuildContext { gpu, renderer: &renderer, options })?;
    let frame_target = PipelineTarget {
        render_pass: renderer.targets.render_pass,
        colour_attachments: 1,
        samples: renderer.targets.samples(),
        lights: scene.lights.len() as u32,
    };
    let frame_layout = renderer.frame_layout;
    let skinned_twins = passes.skinned_twins();
    let pipelines = PlanPipelines::build(
        gpu,
        &plan,
        skinned_twins,
        |target| match target {
            Target::Frame => Ok(frame_target),
            // Prepasses draw at one sample: see `Passes::offscreen_pass`.
            Target::Offscreen(target) => passes
                .offscreen_pass(target)
                .map(|(render_pass, colour_attachments)| {
                    PipelineTarget::one_sample(render_pass, colour_attachments).with_lights(scene.lights.len())
                })
                .ok_or_else(|| {
                    Error::Internal(format!("{}: built without render pass '{}'", technique, target.label()))
                }),
        },
        |role| match role {
            SetRole::Frame => Ok(frame_layout),
            SetRole::Own(set) => passes
                .set(set)
                .map(|s| s.layout)
                .ok_or_else(|| Error::Internal(format!("{}: built without set '{}'", technique, set.label()))),
            SetRole::Material => passes
                .materials()
                .map(|m| m.layout())
                .ok_or_else(|| Error::Internal(format!("{}: no materials", technique))),
        },
    )?;
    // Several frames in flight only where each one's data is its own.
    let in_flight = options.frames_in_flight as usize;
    let apart = passes.writes_per_slot() && !options.count_overdraw && !options.keep_samples;
    renderer.set_frames_in_flight(if apart { in_flight } else { 1 })?;
    let warnings = passes.warnings().to_vec();
    Ok(FrameRenderer {
        technique,
        scene,
        renderer,
        #[cfg(test)]
        named_plan: plan.named(),
        plan,
        pipelines,
        passes,
        warnings,
    })
}

impl<K: PassKinds, P> FrameRenderer<'_, K, P> {
    /// The technique's part, as built and as the last frame left it.
    pub fn passes(&self) -> &P {
        &self.passes
    }
}

impl<K: PassKinds, P: Passes<K>> TechniqueRenderer for FrameRenderer<'_, K, P> {
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
        check_same_scene(self.scene, scene, self.technique)?;
        // The frame that last used this slot reads what `prepare` writes in it: done first.
        self.renderer.wait_for_slot()?;
        self.passes.prepare(&self.renderer, scene)?;
        if let Some(palettes) = self.passes.joint_palettes().filter(|p| !p.is_empty()) {
            self.renderer.write_joint_palettes(scene, palettes)?;
        }
        let mut uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        if let Some(light) = self.passes.frame_light() {
            uniforms.move_primary_light(scene.primary_light_index(), light);
        }
        let clear_values = self.passes.clear();
        let clear = scene.background.extend(clear_values.alpha).to_array();
        self.renderer.stencil_clear = clear_values.stencil;
        let conditions = self.passes.conditions(scene);
        let holds = |when: When| when.holds_in(&conditions);
        let (plan, pipelines, draws) = (&self.plan, &self.pipelines, &self.passes);
        let output = self.renderer.render_with_prepass(
            &uniforms,
            clear,
            |rec| record_plan(rec, plan, pipelines, false, &holds, scene, draws),
            |rec| record_plan(rec, plan, pipelines, true, &holds, scene, draws),
        )?;
        let stats = self.passes.stats(&output, scene);
        Ok(TechniqueFrame {
            output,
            stats,
            #[cfg(test)]
            conditions,
            warnings: self.warnings.clone(),
        })
    }

    fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    #[cfg(test)]
    fn plan(&self) -> &PassPlan {
        &self.named_plan
    }

    fn stale_for(&self, scene: &Scene) -> bool {
        self.passes.stale_for(&self.renderer, scene)
    }

    fn frames_to_steady_state(&self) -> u32 {
        self.passes.frames_to_steady_state()
    }

    fn warnings(&self) -> &[String] {
        &self.warnings
    }

    fn skinning(&self) -> Skinning {
        // On the GPU where the technique has the palettes.
        if self.passes.joint_palettes().is_some() {
            Skinning::Gpu
        } else {
            Skinning::Cpu
        }
    }
}

/// Builds the options' technique for `scene` and renders frames until the steady state (a
/// fixed light's shadow map and bake are cached by then); returns the last.
pub fn render_one(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions) -> Result<TechniqueFrame> {
    let mut renderer = options.technique.build(gpu, scene, options)?;
    for _ in 1..renderer.frames_to_steady_state() {
        renderer.frame_with(scene)?;
    }
    renderer.frame_with(scene)
}
