//! The two seed 004 techniques, as the registry, `bench` and Table 1 name them.

use std::sync::Arc;

use super::passes::plan;
use super::renderer::build;
use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::plan::PassPlan;
use crate::scene::Scene;
use crate::technique::interface::{BenchTable, RenderOptions, SceneRenderer, Technique, Variant};
use crate::technique::options::{LightMode, ShadowKind};

/// A depth-compared shadow map from the light.
pub struct ShadowMap;

/// Shadow textures baked into each model's atlas from the shadow map.
pub struct ShadowTextureAtlas;

/// The technique that draws `kind`.
pub fn technique_of(kind: ShadowKind) -> &'static dyn Technique {
    match kind {
        ShadowKind::Map => &ShadowMap,
        ShadowKind::Atlas => &ShadowTextureAtlas,
    }
}

fn build_boxed<'s>(
    technique: &'static dyn Technique,
    kind: ShadowKind,
    gpu: &Arc<Gpu>,
    scene: &'s Scene,
    options: &RenderOptions,
) -> Result<Box<dyn SceneRenderer + 's>> {
    Ok(Box::new(build(technique, kind, gpu, scene, options, &mut |_, _| {})?))
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

fn describe(name: &str, options: &RenderOptions) -> String {
    format!("{name} ({}, {} light)", options.stencil.name(), options.shadow_atlas.light.name())
}

impl Technique for ShadowMap {
    fn name(&self) -> &'static str {
        ShadowKind::Map.name()
    }

    fn about(&self) -> &'static str {
        "a depth-compared shadow map from the light (seed 004's comparison)"
    }

    fn plan(&self, _options: &RenderOptions) -> Result<PassPlan> {
        Ok(plan(ShadowKind::Map))
    }

    fn build<'s>(
        &self,
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        options: &RenderOptions,
    ) -> Result<Box<dyn SceneRenderer + 's>> {
        build_boxed(&ShadowMap, ShadowKind::Map, gpu, scene, options)
    }

    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        light_variants(self.name(), options)
    }

    fn describe(&self, options: &RenderOptions) -> String {
        describe(self.name(), options)
    }

    fn bench_table(&self) -> Option<BenchTable> {
        Some(BenchTable::Seed004Table1)
    }
}

impl Technique for ShadowTextureAtlas {
    fn name(&self) -> &'static str {
        ShadowKind::Atlas.name()
    }

    fn about(&self) -> &'static str {
        "shadow textures baked into each model's atlas from the shadow map (seed 004)"
    }

    fn plan(&self, _options: &RenderOptions) -> Result<PassPlan> {
        Ok(plan(ShadowKind::Atlas))
    }

    fn build<'s>(
        &self,
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        options: &RenderOptions,
    ) -> Result<Box<dyn SceneRenderer + 's>> {
        build_boxed(&ShadowTextureAtlas, ShadowKind::Atlas, gpu, scene, options)
    }

    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        light_variants(self.name(), options)
    }

    fn describe(&self, options: &RenderOptions) -> String {
        describe(self.name(), options)
    }

    fn bench_table(&self) -> Option<BenchTable> {
        Some(BenchTable::Seed004Table1)
    }
}
