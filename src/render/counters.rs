//! Per-pass fill-rate counters, as the frame's queries returned them.
//!
//! Two different figures are kept apart on purpose:
//! - `fragment_invocations` (pipeline statistics) counts fragment shader invocations. On
//!   lavapipe this is not a pixel count: it is 16 x the 4x4 pixel blocks each triangle touches,
//!   depth-rejected blocks included (DESIGN.md section 7). Hardware differs again (2x2 quads).
//! - `samples_passed` (precise occlusion query) counts samples that passed the depth and stencil
//!   tests: exact, the same on every conformant device.

use serde::Serialize;

use crate::frame::render_pass::RenderPassTraffic;
use crate::gpu::queries::RawPassQueries;

#[derive(Debug, Clone, Serialize)]
pub struct PassCounters {
    pub name: String,
    pub draws: u32,
    /// Vertex shader invocations (pipeline statistics; None where the device lacks them).
    pub vertex_invocations: Option<u64>,
    /// Primitives that left the clipper (pipeline statistics).
    pub clipping_primitives: Option<u64>,
    /// Fragment shader invocations (pipeline statistics; see the module docs for lavapipe's rule).
    pub fragment_invocations: Option<u64>,
    /// Samples that passed depth/stencil tests (precise occlusion query): exact.
    pub samples_passed: u64,
    /// GPU time between the pass's two timestamps, in milliseconds.
    pub gpu_ms: f64,
    /// Start of the pass relative to the frame's first timestamp, in milliseconds.
    pub start_ms: f64,
}

impl PassCounters {
    pub fn from_queries(name: String, draws: u32, raw: &RawPassQueries, frame_start_ns: f64) -> Self {
        PassCounters {
            name,
            draws,
            vertex_invocations: raw.vertex_invocations,
            clipping_primitives: raw.clipping_primitives,
            fragment_invocations: raw.fragment_invocations,
            samples_passed: raw.samples_passed,
            gpu_ms: (raw.end_ns - raw.begin_ns).max(0.0) / 1e6,
            start_ms: (raw.begin_ns - frame_start_ns) / 1e6,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct FrameCounters {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the frame (its passes' samples passed count every sample).
    pub samples: u32,
    pub passes: Vec<PassCounters>,
    /// Tile traffic of every render pass the frame began (prepasses' targets and the frame).
    pub render_passes: Vec<RenderPassTraffic>,
}

impl FrameCounters {
    pub fn pixels(&self) -> u64 {
        self.width as u64 * self.height as u64
    }

    pub fn pass(&self, name: &str) -> Option<&PassCounters> {
        self.passes.iter().find(|p| p.name == name)
    }

    /// Sum of fragment shader invocations over all passes (None without pipeline statistics).
    pub fn total_fragment_invocations(&self) -> Option<u64> {
        self.passes.iter().map(|p| p.fragment_invocations).sum()
    }

    pub fn total_samples_passed(&self) -> u64 {
        self.passes.iter().map(|p| p.samples_passed).sum()
    }

    pub fn total_gpu_ms(&self) -> f64 {
        self.passes.iter().map(|p| p.gpu_ms).sum()
    }

    /// Samples the frame holds: W x H x N.
    pub fn frame_samples(&self) -> u64 {
        self.pixels() * self.samples.max(1) as u64
    }

    /// Samples passed per frame sample, samples / (W x H x N): how many times each sample was
    /// written on average, the same figure at any sample count.
    pub fn overdraw(&self) -> f64 {
        self.total_samples_passed() as f64 / self.frame_samples() as f64
    }
}
