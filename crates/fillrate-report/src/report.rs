//! The layer's result file, schema "nostencil-fillrate/1": what the layer writes and what
//! `nostencil profile-app` reads back (the same serde types both ways).

use serde::{Deserialize, Serialize};

use nostencil_tiler::bandwidth::{pass_bandwidth, AttachmentCost, Bandwidth};

/// Version of the JSON layout; bump on any incompatible change.
pub const FILLRATE_SCHEMA: &str = "nostencil-fillrate/1";

/// How many frames `frames` keeps when the number of frames is not limited (the aggregate still
/// covers every measured frame).
pub const KEPT_FRAMES: usize = 64;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FillrateReport {
    pub schema: String,
    /// `VkApplicationInfo::pApplicationName`, or the process name when the application gave none.
    pub application: String,
    /// `VkPhysicalDeviceProperties::deviceName` of the (last) device created.
    pub device: String,
    pub counters: CounterSupport,
    pub frames_measured: u64,
    /// Render pass instances (or whole things) the layer saw and could not measure, by reason.
    pub not_measured: Vec<NotMeasured>,
    pub frames: Vec<FrameRows>,
    pub aggregate: Vec<AggregateRow>,
    /// Mean, min and max of each dispatch group and transfer over the frames (work_aggregate.rs),
    /// matched by position among the frame's work, kind, command and label.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub work_aggregate: Vec<AggregateWork>,
    /// How the program's run ended, when `profile-app` ran it (the layer itself leaves it out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<RunEnd>,
    /// Device extensions the layer kept from the program, because their commands would record
    /// work it cannot measure (the layer's extensions.rs), each with why.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hidden_extensions: Vec<HiddenExtension>,
    /// With `NOSTENCIL_FILLRATE_TILER=1` (`profile-app --tiler-check`): the load/store mistakes
    /// found and the attachments filled with the pattern (tiler_check.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tiler_check: Option<crate::tiler::TilerReport>,
}

/// One line of the frame journal, `OUT.frames` beside the result file (written when
/// `NOSTENCIL_FILLRATE_EVERY` is set, as profile-app sets it): a finished frame and the report's
/// totals then, appended as the frame finishes, so a program that dies leaves every frame it
/// finished even between two rewrites of the whole file. Removed once the report is complete.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JournalLine {
    pub application: String,
    pub device: String,
    pub counters: CounterSupport,
    pub frames_measured: u64,
    pub not_measured: Vec<NotMeasured>,
    pub frame: FrameRows,
}

/// The journal beside the result file `out`.
pub fn journal_path(out: &std::path::Path) -> std::path::PathBuf {
    let mut path = out.as_os_str().to_owned();
    path.push(".frames");
    path.into()
}

/// How a program run by `profile-app` ended, and whether the report covers all it was asked to.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunEnd {
    /// "exited" (by itself), "ended" (by profile-app: --frames, --seconds), "interrupted"
    /// (Ctrl-C), "killed" (a signal from elsewhere), "crashed" (SIGSEGV, SIGABRT, ...) or "failed"
    /// (a non-zero exit status).
    pub how: String,
    /// One line for a person, e.g. "crashed with SIGSEGV after 3 measured frames".
    pub detail: String,
    /// The frames asked for were not all measured: the report holds those that were.
    pub partial: bool,
}

/// Which counters the device gave the layer.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CounterSupport {
    pub pipeline_statistics: bool,
    pub occlusion_precise: bool,
    pub timestamps: bool,
}

/// A device extension the program was not offered.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct HiddenExtension {
    pub name: String,
    pub why: String,
}

#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct NotMeasured {
    pub what: String,
    pub count: u64,
}

/// One frame: the render pass instances submitted between two presents, in submission order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameRows {
    pub index: u64,
    pub render_passes: Vec<RenderPassRow>,
    /// Compute and transfer work outside render passes, in submission order (work.rs).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub work: Vec<WorkRow>,
}

/// A group of dispatches (between two barriers, label calls or other work) or one transfer
/// command, outside render passes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkRow {
    /// Position among the frame's work rows, from 0.
    pub index: u32,
    /// "compute" | "transfer".
    pub kind: String,
    /// The (first) command, e.g. "vkCmdDispatch", "vkCmdBlitImage".
    pub api: String,
    /// The innermost debug-utils label open at the first command, if any.
    pub label: Option<String>,
    /// Null when the results could not be read (then `not_measured` says why).
    pub counters: Option<WorkCounters>,
    #[serde(default)]
    pub not_measured: Option<String>,
    /// e.g. a full-frame blit into a swapchain image (a `--tiler-check` finding).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// A work row's figures (`N` = u64), or their mean over frames (`N` = f64).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WorkCounters<N = u64> {
    /// Dispatches in the group; 1 for a transfer.
    pub commands: N,
    /// Workgroups as recorded (null when an indirect dispatch is in the group, and for
    /// transfers).
    pub workgroups: Option<N>,
    /// Compute-shader invocations (pipeline statistics; null without them, and for transfers).
    pub compute_invocations: Option<N>,
    /// Bytes a transfer reads and writes, from its regions (0 for compute: its memory traffic
    /// is not known to the layer).
    pub bytes_read: N,
    pub bytes_written: N,
    pub gpu_ms: Option<f64>,
}

impl WorkCounters {
    /// A transfer's bytes go through system memory on a tiler and an immediate-mode GPU alike.
    pub fn bandwidth(&self) -> Bandwidth {
        let bytes = self.bytes_read + self.bytes_written;
        Bandwidth { tiler_bytes: bytes, immediate_bytes: bytes }
    }
}

/// Mean, min and max of one work row over the frames that had it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AggregateWork {
    pub position: u32,
    pub kind: String,
    pub api: String,
    pub label: Option<String>,
    pub frames: u64,
    pub mean: WorkCounters<f64>,
    pub min: WorkCounters,
    pub max: WorkCounters,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RenderPassRow {
    /// Position in the frame, from 0.
    pub index: u32,
    /// The innermost debug-utils label open when the pass began, if any.
    pub label: Option<String>,
    /// "vkCmdBeginRenderPass" | "vkCmdBeginRenderPass2" | "vkCmdBeginRendering".
    pub api: String,
    pub render_area: RenderArea,
    /// Samples per pixel of the pass (the most of its attachments').
    pub samples: u32,
    /// Views a multiview pass renders (the most of its subpasses'; 1 otherwise): its figures
    /// per pixel are per pixel of every view, and its attachments' traffic covers every view.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub views: u32,
    pub attachments: Vec<AttachmentRow>,
    /// Null when the pass was not measured (then `not_measured` says why).
    pub counters: Option<Counters>,
    #[serde(default)]
    pub not_measured: Option<String>,
    /// The draws and the statistics disagree (`Counters::disagreement`): measured, but not to
    /// be read as a clean figure.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flag: Option<String>,
    /// `NOSTENCIL_FILLRATE_PER_DRAW=1` (`profile-app --per-draw`): each draw, in recording order;
    /// their sums are the pass's counters. Empty when off or when a draw could not be measured
    /// alone (inside an application query of the same type).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_draw: Vec<DrawRow>,
    /// The parts of the pass between debug-utils label calls made inside it (an application
    /// that labels draw groups inside one render pass), in recording order; their counters sum
    /// to the pass's exactly (GPU time aside: the pass's also covers its loads, stores and
    /// what lies between sections). Empty when no label call was made inside the pass.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<SectionRow>,
}

/// A section of a render pass instance: its draws between two label calls.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionRow {
    /// The labels begun inside the pass and open in this section, outermost first, joined by
    /// " / "; null for the unlabelled draws between labelled sections.
    pub label: Option<String>,
    /// Tile traffic belongs to the pass: a section's bytes are 0.
    pub counters: Option<Counters>,
    #[serde(default)]
    pub not_measured: Option<String>,
    /// `per_draw`: this section's share of the pass's draws.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_draw: Vec<DrawRow>,
}

/// One draw of a measured render pass.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DrawRow {
    pub fragment_invocations: Option<u64>,
    pub samples_passed: u64,
    /// Between timestamps right before and right after the draw.
    pub gpu_ms: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct RenderArea {
    pub x: i32,
    pub y: i32,
    pub width: u32,
    pub height: u32,
}

impl RenderArea {
    pub fn pixels(&self) -> u64 {
        self.width as u64 * self.height as u64
    }
}

#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AttachmentRow {
    /// "colour" | "depth" | "stencil" | "depth_stencil" | "resolve" | "input" | "unused".
    pub role: String,
    /// Vulkan format name without the prefix, e.g. "R8G8B8A8_SRGB".
    pub format: String,
    pub samples: u32,
    pub load_op: String,
    pub store_op: String,
    /// The stencil aspect's ops, for formats with stencil only.
    #[serde(default)]
    pub stencil_load_op: Option<String>,
    #[serde(default)]
    pub stencil_store_op: Option<String>,
    /// Tile traffic over the render area (`nostencil profile`'s rule: LOAD loads and STORE
    /// stores W x H x bytes x samples; CLEAR, DONT_CARE and NONE move nothing).
    pub bytes_loaded: u64,
    pub bytes_stored: u64,
    /// Bytes its CLEAR ops write over the render area, every sample (the immediate-mode
    /// estimate's; frame/bandwidth.rs).
    #[serde(default)]
    pub bytes_cleared: u64,
    /// Bytes of one sample of its format, all aspects.
    #[serde(default)]
    pub bytes_per_sample: u64,
}

/// One render pass instance's counters (`N` = u64), or their mean over frames (`N` = f64).
/// Optional counters are null where the device lacks them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Counters<N = u64> {
    pub draws: N,
    pub vertex_invocations: Option<N>,
    pub clipping_primitives: Option<N>,
    pub fragment_invocations: Option<N>,
    /// Fragment shader invocations / (width x height) of the render area.
    pub fragments_per_pixel: Option<f64>,
    /// Samples that passed depth/stencil (precise occlusion query): exact.
    pub samples_passed: N,
    /// Samples passed / (width x height x samples).
    pub overdraw: f64,
    pub gpu_ms: Option<f64>,
    pub bytes_loaded: N,
    pub bytes_stored: N,
    /// Bytes a tile-based GPU moves for the pass (loads, stores, resolves) and an immediate-mode
    /// one (clears, resolves, every passing sample read and written): frame/bandwidth.rs, after
    /// Mesa turnip's `tu_render_pass_bandwidth_config` and autotuner.
    #[serde(default)]
    pub tiler_bytes: N,
    #[serde(default)]
    pub immediate_bytes: N,
}

/// Raw per-pass results before the derived figures are filled in.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RawCounters {
    pub draws: u64,
    pub vertex_invocations: Option<u64>,
    pub clipping_primitives: Option<u64>,
    pub fragment_invocations: Option<u64>,
    pub samples_passed: u64,
    /// GPU nanoseconds between the pass's two timestamps.
    pub gpu_ns: Option<f64>,
}

fn one() -> u32 {
    1
}

fn is_one(n: &u32) -> bool {
    *n == 1
}

impl Counters {
    /// The row's counters: the raw results plus the figures derived from the pass's area,
    /// sample count and attachments' traffic.
    pub fn new(raw: &RawCounters, area: &RenderArea, samples: u32, attachments: &[AttachmentRow]) -> Self {
        Self::with_views(raw, area, samples, attachments, 1)
    }

    /// [`Counters::new`] for a pass rendering `views` views of `area` (multiview): per pixel is
    /// per pixel of all views.
    pub fn with_views(
        raw: &RawCounters,
        area: &RenderArea,
        samples: u32,
        attachments: &[AttachmentRow],
        views: u32,
    ) -> Self {
        let covered = area.pixels() * views.max(1) as u64;
        let pixels = covered.max(1);
        let costs: Vec<AttachmentCost> = attachments
            .iter()
            .map(|a| {
                let resolve = a.role == "resolve";
                AttachmentCost {
                    tile_bytes: a.bytes_loaded + a.bytes_stored,
                    cleared_bytes: a.bytes_cleared,
                    bytes_per_sample: a.bytes_per_sample,
                    resolve_of: resolve.then_some(samples.max(1)),
                    drawn: matches!(a.role.as_str(), "colour" | "depth" | "stencil" | "depth_stencil"),
                }
            })
            .collect();
        let bandwidth = pass_bandwidth(&costs, covered, raw.samples_passed);
        Counters {
            draws: raw.draws,
            vertex_invocations: raw.vertex_invocations,
            clipping_primitives: raw.clipping_primitives,
            fragment_invocations: raw.fragment_invocations,
            fragments_per_pixel: raw.fragment_invocations.map(|f| f as f64 / pixels as f64),
            samples_passed: raw.samples_passed,
            overdraw: raw.samples_passed as f64 / (pixels * samples.max(1) as u64) as f64,
            gpu_ms: raw.gpu_ns.map(|ns| ns.max(0.0) / 1e6),
            bytes_loaded: attachments.iter().map(|a| a.bytes_loaded).sum(),
            bytes_stored: attachments.iter().map(|a| a.bytes_stored).sum(),
            tiler_bytes: bandwidth.tiler_bytes,
            immediate_bytes: bandwidth.immediate_bytes,
        }
    }

    /// The pass's bytes on a tiler and an immediate-mode GPU.
    pub fn bandwidth(&self) -> Bandwidth {
        Bandwidth { tiler_bytes: self.tiler_bytes, immediate_bytes: self.immediate_bytes }
    }

    /// Where the draw count and the statistics cannot both be true, why: draws with no
    /// invocation at all (nothing in them, or a GPU that skipped them), or invocations with no
    /// draw seen (a draw command the layer did not see). A pass that neither draws nor shades
    /// (a clear) agrees.
    pub fn disagreement(&self) -> Option<String> {
        let shaded = [self.vertex_invocations, self.fragment_invocations].into_iter().flatten().sum::<u64>()
            + self.samples_passed;
        let known = self.vertex_invocations.is_some() || self.fragment_invocations.is_some();
        if self.draws > 0 && known && shaded == 0 {
            return Some(format!(
                "{} draws, but no vertex or fragment shader invocation and no sample passed",
                self.draws
            ));
        }
        if self.draws == 0 && shaded > 0 {
            return Some("vertex or fragment shader invocations with no draw seen".into());
        }
        None
    }
}

/// Mean, min and max of one render pass over the frames that had it at the same position with
/// the same key.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AggregateRow {
    /// Position in the frame, from 0.
    pub position: u32,
    /// Render area and attachment formats/ops: what makes two frames' passes "the same pass".
    pub key: String,
    /// Frames that had this pass measured.
    pub frames: u64,
    /// The label of the last frame's pass at this position.
    pub label: Option<String>,
    pub mean: Counters<f64>,
    pub min: Counters,
    pub max: Counters,
    /// The pass's sections (see [`RenderPassRow::sections`]), each over the frames that had it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<AggregateSection>,
}

/// Mean, min and max of one section of an aggregated pass: the same position in the pass and
/// the same label.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AggregateSection {
    /// Position among the pass's section rows, from 0.
    pub index: u32,
    pub label: Option<String>,
    pub frames: u64,
    pub mean: Counters<f64>,
    pub min: Counters,
    pub max: Counters,
}

impl RenderPassRow {
    /// Render area and attachment formats/ops, e.g.
    /// "500x500 colour B8G8R8A8_UNORM CLEAR/STORE, depth D16_UNORM CLEAR/DONT_CARE".
    pub fn key(&self) -> String {
        let attachments: Vec<String> = self
            .attachments
            .iter()
            .map(|a| {
                let stencil = match (&a.stencil_load_op, &a.stencil_store_op) {
                    (Some(l), Some(s)) => format!(" stencil {l}/{s}"),
                    _ => String::new(),
                };
                let samples = if a.samples > 1 { format!(" x{}", a.samples) } else { String::new() };
                format!("{} {}{samples} {}/{}{stencil}", a.role, a.format, a.load_op, a.store_op)
            })
            .collect();
        format!("{}x{} {}", self.render_area.width, self.render_area.height, attachments.join(", "))
    }
}

impl FillrateReport {
    /// Reads a result file's text; a wrong schema is named.
    pub fn from_json(text: &str) -> Result<Self, String> {
        let report: FillrateReport =
            serde_json::from_str(text).map_err(|e| format!("not a nostencil fill-rate result: {e}"))?;
        if report.schema != FILLRATE_SCHEMA {
            return Err(format!("fill-rate result has schema '{}', expected '{FILLRATE_SCHEMA}'", report.schema));
        }
        Ok(report)
    }

    /// The last frame kept, if any.
    pub fn last_frame(&self) -> Option<&FrameRows> {
        self.frames.last()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counters(draws: u64, vertices: Option<u64>, fragments: Option<u64>, samples: u64) -> Counters {
        let raw = RawCounters {
            draws,
            vertex_invocations: vertices,
            clipping_primitives: None,
            fragment_invocations: fragments,
            samples_passed: samples,
            gpu_ns: None,
        };
        Counters::new(&raw, &RenderArea { x: 0, y: 0, width: 4, height: 4 }, 1, &[])
    }

    #[test]
    fn draws_and_statistics_that_disagree_are_flagged_and_a_clear_pass_is_not() {
        assert!(counters(3, Some(0), Some(0), 0).disagreement().is_some_and(|f| f.starts_with("3 draws")));
        assert!(counters(0, Some(6), Some(16), 16).disagreement().is_some_and(|f| f.contains("no draw seen")));
        assert_eq!(counters(0, Some(0), Some(0), 0).disagreement(), None, "a clear-only pass");
        assert_eq!(counters(2, Some(6), Some(20), 16).disagreement(), None);
        // Without statistics, draws with no sample are not called empty: nothing says so.
        assert_eq!(counters(2, None, None, 0).disagreement(), None);
    }
}
