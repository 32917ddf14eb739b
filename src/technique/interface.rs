//! The erased face of every technique, [`Technique`], and what crosses it: the options that
//! select a frame, a built renderer, a rendered frame. The command line, `passes`, `bench`,
//! `profile --compare` and the viewer all work through it: none of them knows a technique by
//! name. A technique implements [`TechniqueInfo`] and `unit::TechniqueUnit` and is listed in
//! [`super::registry::TECHNIQUES`] (docs/adding-a-technique.md).

use std::fmt;
use std::sync::Arc;

use super::light_loop::{PlannedLight, ShadowedLights};
use super::options::{CartoonOptions, PlanarOptions, ShadowAtlasOptions, ShadowMode, ShadowVolumeOptions};
use super::shadow_tone::ShadowTone;
use crate::error::{Error, Result};
use crate::frame::render_pass::FrameDestination;
use crate::frame::StencilMode;
use crate::gpu::Gpu;
pub use crate::render::frame_stats::FrameStats;
use crate::render::plan::PassPlan;
#[cfg(test)]
use crate::render::plan::When;
use crate::render::{FrameOutput, PresentedFrame, Renderer, Skinning};
use crate::scene::Scene;

/// Everything that selects how a frame is rendered: size, stencil path, technique, and each
/// technique family's own options. Its `Default` (the lit technique at 256x256, emulated) is in
/// `registry`, which knows the techniques.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub stencil: StencilMode,
    pub technique: Technique,
    pub shadow_volume: ShadowVolumeOptions,
    /// The frame's lighting loop, additive (Doom 3's and Ogre's) or the seeds' modulated frame:
    /// shadow volumes and the planar family read it.
    pub shadow_mode: ShadowMode,
    /// How dark shadows are: shadow volumes and the planar family share it.
    pub shadow_tone: ShadowTone,
    pub shadow_atlas: ShadowAtlasOptions,
    /// Heat-map frame: alpha ends up holding the fragments shaded per pixel.
    pub count_overdraw: bool,
    pub cartoon: CartoonOptions,
    pub planar: PlanarOptions,
    /// Samples per pixel of the frame's colour and depth (1, 2 or 4; docs/design/msaa.md).
    /// Prepasses (shadow map, bake, render-texture shadow, outline mask) keep one.
    pub samples: u32,
    /// Store the multisampled colour instead of leaving it in tile memory, so that a test can
    /// read every sample back (`Renderer::read_samples`). Never in a timed frame.
    pub keep_samples: bool,
    /// Where the frame goes: the renderer's own image (read back, or kept on the GPU), or a
    /// swapchain's images (the viewer), where the technique allows it (`SceneRenderer::presents`).
    pub destination: FrameDestination,
    /// Frames kept in flight (1 to 3): a frame is submitted without waiting, and its results
    /// come back that many frames later (`Renderer::set_frames_in_flight`). Techniques whose
    /// per-frame data is not kept per frame slot (`Passes::writes_per_slot`), heat maps and
    /// kept samples render one frame at a time whatever is asked.
    pub frames_in_flight: u32,
    /// Where skinned objects are posed: in the vertex stage, by techniques whose every stage
    /// has a skinned twin, or on the CPU (`render::Skinning`).
    pub skinning: Skinning,
}

impl RenderOptions {
    /// Checks every family's options, whichever technique is chosen (a typo in an option the
    /// technique ignores is still a typo).
    pub fn check(&self) -> Result<()> {
        if !matches!(self.samples, 1 | 2 | 4) {
            return Err(Error::InvalidInput(format!("--samples {}: use 1, 2 or 4", self.samples)));
        }
        if !(1..=crate::render::renderer::MAX_FRAMES_IN_FLIGHT as u32).contains(&self.frames_in_flight) {
            return Err(Error::InvalidInput(format!(
                "{} frames in flight: use 1 to {}",
                self.frames_in_flight,
                crate::render::renderer::MAX_FRAMES_IN_FLIGHT
            )));
        }
        self.shadow_volume.check()?;
        self.shadow_atlas.check()?;
        self.planar.check()?;
        self.cartoon.check()
    }

    /// These options with another technique.
    pub fn with_technique(&self, technique: Technique) -> Self {
        RenderOptions { technique, ..self.clone() }
    }
}

/// One variant of a technique: a label and the options that select it (`bench` times them side
/// by side, `passes` prints each one's plan, the plan test runs each one).
#[derive(Debug, Clone)]
pub struct Variant {
    pub label: String,
    pub options: RenderOptions,
}

/// A technique: what [`by_name`](super::by_name) finds and [`TECHNIQUES`](super::TECHNIQUES)
/// lists. A port asks it for its name and builds it for a scene; the crate also plans, benches
/// and compares its variants through it.
#[derive(Clone, Copy)]
pub struct Technique(pub(super) &'static dyn ErasedTechnique);

impl Technique {
    /// The `--technique` value.
    pub fn name(self) -> &'static str {
        self.0.name()
    }

    /// One line: what it draws, and which seed it comes from.
    pub fn about(self) -> &'static str {
        self.0.about()
    }

    /// A few words naming it with `options` (the viewer's title).
    pub fn describe(self, options: &RenderOptions) -> String {
        self.0.describe(options)
    }

    /// Its renderer for `scene`, built once and then asked for frames.
    pub fn build<'s>(self, gpu: &Arc<Gpu>, scene: &'s Scene, options: &RenderOptions) -> Result<SceneRenderer<'s>> {
        self.0.build(gpu, scene, options).map(SceneRenderer)
    }

    /// The passes of a frame with `options`, planned for `lights`, by name.
    pub(crate) fn plan(self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan> {
        self.0.plan_by_name(options, lights)
    }

    /// What `bench` times side by side.
    pub(crate) fn bench_variants(self, options: &RenderOptions) -> Vec<Variant> {
        self.0.bench_variants(options)
    }

    /// Every plan `passes` prints and the plan test checks.
    pub(crate) fn plan_variants(self, options: &RenderOptions) -> Vec<Variant> {
        self.0.plan_variants(options)
    }

    /// `profile --compare NAME`: the options of the variant called `name`.
    pub(crate) fn compare_variant(self, name: &str, options: &RenderOptions) -> Result<RenderOptions> {
        self.0.compare_variant(name, options)
    }

    /// What `passes` prints after the plans.
    pub(crate) fn plan_notes(self) -> Result<Option<String>> {
        self.0.plan_notes()
    }

    /// `scene`'s lights as the plan loops over them (`passes --scene` plans with these).
    pub(crate) fn planned_lights(self, scene: &Scene) -> Vec<PlannedLight> {
        self.0.planned_lights(scene)
    }

    /// The lights it shadows with `options`, of `lights` as the plan loops over them.
    pub(crate) fn shadowed_lights(self, options: &RenderOptions, lights: &[PlannedLight]) -> ShadowedLights {
        self.0.shadowed_lights(options, lights)
    }
}

impl fmt::Debug for Technique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl PartialEq for Technique {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for Technique {}

/// What a technique says about itself and the variants it runs, the half of a technique that
/// needs no types of its own: the [`Technique`] handle reaches it directly. Only `name` and
/// `about` have no default. The other half, what it plans and builds, is
/// `unit::TechniqueUnit`.
pub trait TechniqueInfo: Sync + 'static {
    /// The `--technique` value.
    fn name(&self) -> &'static str;

    /// One line for `--help` and `info`: what it draws, and which seed it comes from.
    fn about(&self) -> &'static str;

    /// What `bench` times side by side, the real-stencil reference first where there is one.
    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        stencil_variants(self.name(), options)
    }

    /// Every plan `passes` prints and the plan test checks: each path and each option that
    /// changes the passes.
    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        stencil_variants(self.name(), options)
    }

    /// `profile --compare NAME`: the options of the variant called `name`.
    fn compare_variant(&self, name: &str, options: &RenderOptions) -> Result<RenderOptions> {
        stencil_variant(name, options).ok_or_else(|| {
            Error::InvalidInput(format!("--compare {name}: {} has the variants emulated and reference", self.name()))
        })
    }

    /// What `passes` prints after the plans, when the technique has more to say about them.
    fn plan_notes(&self) -> Result<Option<String>> {
        Ok(None)
    }

    /// The viewer's title: the technique and the options that matter to it.
    fn describe(&self, options: &RenderOptions) -> String {
        format!("{} ({})", self.name(), options.stencil.name())
    }

    /// `scene`'s lights as this technique's plan loops over them: by default each casts
    /// shadows as the scene says; a technique that cannot shadow some light plans it as
    /// unshadowed, so that `passes` prints the passes its renderer runs.
    fn planned_lights(&self, scene: &Scene) -> Vec<PlannedLight> {
        PlannedLight::of_scene(scene)
    }

    /// Which of the scene's lights the technique shadows with `options`, its lights planned as
    /// `lights` (none, by default). One that shadows the primary light alone shades the others
    /// unshadowed, and a frame's warnings name them.
    fn shadowed_lights(&self, options: &RenderOptions, lights: &[PlannedLight]) -> ShadowedLights {
        let _ = (options, lights);
        ShadowedLights::None
    }

    /// Why light `light` of `scene`, which casts shadows, goes unshadowed (the warning says
    /// it beside the light's name); `None`: no reason beyond the technique's.
    fn unshadowed_reason(&self, scene: &Scene, light: usize) -> Option<String> {
        let _ = (scene, light);
        None
    }
}

/// A technique as the crate holds it: its [`TechniqueInfo`], and the plan and build of its
/// `unit::TechniqueUnit` with the unit's types erased. Nothing implements it by hand: the
/// blanket impl in `unit.rs` does, for every unit.
pub(crate) trait ErasedTechnique: TechniqueInfo {
    /// The unit's plan, its kinds kept by name.
    fn plan_by_name(&self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan>;
    fn build<'s>(
        &self,
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        options: &RenderOptions,
    ) -> Result<Box<dyn TechniqueRenderer + 's>>;
}

/// The emulated and the reference path, reference first.
pub fn stencil_variants(name: &str, options: &RenderOptions) -> Vec<Variant> {
    [StencilMode::Reference, StencilMode::Emulated]
        .into_iter()
        .map(|stencil| Variant {
            label: format!("{name} ({})", stencil.name()),
            options: RenderOptions { stencil, ..options.clone() },
        })
        .collect()
}

/// `emulated` or `reference`.
pub fn stencil_variant(name: &str, options: &RenderOptions) -> Option<RenderOptions> {
    let stencil = match name {
        "emulated" => StencilMode::Emulated,
        "reference" => StencilMode::Reference,
        _ => return None,
    };
    Some(RenderOptions { stencil, ..options.clone() })
}

/// A renderer built once for a scene ([`Technique::build`]): it renders that scene frame after
/// frame while its camera, lights, object transforms and joint palettes change (its meshes and
/// objects may not).
pub struct SceneRenderer<'s>(Box<dyn TechniqueRenderer + 's>);

impl SceneRenderer<'_> {
    /// Renders `scene`: the scene this renderer was built for, moved. With one frame in flight
    /// (the default) the result is this frame's. With more (`RenderOptions.frames_in_flight`,
    /// `frames_in_flight`) the frame is submitted without waiting, and the output (image and
    /// counters) is that of the frame as many frames earlier, none while no frame has finished;
    /// the statistics are the technique's for this frame's scene.
    pub fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
        self.0.frame_with(scene)
    }

    /// Leaves each frame on the GPU instead of reading its image back (a frame loop that
    /// presents or only measures).
    pub fn keep_on_gpu(&mut self, keep: bool) {
        self.0.renderer_mut().keep_on_gpu(keep);
    }

    /// What the technique could not honour in the scene, one line each naming the object and
    /// the reason (a mesh that casts no shadow). Fixed when the renderer is built.
    pub fn warnings(&self) -> &[String] {
        self.0.warnings()
    }

    /// Frames until the counters show the steady state, which one-frame renders report (a
    /// fixed light's shadow map and atlases are baked by the first frame and cached after).
    pub fn frames_to_steady_state(&self) -> u32 {
        self.0.frames_to_steady_state()
    }

    /// Whether drawing `scene` needs a rebuilt renderer (shadow volumes with `auto`: the camera
    /// moved into or out of a volume, so the counting method changes).
    pub fn stale_for(&self, scene: &Scene) -> bool {
        self.0.stale_for(scene)
    }

    /// Whether its frames are drawn into swapchain images. Asked for with
    /// `RenderOptions.destination`; a one-sample technique whose subpass reads its own colour
    /// back is drawn offscreen instead (`FrameTargets::presenting`).
    pub fn presents(&mut self) -> bool {
        self.0.renderer_mut().targets.presents()
    }

    /// Draws the next frames into `images`, a swapchain's of the format and size it was built
    /// for (see `presents`); the caller makes sure no frame still uses the images attached before.
    pub fn attach_swapchain(&mut self, images: &[ash::vk::Image]) -> Result<()> {
        self.0.renderer_mut().targets.attach_swapchain(images)
    }

    /// Where it poses skinned objects: `Gpu` where `RenderOptions.skinning` asks for it and
    /// every stage of the technique that draws them has a skinned twin.
    pub fn skinning(&self) -> Skinning {
        self.0.skinning()
    }

    /// Frames it keeps in flight (`RenderOptions.frames_in_flight`, where its technique allows).
    pub fn frames_in_flight(&mut self) -> usize {
        self.0.renderer_mut().frames_in_flight()
    }

    /// Waits for every frame in flight (`Renderer::wait_all`; their results are dropped).
    pub fn wait_all(&mut self) -> Result<()> {
        self.0.renderer_mut().wait_all()
    }

    /// Waits for the frame that last used the next frame's slot (`Renderer::wait_for_slot`):
    /// a presenter calls it before it acquires an image.
    pub fn wait_for_slot(&mut self) -> Result<()> {
        self.0.renderer_mut().wait_for_slot()
    }

    /// Draws the next frame into the acquired swapchain image `frame` names.
    pub fn present_next(&mut self, frame: PresentedFrame) -> Result<()> {
        self.0.renderer_mut().present_next(frame)
    }

    /// The frame renderer, for its switches and targets.
    pub(crate) fn renderer_mut(&mut self) -> &mut Renderer {
        self.0.renderer_mut()
    }

    /// The plan this renderer executes.
    #[cfg(test)]
    pub(crate) fn plan(&self) -> &PassPlan {
        self.0.plan()
    }
}

/// What every technique's renderer is inside a [`SceneRenderer`]: the type-erased face of
/// `frame_renderer.rs`'s `FrameRenderer`, its one implementation (so no method has a default:
/// each says what that renderer does, and [`SceneRenderer`]'s documents it).
pub(crate) trait TechniqueRenderer {
    /// See [`SceneRenderer::frame_with`]; `check_same_scene` refuses another scene.
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame>;
    fn renderer_mut(&mut self) -> &mut Renderer;
    #[cfg(test)]
    fn plan(&self) -> &PassPlan;
    fn stale_for(&self, scene: &Scene) -> bool;
    fn frames_to_steady_state(&self) -> u32;
    fn warnings(&self) -> &[String];
    fn skinning(&self) -> Skinning;
}

/// A rendered frame and what the technique reports about it.
pub struct TechniqueFrame {
    pub output: FrameOutput,
    pub stats: Box<dyn FrameStats>,
    /// Which conditional passes ran (see `render::plan::When`), for the tests.
    #[cfg(test)]
    pub(crate) conditions: Vec<When>,
    /// The renderer's warnings (`SceneRenderer::warnings`), for callers that keep only the
    /// frame.
    pub warnings: Vec<String>,
}

impl TechniqueFrame {
    /// The technique's statistics as their concrete type (`ShadowVolumeStats`, ...).
    pub fn stats<T: 'static>(&self) -> Option<&T> {
        self.stats.as_any().downcast_ref::<T>()
    }

    /// Whether the passes conditioned on `when` ran in this frame.
    #[cfg(test)]
    pub(crate) fn held(&self, when: When) -> bool {
        when.holds_in(&self.conditions)
    }
}

/// Refuses a `scene` that is not a moved pose of `built_for`: a renderer uploads meshes and
/// prepares casters once, so the objects, their meshes and which ones cast shadows must match.
pub fn check_same_scene(built_for: &Scene, scene: &Scene, technique: &str) -> Result<()> {
    let same_objects =
        built_for.objects.len() == scene.objects.len()
            && built_for.objects.iter().zip(&scene.objects).all(|(a, b)| {
                a.mesh == b.mesh && a.casts_shadow == b.casts_shadow && a.skin.is_some() == b.skin.is_some()
            });
    let same_meshes = built_for.meshes.len() == scene.meshes.len()
        && built_for.meshes.iter().zip(&scene.meshes).all(|(a, b)| {
            a.data.positions.len() == b.data.positions.len() && a.data.indices.len() == b.data.indices.len()
        });
    // The passes are planned per light, and the shaders sum as many lights as were built in.
    let same_lights = built_for.lights.len() == scene.lights.len()
        && built_for.lights.iter().zip(&scene.lights).all(|(a, b)| a.casts_shadow == b.casts_shadow);
    if same_objects && same_meshes && same_lights {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "scene '{}' is not the one this {technique} renderer was built for (its objects, meshes or lights differ)",
            scene.name
        )))
    }
}
