//! The page of `profile` (nostencil's own frame) and of `bench`: the same page as
//! `profile-app`'s, from this crate's reports.

use super::charts::{short, stacked_bars, Series};
use super::page::{BudgetBanner, Page, Row, Section};
use crate::profile::bench::BenchReport;
use crate::profile::budget::BudgetFigure;
use crate::profile::report::ProfileReport;

/// What the profile page shows besides the report.
pub struct ProfileExtras<'a> {
    pub budget: Option<(&'a str, &'a [BudgetFigure])>,
    /// The overdraw heat map of the frame (PNG).
    pub heatmap: Option<Vec<u8>>,
    /// The technique's own lines (`profile`'s table prints them under the passes).
    pub technique_lines: String,
    pub json: String,
}

fn banner(budget: Option<(&str, &[BudgetFigure])>) -> Option<BudgetBanner> {
    budget.map(|(file, figures)| BudgetBanner {
        file: file.to_owned(),
        over: figures.iter().filter(|f| f.over()).map(|f| f.to_string()).collect(),
    })
}

pub fn profile_page(report: &ProfileReport, extras: ProfileExtras<'_>) -> Page {
    let figures: &[BudgetFigure] = extras.budget.map_or(&[], |(_, f)| f);
    // Bars numbered as the table's first column: pass names are too long to stand under them.
    let names: Vec<String> = (0..report.passes.len()).map(|i| format!("#{i}")).collect();
    let one = |name: &str, value: &dyn Fn(usize) -> f64| {
        vec![Series { name: name.to_owned(), values: (0..report.passes.len()).map(value).collect() }]
    };
    let p = &report.passes;
    let svgs = vec![
        stacked_bars("GPU time", "ms per pass", &names, &one("GPU ms", &|i| p[i].gpu_ms)),
        stacked_bars(
            "Fragments per pixel",
            "fragment shader invocations / pixels",
            &names,
            &one("fragments / pixel", &|i| p[i].fragments_per_pixel.unwrap_or(0.0)),
        ),
        stacked_bars(
            "Samples passed per pixel",
            "samples passed / (pixels x samples)",
            &names,
            &one("samples / pixel", &|i| p[i].samples_per_pixel),
        ),
        stacked_bars(
            "Bytes",
            "a tile-based GPU's and an immediate-mode GPU's",
            &names,
            &[
                Series { name: "tiler".into(), values: p.iter().map(|p| p.bandwidth.tiler_bytes as f64).collect() },
                Series {
                    name: "immediate-mode".into(),
                    values: p.iter().map(|p| p.bandwidth.immediate_bytes as f64).collect(),
                },
            ],
        ),
    ];
    let rows = report
        .passes
        .iter()
        .enumerate()
        .map(|(i, pass)| {
            let mine: Vec<&BudgetFigure> = figures.iter().filter(|f| f.pass == pass.name).collect();
            Row {
                cells: vec![
                    format!("#{i} {}", pass.name),
                    pass.draws.to_string(),
                    pass.fragment_invocations.map_or("n/a".into(), |f| f.to_string()),
                    pass.fragments_per_pixel.map_or("n/a".into(), |f| format!("{f:.3}")),
                    pass.samples_passed.to_string(),
                    format!("{:.3}", pass.samples_per_pixel),
                    format!("{:.3}", pass.gpu_ms),
                    short(pass.bandwidth.tiler_bytes as f64),
                    mine.iter().map(|f| f.brief()).collect::<Vec<_>>().join("; "),
                ],
                over: mine.iter().any(|f| f.over()),
            }
        })
        .collect();
    let traffic = report
        .render_passes
        .iter()
        .flat_map(|rp| {
            rp.attachments.iter().map(move |a| {
                Row::new(vec![
                    format!(
                        "{} ({}x{}{})",
                        rp.pass,
                        rp.width,
                        rp.height,
                        if rp.count > 1 { format!(" x{}", rp.count) } else { String::new() }
                    ),
                    a.attachment.to_owned(),
                    a.format.clone(),
                    format!("{}", a.samples),
                    a.load_op.clone(),
                    a.store_op.clone(),
                    short(a.bytes_loaded as f64),
                    short(a.bytes_stored as f64),
                ])
            })
        })
        .collect();
    let mut sections = vec![
        Section::Charts { title: "The frame's passes".into(), svgs },
        Section::Table {
            title: "Passes".into(),
            note: Some("One frame, after a first that compiles the shaders (docs/profiling.md).".into()),
            header: [
                "pass",
                "draws",
                "fragments",
                "fragments/px",
                "samples passed",
                "samples/px",
                "GPU ms",
                "tiler B",
                "budget",
            ]
            .iter()
            .map(|h| (*h).to_owned())
            .collect(),
            rows,
        },
        Section::Table {
            title: "Render passes: load and store ops".into(),
            note: Some(
                "Tile traffic as a tile-based GPU would move it: LOAD loads and STORE stores the render area.".into(),
            ),
            header: ["render pass", "attachment", "format", "samples", "load", "store", "loaded B", "stored B"]
                .iter()
                .map(|h| (*h).to_owned())
                .collect(),
            rows: traffic,
        },
    ];
    if let Some(png) = extras.heatmap {
        sections.push(Section::Image {
            title: "Overdraw heat map".into(),
            caption: "Fragments shaded per pixel over the whole frame: blue few, red many (docs/profiling.md).".into(),
            png,
        });
    }
    let lines: Vec<String> = extras.technique_lines.lines().map(str::to_owned).collect();
    if !lines.is_empty() {
        sections.push(Section::Lines { title: format!("{}: its own figures", report.technique), lines });
    }
    Page {
        title: format!("nostencil profile: {} ({}) on {}", report.technique, report.stencil, report.scene),
        facts: vec![
            ("scene".into(), report.scene.clone()),
            ("technique".into(), format!("{} ({})", report.technique, report.stencil)),
            ("device".into(), report.device.clone()),
            ("frame".into(), format!("{}x{} at {}x", report.width, report.height, report.samples)),
            ("frames measured".into(), "1".into()),
        ],
        budget: banner(extras.budget),
        neutral: "No budget checked (--budget FILE checks one)".into(),
        sections,
        json: extras.json,
    }
}

/// `bench`'s page: each variant's frame time with its interval and its ratio to the first.
pub fn bench_page(report: &BenchReport, json: String) -> Page {
    let names: Vec<String> = report.variants.iter().map(|v| v.name.clone()).collect();
    let series = |name: &str, values: Vec<f64>| vec![Series { name: name.into(), values }];
    let svgs = vec![
        stacked_bars(
            "Frame time",
            "median ms (record, submit, wait, read back)",
            &names,
            &series("frame ms", report.variants.iter().map(|v| v.frame_ms.median).collect()),
        ),
        stacked_bars(
            "Ratio to the first",
            "median over rounds of (variant / first) frame time",
            &names,
            &series("ratio", report.variants.iter().map(|v| v.frame_ratio.map_or(0.0, |r| r.median)).collect()),
        ),
    ];
    let rows = report
        .variants
        .iter()
        .map(|v| {
            Row::new(vec![
                v.name.clone(),
                format!("{:.3} [{:.3}-{:.3}]", v.frame_ms.median, v.frame_ms.min, v.frame_ms.max),
                format!("{:.3}", v.gpu_ms.median),
                v.frame_ratio.map_or("n/a".into(), |r| r.brief()),
                v.gpu_ratio.map_or("n/a".into(), |r| r.brief()),
                v.fragment_invocations.map_or("n/a".into(), |f| f.to_string()),
            ])
        })
        .collect();
    Page {
        title: format!("nostencil bench: {} on {}", report.technique, report.scene),
        facts: vec![
            ("technique".into(), report.technique.clone()),
            ("scene".into(), report.scene.clone()),
            ("device".into(), report.device.clone()),
            ("frame".into(), format!("{}x{} at {}x", report.width, report.height, report.samples)),
            ("rounds".into(), format!("{} timed after {} warm-up, {}", report.runs, report.warmup, report.order)),
        ],
        budget: None,
        neutral: format!("Benchmark: {} variants timed round-robin, ratios to the first", report.variants.len()),
        sections: vec![
            Section::Charts { title: "Variants".into(), svgs },
            Section::Table {
                title: "Variants, timed round-robin".into(),
                note: Some("Frame ms: median [min-max]. Ratios: median over rounds [95% bootstrap interval].".into()),
                header: ["variant", "frame ms", "GPU ms", "frame ratio", "GPU ratio", "fragments"]
                    .iter()
                    .map(|h| (*h).to_owned())
                    .collect(),
                rows,
            },
        ],
        json,
    }
}
