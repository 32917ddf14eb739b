//! `bench --loop N`: techniques' frames played as a game's loop plays them (an animated scene,
//! frames left on the GPU), with what each frame costs the render thread: its wall time, the part
//! of it spent waiting for the GPU, and the Vulkan objects it made and the waits it made
//! (counted by `Gpu` as they happen: `gpu::live_objects::Activity`). The techniques take turns,
//! a frame each, as `bench`'s variants do, so that the machine's drift lands on all alike.

use std::fmt::Write as _;
use std::time::Instant;

use serde::Serialize;

use super::bench::Ratio;
use super::bootstrap::Bootstrap;
use crate::error::Result;
use crate::gpu::live_objects::{Activity, ObjectKind};
use crate::gpu::Gpu;

/// One technique's loop: `frame(i)` renders its frame `i`.
pub struct LoopVariant<'a> {
    pub name: String,
    pub frame: Box<dyn FnMut(u32) -> Result<()> + 'a>,
}

/// One frame of a loop, as the render thread saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopFrame {
    pub wall_ms: f64,
    /// What the frame made and waited for.
    pub activity: Activity,
}

impl LoopFrame {
    /// Milliseconds the thread worked: the wall time without its waits for the GPU.
    pub fn cpu_ms(&self) -> f64 {
        (self.wall_ms - self.activity.wait_ns as f64 / 1e6).max(0.0)
    }
}

/// What one technique's loop cost, per frame.
#[derive(Debug, Clone, Serialize)]
pub struct LoopResult {
    pub technique: String,
    pub frames: usize,
    /// Frames per second over the timed frames (their wall times summed).
    pub frames_per_second: f64,
    /// Mean wall time of a frame, ms.
    pub frame_ms: f64,
    /// Mean time a frame kept the render thread busy, its waits for the GPU taken out, ms.
    pub cpu_ms: f64,
    /// Mean time a frame waited for the GPU, ms.
    pub wait_ms: f64,
    /// Memory allocations a frame made: gpu-allocator's sub-allocations and dedicated memory.
    pub allocations_per_frame: f64,
    /// Vulkan buffers a frame made.
    pub buffers_per_frame: f64,
    /// Host waits on the GPU a frame made (fences: the frame's own, uploads', presents').
    pub waits_per_frame: f64,
    /// Throughput over the first technique's: the median over the rounds of (the first's frame
    /// time / this one's), with its bootstrap interval (`None` for the first).
    pub throughput_ratio: Option<Ratio>,
}

/// Every technique's loop, the first being the one the ratios are to.
#[derive(Debug, Clone, Serialize)]
pub struct LoopReport {
    pub device: String,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub warmup: u32,
    pub results: Vec<LoopResult>,
}

/// Plays `warmup` then `frames` rounds, one frame of each variant per round, and measures each
/// timed frame.
pub fn play(gpu: &Gpu, variants: &mut [LoopVariant], warmup: u32, frames: u32) -> Result<Vec<Vec<LoopFrame>>> {
    let mut measured: Vec<Vec<LoopFrame>> = variants.iter().map(|_| Vec::new()).collect();
    for index in 0..warmup + frames {
        for (variant, frames) in variants.iter_mut().zip(&mut measured) {
            let before = gpu.activity();
            let start = Instant::now();
            (variant.frame)(index)?;
            let wall_ms = start.elapsed().as_secs_f64() * 1e3;
            if index >= warmup {
                frames.push(LoopFrame { wall_ms, activity: gpu.activity().since(&before) });
            }
        }
    }
    Ok(measured)
}

/// Each variant's figures from its frames (`names` and `measured` in the same order).
pub fn summarise(names: &[String], measured: &[Vec<LoopFrame>]) -> Vec<LoopResult> {
    let bootstrap = Bootstrap::DEFAULT;
    let first: Vec<f64> = measured.first().map(|f| f.iter().map(|f| f.wall_ms).collect()).unwrap_or_default();
    names
        .iter()
        .zip(measured)
        .enumerate()
        .map(|(index, (name, frames))| {
            let count = frames.len().max(1) as f64;
            let mean = |value: &dyn Fn(&LoopFrame) -> f64| frames.iter().map(value).sum::<f64>() / count;
            let wall: Vec<f64> = frames.iter().map(|f| f.wall_ms).collect();
            let total_ms: f64 = wall.iter().sum();
            LoopResult {
                technique: name.clone(),
                frames: frames.len(),
                frames_per_second: if total_ms > 0.0 { frames.len() as f64 / (total_ms / 1e3) } else { 0.0 },
                frame_ms: mean(&|f| f.wall_ms),
                cpu_ms: mean(&|f| f.cpu_ms()),
                wait_ms: mean(&|f| f.activity.wait_ns as f64 / 1e6),
                allocations_per_frame: mean(&|f| f.activity.made(ObjectKind::MemoryAllocation) as f64),
                buffers_per_frame: mean(&|f| f.activity.made(ObjectKind::Buffer) as f64),
                waits_per_frame: mean(&|f| f.activity.waits as f64),
                // The first's time over this one's: how many of this one's frames fit in one of the first's.
                throughput_ratio: (index > 0).then(|| Ratio::per_round(&first, &wall, &bootstrap)).flatten(),
            }
        })
        .collect()
}

impl LoopReport {
    pub fn table(&self) -> String {
        let mut out = format!(
            "{} | {} | {}x{} | {}x | {} warm-up + {} frames of each, in turn, the scene animated, frames kept on the GPU\n",
            self.device,
            self.scene,
            self.width,
            self.height,
            self.samples,
            self.warmup,
            self.results.first().map_or(0, |r| r.frames),
        );
        let header = [
            "technique",
            "frames/s",
            "x [95% CI]",
            "frame ms",
            "CPU ms",
            "wait ms",
            "allocs/frame",
            "buffers/frame",
            "waits/frame",
        ];
        let rows: Vec<Vec<String>> = self
            .results
            .iter()
            .map(|r| {
                vec![
                    r.technique.clone(),
                    format!("{:.1}", r.frames_per_second),
                    r.throughput_ratio.map_or("1.00".into(), |ratio| ratio.brief()),
                    format!("{:.2}", r.frame_ms),
                    format!("{:.2}", r.cpu_ms),
                    format!("{:.2}", r.wait_ms),
                    format!("{:.1}", r.allocations_per_frame),
                    format!("{:.1}", r.buffers_per_frame),
                    format!("{:.2}", r.waits_per_frame),
                ]
            })
            .collect();
        for line in super::text_table::aligned_lines(&header, &rows) {
            let _ = writeln!(out, "{line}");
        }
        out.push_str(
            "x: throughput over the first technique's (median over the frames of its frame time / this one's, \
             bootstrap interval); CPU ms: the frame's wall time without its waits for the GPU; allocs: memory \
             allocations made (gpu-allocator's and dedicated); waits: host waits on a fence\n",
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(wall_ms: f64) -> LoopFrame {
        LoopFrame { wall_ms, activity: Activity::default() }
    }

    #[test]
    fn a_frame_without_waits_is_all_cpu_time() {
        assert_eq!(frame(4.0).cpu_ms(), 4.0);
    }

    #[test]
    fn throughput_is_frames_over_their_time_and_its_ratio_is_to_the_first() {
        let names = ["a".to_owned(), "b".to_owned()];
        let measured = vec![vec![frame(10.0); 4], vec![frame(20.0); 4]];
        let results = summarise(&names, &measured);
        assert!((results[0].frames_per_second - 100.0).abs() < 1e-9);
        assert!((results[1].frames_per_second - 50.0).abs() < 1e-9);
        assert!(results[0].throughput_ratio.is_none());
        let ratio = results[1].throughput_ratio.expect("a ratio to the first");
        assert!((ratio.median - 0.5).abs() < 1e-9, "{ratio:?}");
    }
}
