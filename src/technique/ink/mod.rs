//! The ink renderer (seed 002, docs/design/outlines.md): the scene shaded Lambert (`silhouette`)
//! or through a toon ramp (`toon`), then ink on its silhouettes by one of these methods:
//! - `edges`: per frame on the CPU, each object's unique edge list is classified from the eye
//!   (`mesh::classify`), and the flagged edges are drawn as screen-space quads, one draw per
//!   class (the mobile profile has no wideLines): [`edges`];
//! - `shader`: the scene's vertex shader computes N.V and the fragment shader looks it up in a
//!   1D texture whose first texels are dark (a rim);
//! - `hull`: the two-pass inverted hull: the mesh pushed out along its normals, front faces
//!   culled, drawn in ink behind the model;
//! - `alpha-test`: Dietrich's method: N.V per pixel is the alpha, and an alpha test (a
//!   `discard`) keeps as ink the pixels at most a reference value, which sets the thickness.
//!
//! The recipes and pass plan are in [`recipes`], the renderer in [`renderer`].

pub mod edges;
pub mod recipes;
pub mod renderer;

use super::frame_renderer::BuildContext;
use super::interface::{RenderOptions, TechniqueInfo, Variant};
use super::light_loop::PlannedLight;
use super::options::SilhouetteMethod;
use super::unit::{Prepared, TechniqueUnit};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::plan::PassPlan;
use crate::scene::Scene;
use recipes::InkKinds;
use renderer::InkPasses;

/// Ink on the scene's silhouettes, shaded Lambert or through a toon ramp.
pub struct Ink {
    name: &'static str,
    about: &'static str,
    toon: bool,
}

/// Lambert shading with ink lines.
pub static SILHOUETTE: Ink =
    Ink { name: "silhouette", about: "Lambert shading with ink lines (seed 002)", toon: false };

/// Toon shading with ink lines.
pub static TOON: Ink =
    Ink { name: "toon", about: "toon shading (N.L through a ramp) with ink lines (seed 002)", toon: true };

impl TechniqueInfo for Ink {
    fn name(&self) -> &'static str {
        self.name
    }

    fn about(&self) -> &'static str {
        self.about
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        method_variants(self.name, options)
    }

    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        method_variants(self.name, options)
    }

    fn describe(&self, options: &RenderOptions) -> String {
        let ink_only = if options.cartoon.ink_only { ", ink only" } else { "" };
        format!("{} ({}, {}{ink_only})", self.name, options.stencil.name(), options.cartoon.silhouette.name())
    }
}

impl TechniqueUnit for Ink {
    type Kinds = InkKinds;
    type Setup = ();
    type Passes = InkPasses;

    fn plan(&self, options: &RenderOptions, _lights: &[PlannedLight]) -> Result<PassPlan<InkKinds>> {
        Ok(recipes::plan(options.cartoon.silhouette))
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, _setup: ()) -> Result<InkPasses> {
        renderer::make(ctx, scene, self.toon)
    }
}

/// Each `--silhouette` method (the passes differ, the stencil path does not change them), then
/// the edges method ink only (`--ink-only`: flat faces, no lighting).
fn method_variants(name: &str, options: &RenderOptions) -> Vec<Variant> {
    let mut variants: Vec<Variant> = SilhouetteMethod::ALL
        .iter()
        .map(|&method| {
            let mut options = options.clone();
            options.cartoon.silhouette = method;
            options.cartoon.ink_only = false;
            Variant { label: format!("{name} {}", method.name()), options }
        })
        .collect();
    let mut ink_only = options.clone();
    ink_only.cartoon.silhouette = SilhouetteMethod::Edges;
    ink_only.cartoon.ink_only = true;
    variants.push(Variant { label: format!("{name} edges ink-only"), options: ink_only });
    variants
}
