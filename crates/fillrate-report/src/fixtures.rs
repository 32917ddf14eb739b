//! Rows made up for the tests of what reads the report (this crate's and the layer's).

use crate::report::{Counters, RawCounters, RenderArea, RenderPassRow};

/// A `width` x 10 render pass of two draws whose `samples_passed` samples each shaded twice.
pub fn row(width: u32, samples_passed: u64, gpu_ns: Option<f64>) -> RenderPassRow {
    let area = RenderArea { x: 0, y: 0, width, height: 10 };
    let raw = RawCounters {
        draws: 2,
        vertex_invocations: Some(6),
        clipping_primitives: Some(2),
        fragment_invocations: Some(samples_passed * 2),
        samples_passed,
        gpu_ns,
    };
    RenderPassRow {
        per_draw: Vec::new(),
        sections: Vec::new(),
        index: 0,
        label: None,
        api: "vkCmdBeginRenderPass".into(),
        render_area: area,
        samples: 1,
        views: 1,
        attachments: Vec::new(),
        counters: Some(Counters::new(&raw, &area, 1, &[])),
        not_measured: None,
        flag: None,
    }
}
