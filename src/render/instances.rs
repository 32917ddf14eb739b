//! Render pass instances as the GPU sees them: which measured passes drew into which instance,
//! and the counters summed per instance (`FrameCounters::render_pass_sums`). A tool that
//! brackets every render pass instance with its own queries (the fill-rate layer) measures
//! exactly these sums, so they are what it is compared with.

use serde::Serialize;

use crate::frame::bandwidth::{bytes_per_passing_sample, fixed_bandwidth, AttachmentCost, Bandwidth};
use crate::frame::render_pass::{AttachmentTraffic, RESOLVED_NAME};

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
    /// Bytes the instances move to and from memory on a tiler and an immediate-mode GPU
    /// (frame/bandwidth.rs, after Mesa turnip).
    #[serde(flatten)]
    pub bandwidth: Bandwidth,
}

impl RenderPassInstance {
    /// Its attachments as the bandwidth model sees them.
    pub fn costs(&self) -> Vec<AttachmentCost> {
        self.attachments
            .iter()
            .map(|a| {
                let resolve = a.attachment == RESOLVED_NAME;
                AttachmentCost {
                    tile_bytes: a.bytes_loaded + a.bytes_stored,
                    cleared_bytes: a.bytes_cleared,
                    bytes_per_sample: a.bytes_per_sample,
                    resolve_of: resolve.then_some(self.samples),
                    drawn: !resolve,
                }
            })
            .collect()
    }
}

/// The traffic of consecutive `instances` whose draws let `samples_passed` samples pass (the
/// draws' bytes per sample are the first instance's: the instances of one group are alike).
pub fn group_bandwidth(instances: &[RenderPassInstance], samples_passed: u64) -> Bandwidth {
    let fixed = group_fixed_bandwidth(instances);
    Bandwidth {
        tiler_bytes: fixed.tiler_bytes,
        immediate_bytes: fixed.immediate_bytes + samples_passed * group_bytes_per_sample(instances),
    }
}

/// What consecutive `instances` move whatever is drawn in them: loads, stores, clears, resolves.
pub fn group_fixed_bandwidth(instances: &[RenderPassInstance]) -> Bandwidth {
    instances
        .iter()
        .map(|instance| fixed_bandwidth(&instance.costs(), instance.width as u64 * instance.height as u64))
        .sum()
}

/// Bytes an immediate-mode GPU moves per sample passing in the group (its first instance's).
pub fn group_bytes_per_sample(instances: &[RenderPassInstance]) -> u64 {
    instances.first().map_or(0, |instance| bytes_per_passing_sample(&instance.costs()))
}
