//! The result file: JSON (the report types), CSV (one line per render pass of every kept frame,
//! then the aggregate's mean/min/max lines) or a table like `nostencil profile`'s. Written
//! atomically: a temp file beside the target, then a rename.

use std::fmt::Write as _;
use std::path::Path;

use crate::report::{Counters, FillrateReport, RenderPassRow, SectionRow, WorkCounters};
use crate::text_table::aligned_lines;
use crate::tiler::TilerReport;

/// Output format of the result file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    Json,
    Csv,
    Table,
}

pub fn render(report: &FillrateReport, format: OutputFormat) -> String {
    match format {
        OutputFormat::Json => {
            serde_json::to_string_pretty(report).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
        }
        OutputFormat::Csv => csv(report),
        OutputFormat::Table => table(report),
    }
}

/// Writes `bytes` under a temporary name in the same folder, then renames it to `path`, so a
/// reader never sees half a file and a failure leaves none behind (the temporary file is
/// removed). The one writer of every output file: reports here, and the renderer's PNGs.
pub fn write_atomically(path: &Path, bytes: impl AsRef<[u8]>) -> std::io::Result<()> {
    let temp = temporary_sibling(path);
    let written = (|| {
        let mut file = std::fs::File::create(&temp)?;
        std::io::Write::write_all(&mut file, bytes.as_ref())?;
        file.sync_all()?;
        std::fs::rename(&temp, path)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    written
}

/// A hidden name beside `path` that no other process writing the same file uses.
fn temporary_sibling(path: &Path) -> std::path::PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    path.with_file_name(format!(".{name}.{}.partial", std::process::id()))
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

const CSV_HEADER: &str = "frame,index,label,api,x,y,width,height,samples,attachments,draws,vertex_invocations,\
clipping_primitives,fragment_invocations,fragments_per_pixel,samples_passed,overdraw,gpu_ms,bytes_loaded,bytes_stored,\
tiler_bytes,immediate_bytes,not_measured,section,kind,commands,workgroups,compute_invocations,bytes_read,bytes_written";

/// The last columns of a render pass's (or section's) line: its kind, and no work figures.
const CSV_PASS_TAIL: &str = "render_pass,,,,,";

/// A work row's line (work.rs): the pass columns empty but GPU time and the bytes, then the
/// work columns. `frame` is the frame index, or "mean"/"min"/"max" in the aggregate.
fn csv_work_line<N: std::fmt::Display + Copy>(
    frame: &str,
    index: u32,
    (kind, api, label): (&str, &str, Option<&str>),
    counters: Option<&WorkCounters<N>>,
    tiler_bytes: String,
    not_measured: Option<&str>,
) -> String {
    let label = csv_field(label.unwrap_or(""));
    let not_measured = csv_field(not_measured.unwrap_or(""));
    let (gpu_ms, figures) = match counters {
        Some(c) => (
            opt(c.gpu_ms),
            format!(
                "{},{},{},{},{}",
                c.commands,
                opt(c.workgroups),
                opt(c.compute_invocations),
                c.bytes_read,
                c.bytes_written
            ),
        ),
        None => (String::new(), ",,,,".to_owned()),
    };
    format!(
        "{frame},{index},{label},{api},,,,,,,,,,,,,,{gpu_ms},,,{tiler_bytes},{tiler_bytes},{not_measured},,{kind},{figures}"
    )
}

fn opt<T: std::fmt::Display>(value: Option<T>) -> String {
    value.map_or(String::new(), |v| v.to_string())
}

/// The counter columns of a CSV line.
fn csv_counters<N: std::fmt::Display + Copy>(c: &Counters<N>) -> String {
    format!(
        "{},{},{},{},{},{},{},{},{},{},{},{}",
        c.draws,
        opt(c.vertex_invocations),
        opt(c.clipping_primitives),
        opt(c.fragment_invocations),
        opt(c.fragments_per_pixel),
        c.samples_passed,
        c.overdraw,
        opt(c.gpu_ms),
        c.bytes_loaded,
        c.bytes_stored,
        c.tiler_bytes,
        c.immediate_bytes
    )
}

/// A render pass row's first columns (frame to attachments), shared by its sections' rows.
fn csv_row_prefix(frame: u64, row: &RenderPassRow) -> String {
    let a = &row.render_area;
    format!(
        "{frame},{},{},{},{},{},{},{},{},{}",
        row.index,
        csv_field(row.label.as_deref().unwrap_or("")),
        row.api,
        a.x,
        a.y,
        a.width,
        a.height,
        row.samples,
        csv_field(&row.key())
    )
}

fn csv(report: &FillrateReport) -> String {
    let mut out = format!("{CSV_HEADER}\n");
    for frame in &report.frames {
        for row in &frame.render_passes {
            let prefix = csv_row_prefix(frame.index, row);
            let counters = row.counters.as_ref().map_or(",,,,,,,,,,,".to_owned(), csv_counters);
            let not_measured = csv_field(row.not_measured.as_deref().unwrap_or(""));
            let _ = writeln!(out, "{prefix},{counters},{not_measured},,{CSV_PASS_TAIL}");
            // A section: the pass's columns, its own counters, its label in the section column.
            for section in &row.sections {
                let counters = section.counters.as_ref().map_or(",,,,,,,,,,,".to_owned(), csv_counters);
                let not_measured = csv_field(section.not_measured.as_deref().unwrap_or(""));
                let name = csv_field(&section_name(section.label.as_deref()));
                let _ = writeln!(out, "{prefix},{counters},{not_measured},{name},{CSV_PASS_TAIL}");
            }
        }
        for w in &frame.work {
            let bytes = w.counters.map_or(String::new(), |c| c.bandwidth().tiler_bytes.to_string());
            let what = (w.kind.as_str(), w.api.as_str(), w.label.as_deref());
            let line = csv_work_line(
                &frame.index.to_string(),
                w.index,
                what,
                w.counters.as_ref(),
                bytes,
                w.not_measured.as_deref(),
            );
            let _ = writeln!(out, "{line}");
        }
    }
    // The aggregate: "mean"/"min"/"max" in the frame column, the position as index.
    for agg in &report.aggregate {
        let label = csv_field(agg.label.as_deref().unwrap_or(""));
        let key = csv_field(&agg.key);
        let lines =
            [("mean", csv_counters(&agg.mean)), ("min", csv_counters(&agg.min)), ("max", csv_counters(&agg.max))];
        for (what, counters) in lines {
            let _ = writeln!(out, "{what},{},{label},,,,,,,{key},{counters},,,{CSV_PASS_TAIL}", agg.position);
        }
        for section in &agg.sections {
            let name = csv_field(&section_name(section.label.as_deref()));
            let lines = [
                ("mean", csv_counters(&section.mean)),
                ("min", csv_counters(&section.min)),
                ("max", csv_counters(&section.max)),
            ];
            for (what, counters) in lines {
                let _ = writeln!(out, "{what},{},{label},,,,,,,{key},{counters},,{name},{CSV_PASS_TAIL}", agg.position);
            }
        }
    }
    for w in &report.work_aggregate {
        let what = (w.kind.as_str(), w.api.as_str(), w.label.as_deref());
        let mean_bytes = (w.mean.bytes_read + w.mean.bytes_written).to_string();
        let line = |frame: &str, c: &WorkCounters, bytes: u64| {
            csv_work_line(frame, w.position, what, Some(c), bytes.to_string(), None)
        };
        let _ = writeln!(out, "{}", csv_work_line("mean", w.position, what, Some(&w.mean), mean_bytes, None));
        let _ = writeln!(out, "{}", line("min", &w.min, w.min.bandwidth().tiler_bytes));
        let _ = writeln!(out, "{}", line("max", &w.max, w.max.bandwidth().tiler_bytes));
    }
    out
}

/// The tiler check's flags and poisoned attachments, one line each.
pub fn tiler_lines(check: &TilerReport) -> String {
    let mut out = String::new();
    let name = |pass: u32, label: &Option<String>| match label {
        Some(label) => format!("pass #{pass} '{label}'"),
        None => format!("pass #{pass}"),
    };
    let _ = writeln!(out, "\ntiler check: {} flag(s)", check.flags.len());
    for f in &check.flags {
        let attachment = f.attachment.as_deref().map_or(String::new(), |a| format!(" {a}"));
        let times = if f.count > 1 { format!(" (x{})", f.count) } else { String::new() };
        let place = match f.work {
            Some(work) => work_name(work, f.label.as_deref()).replacen('#', "work #", 1),
            None => name(f.pass, &f.label),
        };
        let _ = writeln!(out, "  {}: frame {} {place}{attachment}{times}: {}", f.kind, f.frame, f.detail);
    }
    if let Some(why) = &check.reads_unknown {
        let _ = writeln!(out, "  (reads not all seen: {why}; unread and dead-pass flags are not given)");
    }
    if !check.poisoned.is_empty() {
        let _ = writeln!(out, "filled with the pattern (what a tiler would not keep):");
        for p in &check.poisoned {
            let read = p.read_by.as_deref().map_or("nothing read it".to_owned(), |r| format!("read by {r}"));
            let _ = writeln!(out, "  {} {} {}: {read}", name(p.pass, &p.label), p.attachment, p.when);
        }
    }
    out
}

/// "#2 blur": a work row's name.
fn work_name(index: u32, label: Option<&str>) -> String {
    match label {
        Some(label) => format!("#{index} {label}"),
        None => format!("#{index}"),
    }
}

/// The frame's dispatch groups and transfers, one row each (nothing when it has none).
fn work_table(work: &[crate::report::WorkRow]) -> String {
    if work.is_empty() {
        return String::new();
    }
    let optu = |v: Option<u64>| v.map_or("n/a".to_owned(), |v| v.to_string());
    let header = ["work", "kind", "api", "commands", "workgroups", "invocations", "read B", "written B", "GPU ms"];
    let mut rows = Vec::new();
    for w in work {
        let mut cells = vec![work_name(w.index, w.label.as_deref()), w.kind.clone(), w.api.clone()];
        match &w.counters {
            Some(c) => cells.extend([
                c.commands.to_string(),
                optu(c.workgroups),
                optu(c.compute_invocations),
                c.bytes_read.to_string(),
                c.bytes_written.to_string(),
                c.gpu_ms.map_or("n/a".to_owned(), |v| format!("{v:.3}")),
            ]),
            None => {
                cells.push(format!("not measured: {}", w.not_measured.as_deref().unwrap_or("unknown")));
                cells.extend(vec![String::new(); 5]);
            }
        }
        rows.push(cells);
    }
    let mut out = String::from("\ncompute and transfers outside render passes (bytes: transfers' regions):\n");
    out += &aligned(&header, &rows);
    for w in work.iter().filter(|w| w.note.is_some()) {
        let _ = writeln!(out, "  {}: {}", work_name(w.index, w.label.as_deref()), w.note.as_deref().unwrap_or(""));
    }
    out
}

/// Mean, min and max of each work row over the frames (nothing when there was no work).
fn work_aggregate_table(report: &FillrateReport) -> String {
    if report.work_aggregate.is_empty() {
        return String::new();
    }
    let optu = |v: Option<u64>| v.map_or("n/a".to_owned(), |v| v.to_string());
    let optf = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.3}"));
    let header =
        ["work", "kind", "api", "frames", "invocations mean", "min", "max", "bytes mean", "GPU ms mean", "min", "max"];
    let rows: Vec<Vec<String>> = report
        .work_aggregate
        .iter()
        .map(|w| {
            vec![
                work_name(w.position, w.label.as_deref()),
                w.kind.clone(),
                w.api.clone(),
                w.frames.to_string(),
                w.mean.compute_invocations.map_or("n/a".to_owned(), |v| format!("{v:.1}")),
                optu(w.min.compute_invocations),
                optu(w.max.compute_invocations),
                format!("{:.0}", w.mean.bytes_read + w.mean.bytes_written),
                optf(w.mean.gpu_ms),
                optf(w.min.gpu_ms),
                optf(w.max.gpu_ms),
            ]
        })
        .collect();
    let mut out =
        String::from("\naggregate of the work outside render passes, matched by position, kind, command and label:\n");
    out += &aligned(&header, &rows);
    out
}

/// Left-aligned first column, right-aligned others, two spaces apart.
fn aligned(header: &[&str], rows: &[Vec<String>]) -> String {
    aligned_lines(header, rows).into_iter().map(|line| line + "\n").collect()
}

/// A section's name: its label, or "(unlabelled)" for the draws between labelled sections.
pub fn section_name(label: Option<&str>) -> String {
    label.unwrap_or("(unlabelled)").to_owned()
}

fn pass_name(row: &RenderPassRow) -> String {
    match &row.label {
        Some(label) => format!("#{} {label}", row.index),
        None => format!("#{}", row.index),
    }
}

/// "#3 frame / volumes (alpha, z-pass)": the pass's name, then the section's.
fn section_row_name(row: &RenderPassRow, section: &SectionRow) -> String {
    format!("{} / {}", pass_name(row), section_name(section.label.as_deref()))
}

fn table(report: &FillrateReport) -> String {
    let optu = |v: Option<u64>| v.map_or("n/a".to_owned(), |v| v.to_string());
    let optf = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.3}"));
    let c = report.counters;
    let mut out = format!(
        "{} | {} | {} frame(s) measured | pipeline statistics {} | precise occlusion {} | timestamps {}\n",
        report.application,
        report.device,
        report.frames_measured,
        if c.pipeline_statistics { "yes" } else { "no" },
        if c.occlusion_precise { "yes" } else { "no" },
        if c.timestamps { "yes" } else { "no" },
    );
    if let Some(run) = &report.run {
        let partial = if run.partial { " (partial report: the frames measured before)" } else { "" };
        let _ = writeln!(out, "run: {}{partial}", run.detail);
    }
    if let Some(frame) = report.frames.last() {
        let _ = writeln!(out, "\nframe {} (last measured):", frame.index);
        let header = [
            "pass",
            "api",
            "area",
            "draws",
            "vertices",
            "primitives",
            "fragments",
            "frag/px",
            "samples",
            "overdraw",
            "GPU ms",
            "loaded B",
            "stored B",
            "tiler B",
            "immediate B",
        ];
        let optu2 = optu;
        let cells_of =
            move |name: String, api: String, area: String, counters: Option<&Counters>, why: Option<&str>| {
                let mut cells = vec![name, api, area];
                match counters {
                    Some(c) => cells.extend([
                        c.draws.to_string(),
                        optu2(c.vertex_invocations),
                        optu2(c.clipping_primitives),
                        optu2(c.fragment_invocations),
                        optf(c.fragments_per_pixel),
                        c.samples_passed.to_string(),
                        format!("{:.3}", c.overdraw),
                        optf(c.gpu_ms),
                        c.bytes_loaded.to_string(),
                        c.bytes_stored.to_string(),
                        c.tiler_bytes.to_string(),
                        c.immediate_bytes.to_string(),
                    ]),
                    None => {
                        cells.push(format!("not measured: {}", why.unwrap_or("unknown")));
                        cells.extend(vec![String::new(); 11]);
                    }
                }
                cells
            };
        let mut rows: Vec<Vec<String>> = Vec::new();
        for r in &frame.render_passes {
            let a = &r.render_area;
            let area = format!("{}x{}x{}", a.width, a.height, r.samples);
            rows.push(cells_of(pass_name(r), r.api.clone(), area, r.counters.as_ref(), r.not_measured.as_deref()));
            // Sections under their pass: "#3 frame / volumes (alpha, z-pass)".
            for section in &r.sections {
                let name = section_row_name(r, section);
                let why = section.not_measured.as_deref();
                rows.push(cells_of(name, String::new(), String::new(), section.counters.as_ref(), why));
            }
        }
        out += &aligned(&header, &rows);
        out += &work_table(&frame.work);
        let measured = frame.render_passes.iter().filter_map(|r| r.counters.as_ref());
        let passes: nostencil_tiler::bandwidth::Bandwidth = measured.map(Counters::bandwidth).sum();
        let transfers: nostencil_tiler::bandwidth::Bandwidth =
            frame.work.iter().filter_map(|w| w.counters).map(|c| c.bandwidth()).sum();
        let bytes = passes + transfers;
        let _ = writeln!(
            out,
            "frame bandwidth estimate: tiler {} B, immediate-mode {} B, transfers' {} B included (Mesa turnip's model, docs/fillrate-layer.md)",
            bytes.tiler_bytes, bytes.immediate_bytes, transfers.tiler_bytes
        );
        let _ = writeln!(out, "\nattachments (tile traffic from the load/store ops, over the render area):");
        for r in &frame.render_passes {
            let _ = writeln!(out, "  {}", pass_name(r));
            for a in &r.attachments {
                let stencil = match (&a.stencil_load_op, &a.stencil_store_op) {
                    (Some(l), Some(s)) => format!("  stencil {l}/{s}"),
                    _ => String::new(),
                };
                let _ = writeln!(
                    out,
                    "    {:<13} {:<20} {:>2} samples  load {:<9} store {:<9}{stencil}  loaded {:>10} B  stored {:>10} B",
                    a.role, a.format, a.samples, a.load_op, a.store_op, a.bytes_loaded, a.bytes_stored
                );
            }
        }
    }
    if !report.aggregate.is_empty() {
        let _ = writeln!(
            out,
            "\naggregate over {} frame(s), passes matched by position and attachments:",
            report.frames_measured
        );
        let header = [
            "pass",
            "frames",
            "samples mean",
            "min",
            "max",
            "fragments mean",
            "min",
            "max",
            "GPU ms mean",
            "min",
            "max",
        ];
        let mut rows: Vec<Vec<String>> = Vec::new();
        for a in &report.aggregate {
            let name = match &a.label {
                Some(label) => format!("#{} {label}", a.position),
                None => format!("#{}", a.position),
            };
            let cells = |name: String, frames: u64, mean: &Counters<f64>, min: &Counters, max: &Counters| {
                vec![
                    name,
                    frames.to_string(),
                    format!("{:.1}", mean.samples_passed),
                    min.samples_passed.to_string(),
                    max.samples_passed.to_string(),
                    optf(mean.fragment_invocations),
                    optu(min.fragment_invocations),
                    optu(max.fragment_invocations),
                    optf(mean.gpu_ms),
                    optf(min.gpu_ms),
                    optf(max.gpu_ms),
                ]
            };
            rows.push(cells(name.clone(), a.frames, &a.mean, &a.min, &a.max));
            for s in &a.sections {
                let section = format!("{name} / {}", section_name(s.label.as_deref()));
                rows.push(cells(section, s.frames, &s.mean, &s.min, &s.max));
            }
        }
        out += &aligned(&header, &rows);
        for a in &report.aggregate {
            let _ = writeln!(out, "  #{}: {}", a.position, a.key);
        }
    }
    out += &work_aggregate_table(report);
    if let Some(check) = &report.tiler_check {
        out += &tiler_lines(check);
    }
    let flagged: Vec<_> = report
        .frames
        .iter()
        .flat_map(|f| f.render_passes.iter().filter_map(move |p| Some((f.index, p.index, p.flag.as_ref()?))))
        .collect();
    if !flagged.is_empty() {
        let _ = writeln!(out, "\nflagged (draws and statistics disagree):");
        for (frame, pass, flag) in flagged {
            let _ = writeln!(out, "  frame {frame} pass #{pass}: {flag}");
        }
    }
    if !report.hidden_extensions.is_empty() {
        let _ = writeln!(out, "\nhidden from the program (their commands would record work the layer cannot measure):");
        for h in &report.hidden_extensions {
            let _ = writeln!(out, "  {}: {}", h.name, h.why);
        }
    }
    if !report.not_measured.is_empty() {
        let _ = writeln!(out, "\nnot measured:");
        for n in &report.not_measured {
            let _ = writeln!(out, "  {} x {}", n.count, n.what);
        }
    }
    out
}

#[cfg(test)]
mod tests;
