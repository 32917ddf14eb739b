//! Frame benchmarks: several variants of one technique measured in one run. After warm-up
//! (llvmpipe compiles shaders at their first draw) the variants take turns, one frame each per
//! round (A B C D, A B C D, ...), so drift of the machine (clock, caches, the other processes on
//! it) lands on every variant alike. Each variant is reported by its medians with their spread and
//! by the median of its per-round ratios to the first variant (the reference), with a bootstrap
//! confidence interval.

use std::fmt::Write as _;
use std::time::Instant;

use serde::Serialize;

use super::bootstrap::{median, Bootstrap, Interval};
use crate::error::Result;
use crate::render::{FrameCounters, FrameOutput};

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
    fn of(values: &[f64]) -> Self {
        let (min, max) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        match median(values) {
            Some(median) => Spread { median, min, max },
            None => Spread { median: 0.0, min: 0.0, max: 0.0 },
        }
    }
}

/// A variant's time relative to the reference: the median over the rounds of (this variant's
/// time / the reference's time in the same round), and that median's bootstrap interval.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Ratio {
    pub median: f64,
    pub ci95: Interval,
}

impl Ratio {
    /// Rounds where the reference's time is not positive (no GPU timestamps) are left out;
    /// `None` when none is left.
    pub fn per_round(times: &[f64], reference: &[f64], bootstrap: &Bootstrap) -> Option<Ratio> {
        let ratios: Vec<f64> = times.iter().zip(reference).filter(|(_, &r)| r > 0.0).map(|(&t, &r)| t / r).collect();
        Some(Ratio { median: median(&ratios)?, ci95: bootstrap.median_interval(&ratios)? })
    }

    /// `1.02 [0.99-1.05]`.
    pub fn brief(&self) -> String {
        format!("{:.2} [{:.2}-{:.2}]", self.median, self.ci95.low, self.ci95.high)
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
    /// Frame time relative to the reference, round by round (1 for the reference itself).
    pub frame_ratio: Option<Ratio>,
    /// GPU time relative to the reference, round by round.
    pub gpu_ratio: Option<Ratio>,
    pub fragment_ratio: Option<f64>,
    /// The timed frames in round order, ms: the ratios can be recomputed from them.
    pub frame_ms_rounds: Vec<f64>,
    pub gpu_ms_rounds: Vec<f64>,
}

/// One variant at N samples per pixel against the same variant at one sample, measured in the
/// same rounds: `bench --samples N` (N > 1) runs every variant at both counts, side by side.
#[derive(Debug, Clone, Serialize)]
pub struct MsaaRatio {
    /// The variant's label, without its sample count.
    pub variant: String,
    pub samples: u32,
    /// Frame time at N / at 1, round by round (median and bootstrap interval).
    pub frame_ratio: Option<Ratio>,
    pub gpu_ratio: Option<Ratio>,
    /// Fragment shader invocations at N / at 1 (deterministic).
    pub fragment_ratio: Option<f64>,
    /// Samples passed at N / at 1 (deterministic; N for a frame whose draws cover whole pixels).
    pub samples_passed_ratio: Option<f64>,
}

impl MsaaRatio {
    /// `multi` is the variant's result at `samples` samples, `single` at one, from one run.
    pub fn of(
        variant: &str,
        samples: u32,
        multi: &VariantResult,
        single: &VariantResult,
        bootstrap: &Bootstrap,
    ) -> Self {
        let quotient = |a: u64, b: u64| (b > 0).then(|| a as f64 / b as f64);
        MsaaRatio {
            variant: variant.to_owned(),
            samples,
            frame_ratio: Ratio::per_round(&multi.frame_ms_rounds, &single.frame_ms_rounds, bootstrap),
            gpu_ratio: Ratio::per_round(&multi.gpu_ms_rounds, &single.gpu_ms_rounds, bootstrap),
            fragment_ratio: multi
                .fragment_invocations
                .zip(single.fragment_invocations)
                .and_then(|(a, b)| quotient(a, b)),
            samples_passed_ratio: quotient(multi.samples_passed, single.samples_passed),
        }
    }
}

/// The label of `variant` at `samples` samples per pixel, as `bench --samples N` lists it.
pub fn label_at(variant: &str, samples: u32) -> String {
    format!("{variant} @{samples}x")
}

#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub schema: &'static str,
    pub device: String,
    pub technique: String,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// `--samples`: the variants' sample count (each also runs at 1 when it is more).
    pub samples: u32,
    pub warmup: u32,
    pub runs: u32,
    /// How the variants were ordered: `round-robin` (one frame of each per round).
    pub order: &'static str,
    /// How the ratios' intervals were drawn.
    pub bootstrap: Bootstrap,
    pub variants: Vec<VariantResult>,
    /// With `--samples N` > 1: each variant at N against itself at 1 (else empty).
    pub msaa: Vec<MsaaRatio>,
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

/// Timed rounds when `--runs` is not given: at 1280x720 on a 2-core machine shared with other
/// work, 150 rounds kept the 95% interval of the shadow-volume subpass ratio within +-4% of its
/// median (measured: docs/profiling.md, Benchmarks), in about 40 s.
pub const DEFAULT_RUNS: u32 = 150;

pub struct BenchSettings {
    /// Rounds rendered and discarded before timing.
    pub warmup: u32,
    /// Timed rounds.
    pub runs: u32,
    /// Print a progress line on stderr.
    pub progress: bool,
}

/// Calls `frame(v)` for each of `variants` once per round, in order (0 1 2 .. 0 1 2 ..): first
/// `warmup` rounds whose results are dropped, then `runs` rounds returned as `[round][variant]`.
fn round_robin<T>(
    variants: usize,
    warmup: u32,
    runs: u32,
    mut frame: impl FnMut(usize) -> Result<T>,
) -> Result<Vec<Vec<T>>> {
    let mut rounds = Vec::with_capacity(runs as usize);
    for round in 0..warmup + runs {
        let results = (0..variants).map(&mut frame).collect::<Result<Vec<T>>>()?;
        if round >= warmup {
            rounds.push(results);
        }
    }
    Ok(rounds)
}

/// One timed frame.
#[derive(Debug, Clone, Copy)]
struct Timing {
    frame_ms: f64,
    gpu_ms: f64,
}

/// Runs `warmup + runs` rounds of the variants, round-robin, and summarises each variant; the
/// first variant is the reference of the ratios.
pub fn run(variants: Vec<Variant>, settings: &BenchSettings) -> Result<Vec<VariantResult>> {
    run_traced(variants, settings, None)
}

/// [`run`], each frame (warm-up ones too) also put on `trace`'s timeline (`bench --trace`) at
/// the time it began.
pub fn run_traced(
    mut variants: Vec<Variant>,
    settings: &BenchSettings,
    mut trace: Option<&mut crate::profile::trace::Trace>,
) -> Result<Vec<VariantResult>> {
    let count = variants.len();
    let origin = Instant::now();
    let mut traced = 0u64;
    let progress = progress_bar(settings.progress, count as u64 * u64::from(settings.warmup + settings.runs));
    let mut last: Vec<Option<FrameCounters>> = vec![None; count];
    let rounds = round_robin(count, settings.warmup, settings.runs, |v| {
        progress.set_message(variants[v].name.clone());
        let start = Instant::now();
        // An error replaces the progress line rather than continuing it.
        let output = (variants[v].frame)().inspect_err(|_| progress.finish_and_clear())?;
        let frame_ms = start.elapsed().as_secs_f64() * 1e3;
        let gpu_ms = output.counters.total_gpu_ms();
        if let Some(trace) = trace.as_deref_mut() {
            let at = start.duration_since(origin).as_secs_f64() * 1e6;
            trace.own_frame(&variants[v].name, traced, at, &output.counters);
            traced += 1;
        }
        last[v] = Some(output.counters);
        progress.inc(1);
        Ok(Timing { frame_ms, gpu_ms })
    })?;
    progress.finish();
    Ok(summarise(variants.drain(..).map(|v| v.name).zip(last).collect(), &rounds, &Bootstrap::DEFAULT))
}

/// Each variant's spreads, counters and per-round ratios to variant 0, from the timed rounds.
fn summarise(
    variants: Vec<(String, Option<FrameCounters>)>,
    rounds: &[Vec<Timing>],
    bootstrap: &Bootstrap,
) -> Vec<VariantResult> {
    let series = |v: usize, of: fn(&Timing) -> f64| rounds.iter().map(|round| of(&round[v])).collect::<Vec<f64>>();
    let (reference_frame, reference_gpu) = (series(0, |t| t.frame_ms), series(0, |t| t.gpu_ms));
    let reference_fragments = variants.first().and_then(|(_, c)| c.as_ref()?.total_fragment_invocations());
    variants
        .into_iter()
        .enumerate()
        .map(|(v, (name, counters))| {
            let (frame_ms, gpu_ms) = (series(v, |t| t.frame_ms), series(v, |t| t.gpu_ms));
            let fragment_invocations = counters.as_ref().and_then(|c| c.total_fragment_invocations());
            VariantResult {
                name,
                frame_ms: Spread::of(&frame_ms),
                gpu_ms: Spread::of(&gpu_ms),
                fragment_invocations,
                samples_passed: counters.as_ref().map_or(0, |c| c.total_samples_passed()),
                passes: counters.as_ref().map_or(0, |c| c.passes.len()),
                frame_ratio: Ratio::per_round(&frame_ms, &reference_frame, bootstrap),
                gpu_ratio: Ratio::per_round(&gpu_ms, &reference_gpu, bootstrap),
                fragment_ratio: fragment_invocations.zip(reference_fragments).map(|(a, b)| a as f64 / b as f64),
                frame_ms_rounds: frame_ms,
                gpu_ms_rounds: gpu_ms,
            }
        })
        .collect()
}

impl BenchReport {
    pub fn table(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{} | {} on scene {} | {}x{} | {} warm-up + {} timed rounds, one frame of each variant per round",
            self.device, self.technique, self.scene, self.width, self.height, self.warmup, self.runs
        );
        let name_width = self.variants.iter().map(|v| v.name.len()).max().unwrap_or(0).max("variant".len());
        let _ = writeln!(
            out,
            "{:<name_width$} {:>7} {:>22} {:>9} {:>13} {:>12} {:>19} {:>8} {:>8}",
            "variant",
            "passes",
            "frame ms (min-max)",
            "GPU ms",
            "fragments",
            "samples",
            "frame x [95% CI]",
            "GPU x",
            "frag x"
        );
        let ratio = |r: &Option<Ratio>, brief: bool| match r {
            Some(r) if brief => r.brief(),
            Some(r) => format!("{:.2}", r.median),
            None => "n/a".into(),
        };
        for v in &self.variants {
            let _ = writeln!(
                out,
                "{:<name_width$} {:>7} {:>9.2} ({:>5.2}-{:>5.2}) {:>9.2} {:>13} {:>12} {:>19} {:>8} {:>8}",
                v.name,
                v.passes,
                v.frame_ms.median,
                v.frame_ms.min,
                v.frame_ms.max,
                v.gpu_ms.median,
                v.fragment_invocations.map_or("n/a".into(), |f| f.to_string()),
                v.samples_passed,
                ratio(&v.frame_ratio, true),
                ratio(&v.gpu_ratio, false),
                v.fragment_ratio.map_or("n/a".into(), |r| format!("{r:.2}")),
            );
        }
        if let Some(first) = self.variants.first() {
            let _ = writeln!(
                out,
                "frame x, GPU x: median over the rounds of each round's time / the first row's ({}) in the same round;\n\
                 [95% CI]: percentile bootstrap of that median ({} resamples of the {} rounds, seed {:#x})",
                first.name, self.bootstrap.resamples, self.runs, self.bootstrap.seed
            );
        }
        if !self.msaa.is_empty() {
            out += &self.msaa_table();
        }
        out
    }

    /// The `--samples N` section: each variant at N samples over itself at one.
    fn msaa_table(&self) -> String {
        let mut out = String::new();
        let name_width = self.msaa.iter().map(|m| m.variant.len()).max().unwrap_or(0).max("variant".len());
        let n = self.msaa.first().map_or(0, |m| m.samples);
        let _ = writeln!(
            out,
            "
{n}x / 1x, the same variant in the same rounds:"
        );
        let _ = writeln!(
            out,
            "{:<name_width$} {:>19} {:>8} {:>11} {:>10}",
            "variant", "frame x [95% CI]", "GPU x", "fragments x", "samples x"
        );
        let value = |v: Option<f64>| v.map_or("n/a".into(), |v| format!("{v:.2}"));
        for m in &self.msaa {
            let _ = writeln!(
                out,
                "{:<name_width$} {:>19} {:>8} {:>11} {:>10}",
                m.variant,
                m.frame_ratio.map_or("n/a".into(), |r| r.brief()),
                value(m.gpu_ratio.map(|r| r.median)),
                value(m.fragment_ratio),
                value(m.samples_passed_ratio),
            );
        }
        let _ = writeln!(
            out,
            "frame x, GPU x: median over the rounds of (time at {n}x / time at 1x in the same round); fragments x,\n\
             samples x: fragment shader invocations and samples passed at {n}x over 1x (samples count every sample)"
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variants_take_turns_after_the_warm_up() {
        let mut seen = Vec::new();
        let rounds = round_robin(4, 2, 3, |v| {
            seen.push(b"ABCD"[v] as char);
            Ok(seen.len())
        })
        .unwrap();
        assert_eq!(seen.iter().collect::<String>(), "ABCD".repeat(5));
        // The two warm-up rounds (calls 1..=8) are dropped; the timed rounds keep variant order.
        assert_eq!(rounds, vec![vec![9, 10, 11, 12], vec![13, 14, 15, 16], vec![17, 18, 19, 20]]);
    }

    #[test]
    fn an_error_stops_the_rounds() {
        let mut calls = 0;
        let result = round_robin(3, 1, 4, |v| {
            calls += 1;
            if calls == 5 {
                Err(crate::error::Error::InvalidInput(format!("variant {v} failed")))
            } else {
                Ok(())
            }
        });
        assert!(result.is_err());
        assert_eq!(calls, 5);
    }

    /// A machine that slows down over the run: every frame costs `base * drift(round)`.
    fn drifting_rounds(bases: &[f64], rounds: usize) -> Vec<Vec<Timing>> {
        (0..rounds)
            .map(|r| {
                let drift = 1.0 + r as f64 * 0.05 + if r % 7 == 3 { 0.8 } else { 0.0 };
                bases.iter().map(|b| Timing { frame_ms: b * drift, gpu_ms: b * drift * 0.5 }).collect()
            })
            .collect()
    }

    #[test]
    fn per_round_ratios_cancel_drift_that_hits_every_variant() {
        let rounds = drifting_rounds(&[10.0, 9.0, 12.5], 40);
        let names = ["ref", "fast", "slow"].map(|n| (n.to_string(), None)).to_vec();
        let results = summarise(names, &rounds, &Bootstrap::DEFAULT);
        for (result, expected) in results.iter().zip([1.0, 0.9, 1.25]) {
            let ratio = result.frame_ratio.unwrap();
            assert!((ratio.median - expected).abs() < 1e-12, "{}: {ratio:?}", result.name);
            assert!(ratio.ci95.width() < 1e-12, "{}: drift widened the interval: {ratio:?}", result.name);
            assert!((result.gpu_ratio.unwrap().median - expected).abs() < 1e-12);
        }
        // The drift is in the times themselves: their spread is wide.
        assert!(results[0].frame_ms.max > 2.5 * results[0].frame_ms.min);
        assert_eq!(results[1].frame_ms_rounds.len(), 40);
    }

    #[test]
    fn ratio_interval_holds_the_median_of_noisy_rounds() {
        // The variant is 0.95x the reference with +-10 % noise of its own in each round.
        let mut rounds = drifting_rounds(&[20.0, 19.0], 61);
        for (r, round) in rounds.iter_mut().enumerate() {
            round[1].frame_ms *= 1.0 + 0.1 * ((r as f64 * 2.399).sin());
        }
        let names = vec![("ref".to_string(), None), ("variant".to_string(), None)];
        let ratio = summarise(names, &rounds, &Bootstrap::DEFAULT)[1].frame_ratio.unwrap();
        assert!(ratio.ci95.contains(ratio.median), "{ratio:?}");
        assert!(ratio.ci95.contains(0.95), "{ratio:?}");
        assert!(ratio.ci95.width() > 0.0 && ratio.ci95.width() < 0.1, "{ratio:?}");
    }

    #[test]
    fn msaa_ratios_pair_a_variant_with_itself_at_one_sample_round_by_round() {
        // The 4x variant costs 2.5x its 1x twin in every round, whatever the drift.
        let rounds = drifting_rounds(&[7.0, 10.0, 4.0], 30);
        let names = ["other", "x @4x", "x @1x"].map(|n| (n.to_string(), None)).to_vec();
        let mut results = summarise(names, &rounds, &Bootstrap::DEFAULT);
        (results[1].fragment_invocations, results[1].samples_passed) = (Some(1200), 4000);
        (results[2].fragment_invocations, results[2].samples_passed) = (Some(1000), 1000);
        let ratio = MsaaRatio::of("x", 4, &results[1], &results[2], &Bootstrap::DEFAULT);
        let frame = ratio.frame_ratio.unwrap();
        assert!((frame.median - 2.5).abs() < 1e-12 && frame.ci95.width() < 1e-12, "{frame:?}");
        assert!((ratio.gpu_ratio.unwrap().median - 2.5).abs() < 1e-12);
        assert_eq!((ratio.fragment_ratio, ratio.samples_passed_ratio), (Some(1.2), Some(4.0)));
        assert_eq!(label_at("x", 4), "x @4x");
    }

    #[test]
    fn a_reference_without_gpu_time_gives_no_gpu_ratio() {
        let rounds = vec![vec![Timing { frame_ms: 2.0, gpu_ms: 0.0 }, Timing { frame_ms: 3.0, gpu_ms: 1.0 }]; 5];
        let names = vec![("ref".to_string(), None), ("variant".to_string(), None)];
        let results = summarise(names, &rounds, &Bootstrap::DEFAULT);
        assert!(results[1].gpu_ratio.is_none());
        assert_eq!(results[1].frame_ratio.unwrap().median, 1.5);
    }
}
