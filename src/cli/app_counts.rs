//! An application's render passes, as the fill-rate layer measured them, turned into what
//! `profile`'s budgets, charts and traces take: one entry per position in the frame, named by
//! position and debug label.

use crate::frame::bandwidth::Bandwidth;
use crate::profile::budget::{PassBudget, WorkBudget};
use crate::profile::chart::ChartRow;
use crate::profile::trace::{Trace, GPU_TID};
use nostencil_fillrate_report::report::{AggregateRow, FillrateReport};
use serde_json::json;

/// "render pass #2", or "render pass #2 'shadows'" when the application labelled it: what a
/// budget matches, so the same pass matches at another window size.
pub use crate::profile::budget::application_pass_name as pass_name;

/// One position of the frame: its name, the render area of the rows there, and the most of
/// each deterministic counter over the measured frames.
#[derive(Debug, Clone, PartialEq)]
pub struct PositionCounts {
    pub count: PassBudget,
    /// "WxH" of the render area (several, comma-separated, if it changed between frames).
    pub area: String,
}

/// Per position in the frame, the most of each counter over every measured frame (from the
/// aggregate, which covers them all). Positions whose passes were never measured are left out;
/// `not_measured` in the report says why.
pub fn worst_per_position(report: &FillrateReport) -> Vec<PositionCounts> {
    let mut positions: Vec<u32> = report.aggregate.iter().map(|a| a.position).collect();
    positions.sort_unstable();
    positions.dedup();
    positions
        .into_iter()
        .map(|position| {
            let rows: Vec<&AggregateRow> = report.aggregate.iter().filter(|a| a.position == position).collect();
            let label = rows.iter().rev().find_map(|r| r.label.as_deref());
            let mut areas: Vec<String> = rows.iter().map(|r| area_of_key(&r.key)).collect();
            areas.dedup();
            let fragments = rows.iter().map(|r| r.max.fragment_invocations).collect::<Option<Vec<u64>>>();
            PositionCounts {
                count: PassBudget {
                    name: pass_name(position, label),
                    draws: rows.iter().map(|r| r.max.draws).max().unwrap_or(0).min(u32::MAX as u64) as u32,
                    samples_passed: rows.iter().map(|r| r.max.samples_passed).max().unwrap_or(0),
                    fragment_invocations: fragments.and_then(|f| f.into_iter().max()),
                },
                area: areas.join(", "),
            }
        })
        .collect()
}

/// "compute #0", "transfer #2 'upload'": what a budget matches a work row by.
pub fn work_name(kind: &str, position: u32, label: Option<&str>) -> String {
    match label {
        Some(label) => format!("{kind} #{position} '{label}'"),
        None => format!("{kind} #{position}"),
    }
}

/// Per work row (position, kind, label), the most of each figure over the measured frames.
pub fn worst_work(report: &FillrateReport) -> Vec<WorkBudget> {
    let mut worst: Vec<WorkBudget> = Vec::new();
    for w in &report.work_aggregate {
        let name = work_name(&w.kind, w.position, w.label.as_deref());
        let bytes = w.max.bytes_read + w.max.bytes_written;
        match worst.iter_mut().find(|b| b.name == name) {
            Some(b) => {
                b.workgroups = b.workgroups.max(w.max.workgroups);
                b.compute_invocations = b.compute_invocations.max(w.max.compute_invocations);
                b.bytes = b.bytes.max(bytes);
            }
            None => worst.push(WorkBudget {
                name,
                workgroups: w.max.workgroups,
                compute_invocations: w.max.compute_invocations,
                bytes,
            }),
        }
    }
    worst
}

/// The most bytes one kept frame moved, on a tiler and on an immediate-mode GPU (each its own
/// worst frame): what a budget holds per frame. A transfer's bytes count on both.
pub fn worst_frame_bandwidth(report: &FillrateReport) -> Bandwidth {
    let frames = report.frames.iter().map(|f| {
        let passes = f.render_passes.iter().filter_map(|p| p.counters).map(|c| c.bandwidth());
        passes.chain(f.work.iter().filter_map(|w| w.counters).map(|c| c.bandwidth())).collect::<Vec<_>>()
    });
    frames.map(|parts| parts.into_iter().sum::<Bandwidth>()).fold(Bandwidth::default(), |worst, frame| Bandwidth {
        tiler_bytes: worst.tiler_bytes.max(frame.tiler_bytes),
        immediate_bytes: worst.immediate_bytes.max(frame.immediate_bytes),
    })
}

/// The layer's kept frames on `trace`'s timeline (`profile-app --trace`): each measured pass's GPU time laid end to end, frame after
/// frame (the layer keeps each pass's duration, not its place on the GPU's clock).
pub fn trace_frames(trace: &mut Trace, report: &FillrateReport) {
    let mut cursor = 0.0;
    for frame in &report.frames {
        let measured: Vec<_> = frame.render_passes.iter().filter_map(|p| Some((p, p.counters?))).collect();
        let fragments = measured.iter().map(|(_, c)| c.fragment_invocations).sum::<Option<u64>>();
        let samples = measured.iter().map(|(_, c)| c.samples_passed).sum();
        // The frame's bytes: its passes' and its transfers' (as the table's estimate counts them).
        let transfers = frame.work.iter().filter_map(|w| w.counters).map(|c| c.bandwidth());
        let bytes = measured.iter().map(|(_, c)| c.bandwidth()).chain(transfers).sum();
        trace.counters(cursor, frame.index, fragments, samples, bytes);
        for (pass, counters) in measured {
            let Some(ms) = counters.gpu_ms else { continue };
            let name = match &pass.label {
                Some(label) => format!("#{} {label}", pass.index),
                None => format!("#{}", pass.index),
            };
            let args = json!({
                "frame": frame.index,
                "area": format!("{}x{}x{}", pass.render_area.width, pass.render_area.height, pass.samples),
                "draws": counters.draws,
                "samples passed": counters.samples_passed,
                "fragments": counters.fragment_invocations,
                "tiler bytes": counters.tiler_bytes,
                "immediate-mode bytes": counters.immediate_bytes,
            });
            trace.slice(GPU_TID, &name, "gpu", cursor, ms * 1e3, args);
            cursor += ms * 1e3;
        }
        // Then the frame's dispatch groups and transfers, also end to end.
        for w in &frame.work {
            let Some(ms) = w.counters.and_then(|c| c.gpu_ms) else { continue };
            let Some(c) = w.counters else { continue };
            let name = work_name(&w.kind, w.index, w.label.as_deref());
            let args = json!({
                "frame": frame.index,
                "command": w.api,
                "commands": c.commands,
                "workgroups": c.workgroups,
                "compute invocations": c.compute_invocations,
                "bytes read": c.bytes_read,
                "bytes written": c.bytes_written,
            });
            let category = if w.kind == "compute" { "compute" } else { "transfer" };
            trace.slice(GPU_TID, &name, category, cursor, ms * 1e3, args);
            cursor += ms * 1e3;
        }
    }
}

/// The "WxH" an aggregate key starts with.
fn area_of_key(key: &str) -> String {
    key.split_whitespace().next().unwrap_or("?").to_owned()
}

/// The largest render area over the positions, as (width, height) by pixel count.
pub fn largest_area(report: &FillrateReport) -> (u32, u32) {
    let sizes = report.aggregate.iter().filter_map(|a| {
        let (w, h) = area_of_key(&a.key).split_once('x').map(|(w, h)| (w.parse().ok(), h.parse().ok()))?;
        Some((w?, h?))
    });
    sizes.max_by_key(|&(w, h): &(u32, u32)| w as u64 * h as u64).unwrap_or((0, 0))
}

/// One chart row per aggregate row: the mean over frames; then one per work row (dispatch
/// group or transfer), which has GPU time only.
pub fn chart_rows(report: &FillrateReport) -> Vec<ChartRow> {
    let passes = report.aggregate.iter().map(|a| ChartRow {
        name: format!("{} {}", pass_name(a.position, a.label.as_deref()), area_of_key(&a.key)),
        fragments_per_pixel: a.mean.fragments_per_pixel.unwrap_or(0.0),
        samples_per_pixel: a.mean.overdraw,
        gpu_ms: a.mean.gpu_ms.unwrap_or(0.0),
    });
    let work = report.work_aggregate.iter().map(|w| ChartRow {
        name: format!("{} {}", work_name(&w.kind, w.position, w.label.as_deref()), w.api),
        fragments_per_pixel: 0.0,
        samples_per_pixel: 0.0,
        gpu_ms: w.mean.gpu_ms.unwrap_or(0.0),
    });
    passes.chain(work).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nostencil_fillrate_report::report::{CounterSupport, Counters, FILLRATE_SCHEMA};

    fn counters(samples: u64) -> Counters {
        Counters {
            draws: 1,
            vertex_invocations: None,
            clipping_primitives: None,
            fragment_invocations: Some(samples + 16),
            fragments_per_pixel: None,
            samples_passed: samples,
            overdraw: 0.0,
            gpu_ms: None,
            bytes_loaded: 0,
            bytes_stored: 0,
            tiler_bytes: 0,
            immediate_bytes: 0,
        }
    }

    fn row(position: u32, key: &str, label: Option<&str>, max: u64) -> AggregateRow {
        let mean = Counters {
            draws: 1.0,
            vertex_invocations: None,
            clipping_primitives: None,
            fragment_invocations: None,
            fragments_per_pixel: Some(0.5),
            samples_passed: max as f64,
            overdraw: 0.25,
            gpu_ms: Some(1.5),
            bytes_loaded: 0.0,
            bytes_stored: 0.0,
            tiler_bytes: 0.0,
            immediate_bytes: 0.0,
        };
        AggregateRow {
            position,
            key: key.into(),
            frames: 3,
            label: label.map(str::to_owned),
            mean,
            min: counters(max / 2),
            max: counters(max),
            sections: Vec::new(),
        }
    }

    fn report(aggregate: Vec<AggregateRow>) -> FillrateReport {
        FillrateReport {
            schema: FILLRATE_SCHEMA.into(),
            application: "app".into(),
            device: "llvmpipe".into(),
            counters: CounterSupport::default(),
            frames_measured: 3,
            not_measured: Vec::new(),
            frames: Vec::new(),
            aggregate,
            work_aggregate: Vec::new(),
            run: None,
            hidden_extensions: Vec::new(),
            tiler_check: None,
        }
    }

    #[test]
    fn each_position_takes_the_most_of_its_rows_under_its_label() {
        let report = report(vec![
            row(0, "500x500 colour B8G8R8A8_UNORM CLEAR/STORE", None, 100),
            row(1, "64x64 colour R8_UNORM CLEAR/STORE", Some("shadow"), 10),
            row(0, "600x600 colour B8G8R8A8_UNORM CLEAR/STORE", None, 300),
        ]);
        let worst = worst_per_position(&report);
        assert_eq!(worst.len(), 2);
        assert_eq!(worst[0].count.name, "render pass #0");
        assert_eq!((worst[0].count.samples_passed, worst[0].count.fragment_invocations), (300, Some(316)));
        assert_eq!(worst[0].area, "500x500, 600x600");
        assert_eq!(worst[1].count.name, "render pass #1 'shadow'");
        assert_eq!(largest_area(&report), (600, 600));
        let chart = chart_rows(&report);
        assert_eq!(chart[1].name, "render pass #1 'shadow' 64x64");
        assert_eq!((chart[0].fragments_per_pixel, chart[0].samples_per_pixel, chart[0].gpu_ms), (0.5, 0.25, 1.5));
    }
}
