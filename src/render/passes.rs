//! [`Passes`]: the one trait a technique implements for what it builds for a scene. The
//! renderer skeleton (`technique::frame_renderer`) calls it around each frame, and
//! [`record_plan`](super::plan_execution::record_plan) calls it for the sets, meshes and draws
//! of the technique's plan, typed by the technique's [`PassKinds`].

use ash::vk;

use super::frame_stats::{FrameStats, NoStats};
use super::gpu_mesh::GpuScene;
use super::materials::GpuMaterials;
use super::pipeline_object::Pipeline;
use super::plan::{PassKinds, PlannedPass, Scissor, When};
use super::recorder::FrameRecorder;
use super::renderer::{FrameOutput, Renderer};
use crate::error::Result;
use crate::gpu::descriptors::DescriptorSet;
use crate::scene::{JointPalettes, Light, Scene};

/// A technique's side of a renderer: what it built for the scene (its descriptor sets, the
/// scene's meshes for the object passes the recorder draws, its offscreen render passes), the
/// draws only it knows how to make, and what it does per frame. Only `draw` and `prepare` have
/// no default; each default is what most techniques need, and is overridden by those that differ.
pub trait Passes<K: PassKinds> {
    /// Records the technique's own draw `draw` of `pass` (the recorder has opened the measured
    /// pass, made the colour target readable if the pass reads it, and, in the frame's render
    /// pass, bound the pass's main pipeline with its sets).
    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: K::Draw,
        pass: &PlannedPass<K>,
        pipelines: &[&Pipeline],
    ) -> Result<()>;

    /// Per-frame CPU work before recording: re-pose skinned copies, rebuild and upload the
    /// geometry the frame draws.
    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()>;

    /// Whether every buffer `prepare` writes is written in the copy of the frame's slot
    /// (`Renderer::slot`, `FrameRecorder::slot`), which no other frame in flight reads: then
    /// the renderer may keep several frames in flight (`RenderOptions.frames_in_flight`).
    /// Otherwise it renders one frame at a time.
    fn writes_per_slot(&self) -> bool {
        false
    }

    /// A set of its own, bound by the passes that name it (its layout is also what the
    /// pipelines are built with; the frame's uniforms are the recorder's).
    fn set(&self, set: K::Set) -> Option<&DescriptorSet> {
        let _ = set;
        None
    }

    /// The scene's meshes, for passes that draw `Draws::Objects` (the recorder draws those).
    fn meshes(&self) -> Option<&GpuScene> {
        None
    }

    /// Where the skinned objects' palettes lie, when the technique skins them on the GPU: each
    /// of its passes that draws them binds its pipelines' skinned twins, which the plan is then
    /// built with, and every frame carries the palettes. The meshes' choice by default
    /// (`GpuScene::upload_for`).
    fn joint_palettes(&self) -> Option<&JointPalettes> {
        self.meshes().and_then(GpuScene::joint_palettes)
    }

    /// Whether the plan's pipelines are built with their skinned twins (`Pipeline::skinned`),
    /// which its draws bind for objects skinned on the GPU: where it has the palettes of a scene
    /// with skinned objects, unless its plans name skinned pipelines of their own (the planar
    /// family).
    fn skinned_twins(&self) -> bool {
        self.joint_palettes().is_some_and(|palettes| !palettes.is_empty())
    }

    /// The materials whose sets the plan's object passes bind (the template with the pass's
    /// sets, then each object's own): the meshes' by default.
    fn materials(&self) -> Option<&GpuMaterials> {
        self.meshes().map(|meshes| &meshes.materials)
    }

    /// Where the plan's scissored pass `pass` draws this frame (in a per-light loop, its
    /// `light` says whose scissor).
    fn scissor(&self, pass: &PlannedPass<K>) -> Scissor {
        let _ = pass;
        Scissor::Frame
    }

    /// The render pass (and its colour attachment count) of an offscreen target. Prepasses
    /// render at one sample: a shadow map's depth compare, a bake's texels and a mask's
    /// coverage are sampled and filtered later, where extra samples would only be resolved
    /// away (docs/msaa.md).
    fn offscreen_pass(&self, target: K::Target) -> Option<(vk::RenderPass, usize)> {
        let _ = target;
        None
    }

    /// What the frame's alpha (and, on the reference path, its stencil) is cleared to.
    fn clear(&self) -> Clear {
        Clear::default()
    }

    /// The light of this frame's uniforms, when it is not the scene's (a light that turns
    /// from frame to frame).
    fn frame_light(&self) -> Option<Light> {
        None
    }

    /// Which conditional passes run in this frame.
    fn conditions(&self, scene: &Scene) -> Vec<When> {
        let _ = scene;
        Vec::new()
    }

    /// What the frame did, from its output; called once per frame after it completed
    /// ([`NoStats`] for a technique with nothing to report).
    fn stats(&mut self, output: &FrameOutput, scene: &Scene) -> Box<dyn FrameStats> {
        let _ = (output, scene);
        Box::new(NoStats)
    }

    /// Whether `scene` needs a rebuilt renderer (see `SceneRenderer::stale_for`).
    fn stale_for(&self, renderer: &Renderer, scene: &Scene) -> bool {
        let _ = (renderer, scene);
        false
    }

    /// See `SceneRenderer::frames_to_steady_state`.
    fn frames_to_steady_state(&self) -> u32 {
        1
    }

    /// See `SceneRenderer::warnings`.
    fn warnings(&self) -> &[String] {
        &[]
    }
}

/// The clear values a technique starts its frame with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clear {
    /// The colour target's alpha: 1 for most; the counter's 0 for shadow volumes and the
    /// outline's unmarked 0.
    pub alpha: f32,
    /// The stencil's value on the reference path: 0 for most; the volume count's zero for
    /// shadow volumes.
    pub stencil: u32,
}

impl Default for Clear {
    fn default() -> Self {
        Clear { alpha: 1.0, stencil: 0 }
    }
}
