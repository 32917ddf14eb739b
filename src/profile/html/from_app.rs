//! The page of a `profile-app` run: the fill-rate layer's report of any program, its budget's
//! verdict, the tiler check's findings with advice, the captured frame and the top draws.

use nostencil_fillrate_report::report::{FillrateReport, FrameRows, RenderPassRow};
use nostencil_fillrate_report::tiler::TilerFlag;

use super::charts::{short, stacked_bars, Series};
use super::page::{BudgetBanner, Finding, Page, Row, Section};
use crate::profile::budget::{application_pass_name, BudgetFigure};

/// What the page shows besides the report.
pub struct AppExtras<'a> {
    /// The budget file and every figure it was compared on (None: no budget).
    pub budget: Option<(&'a str, &'a [BudgetFigure])>,
    /// The captured frame (`--capture`): its index and PNG.
    pub capture: Option<(u64, Vec<u8>)>,
    /// The report as `--format json` prints it.
    pub json: String,
}

/// One sentence of advice per tiler-check finding, as Arm's Frame Advisor gives it.
pub fn advice(kind: &str) -> &'static str {
    match kind {
        "dont_care_load_read" => "Load the attachment (LOAD or CLEAR) if the pass needs its old contents; a tiler's DONT_CARE is garbage.",
        "multisampled_stored" => "Store the multisampled attachment DONT_CARE and resolve it in the pass with a resolve attachment.",
        "resolve_outside_pass" => "Resolve in the pass (a resolve attachment) instead of vkCmdResolveImage, so only one sample leaves tile memory.",
        "transient_outside_pass" => "Use the transient image only as an attachment inside its pass, or drop TRANSIENT_ATTACHMENT.",
        "stored_then_overwritten" => "Store this attachment DONT_CARE (or invalidate it): nothing reads it before it is replaced.",
        "stored_never_read" => "Store this attachment DONT_CARE and make it transient: nothing reads it.",
        "dead_pass" => "Remove the pass, or read what it draws: none of its outputs is used.",
        "load_after_dont_care" => "Store the attachment in the pass that draws it, or clear it in the pass that loads it.",
        "full_frame_copy_to_swapchain" => "Render the last pass into the swapchain image instead of copying a finished frame into it.",
        "clear_then_load" => "Clear the attachment with LOAD_OP_CLEAR in the pass instead of vkCmdClear*Image before it.",
        "redundant_clear" => "Drop the vkCmdClear*Image: the pass clears or discards the attachment anyway.",
        "attachment_loaded" => "Use LOAD_OP_CLEAR or DONT_CARE unless the pass needs the old contents (a partial update does).",
        _ => "See docs/fillrate-layer.md, \"The tiler check\".",
    }
}

fn pass_name(position: u32, label: &Option<String>) -> String {
    match label {
        Some(label) => format!("#{position} '{label}'"),
        None => format!("#{position}"),
    }
}

/// The tiler check's findings, each with its place and advice.
pub fn findings(flags: &[TilerFlag]) -> Vec<Finding> {
    flags
        .iter()
        .map(|f| {
            let mut place = format!("frame {} pass {}", f.frame, pass_name(f.pass, &f.label));
            if let Some(work) = f.work {
                place = format!("frame {} work row #{work}", f.frame);
            }
            if let Some(attachment) = &f.attachment {
                place.push_str(&format!(", {attachment}"));
            }
            let times = if f.count > 1 { format!(" ({} times)", f.count) } else { String::new() };
            Finding { place, what: format!("{}: {}{times}", f.kind, f.detail), advice: advice(&f.kind).to_owned() }
        })
        .collect()
}

/// The charts over the kept frames: one bar per frame, its render passes (and work rows)
/// stacked by position.
fn frame_charts(frames: &[FrameRows]) -> Vec<String> {
    let bars: Vec<String> = frames.iter().map(|f| f.index.to_string()).collect();
    let positions = frames.iter().map(|f| f.render_passes.len()).max().unwrap_or(0);
    let work_positions = frames.iter().map(|f| f.work.len()).max().unwrap_or(0);
    let pass_series = |value: &dyn Fn(&RenderPassRow) -> Option<f64>| -> Vec<Series> {
        (0..positions)
            .map(|p| Series {
                name: frames
                    .iter()
                    .find_map(|f| f.render_passes.get(p))
                    .map_or(format!("render pass #{p}"), |r| format!("render pass {}", pass_name(p as u32, &r.label))),
                values: frames.iter().map(|f| f.render_passes.get(p).and_then(value).unwrap_or(0.0)).collect(),
            })
            .collect()
    };
    let mut gpu = pass_series(&|r| r.counters.and_then(|c| c.gpu_ms));
    gpu.extend((0..work_positions).map(|w| {
        Series {
            name: frames
                .iter()
                .find_map(|f| f.work.get(w))
                .map_or(format!("work #{w}"), |r| format!("{} #{w} {}", r.kind, r.api)),
            values: frames.iter().map(|f| f.work.get(w).and_then(|r| r.counters?.gpu_ms).unwrap_or(0.0)).collect(),
        }
    }));
    let fragments = pass_series(&|r| r.counters.and_then(|c| c.fragments_per_pixel));
    let samples = pass_series(&|r| r.counters.map(|c| c.samples_passed as f64));
    let tiler = pass_series(&|r| r.counters.map(|c| c.tiler_bytes as f64));
    let immediate = pass_series(&|r| r.counters.map(|c| c.immediate_bytes as f64));
    vec![
        stacked_bars("GPU time", "ms per frame, render passes then compute and transfers", &bars, &gpu),
        stacked_bars("Fragments per pixel", "fragment shader invocations / pixels of each pass", &bars, &fragments),
        stacked_bars("Samples passed", "per frame (exact)", &bars, &samples),
        stacked_bars("Tiler bytes", "a tile-based GPU's loads, stores, resolves", &bars, &tiler),
        stacked_bars(
            "Immediate-mode bytes",
            "clears, resolves, every passing sample read and written",
            &bars,
            &immediate,
        ),
    ]
}

/// The per-pass table (the aggregate over the measured frames), each pass's budget margin.
fn pass_table(report: &FillrateReport, figures: &[BudgetFigure]) -> Section {
    let header = [
        "pass",
        "frames",
        "draws",
        "fragments/px",
        "samples passed",
        "overdraw",
        "GPU ms",
        "tiler B",
        "immediate B",
        "budget",
    ];
    let rows = report
        .aggregate
        .iter()
        .map(|a| {
            let name = pass_name(a.position, &a.label);
            let budgeted = application_pass_name(a.position, a.label.as_deref());
            let mine: Vec<&BudgetFigure> = figures.iter().filter(|f| f.pass == budgeted).collect();
            let over = mine.iter().any(|f| f.over());
            let margin = if mine.is_empty() {
                String::new()
            } else {
                mine.iter().map(|f| f.brief()).collect::<Vec<_>>().join("; ")
            };
            let opt = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.3}"));
            Row {
                cells: vec![
                    name,
                    a.frames.to_string(),
                    format!("{:.1}", a.mean.draws),
                    opt(a.mean.fragments_per_pixel),
                    short(a.mean.samples_passed),
                    format!("{:.3}", a.mean.overdraw),
                    opt(a.mean.gpu_ms),
                    short(a.mean.tiler_bytes),
                    short(a.mean.immediate_bytes),
                    margin,
                ],
                over,
            }
        })
        .collect();
    Section::Table {
        title: "Render passes".into(),
        note: Some("Means over the measured frames, passes matched by position, area and attachments (docs/fillrate-layer.md).".into()),
        header: header.iter().map(|h| (*h).to_owned()).collect(),
        rows,
    }
}

/// The draws that shaded the most fragments, over the kept frames (`--per-draw`).
fn top_draws(frames: &[FrameRows]) -> Option<Section> {
    let mut draws: Vec<(u64, u32, usize, u64, u64, Option<f64>)> = frames
        .iter()
        .flat_map(|f| {
            f.render_passes.iter().flat_map(move |p| {
                p.per_draw.iter().enumerate().map(move |(i, d)| {
                    (f.index, p.index, i, d.fragment_invocations.unwrap_or(0), d.samples_passed, d.gpu_ms)
                })
            })
        })
        .collect();
    if draws.is_empty() {
        return None;
    }
    draws.sort_by_key(|d| std::cmp::Reverse(d.3));
    let rows = draws
        .iter()
        .take(12)
        .map(|(frame, pass, draw, fragments, samples, ms)| {
            Row::new(vec![
                frame.to_string(),
                format!("#{pass}"),
                draw.to_string(),
                fragments.to_string(),
                samples.to_string(),
                ms.map_or("n/a".into(), |m| format!("{m:.3}")),
            ])
        })
        .collect();
    Some(Section::Table {
        title: "Top draws by fragments".into(),
        note: Some("Each draw command measured alone (--per-draw).".into()),
        header: ["frame", "pass", "draw", "fragments", "samples passed", "GPU ms"]
            .iter()
            .map(|h| (*h).to_owned())
            .collect(),
        rows,
    })
}

pub fn page(report: &FillrateReport, extras: AppExtras<'_>) -> Page {
    let figures: &[BudgetFigure] = extras.budget.map_or(&[], |(_, f)| f);
    let area = report
        .frames
        .iter()
        .flat_map(|f| &f.render_passes)
        .map(|p| (p.render_area.width, p.render_area.height))
        .max_by_key(|(w, h)| *w as u64 * *h as u64)
        .map_or("n/a".to_owned(), |(w, h)| format!("{w}x{h}"));
    let mut facts = vec![
        ("program".to_owned(), report.application.clone()),
        ("device".to_owned(), report.device.clone()),
        ("largest render area".to_owned(), area),
        ("frames measured".to_owned(), report.frames_measured.to_string()),
    ];
    if let Some(run) = &report.run {
        facts.push(("run".to_owned(), run.detail.clone()));
    }
    let mut sections = vec![
        Section::Charts {
            title: format!("The last {} frames", report.frames.len()),
            svgs: frame_charts(&report.frames),
        },
        pass_table(report, figures),
    ];
    let other: Vec<Row> = figures
        .iter()
        .filter(|f| !report.aggregate.iter().any(|a| f.pass == application_pass_name(a.position, a.label.as_deref())))
        .map(|f| Row { cells: vec![f.pass.clone(), f.brief()], over: f.over() })
        .collect();
    if !other.is_empty() {
        sections.push(Section::Table {
            title: "Work and frame budgets".into(),
            note: None,
            header: vec!["what".into(), "against the budget".into()],
            rows: other,
        });
    }
    if let Some(check) = &report.tiler_check {
        sections.push(Section::Findings {
            title: "Tiler check".into(),
            note: check.reads_unknown.as_ref().map(|why| format!("Some reads could not be followed ({why}).")),
            findings: findings(&check.flags),
        });
    }
    if let Some((frame, png)) = extras.capture {
        sections.push(Section::Image {
            title: "Captured frame".into(),
            caption: format!("The image presented at the end of frame {frame} (--capture)."),
            png,
        });
    }
    sections.extend(top_draws(&report.frames));
    let mut notes: Vec<String> =
        report.not_measured.iter().map(|n| format!("not measured: {} x {}", n.count, n.what)).collect();
    notes.extend(report.hidden_extensions.iter().map(|h| format!("hidden from the program: {}: {}", h.name, h.why)));
    notes.extend(report.frames.iter().flat_map(|f| {
        f.render_passes
            .iter()
            .filter_map(move |p| Some(format!("frame {} pass #{}: {}", f.index, p.index, p.flag.as_ref()?)))
    }));
    if !notes.is_empty() {
        sections.push(Section::Lines { title: "Not measured, hidden and flagged".into(), lines: notes });
    }
    Page {
        title: format!("nostencil profile-app: {}", report.application),
        facts,
        budget: extras.budget.map(|(file, figures)| BudgetBanner {
            file: file.to_owned(),
            over: figures.iter().filter(|f| f.over()).map(|f| f.to_string()).collect(),
        }),
        neutral: "No budget checked (--budget FILE checks one)".into(),
        sections,
        json: extras.json,
    }
}
