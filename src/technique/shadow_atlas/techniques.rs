//! The seed 004 techniques, as the registry, `bench` and Table 1 name them: the atlas, the
//! shadow map it is timed against, and the projective texture it replaces.

use super::maps::{self, Coverage};
use super::passes::{plan, AtlasKinds};
use super::renderer::ShadowPasses;
use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::plan::PassPlan;
use crate::scene::Scene;
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::{RenderOptions, Technique, TechniqueInfo, Variant};
use crate::technique::light_loop::{PlannedLight, ShadowedLights};
use crate::technique::options::{LightMode, ShadowKind};
use crate::technique::unit::{Prepared, TechniqueUnit};

/// One of the two seed 004 techniques: the shadow map sampled in the scene pass, or shadow
/// textures baked from it into each model's tile of one atlas page.
pub struct ShadowTechnique {
    kind: ShadowKind,
    about: &'static str,
}

/// Depth-compared shadow maps, one per shadowing light.
pub static SHADOW_MAP: ShadowTechnique = ShadowTechnique {
    kind: ShadowKind::Map,
    about: "depth-compared shadow maps, one per light (seed 004's comparison)",
};

/// Shadow textures baked from the shadow maps into one atlas page, a tile per model, a channel
/// per light.
pub static SHADOW_TEXTURE_ATLAS: ShadowTechnique = ShadowTechnique {
    kind: ShadowKind::Atlas,
    about: "shadow textures baked from the shadow maps into one atlas page, a tile per model, a channel per light (seed 004)",
};

/// Each model's shadow texture projected from the light: the method the atlas replaces, which
/// shadows the lit side of a concave model (the paper's figure 2).
pub static PROJECTIVE_TEXTURE: ShadowTechnique = ShadowTechnique {
    kind: ShadowKind::Projective,
    about: "each model's shadow texture projected from the light (seed 004's figure 2: wrong on concave models)",
};

impl ShadowKind {
    /// The technique that draws this kind.
    pub fn technique(self) -> Technique {
        match self {
            ShadowKind::Map => Technique(&SHADOW_MAP),
            ShadowKind::Atlas => Technique(&SHADOW_TEXTURE_ATLAS),
            ShadowKind::Projective => Technique(&PROJECTIVE_TEXTURE),
        }
    }
}

/// Both light modes: a moving light re-renders the cached passes every frame.
fn light_variants(name: &str, options: &RenderOptions) -> Vec<Variant> {
    [LightMode::Fixed, LightMode::Moving]
        .into_iter()
        .map(|light| Variant {
            label: format!("{name} ({} light)", light.name()),
            options: RenderOptions {
                shadow_atlas: crate::technique::options::ShadowAtlasOptions { light, ..options.shadow_atlas },
                ..options.clone()
            },
        })
        .collect()
}

impl TechniqueInfo for ShadowTechnique {
    fn name(&self) -> &'static str {
        self.kind.name()
    }

    /// The lights with a map layer, as `setup` planned them (the projective texture: the
    /// primary light's alone, which the warning says as it always has).
    fn shadowed_lights(&self, _options: &RenderOptions, lights: &[PlannedLight]) -> ShadowedLights {
        match self.kind {
            ShadowKind::Projective => ShadowedLights::Primary,
            _ => ShadowedLights::Listed(maps::shadowed_mask(lights)),
        }
    }

    fn unshadowed_reason(&self, scene: &Scene, light: usize) -> Option<String> {
        if self.kind == ShadowKind::Projective {
            return None;
        }
        match maps::coverage(self.kind, scene).get(light) {
            Some(Coverage::Unshadowed(why)) => Some((*why).to_owned()),
            _ => None,
        }
    }

    fn about(&self) -> &'static str {
        self.about
    }

    /// A map pass for each light that gets a layer (`maps::coverage`), none for the others.
    fn planned_lights(&self, scene: &Scene) -> Vec<PlannedLight> {
        maps::planned_lights(&maps::coverage(self.kind, scene), scene)
    }

    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        light_variants(self.name(), options)
    }

    /// The projective texture is timed against the atlas that replaces it (the atlas with a
    /// fixed light is the reference), both lights each; the others have Table 1.
    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        let with =
            |technique: Technique| light_variants(technique.name(), &RenderOptions { technique, ..options.clone() });
        with(Technique(&SHADOW_TEXTURE_ATLAS)).into_iter().chain(with(self.kind.technique())).collect()
    }

    fn describe(&self, options: &RenderOptions) -> String {
        format!("{} ({}, {} light)", self.name(), options.stencil.name(), options.shadow_atlas.light.name())
    }
}

impl TechniqueUnit for ShadowTechnique {
    type Kinds = AtlasKinds;
    type Setup = ();
    type Passes = ShadowPasses;

    fn plan(&self, _options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan<AtlasKinds>> {
        Ok(plan(self.kind, lights))
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, _setup: ()) -> Result<ShadowPasses> {
        let options = (ctx.options.shadow_atlas, ctx.options.skinning);
        ShadowPasses::new(ctx.gpu, scene, self.kind, options, &mut |_, _| {})
    }
}
