//! The lit scene: every object with Lambert + ambient shading, depth tested and written. Other
//! techniques draw its pass first and add their own on top.

use std::sync::Arc;

use super::frame_renderer::BuildContext;
use super::interface::{RenderOptions, TechniqueInfo};
use super::light_loop::PlannedLight;
use super::material_variants::with_surface_variants;
use super::unit::{Prepared, TechniqueUnit};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::pipeline::{FixedFunction, PipelineDesc, VertexLayout};
use crate::render::passes::Passes;
use crate::render::plan::{NoOwn, PassKinds, PassPlan, PlannedPass, RecorderOnly, SetRole};
use crate::render::{FrameRecorder, GpuScene, Pipeline, Renderer, OBJECT_PUSH_BYTES};
use crate::scene::Scene;
use crate::shaders;

pub fn scene_pipeline_desc() -> PipelineDesc {
    PipelineDesc {
        name: "scene",
        vertex_shader: shaders::LIT_VERT,
        fragment_shader: shaders::LIT_FRAG,
        vertex_layout: VertexLayout::SCENE,
        fixed: FixedFunction::OPAQUE,
        push_constant_bytes: OBJECT_PUSH_BYTES,
    }
}

/// The lit scene pass: every object with its material, writing `alpha` (the counter's start,
/// or opaque 1).
pub fn scene_pass<K: PassKinds>(alpha: f32) -> PlannedPass<K> {
    let desc = scene_pipeline_desc();
    let pass = PlannedPass::objects("scene", desc.clone(), alpha);
    with_surface_variants(pass, &desc).with_sets(&[SetRole::Frame, SetRole::Material])
}

/// Lambert + ambient, no shadows.
pub struct Lit;

impl TechniqueInfo for Lit {
    fn name(&self) -> &'static str {
        "lit"
    }

    fn about(&self) -> &'static str {
        "Lambert + ambient, no shadows: the base every technique adds to"
    }
}

impl TechniqueUnit for Lit {
    type Kinds = RecorderOnly;
    type Setup = ();
    type Passes = LitPasses;

    /// The lit frame: the scene pass alone.
    fn plan(&self, _options: &RenderOptions, _lights: &[PlannedLight]) -> Result<PassPlan<RecorderOnly>> {
        Ok(PassPlan { passes: vec![scene_pass(1.0)] })
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, _setup: ()) -> Result<LitPasses> {
        Ok(LitPasses { gpu: ctx.gpu.clone(), meshes: GpuScene::upload_for(ctx.gpu, scene, ctx.options.skinning)? })
    }
}

pub struct LitPasses {
    gpu: Arc<Gpu>,
    meshes: GpuScene,
}

impl Passes<RecorderOnly> for LitPasses {
    fn meshes(&self) -> Option<&GpuScene> {
        Some(&self.meshes)
    }

    fn draw(
        &self,
        _: &mut FrameRecorder,
        _: &Scene,
        draw: NoOwn,
        _: &PlannedPass<RecorderOnly>,
        _: &[&Pipeline],
    ) -> Result<()> {
        match draw {}
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        self.meshes.follow_pose(&self.gpu, scene, renderer.slot())
    }

    fn writes_per_slot(&self) -> bool {
        true
    }
}
