//! `nostencil bench`: frames timed in one run, round-robin (one frame of each variant per
//! round): one technique's variants, every technique in turn (`--technique all`), or several
//! techniques side by side (`--technique shadow-volume,shadow-map`), each rendered as the rest
//! of the command line asks, its ratios taken to the first listed.

use std::path::Path;
use std::sync::Arc;

use super::args::FrameArgs;
use super::frame_setup::{load_scene, open_gpu, options, print_warnings};
use super::output_path::check_output_path;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::profile::bench::{self, BenchReport, BenchSettings, Variant};
use crate::profile::table1;
use crate::scene::Scene;
use crate::technique::{by_name, RenderOptions, TECHNIQUES};

/// The files `bench` writes besides its table or JSON.
#[derive(Clone, Copy, Default)]
pub struct BenchOutputs<'a> {
    /// The frames on a timeline (`--trace`).
    pub trace: Option<&'a Path>,
    /// The run's page (`--html`).
    pub html: Option<&'a Path>,
}

/// What `bench` times and how it reports it.
struct Timed<'a> {
    /// The report's `technique` field: one name, or the list as given.
    technique: String,
    /// (label, options) per variant, before the 1-sample twins `--samples N` adds.
    variants: Vec<(String, RenderOptions)>,
    samples: u32,
    warmup: u32,
    runs: u32,
    json: bool,
    outputs: BenchOutputs<'a>,
}

pub(super) fn bench(
    frame: &FrameArgs,
    warmup: u32,
    runs: Option<u32>,
    json: bool,
    table1_out: Option<&Path>,
    outputs: BenchOutputs<'_>,
) -> Result<()> {
    if runs == Some(0) {
        return Err(Error::InvalidInput("--runs must be at least 1".into()));
    }
    if frame.shadow_volume.saturation_probe {
        return Err(Error::InvalidInput(
            "--saturation-probe is a diagnostic pass and is never timed: use it with render or profile".into(),
        ));
    }
    if frame.technique == "all" {
        if json {
            return Err(Error::InvalidInput("--json takes one technique; run bench once per technique".into()));
        }
        for technique in TECHNIQUES {
            let one = FrameArgs { technique: technique.name().to_owned(), ..frame.clone() };
            // Only the technique with a paper table records it.
            bench(
                &one,
                warmup,
                runs,
                false,
                table1_out.filter(|_| table1::covers(*technique)),
                BenchOutputs::default(),
            )?;
            println!();
        }
        return Ok(());
    }
    if frame.technique.contains(',') {
        if table1_out.is_some() {
            return Err(Error::InvalidInput(
                "--table1-out records one technique's paper table: give one --technique".into(),
            ));
        }
        return bench_techniques(frame, warmup, runs, json, outputs);
    }
    let options = options(frame)?;
    if table1_out.is_some() && !table1::covers(options.technique) {
        return Err(Error::InvalidInput(format!(
            "--table1-out records seed 004's Table 1: use it with --technique shadow-texture-atlas or shadow-map, not {}",
            options.technique.name()
        )));
    }
    for path in [outputs.trace, outputs.html].into_iter().flatten() {
        check_output_path(path)?;
    }
    if let Some(dir) = table1_out {
        // Made (or refused) before minutes of timing, not after.
        std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_owned(), source })?;
    }
    let scene = load_scene(frame)?;
    let gpu = open_gpu(&frame.gpu)?;
    if table1::covers(options.technique) {
        // Seed 004's Table 1: both techniques, fixed and moving light, on its two scenes.
        let runs = runs.unwrap_or(table1::DEFAULT_RUNS);
        return table1::bench(&gpu, &options, warmup, runs, json, table1_out);
    }
    let variants = options.technique.bench_variants(&options).into_iter().map(|v| (v.label, v.options)).collect();
    let timed = Timed {
        technique: options.technique.name().into(),
        variants,
        samples: options.samples,
        warmup,
        runs: runs.unwrap_or(bench::DEFAULT_RUNS),
        json,
        outputs,
    };
    time_variants(&gpu, &scene, timed)
}

/// `--technique A,B,...`: each technique as the command line renders it, one variant each,
/// interleaved; every ratio is to A.
fn bench_techniques(
    frame: &FrameArgs,
    warmup: u32,
    runs: Option<u32>,
    json: bool,
    outputs: BenchOutputs<'_>,
) -> Result<()> {
    let names: Vec<&str> = frame.technique.split(',').map(str::trim).collect();
    let mut variants = Vec::new();
    for (index, name) in names.iter().enumerate() {
        if name.is_empty() || *name == "all" || names[..index].contains(name) {
            return Err(Error::InvalidInput(format!(
                "--technique {}: a list names each technique once, without `all` (e.g. shadow-volume,shadow-map)",
                frame.technique
            )));
        }
        let technique = by_name(name)?;
        let one = FrameArgs { technique: (*name).to_owned(), ..frame.clone() };
        variants.push((technique.name().to_owned(), options(&one)?));
    }
    for path in [outputs.trace, outputs.html].into_iter().flatten() {
        check_output_path(path)?;
    }
    let scene = load_scene(frame)?;
    let gpu = open_gpu(&frame.gpu)?;
    let samples = frame.samples;
    let timed = Timed {
        technique: names.join(","),
        variants,
        samples,
        warmup,
        runs: runs.unwrap_or(bench::DEFAULT_RUNS),
        json,
        outputs,
    };
    time_variants(&gpu, &scene, timed)
}

/// Builds a renderer per variant (and its 1-sample twin at N > 1), times them round-robin and
/// prints the table or JSON.
fn time_variants(gpu: &Arc<Gpu>, scene: &Scene, timed: Timed) -> Result<()> {
    let Timed { technique, variants: listed, samples, warmup, runs, json, outputs } = timed;
    let trace_path = outputs.trace;
    // At N > 1 samples each variant also runs at 1, next to it in every round.
    let mut paired = Vec::new();
    for (label, options) in &listed {
        if samples > 1 {
            let single = RenderOptions { samples: 1, ..options.clone() };
            paired.push((bench::label_at(label, samples), options.clone()));
            paired.push((bench::label_at(label, 1), single));
        } else {
            paired.push((label.clone(), options.clone()));
        }
    }
    let mut variants = Vec::new();
    let mut warned: Vec<&str> = Vec::new();
    for (label, options) in paired {
        let mut renderer = options.technique.build(gpu, scene, &options)?;
        // Every variant of a technique draws the same scene: its warnings once.
        if !warned.contains(&options.technique.name()) {
            print_warnings(options.technique.name(), renderer.warnings());
            warned.push(options.technique.name());
        }
        variants.push(Variant { name: label, frame: Box::new(move || Ok(renderer.frame_with(scene)?.output)) });
    }
    let process = format!("nostencil bench: {technique} on {}", scene.name);
    let mut trace = trace_path.map(|_| crate::profile::trace::Trace::new(&process, true));
    let results = bench::run_traced(variants, &BenchSettings { warmup, runs, progress: !json }, trace.as_mut())?;
    if let (Some(trace), Some(path)) = (&trace, trace_path) {
        trace.write(path)?;
        eprintln!("wrote {}", path.display());
    }
    let bootstrap = crate::profile::bootstrap::Bootstrap::DEFAULT;
    let msaa = if samples > 1 {
        listed
            .iter()
            .zip(results.chunks_exact(2))
            .map(|((label, _), pair)| bench::MsaaRatio::of(label, samples, &pair[0], &pair[1], &bootstrap))
            .collect()
    } else {
        Vec::new()
    };
    let (width, height) = listed.first().map_or((0, 0), |(_, o)| (o.width, o.height));
    let report = BenchReport {
        schema: "nostencil-bench/2",
        order: "round-robin",
        bootstrap,
        device: gpu.device.info.name.clone(),
        technique,
        scene: scene.name.clone(),
        width,
        height,
        samples,
        warmup,
        runs,
        variants: results,
        msaa,
    };
    let json_text = serde_json::to_string_pretty(&report).map_err(|e| Error::Internal(e.to_string()))?;
    if json {
        println!("{json_text}");
    } else {
        print!("{}", report.table());
    }
    if let Some(path) = outputs.html {
        crate::profile::html::from_profile::bench_page(&report, json_text).write(path)?;
    }
    Ok(())
}
