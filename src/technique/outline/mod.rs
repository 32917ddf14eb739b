//! The selection outline without a stencil (seed 003, docs/design/outlines.md): the selected
//! objects mark alpha, and their copies (extruded, or scaled up as the document does: see
//! [`scaled`]) are drawn only where it is unmarked. Proven against the document's
//! real-stencil version. The recipes and pass plan are in [`recipes`], the renderer in
//! [`renderer`].

pub mod blur;
pub mod copies;
pub mod kinds;
pub mod recipes;
pub mod renderer;
pub mod scaled;

use super::frame_renderer::BuildContext;
use super::interface::{stencil_variants, RenderOptions, TechniqueInfo, Variant};
use super::light_loop::PlannedLight;
use super::unit::{Prepared, TechniqueUnit};
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::render::plan::PassPlan;
use crate::scene::Scene;
use crate::technique::options::OutlineMethod;
use kinds::OutlineKinds;
use renderer::OutlinePasses;

/// Selected objects outlined in one colour, emulated in alpha or with the real stencil.
pub struct Outline;

impl TechniqueInfo for Outline {
    fn name(&self) -> &'static str {
        "outline"
    }

    fn about(&self) -> &'static str {
        "selection outline without a stencil (seed 003)"
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        method_variants(options)
    }

    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        method_variants(options)
    }

    fn describe(&self, options: &RenderOptions) -> String {
        let cartoon = &options.cartoon;
        let blur = if cartoon.outline_blur > 0 { format!(", blur {}", cartoon.outline_blur) } else { String::new() };
        format!("{} ({}, {}{blur})", self.name(), options.stencil.name(), cartoon.outline_method.name())
    }
}

impl TechniqueUnit for Outline {
    type Kinds = OutlineKinds;

    /// Per object: whether it is outlined.
    type Setup = Vec<bool>;
    type Passes = OutlinePasses;

    fn plan(&self, options: &RenderOptions, _lights: &[PlannedLight]) -> Result<PassPlan<OutlineKinds>> {
        Ok(recipes::plan(options.stencil, &options.cartoon))
    }

    /// An unknown selected name is refused before anything is uploaded.
    fn setup(&self, _gpu: &Gpu, scene: &Scene, options: &RenderOptions) -> Result<Prepared<Vec<bool>>> {
        let selected = resolve_selection(scene, &options.cartoon.select)?;
        Ok(Prepared { options: options.clone(), setup: selected })
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, selected: Vec<bool>) -> Result<OutlinePasses> {
        renderer::make(ctx, scene, selected)
    }
}

/// The blur radius of the blurred variants when the options ask for none.
const BENCH_BLUR: u32 = 4;

/// Each `--outline-method`, sharp and blurred (by the options' `--outline-blur`, else
/// `BENCH_BLUR` pixels), each with the reference and the emulated path (reference first).
fn method_variants(options: &RenderOptions) -> Vec<Variant> {
    let blurred = match options.cartoon.outline_blur {
        0 => BENCH_BLUR,
        radius => radius,
    };
    let mut variants = Vec::new();
    for &method in OutlineMethod::ALL {
        for blur in [0, blurred] {
            let mut options = options.clone();
            options.cartoon.outline_method = method;
            options.cartoon.outline_blur = blur;
            for mut variant in stencil_variants("outline", &options) {
                let path = match variant.options.stencil {
                    StencilMode::Reference => "reference (stencil)",
                    StencilMode::Emulated => "emulated",
                };
                let blur = if blur > 0 { format!(" blur {blur}") } else { String::new() };
                variant.label = format!("{}{blur} {path}", method.name());
                variants.push(variant);
            }
        }
    }
    variants
}

/// Which objects are selected, by index: those named, or with no names the scene's first
/// shadow caster (else its first object). An unknown name is refused with the scene's names.
pub fn resolve_selection(scene: &Scene, names: &[String]) -> Result<Vec<bool>> {
    let mut selected = vec![false; scene.objects.len()];
    if names.is_empty() {
        let first = scene.objects.iter().position(|o| o.casts_shadow).or((!scene.objects.is_empty()).then_some(0));
        if let Some(i) = first {
            selected[i] = true;
        }
        return Ok(selected);
    }
    for name in names {
        let index = scene.objects.iter().position(|o| &o.name == name).ok_or_else(|| {
            Error::InvalidInput(format!(
                "--select: scene '{}' has no object '{name}'; its objects: {}",
                scene.name,
                scene.objects.iter().map(|o| o.name.as_str()).collect::<Vec<_>>().join(", ")
            ))
        })?;
        selected[index] = true;
    }
    Ok(selected)
}
