//! The lit scene pass: every object with Lambert + ambient shading, depth tested and written.
//! Other techniques draw it first and add their own passes on top.

use std::sync::Arc;

use glam::{Mat4, Vec4};

use crate::error::Result;
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::pipeline::{FixedFunction, Pipeline, PipelineDesc, VertexLayout};
use crate::render::{FrameOutput, FrameRecorder, FrameUniforms, GpuScene, Renderer};
use crate::scene::Scene;

/// Mirrors `ObjectPush` in `shaders/object_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ObjectPush {
    pub model: Mat4,
    /// rgb: albedo; a: the alpha the draw writes.
    pub colour: Vec4,
}

pub const OBJECT_PUSH_BYTES: u32 = std::mem::size_of::<ObjectPush>() as u32;

pub fn scene_pipeline_desc() -> PipelineDesc {
    PipelineDesc {
        name: "scene",
        vertex_shader: "lit.vert",
        fragment_shader: "lit.frag",
        vertex_layout: VertexLayout::POSITION_NORMAL,
        fixed: FixedFunction::OPAQUE,
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

pub struct LitPass {
    pipeline: Pipeline,
}

impl LitPass {
    pub fn new(gpu: &Arc<Gpu>, renderer: &Renderer) -> Result<Self> {
        let pipeline =
            Pipeline::new(gpu, &scene_pipeline_desc(), renderer.targets.render_pass, &[renderer.frame.layout])?;
        Ok(LitPass { pipeline })
    }

    /// Draws every object; `alpha_of(object index)` is the alpha each one writes.
    pub fn record(
        &self,
        recorder: &mut FrameRecorder,
        scene: &Scene,
        meshes: &GpuScene,
        alpha_of: impl Fn(usize) -> f32,
    ) -> Result<()> {
        recorder.pass("scene", |rec| {
            rec.bind(&self.pipeline);
            for (index, object) in scene.objects.iter().enumerate() {
                let push = ObjectPush { model: object.transform, colour: object.colour.extend(alpha_of(index)) };
                rec.push(&self.pipeline, &push);
                rec.draw_mesh(&meshes.meshes[object.mesh]);
            }
            Ok(())
        })
    }
}

/// The lit scene alone, built once: the base every technique adds to.
pub struct LitRenderer<'s> {
    scene: &'s Scene,
    renderer: Renderer,
    meshes: GpuScene,
    lit: LitPass,
}

impl<'s> LitRenderer<'s> {
    pub fn new(gpu: &Arc<Gpu>, scene: &'s Scene, width: u32, height: u32, stencil: StencilMode) -> Result<Self> {
        let renderer = Renderer::new(gpu, width, height, stencil, false)?;
        let meshes = GpuScene::upload(gpu, scene)?;
        let lit = LitPass::new(gpu, &renderer)?;
        Ok(LitRenderer { scene, renderer, meshes, lit })
    }

    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// Renders `scene`, a moved pose of the one this renderer was built for.
    pub fn frame_with(&mut self, scene: &Scene) -> Result<FrameOutput> {
        super::check_same_scene(self.scene, scene, "lit")?;
        self.meshes.follow_pose(&self.renderer.gpu, scene)?;
        let uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        let clear = scene.background.extend(1.0).to_array();
        let (lit, meshes) = (&self.lit, &self.meshes);
        self.renderer.render(&uniforms, clear, |rec| lit.record(rec, scene, meshes, |_| 1.0))
    }
}
