//! X-ray: the casters hidden behind other surfaces show through them, a half-transparent ghost
//! of themselves: the "seen through the wall" a game draws with a stencil. Without one it is one pass
//! after the scene: the casters again, depth test GREATER (only where something nearer hides
//! them), depth write off, blended over the frame. The walkthrough technique of
//! docs/adding-a-technique.md: one folder and three one-line lists.

use std::sync::Arc;

use ash::vk;

use super::frame_renderer::BuildContext;
use super::interface::{RenderOptions, TechniqueInfo};
use super::light_loop::PlannedLight;
use super::lit::scene_pass;
use super::unit::{Prepared, TechniqueUnit};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::pipeline::{BlendEquation, BlendState, DepthState, FixedFunction, PipelineDesc, VertexLayout};
use crate::render::object_push::object_push;
use crate::render::passes::Passes;
use crate::render::plan::{DrawKind, NoOwn, PassKinds, PassPlan, PlannedPass, SetRole};
use crate::render::{FrameRecorder, GpuScene, Pipeline, Renderer, OBJECT_PUSH_BYTES};
use crate::scene::Scene;
use crate::shaders;

/// How much of a hidden caster's colour shows through (the blend's source alpha).
pub const SHOW_THROUGH: f32 = 0.5;

/// Hidden casters shown through what hides them.
pub struct XRay;

/// Its pass kinds: one draw of its own, no sets or render passes of its own.
pub struct XRayKinds;

impl PassKinds for XRayKinds {
    type Draw = XRayDraw;
    type Set = NoOwn;
    type Target = NoOwn;
}

/// The draw the x-ray renderer records itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum XRayDraw {
    /// The shadow casters, lit in their own materials, alpha `SHOW_THROUGH`.
    HiddenCasters,
}

impl DrawKind for XRayDraw {
    fn describe(self) -> &'static str {
        match self {
            XRayDraw::HiddenCasters => "shadow casters, where something nearer hides them",
        }
    }
}

/// The casters where the depth test says something nearer hides them, lit as the scene pass
/// lights them and blended: colour = caster x a + frame x (1 - a); the frame's alpha is kept.
fn hidden_pass() -> PlannedPass<XRayKinds> {
    let blend = BlendState {
        colour: Some(BlendEquation::new(
            vk::BlendOp::ADD,
            vk::BlendFactor::SRC_ALPHA,
            vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
        )),
        alpha: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::ONE)),
        write_mask: vk::ColorComponentFlags::RGBA,
    };
    let desc = PipelineDesc {
        name: "hidden casters",
        vertex_shader: shaders::LIT_VERT,
        fragment_shader: shaders::LIT_FRAG,
        vertex_layout: VertexLayout::SCENE,
        fixed: FixedFunction {
            depth: DepthState { compare: Some(vk::CompareOp::GREATER), write: false },
            blend,
            ..FixedFunction::OPAQUE
        },
        push_constant_bytes: OBJECT_PUSH_BYTES,
    };
    PlannedPass::own("x-ray", desc, XRayDraw::HiddenCasters, "object transform and colour, alpha 0.5")
        .with_sets(&[SetRole::Frame, SetRole::Material])
}

impl TechniqueInfo for XRay {
    fn name(&self) -> &'static str {
        "x-ray"
    }

    fn about(&self) -> &'static str {
        "hidden shadow casters shown through what hides them, by a depth-GREATER pass (the technique docs/adding-a-technique.md adds)"
    }
}

impl TechniqueUnit for XRay {
    type Kinds = XRayKinds;
    type Setup = ();
    type Passes = XRayPasses;

    fn plan(&self, _options: &RenderOptions, _lights: &[PlannedLight]) -> Result<PassPlan<XRayKinds>> {
        Ok(PassPlan { passes: vec![scene_pass(1.0), hidden_pass()] })
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, _setup: ()) -> Result<XRayPasses> {
        Ok(XRayPasses { gpu: ctx.gpu.clone(), meshes: GpuScene::upload_for(ctx.gpu, scene, ctx.options.skinning)? })
    }
}

/// What the x-ray renderer keeps: the scene's meshes.
pub struct XRayPasses {
    gpu: Arc<Gpu>,
    meshes: GpuScene,
}

impl Passes<XRayKinds> for XRayPasses {
    fn meshes(&self) -> Option<&GpuScene> {
        Some(&self.meshes)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: XRayDraw,
        _pass: &PlannedPass<XRayKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        match draw {
            XRayDraw::HiddenCasters => {
                let Some(&pipeline) = pipelines.first() else { return Ok(()) };
                let mut bound = pipeline;
                for (index, object) in scene.objects.iter().enumerate().filter(|(_, o)| o.casts_shadow) {
                    // A GPU-skinned caster is drawn by the pipeline's skinned twin.
                    let (mesh, wanted) = self.meshes.object_draw(scene, index, pipeline)?;
                    if !std::ptr::eq(wanted, bound) {
                        rec.bind(wanted);
                        bound = wanted;
                    }
                    rec.bind_material(bound, self.meshes.materials.set(object.material));
                    rec.push(bound, &object_push(scene, object, SHOW_THROUGH));
                    rec.draw_mesh(mesh);
                }
                Ok(())
            }
        }
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        // Skinned casters posed on the CPU follow the pose (`--skinning cpu`).
        self.meshes.follow_pose(&self.gpu, scene, renderer.slot())
    }

    fn writes_per_slot(&self) -> bool {
        true
    }
}
