//! A technique as one typed unit: the half of a technique's folder that has types of its own
//! (the other half is [`TechniqueInfo`]). Its pass kinds tie its plan to its draws (an
//! exhaustive `match`, checked when it compiles), and the build every technique shares is
//! written once, here, by the blanket `impl ErasedTechnique` that lets the registry hold a unit
//! as the [`Technique`](super::Technique) the command line, `bench`, `passes` and the viewer
//! hold.
//! Adding a technique: docs/adding-a-technique.md.

use std::sync::Arc;

use super::frame_renderer::{self, BuildContext};
use super::interface::{ErasedTechnique, RenderOptions, TechniqueInfo, TechniqueRenderer};
use super::light_loop::{PlannedLight, ShadowedLights};
use super::options::ShadowMode;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::passes::Passes;
use crate::render::plan::{PassKinds, PassPlan};
use crate::scene::Scene;

/// What a technique's folder implements, beside [`TechniqueInfo`]: the types that tie its plan
/// to its draws, its plan, and what it builds for a scene (see docs/adding-a-technique.md).
pub trait TechniqueUnit: TechniqueInfo {
    /// Its own draws, descriptor sets and render passes (`RecorderOnly` when it has none).
    type Kinds: PassKinds;
    /// What it works out from the scene on the CPU before the frame is planned (the casters
    /// whose volumes decide z-fail, the objects an outline selects): `()` when nothing.
    type Setup;
    /// What it builds for a scene: its GPU resources, its draws, its statistics.
    type Passes: Passes<Self::Kinds>;

    /// The passes of a frame with `options`, in the order they run, with a per-light loop over
    /// `lights` (`planned_lights` of the scene; a plan printed without a scene has the one
    /// default sun). A choice that depends on the scene is made by `setup`, whose options the
    /// built renderer plans with.
    fn plan(&self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan<Self::Kinds>>;

    /// The CPU work on `scene` before planning, and the options resolved with it. Errors
    /// here come before anything is uploaded. A unit with none returns
    /// [`Prepared::as_given`]: the options as given, and `()`.
    fn setup(&self, gpu: &Gpu, scene: &Scene, options: &RenderOptions) -> Result<Prepared<Self::Setup>>;

    /// Builds the technique's part of a renderer for `scene`, once the frame renderer exists.
    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, setup: Self::Setup) -> Result<Self::Passes>;
}

/// What the warning about unshadowed lights tells a user to do: a technique that shadows every
/// light in the additive mode names that mode; the others point to the techniques that do,
/// which `nostencil info` lists (`registry::shadowing_every_light`: this layer lies below the
/// registry and names no technique).
fn every_light_hint<T: TechniqueUnit>(unit: &T, options: &RenderOptions, lights: &[PlannedLight]) -> &'static str {
    let additive = RenderOptions { shadow_mode: ShadowMode::Additive, ..options.clone() };
    if unit.shadowed_lights(&additive, lights) == ShadowedLights::Every {
        "--shadow-mode additive shadows every light"
    } else {
        "`nostencil info` lists the techniques that shadow every light"
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
    /// No CPU work before planning: the options as given.
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
    fn plan_by_name(&self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan> {
        self.plan(options, lights).map(|plan| plan.named())
    }

    fn build<'s>(
        &self,
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        options: &RenderOptions,
    ) -> Result<Box<dyn TechniqueRenderer + 's>> {
        Ok(Box::new(build_unit(self, gpu, scene, options)?))
    }
}
