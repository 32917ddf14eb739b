//! Frame benchmarks: several variants of one technique measured in one run, after warm-up
//! (llvmpipe compiles shaders at their first draw), reported as medians with their spread and
//! as ratios to the first variant (the reference).

use std::fmt::Write as _;
use std::time::Instant;

use serde::Serialize;

use crate::error::Result;
use crate::render::FrameOutput;

pub struct Variant<'a> {
    pub name: String,
    pub frame: Box<dyn FnMut() -> Result<FrameOutput> + 'a>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    fn of(mut values: Vec<f64>) -> Self {
        values.sort_by(f64::total_cmp);
        let n = values.len();
        let median = if n == 0 {
            0.0
        } else if n % 2 == 1 {
            values[n / 2]
        } else {
            (values[n / 2 - 1] + values[n / 2]) / 2.0
        };
        Spread { median, min: values.first().copied().unwrap_or(0.0), max: values.last().copied().unwrap_or(0.0) }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct VariantResult {
    pub name: String,
    /// Wall-clock time of a whole frame (record, submit, wait, read back), ms.
    pub frame_ms: Spread,
    /// Sum of the passes' GPU timestamps, ms.
    pub gpu_ms: Spread,
    /// Fragment shader invocations of the frame (deterministic).
    pub fragment_invocations: Option<u64>,
    /// Samples passed over all passes (deterministic).
    pub samples_passed: u64,
    pub passes: usize,
    /// Median frame time / the reference's.
    pub frame_ratio: f64,
    pub gpu_ratio: f64,
    pub fragment_ratio: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub schema: &'static str,
    pub device: String,
    pub technique: String,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub warmup: u32,
    pub runs: u32,
    pub variants: Vec<VariantResult>,
}

/// The `bench: variant  done/total` line on stderr (drawn only on a terminal), or nothing.
fn progress_bar(shown: bool, total: u64) -> indicatif::ProgressBar {
    if !shown {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    if let Ok(style) = indicatif::ProgressStyle::with_template("bench: {msg:<28} {pos:>4}/{len}") {
        bar.set_style(style);
    }
    bar
}

pub struct BenchSettings {
    pub warmup: u32,
    pub runs: u32,
    /// Print a progress line on stderr.
    pub progress: bool,
}

/// Runs every variant `warmup + runs` times, interleaving nothing: each variant's runs follow
/// its own warm-up, so caches are warm for the variant being measured.
pub fn run(variants: Vec<Variant>, settings: &BenchSettings) -> Result<Vec<VariantResult>> {
    let mut results: Vec<VariantResult> = Vec::new();
    let total = variants.len() as u64 * (settings.warmup + settings.runs) as u64;
    let progress = progress_bar(settings.progress, total);
    for mut variant in variants {
        progress.set_message(variant.name.clone());
        let (mut frame_ms, mut gpu_ms) = (Vec::new(), Vec::new());
        let mut last = None;
        for i in 0..settings.warmup + settings.runs {
            let start = Instant::now();
            // An error replaces the progress line rather than continuing it.
            let output = (variant.frame)().inspect_err(|_| progress.finish_and_clear())?;
            let elapsed = start.elapsed().as_secs_f64() * 1e3;
            if i >= settings.warmup {
                frame_ms.push(elapsed);
                gpu_ms.push(output.counters.total_gpu_ms());
            }
            last = Some(output);
            progress.inc(1);
        }
        let counters = last.map(|o| o.counters);
        results.push(VariantResult {
            name: variant.name,
            frame_ms: Spread::of(frame_ms),
            gpu_ms: Spread::of(gpu_ms),
            fragment_invocations: counters.as_ref().and_then(|c| c.total_fragment_invocations()),
            samples_passed: counters.as_ref().map_or(0, |c| c.total_samples_passed()),
            passes: counters.as_ref().map_or(0, |c| c.passes.len()),
            frame_ratio: 1.0,
            gpu_ratio: 1.0,
            fragment_ratio: None,
        });
    }
    progress.finish();
    if let Some(reference) = results.first().cloned() {
        for r in &mut results {
            r.frame_ratio = r.frame_ms.median / reference.frame_ms.median;
            r.gpu_ratio = r.gpu_ms.median / reference.gpu_ms.median;
            r.fragment_ratio =
                r.fragment_invocations.zip(reference.fragment_invocations).map(|(a, b)| a as f64 / b as f64);
        }
    }
    Ok(results)
}

impl BenchReport {
    pub fn table(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{} | {} on scene {} | {}x{} | {} warm-up + {} runs per variant",
            self.device, self.technique, self.scene, self.width, self.height, self.warmup, self.runs
        );
        let name_width = self.variants.iter().map(|v| v.name.len()).max().unwrap_or(0).max("variant".len());
        let _ = writeln!(
            out,
            "{:<name_width$} {:>7} {:>22} {:>9} {:>13} {:>12} {:>8} {:>8} {:>8}",
            "variant", "passes", "frame ms (min-max)", "GPU ms", "fragments", "samples", "frame x", "GPU x", "frag x"
        );
        for v in &self.variants {
            let _ = writeln!(
                out,
                "{:<name_width$} {:>7} {:>9.2} ({:>5.2}-{:>5.2}) {:>9.2} {:>13} {:>12} {:>8.2} {:>8.2} {:>8}",
                v.name,
                v.passes,
                v.frame_ms.median,
                v.frame_ms.min,
                v.frame_ms.max,
                v.gpu_ms.median,
                v.fragment_invocations.map_or("n/a".into(), |f| f.to_string()),
                v.samples_passed,
                v.frame_ratio,
                v.gpu_ratio,
                v.fragment_ratio.map_or("n/a".into(), |r| format!("{r:.2}")),
            );
        }
        if let Some(first) = self.variants.first() {
            let _ = writeln!(out, "ratios are to the first row ({}), taken in this run", first.name);
        }
        out
    }
}
