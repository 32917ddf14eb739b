//! The profile report: a per-pass table for people, JSON (versioned schema) and CSV for programs.

use std::fmt::Write as _;

use serde::Serialize;

use super::text_table::aligned_lines;
use crate::frame::bandwidth::Bandwidth;
use crate::frame::render_pass::RenderPassTraffic;
use crate::render::instances::{RenderPassInstance, RenderPassSums};
use crate::render::FrameCounters;

/// Version of the JSON layout; bump on any incompatible change (documented in docs/command-line.md).
pub const PROFILE_SCHEMA: &str = "nostencil-profile/2";

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReportFormat {
    Table,
    Json,
    Csv,
}

#[derive(Debug, Clone, Serialize)]
pub struct PassRow {
    pub name: String,
    pub draws: u32,
    /// State and draw commands it recorded (`PassCounters::commands`).
    pub commands: u32,
    pub vertex_invocations: Option<u64>,
    pub clipping_primitives: Option<u64>,
    pub fragment_invocations: Option<u64>,
    /// Fragment shader invocations / (width x height).
    pub fragments_per_pixel: Option<f64>,
    pub samples_passed: u64,
    /// Samples per pixel of the target the pass drew into (the frame's; 1 for a prepass).
    pub samples: u32,
    /// Samples passed / (width x height x samples): the pass's cost in full-screen writes, the
    /// same figure at any sample count.
    pub samples_per_pixel: f64,
    pub gpu_ms: f64,
    /// This pass's share of the frame's GPU time, 0..1.
    pub share: f64,
    /// The render pass instances its draws went into (indices into `render_pass_instances`).
    pub render_pass_instances: Vec<u32>,
    /// Its part of the frame's bytes (`FrameCounters::pass_bandwidths`): its draws' bytes, and
    /// in the first pass of a group of instances the group's loads, stores, clears and resolves.
    #[serde(flatten)]
    pub bandwidth: Bandwidth,
}

#[derive(Debug, Clone, Serialize)]
pub struct Totals {
    pub draws: u32,
    /// State and draw commands the measured passes recorded.
    pub commands: u32,
    pub fragment_invocations: Option<u64>,
    pub fragments_per_pixel: Option<f64>,
    pub samples_passed: u64,
    /// Samples passed / (width x height x samples) over all passes.
    pub overdraw: f64,
    pub gpu_ms: f64,
    /// The frame's bytes to and from memory on a tiler and an immediate-mode GPU
    /// (frame/bandwidth.rs, after Mesa turnip's model).
    #[serde(flatten)]
    pub bandwidth: Bandwidth,
}

#[derive(Debug, Clone, Serialize)]
pub struct ProfileReport {
    pub schema: &'static str,
    pub device: String,
    pub scene: String,
    pub technique: String,
    pub stencil: String,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the frame (`--samples`).
    pub samples: u32,
    /// The frame's attachment formats (the colour is sRGB-encoded, its alpha linear).
    pub frame_formats: FrameFormats,
    pub passes: Vec<PassRow>,
    pub totals: Totals,
    /// Bytes a tile-based GPU loads/stores per attachment, for every render pass the frame
    /// began: the prepasses' own targets under the pass that drew them, then "frame".
    pub render_passes: Vec<RenderPassTraffic>,
    /// Every render pass instance the frame began, in submission order, with the measured
    /// passes that drew into it.
    pub render_pass_instances: Vec<RenderPassInstance>,
    /// The passes' counters summed per render pass instance (consecutive instances together
    /// where one measured pass began them all): what a tool bracketing each render pass
    /// instance with queries of its own measures (`nostencil profile-app`).
    pub render_pass_sums: Vec<RenderPassSums>,
    /// What the technique reports beyond counters (for shadow volumes: method, capacity,
    /// saturated samples), or null.
    pub technique_stats: Option<serde_json::Value>,
}

pub struct ReportContext {
    pub device: String,
    pub scene: String,
    pub technique: String,
    pub stencil: String,
    pub frame_formats: FrameFormats,
}

/// Vulkan format names of the frame's attachments.
#[derive(Debug, Clone, Serialize)]
pub struct FrameFormats {
    pub colour: String,
    pub depth: String,
}

impl ProfileReport {
    pub fn new(context: ReportContext, counters: &FrameCounters) -> Self {
        let pixels = counters.pixels() as f64;
        let total_ms = counters.total_gpu_ms();
        let passes = counters
            .passes
            .iter()
            .zip(counters.pass_bandwidths())
            .map(|(p, bandwidth)| PassRow {
                name: p.name.clone(),
                draws: p.draws,
                commands: p.commands,
                vertex_invocations: p.vertex_invocations,
                clipping_primitives: p.clipping_primitives,
                fragment_invocations: p.fragment_invocations,
                fragments_per_pixel: p.fragment_invocations.map(|f| f as f64 / pixels),
                samples_passed: p.samples_passed,
                samples: counters.pass_samples(p),
                samples_per_pixel: counters.samples_per_pixel(p),
                gpu_ms: p.gpu_ms,
                share: if total_ms > 0.0 { p.gpu_ms / total_ms } else { 0.0 },
                render_pass_instances: p.render_pass_instances.clone(),
                bandwidth,
            })
            .collect();
        let fragments = counters.total_fragment_invocations();
        ProfileReport {
            schema: PROFILE_SCHEMA,
            device: context.device,
            scene: context.scene,
            technique: context.technique,
            stencil: context.stencil,
            width: counters.width,
            height: counters.height,
            samples: counters.samples,
            frame_formats: context.frame_formats,
            passes,
            totals: Totals {
                draws: counters.passes.iter().map(|p| p.draws).sum(),
                commands: counters.passes.iter().map(|p| p.commands).sum(),
                fragment_invocations: fragments,
                fragments_per_pixel: fragments.map(|f| f as f64 / pixels),
                samples_passed: counters.total_samples_passed(),
                overdraw: counters.overdraw(),
                gpu_ms: total_ms,
                bandwidth: counters.bandwidth(),
            },
            render_passes: counters.render_passes.clone(),
            render_pass_instances: counters.render_pass_instances.clone(),
            render_pass_sums: counters.render_pass_sums(),
            technique_stats: None,
        }
    }

    pub fn render(&self, format: ReportFormat) -> String {
        match format {
            ReportFormat::Table => self.table(),
            ReportFormat::Json => {
                serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
            }
            ReportFormat::Csv => self.csv(),
        }
    }

    fn table(&self) -> String {
        let opt = |v: Option<u64>| v.map_or("n/a".to_owned(), |v| v.to_string());
        let optf = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.3}"));
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{} | scene {} | technique {} | stencil {} | {}x{} | {}x MSAA | colour {} depth {}",
            self.device,
            self.scene,
            self.technique,
            self.stencil,
            self.width,
            self.height,
            self.samples,
            self.frame_formats.colour,
            self.frame_formats.depth
        );
        let header = [
            "pass",
            "draws",
            "vertices",
            "primitives",
            "fragments",
            "frag/px",
            "samples",
            "samples/px",
            "GPU ms",
            "share",
        ];
        let mut rows: Vec<[String; 10]> = self
            .passes
            .iter()
            .map(|p| {
                [
                    p.name.clone(),
                    p.draws.to_string(),
                    opt(p.vertex_invocations),
                    opt(p.clipping_primitives),
                    opt(p.fragment_invocations),
                    optf(p.fragments_per_pixel),
                    p.samples_passed.to_string(),
                    format!("{:.3}", p.samples_per_pixel),
                    format!("{:.3}", p.gpu_ms),
                    format!("{:.1}%", p.share * 100.0),
                ]
            })
            .collect();
        let t = &self.totals;
        rows.push([
            "frame".into(),
            t.draws.to_string(),
            String::new(),
            String::new(),
            opt(t.fragment_invocations),
            optf(t.fragments_per_pixel),
            t.samples_passed.to_string(),
            format!("{:.3}", t.overdraw),
            format!("{:.3}", t.gpu_ms),
            "100%".into(),
        ]);
        let lines = aligned_lines(&header, &rows);
        let _ = writeln!(out, "{}", lines[0]);
        for (i, line) in lines[1..].iter().enumerate() {
            // A rule above the last row, the frame's totals.
            if i + 1 == rows.len() {
                let _ = writeln!(out, "{}", "-".repeat(lines[0].len()));
            }
            let _ = writeln!(out, "{line}");
        }
        let _ = writeln!(
            out,
            "\ntile memory traffic per render pass (from its load/store ops: what a tile-based GPU moves\n\
             between tile memory and main memory):"
        );
        let name_width =
            self.render_passes.iter().flat_map(|rp| &rp.attachments).map(|a| a.attachment.len()).max().unwrap_or(0);
        for rp in &self.render_passes {
            let times = if rp.count > 1 { format!(" x {}", rp.count) } else { String::new() };
            let _ = writeln!(out, "  {} ({}x{}{times})", rp.pass, rp.width, rp.height);
            for a in &rp.attachments {
                let _ = writeln!(
                    out,
                    "    {:<name_width$} {:<20} {:>2} samples  load {:<9} store {:<9} loaded {:>10} B  stored {:>10} B{}",
                    a.attachment,
                    a.format,
                    a.samples,
                    a.load_op,
                    a.store_op,
                    a.bytes_loaded * rp.count as u64,
                    a.bytes_stored * rp.count as u64,
                    if a.transient { "  (transient)" } else { "" }
                );
            }
        }
        let (loaded, stored) =
            self.render_passes.iter().fold((0, 0), |(l, s), rp| (l + rp.bytes_loaded(), s + rp.bytes_stored()));
        let _ = writeln!(out, "  frame total: loaded {loaded} B, stored {stored} B");
        self.instance_table(&mut out);
        let bandwidth = self.totals.bandwidth;
        let _ = writeln!(
            out,
            "\nframe bandwidth estimate: tiler {} B, immediate-mode {} B (Mesa turnip's model: loads,\n\
             stores and resolves on a tiler; clears, resolves and every passing sample read and written\n\
             on an immediate-mode GPU; docs/profiling.md)",
            bandwidth.tiler_bytes, bandwidth.immediate_bytes
        );
        let _ = writeln!(
            out,
            "\nfragments = fragment shader invocations (pipeline statistics; on lavapipe 16 per 4x4 block a\n\
             triangle touches, depth-rejected blocks included); samples = samples passing depth/stencil\n\
             (precise occlusion query, exact, every sample counted); samples/px = samples / (W x H x N) at\n\
             N samples per pixel, the same figure at any N; samples/px of the frame = overdraw."
        );
        out
    }

    /// The counters per render pass instance, as a layer around each instance sees them.
    fn instance_table(&self, out: &mut String) {
        let _ = writeln!(out, "\nper render pass instance, in submission order (the passes' counters summed):");
        for sum in &self.render_pass_sums {
            let span = if sum.count > 1 {
                format!("#{}..#{}", sum.first, sum.first + sum.count - 1)
            } else {
                format!("#{}", sum.first)
            };
            let size = self
                .render_pass_instances
                .get(sum.first as usize)
                .map_or(String::new(), |i| format!(" {}x{} {}x", i.width, i.height, i.samples));
            let fragments = sum.fragment_invocations.map_or("n/a".to_owned(), |f| f.to_string());
            let _ = writeln!(
                out,
                "  {span}{size}  draws {}  samples {}  fragments {}  tiler {} B  immediate {} B  ({})",
                sum.draws,
                sum.samples_passed,
                fragments,
                sum.bandwidth.tiler_bytes,
                sum.bandwidth.immediate_bytes,
                sum.passes.join(", ")
            );
        }
    }

    /// One row per measured pass. `render_pass_instances` lists the instances its draws went
    /// into (space-separated); `tiler_bytes` and `immediate_bytes` are its part of the frame's
    /// bytes, so that each column sums to the frame's (`PassRow::bandwidth`).
    fn csv(&self) -> String {
        let opt = |v: Option<u64>| v.map_or(String::new(), |v| v.to_string());
        let optf = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.6}"));
        let mut out = format!("{CSV_HEADER}\n");
        for p in &self.passes {
            let instances: Vec<String> = p.render_pass_instances.iter().map(u32::to_string).collect();
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{},{:.6},{:.6},{:.6},{},{},{}",
                csv_field(&p.name),
                p.draws,
                opt(p.vertex_invocations),
                opt(p.clipping_primitives),
                opt(p.fragment_invocations),
                optf(p.fragments_per_pixel),
                p.samples_passed,
                p.samples_per_pixel,
                p.gpu_ms,
                p.share,
                instances.join(" "),
                p.bandwidth.tiler_bytes,
                p.bandwidth.immediate_bytes
            );
        }
        out
    }
}

/// The CSV's columns (docs/profiling.md says what the last three mean).
pub const CSV_HEADER: &str = "pass,draws,vertex_invocations,clipping_primitives,fragment_invocations,\
fragments_per_pixel,samples_passed,samples_per_pixel,gpu_ms,share,render_pass_instances,tiler_bytes,immediate_bytes";

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}
