//! The heat-map frame's pipelines: each pipeline a technique binds into the frame's render pass
//! is stood in for by its overdraw counter (`Pipeline::overdraw_counter`), built on first use.
//! In `render`, not `profile`, though only profiling asks for it: the renderer owns the
//! pipelines a frame binds, and `profile` sits above the techniques that build renderers.

use ash::vk;

use crate::error::Result;
use crate::render::pipeline_object::Pipeline;

/// Overdraw counters standing in for the technique's pipelines in a heat-map frame, built on
/// first use, keyed by the pipeline they replace; the renderer empties it before each frame.
#[derive(Default)]
pub struct OverdrawPipelines {
    pub(crate) frame_render_pass: vk::RenderPass,
    twins: std::cell::RefCell<std::collections::HashMap<vk::Pipeline, Pipeline>>,
}

impl OverdrawPipelines {
    pub(crate) fn new(frame_render_pass: vk::RenderPass) -> Self {
        OverdrawPipelines { frame_render_pass, twins: Default::default() }
    }

    pub(crate) fn clear(&self) {
        self.twins.borrow_mut().clear();
    }

    /// The counter for `pipeline` (its raw handle), or the pipeline itself when it draws into a
    /// target other than the frame (shadow maps are not part of the frame's overdraw).
    pub(crate) fn substitute(&self, pipeline: &Pipeline) -> Result<vk::Pipeline> {
        if pipeline.render_pass != self.frame_render_pass {
            return Ok(pipeline.raw);
        }
        let mut twins = self.twins.borrow_mut();
        if let Some(twin) = twins.get(&pipeline.raw) {
            return Ok(twin.raw);
        }
        let twin = pipeline.overdraw_counter()?;
        let raw = twin.raw;
        twins.insert(pipeline.raw, twin);
        Ok(raw)
    }
}
