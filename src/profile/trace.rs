//! `--trace FILE.json` (`profile`, `profile-app`, `bench`): the frames on a timeline, as Chrome
//! trace-event JSON (the "JSON Array/Object Format" that ui.perfetto.dev and chrome://tracing
//! open). One process; a GPU track (thread 1) with a complete event (`ph: "X"`) per measured
//! pass, its GPU time from the pass's timestamps; for nostencil's own frames a CPU track
//! (thread 2) with the frame's record, submit and wait; counter tracks (`ph: "C"`) per frame:
//! fragments, samples and bytes. Times in microseconds, as the format has them.
//!
//! The GPU's and the CPU's clocks are not calibrated against each other: a frame's passes start
//! where its submit ended on the CPU track (nostencil's frames) or right after the previous
//! frame's passes (an application's, whose CPU side the layer does not time: cli/app_counts.rs
//! lays those out).

use std::path::Path;

use serde::Serialize;
use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::frame::bandwidth::Bandwidth;
use crate::render::FrameCounters;

pub const PID: u32 = 1;
/// The GPU track's thread id.
pub const GPU_TID: u32 = 1;
/// The CPU track's (nostencil's own frames).
pub const CPU_TID: u32 = 2;

/// One trace event (only the fields the format needs for X, C and M events).
#[derive(Debug, Clone, Serialize)]
pub struct TraceEvent {
    pub name: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cat: Option<&'static str>,
    pub ph: &'static str,
    pub pid: u32,
    pub tid: u32,
    /// Microseconds.
    pub ts: f64,
    /// Microseconds, for complete ("X") events.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dur: Option<f64>,
    pub args: Value,
}

/// The whole file.
#[derive(Debug, Clone, Serialize)]
pub struct Trace {
    #[serde(rename = "traceEvents")]
    pub trace_events: Vec<TraceEvent>,
    #[serde(rename = "displayTimeUnit")]
    pub display_time_unit: &'static str,
}

impl Trace {
    /// An empty timeline of `process` (its name), with the tracks named.
    pub fn new(process: &str, cpu_track: bool) -> Self {
        let meta = |name: &str, tid: u32, value: &str| TraceEvent {
            name: name.into(),
            cat: None,
            ph: "M",
            pid: PID,
            tid,
            ts: 0.0,
            dur: None,
            args: json!({ "name": value }),
        };
        let mut trace_events =
            vec![meta("process_name", 0, process), meta("thread_name", GPU_TID, "GPU (render passes)")];
        if cpu_track {
            trace_events.push(meta("thread_name", CPU_TID, "CPU (nostencil: record, submit, wait)"));
        }
        Trace { trace_events, display_time_unit: "ms" }
    }

    /// A complete event on track `tid`: `ts` and `dur` in microseconds.
    pub fn slice(&mut self, tid: u32, name: &str, cat: &'static str, ts: f64, dur: f64, args: Value) {
        self.trace_events.push(TraceEvent {
            name: name.into(),
            cat: Some(cat),
            ph: "X",
            pid: PID,
            tid,
            ts,
            dur: Some(dur),
            args,
        });
    }

    /// The frame's counters at `ts`: one counter track each for fragments, samples and bytes.
    pub fn counters(&mut self, ts: f64, frame: u64, fragments: Option<u64>, samples: u64, bytes: Bandwidth) {
        let counter = |name: &str, args: Value| TraceEvent {
            name: name.into(),
            cat: Some("frame"),
            ph: "C",
            pid: PID,
            tid: 0,
            ts,
            dur: None,
            args,
        };
        if let Some(fragments) = fragments {
            self.trace_events.push(counter("fragments", json!({ "fragments": fragments, "frame": frame })));
        }
        self.trace_events.push(counter("samples", json!({ "samples passed": samples, "frame": frame })));
        self.trace_events.push(counter(
            "bytes",
            json!({ "tiler": bytes.tiler_bytes, "immediate-mode": bytes.immediate_bytes, "frame": frame }),
        ));
    }

    /// One of nostencil's own frames that began `start` microseconds into the trace: the CPU's
    /// phases, then the passes at their timestamps from where the submit ended. Returns where
    /// the frame ends on the timeline.
    pub fn own_frame(&mut self, name: &str, frame: u64, start: f64, counters: &FrameCounters) -> f64 {
        let cpu = counters.cpu;
        let phases = [("record", cpu.record), ("submit", cpu.submit), ("wait", cpu.wait)];
        for (phase, (at, ms)) in phases {
            let args = json!({ "frame": frame, "what": name });
            self.slice(CPU_TID, phase, "cpu", start + at * 1e3, ms * 1e3, args);
        }
        let gpu_start = start + (cpu.submit.0 + cpu.submit.1) * 1e3;
        let mut end = start + (cpu.wait.0 + cpu.wait.1) * 1e3;
        for pass in &counters.passes {
            let args = json!({
                "frame": frame,
                "draws": pass.draws,
                "samples passed": pass.samples_passed,
                "fragments": pass.fragment_invocations,
            });
            let ts = gpu_start + pass.start_ms * 1e3;
            self.slice(GPU_TID, &pass.name, "gpu", ts, pass.gpu_ms * 1e3, args);
            end = end.max(ts + pass.gpu_ms * 1e3);
        }
        let fragments = counters.total_fragment_invocations();
        self.counters(start, frame, fragments, counters.total_samples_passed(), counters.bandwidth());
        end
    }

    /// Written through a temporary file and a rename, like every output.
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string(self).map_err(|e| Error::Internal(e.to_string()))?;
        crate::frame::write_atomically(path, text.as_bytes())
    }
}
