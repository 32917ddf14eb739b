//! Render pass instances as the GPU sees them: which measured passes drew into which instance,
//! and the counters summed per instance (`FrameCounters::render_pass_sums`). A tool that
//! brackets every render pass instance with its own queries (the fill-rate layer) measures
//! exactly these sums, so they are what it is compared with.

use serde::Serialize;

use crate::frame::render_pass::AttachmentTraffic;

/// One render pass instance the frame began, in recording (and submission) order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RenderPassInstance {
    pub index: u32,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of its attachments (the most of any).
    pub samples: u32,
    pub attachments: Vec<AttachmentTraffic>,
    /// The measured passes whose draws went into it: those recorded inside it (the frame's
    /// render pass), or the one pass that began it (a prepass).
    pub passes: Vec<String>,
}

/// The counters of `count` consecutive render pass instances from `first`: one instance, except
/// where one measured pass began several (one bake per model), whose queries cannot tell them
/// apart; then the sum covers them all.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RenderPassSums {
    pub first: u32,
    pub count: u32,
    pub passes: Vec<String>,
    pub draws: u32,
    pub samples_passed: u64,
    /// None without pipeline statistics.
    pub fragment_invocations: Option<u64>,
}
