//! Transitional: the techniques whose renderers are not yet written against `Passes`, behind
//! the `Technique` interface. Their plans come from their pipeline lists until each moves to a
//! pass plan of its own.

use std::any::Any;
use std::sync::Arc;

use super::interface::{FrameStats, RenderOptions, SceneRenderer, Technique, TechniqueFrame};
use super::shadow_atlas::{LightMode, ShadowAtlasRenderer, ShadowAtlasStats, ShadowKind};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::plan::{Draws, PassPlan, PlannedPass, Push};
use crate::render::Renderer;
use crate::scene::Scene;

fn plan_of(descs: Vec<crate::pipeline::PipelineDesc>) -> PassPlan {
    PassPlan {
        passes: descs
            .into_iter()
            .map(|d| PlannedPass::new(d.name, d, Draws::Geometry("(see the technique)"), Push::PerDraw("-")))
            .collect(),
    }
}

struct Adapter<R> {
    inner: R,
    plan: PassPlan,
}

impl SceneRenderer for Adapter<ShadowAtlasRenderer<'_>> {
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
        let frame = self.inner.frame_with(scene)?;
        Ok(TechniqueFrame { output: frame.output, stats: Box::new(frame.stats), conditions: Vec::new() })
    }

    fn renderer_mut(&mut self) -> &mut Renderer {
        self.inner.renderer_mut()
    }

    fn plan(&self) -> &PassPlan {
        &self.plan
    }

    fn frames_to_steady_state(&self) -> u32 {
        match self.inner.light_mode() {
            LightMode::Moving => 1,
            LightMode::Fixed => 2,
        }
    }
}

fn boxed<'s, R: 's>(inner: R, plan: PassPlan) -> Box<dyn SceneRenderer + 's>
where
    Adapter<R>: SceneRenderer,
{
    Box::new(Adapter { inner, plan })
}

macro_rules! atlas_technique {
    ($name:ident, $kind:expr, $text:literal, $about:literal) => {
        pub struct $name;

        impl Technique for $name {
            fn name(&self) -> &'static str {
                $text
            }

            fn about(&self) -> &'static str {
                $about
            }

            fn plan(&self, _o: &RenderOptions) -> Result<PassPlan> {
                Ok(plan_of(super::shadow_atlas::pipeline_descs($kind).into_iter().map(|(_, d)| d).collect()))
            }

            fn build<'s>(
                &self,
                gpu: &Arc<Gpu>,
                scene: &'s Scene,
                o: &RenderOptions,
            ) -> Result<Box<dyn SceneRenderer + 's>> {
                let mut r = ShadowAtlasRenderer::new(gpu, scene, o.width, o.height, o.stencil, $kind, &o.shadow_atlas)?;
                r.renderer_mut().count_overdraw = o.count_overdraw;
                Ok(boxed(r, self.plan(o)?))
            }

            fn describe(&self, options: &RenderOptions) -> String {
                format!("{} ({}, {} light)", $text, options.stencil.name(), options.shadow_atlas.light.name())
            }
        }
    };
}

atlas_technique!(
    ShadowMap,
    ShadowKind::Map,
    "shadow-map",
    "a depth-compared shadow map from the light (seed 004's comparison)"
);
atlas_technique!(
    ShadowTextureAtlas,
    ShadowKind::Atlas,
    "shadow-texture-atlas",
    "shadow textures baked into each model's atlas from the shadow map (seed 004)"
);

fn json_of(value: &impl serde::Serialize) -> serde_json::Value {
    serde_json::to_value(value).unwrap_or_default()
}

impl FrameStats for ShadowAtlasStats {
    fn report(&self) -> String {
        let mut out = format!(
            "{} | light {} | frame {}: {} | shadow map {}x{}",
            self.technique.name(),
            self.light.name(),
            self.frame,
            if self.cached {
                "shadow map and bake skipped (neither light nor models moved since the last frame)"
            } else {
                "shadow map re-rendered (and shadow textures re-baked)"
            },
            self.map_size,
            self.map_size
        );
        if self.technique == ShadowKind::Atlas {
            for atlas in &self.atlases {
                out.push_str(&format!(
                    "\n  atlas of '{}': {} -> {}x{} shadow texture, {} mips",
                    atlas.mesh,
                    atlas.describe(),
                    atlas.size,
                    atlas.size,
                    atlas.mip_levels
                ));
            }
        }
        out
    }

    fn json(&self) -> serde_json::Value {
        json_of(self)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
