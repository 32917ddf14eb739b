//! A technique as one typed unit: what a technique's folder implements. Its pass kinds tie its
//! plan to its draws (an exhaustive `match`, checked when it compiles), and the build every
//! technique shares is written once, here, by the blanket `impl Technique` that turns a unit
//! into the erased [`Technique`] the command line, `bench`, `passes` and the viewer hold.
//! Adding a technique: docs/adding-a-technique.md.

use std::sync::Arc;

use super::frame_renderer::{self, BuildContext, Passes};
use super::interface::{
    stencil_variant, stencil_variants, ErasedTechnique, RenderOptions, TechniqueRenderer, Variant,
};
use super::light_loop::PlannedLight;
use super::options::{ShadowMode, ShadowVolumeOptions};
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::plan::{PassKinds, PassPlan};
use crate::scene::Scene;

/// What a technique's folder implements (see docs/adding-a-technique.md).
pub trait TechniqueUnit: Sync + 'static {
    /// Its own draws, descriptor sets and render passes (`RecorderOnly` when it has none).
    type Kinds: PassKinds;
    /// What it works out from the scene on the CPU before the frame is planned (the casters
    /// whose volumes decide z-fail, the objects an outline selects): `()` when nothing.
    type Setup;
    /// What it builds for a scene: its GPU resources, its draws, its statistics.
    type Passes: Passes<Self::Kinds>;

    /// The `--technique` value.
    fn name(&self) -> &'static str;

    /// One line for `--help` and `info`: what it draws, and which seed it comes from.
    fn about(&self) -> &'static str;

    /// The passes of a frame with `options`, in the order they run, with a per-light loop over
    /// `lights` (`planned_lights` of the scene; a plan printed without a scene has the one
    /// default sun). A choice that depends on the scene is made by `setup`, whose options the
    /// built renderer plans with.
    fn plan(&self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan<Self::Kinds>>;

    /// The CPU work on `scene` before planning, and the options resolved with it. Errors
    /// here come before anything is uploaded.
    fn setup(&self, gpu: &Gpu, scene: &Scene, options: &RenderOptions) -> Result<Prepared<Self::Setup>>;

    /// Builds the technique's part of a renderer for `scene`, once the frame renderer exists.
    fn make(&self, ctx: BuildContext<'_, Self::Kinds>, scene: &Scene, setup: Self::Setup) -> Result<Self::Passes>;

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

/// Which lights a technique shadows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowedLights {
    /// Every light that casts shadows (the additive loop).
    Every,
    /// The primary light only (the first that casts shadows).
    Primary,
    /// None: the technique draws no shadows (lit, outlines, ink).
    None,
    /// The lights whose bit is set (bit i: the scene's light i), the others not: shadow maps
    /// cover what one frustum can (no cube map for a point light inside the scene).
    Listed(u8),
}

impl ShadowedLights {
    /// The lights a family with both modes shadows: every one in the additive loop, the primary
    /// light in the seeds' modulated frame.
    pub fn in_mode(mode: ShadowMode) -> Self {
        match mode {
            ShadowMode::Additive => ShadowedLights::Every,
            ShadowMode::Modulate => ShadowedLights::Primary,
        }
    }

    /// Whether light `index` of `scene`, which casts shadows, is shadowed.
    fn covers(self, scene: &Scene, index: usize) -> bool {
        match self {
            ShadowedLights::Every => true,
            ShadowedLights::Primary => scene.primary_light_index() == Some(index),
            ShadowedLights::None => false,
            ShadowedLights::Listed(mask) => index < 8 && mask & (1 << index) != 0,
        }
    }
}

/// What the warning about unshadowed lights tells a user to do: a technique that shadows every
/// light in the additive mode (shadow volumes, planar) names that mode; the others name those
/// two techniques.
fn every_light_hint<T: TechniqueUnit>(unit: &T, options: &RenderOptions, lights: &[PlannedLight]) -> &'static str {
    let additive = RenderOptions { shadow_mode: ShadowMode::Additive, ..options.clone() };
    if unit.shadowed_lights(&additive, lights) == ShadowedLights::Every {
        "--shadow-mode additive shadows every light"
    } else {
        "--technique shadow-volume or planar shadows every light"
    }
}

/// The warning naming the lights `shadowed` leaves unshadowed in `scene`, if any, each with
/// `reason(index)` when there is one, and `hint` (how to shadow them all).
pub fn unshadowed_lights_warning(
    technique: &str,
    hint: &str,
    shadowed: ShadowedLights,
    scene: &Scene,
    reason: &dyn Fn(usize) -> Option<String>,
) -> Option<String> {
    if shadowed == ShadowedLights::None {
        return None;
    }
    let casting = || scene.lights.iter().enumerate().filter(|(_, light)| light.casts_shadow);
    let named = |i: usize| {
        let name = format!("'{}'", scene.lights[i].name);
        reason(i).map_or(name.clone(), |why| format!("{name} ({why})"))
    };
    let left: Vec<String> = casting().filter(|(i, _)| !shadowed.covers(scene, *i)).map(|(i, _)| named(i)).collect();
    if left.is_empty() {
        return None;
    }
    Some(match shadowed {
        ShadowedLights::Listed(_) => {
            let kept: Vec<String> = casting()
                .filter(|(i, _)| shadowed.covers(scene, *i))
                .map(|(_, light)| format!("'{}'", light.name))
                .collect();
            let kept = if kept.is_empty() { "no light".to_owned() } else { kept.join(", ") };
            let verb = if left.len() == 1 { "shades" } else { "shade" };
            format!("{technique} shadows {kept}: {} {verb} unshadowed ({hint})", left.join(", "))
        }
        _ => format!(
            "{} shadows only the primary light ('{}'): {} shade unshadowed ({hint})",
            technique,
            scene.primary_light().map_or("", |l| l.name.as_str()),
            left.join(", ")
        ),
    })
}

/// The result of [`TechniqueUnit::setup`]: the options the renderer is planned and built with
/// (a scene-dependent choice resolved) and the unit's CPU work.
pub struct Prepared<S> {
    pub options: RenderOptions,
    pub setup: S,
}

impl Prepared<()> {
    /// The options as given, nothing worked out: for units with no setup.
    pub fn as_given(options: &RenderOptions) -> Self {
        Prepared { options: options.clone(), setup: () }
    }
}

/// The build every technique shares: setup, plan with the resolved options, then the frame
/// renderer around the unit's `Passes`.
pub fn build_unit<'s, T: TechniqueUnit>(
    unit: &T,
    gpu: &Arc<Gpu>,
    scene: &'s Scene,
    options: &RenderOptions,
) -> Result<frame_renderer::FrameRenderer<'s, T::Kinds, T::Passes>> {
    options.check()?;
    // Per-light loops are planned for the scene's lights, as the technique can shadow them.
    let lights = unit.planned_lights(scene);
    if lights.len() > crate::scene::MAX_LIGHTS {
        return Err(Error::InvalidInput(format!(
            "{} lights: a frame holds at most {}",
            lights.len(),
            crate::scene::MAX_LIGHTS
        )));
    }
    let Prepared { options, setup } = unit.setup(gpu, scene, options)?;
    let plan = unit.plan(&options, &lights)?;
    let mut renderer =
        frame_renderer::build_typed(unit.name(), plan, gpu, scene, &options, |ctx| unit.make(ctx, scene, setup))?;
    let reason = |light: usize| unit.unshadowed_reason(scene, light);
    let hint = every_light_hint(unit, &options, &lights);
    renderer.warnings.extend(unshadowed_lights_warning(
        unit.name(),
        hint,
        unit.shadowed_lights(&options, &lights),
        scene,
        &reason,
    ));
    Ok(renderer)
}

impl<T: TechniqueUnit> ErasedTechnique for T {
    fn name(&self) -> &'static str {
        TechniqueUnit::name(self)
    }

    fn about(&self) -> &'static str {
        TechniqueUnit::about(self)
    }

    fn plan(&self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan> {
        TechniqueUnit::plan(self, options, lights).map(|plan| plan.named())
    }

    fn build<'s>(
        &self,
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        options: &RenderOptions,
    ) -> Result<Box<dyn TechniqueRenderer + 's>> {
        Ok(Box::new(build_unit(self, gpu, scene, options)?))
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        TechniqueUnit::bench_variants(self, options)
    }

    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        TechniqueUnit::plan_variants(self, options)
    }

    fn compare_variant(&self, name: &str, options: &RenderOptions) -> Result<RenderOptions> {
        TechniqueUnit::compare_variant(self, name, options)
    }

    fn plan_notes(&self) -> Result<Option<String>> {
        TechniqueUnit::plan_notes(self)
    }

    fn describe(&self, options: &RenderOptions) -> String {
        TechniqueUnit::describe(self, options)
    }

    fn planned_lights(&self, scene: &Scene) -> Vec<PlannedLight> {
        TechniqueUnit::planned_lights(self, scene)
    }
}
