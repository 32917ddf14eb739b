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
use crate::render::Skinning;

/// One technique's loop: `frame(i)` renders its frame `i`.
pub struct LoopVariant<'a> {
    /// Renders frame N (submitted; with frames in flight it need not have finished).
    pub frame: Box<dyn FnMut(u32) -> Result<()> + 'a>,
    /// Waits for its frames in flight: the end of its turn.
    pub finish: Box<dyn FnMut() -> Result<()> + 'a>,
}

/// One turn of a loop (one frame, or several in flight, finished at its end), as the render
/// thread saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopFrame {
    /// Frames the turn played.
    pub frames: u32,
    pub wall_ms: f64,
    /// CPU time the render thread used in the turn, where the platform measures it.
    pub thread_cpu_ms: Option<f64>,
    /// What the turn made and waited for.
    pub activity: Activity,
}

impl LoopFrame {
    /// Milliseconds the render thread worked: its CPU time, else the wall time without its
    /// waits for the GPU (on a software GPU sharing the cores, that also counts the time the
    /// thread was not scheduled).
    pub fn cpu_ms(&self) -> f64 {
        self.thread_cpu_ms.unwrap_or((self.wall_ms - self.activity.wait_ns as f64 / 1e6).max(0.0))
    }

    /// Wall milliseconds a frame of the turn took.
    pub fn frame_ms(&self) -> f64 {
        self.wall_ms / f64::from(self.frames.max(1))
    }
}

/// What one technique's loop cost, per frame.
#[derive(Debug, Clone, Serialize)]
pub struct LoopResult {
    pub technique: String,
    /// Frames it kept in flight (1 where its per-frame data is not kept per frame slot).
    pub frames_in_flight: usize,
    /// Where it posed skinned objects.
    pub skinning: Skinning,
    pub frames: usize,
    /// Frames per second over the timed frames (their wall times summed).
    pub frames_per_second: f64,
    /// Mean wall time of a frame, ms.
    pub frame_ms: f64,
    /// Mean time a frame kept the render thread busy, its waits for the GPU taken out, ms.
    pub cpu_ms: f64,
    /// Mean CPU time a frame's jobs took on other threads (shadow volumes built as Doom 3
    /// BFG's jobs), ms: the render thread's `cpu_ms` plus this is the frame's CPU work.
    pub jobs_cpu_ms: f64,
    /// Of `jobs_cpu_ms`, the frame slots' command-pool resets on a worker (every technique has
    /// them; what else a technique runs as jobs is the rest).
    pub pool_reset_cpu_ms: f64,
    /// Mean time a frame waited for the GPU, ms.
    pub wait_ms: f64,
    /// State and draw commands a frame recorded (binds, pushes, scissors, draws, clears: see
    /// `Activity::commands`), exact: most of the render thread's CPU on lavapipe.
    pub commands_per_frame: f64,
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
    /// Frames a technique plays in a turn before its frames in flight are finished.
    pub turn: u32,
    pub results: Vec<LoopResult>,
}

/// Plays `warmup` then `frames` rounds, one turn of each variant per round (`turn` frames,
/// then its `finish`), and measures each timed turn whole.
pub fn play(
    gpu: &Gpu,
    variants: &mut [LoopVariant],
    warmup: u32,
    frames: u32,
    turn: u32,
) -> Result<Vec<Vec<LoopFrame>>> {
    let turn = turn.max(1);
    let mut measured: Vec<Vec<LoopFrame>> = variants.iter().map(|_| Vec::new()).collect();
    for round in 0..warmup + frames {
        for (variant, turns) in variants.iter_mut().zip(&mut measured) {
            let before = gpu.activity();
            let cpu_before = thread_cpu_ms();
            let start = Instant::now();
            for frame in 0..turn {
                (variant.frame)(round * turn + frame)?;
            }
            (variant.finish)()?;
            let wall_ms = start.elapsed().as_secs_f64() * 1e3;
            let thread_cpu_ms = thread_cpu_ms().zip(cpu_before).map(|(after, before)| after - before);
            if round >= warmup {
                let activity = gpu.activity().since(&before);
                turns.push(LoopFrame { frames: turn, wall_ms, thread_cpu_ms, activity });
            }
        }
    }
    Ok(measured)
}

/// CPU time the calling thread has used, in ms.
fn thread_cpu_ms() -> Option<f64> {
    crate::gpu::thread_time::thread_cpu_ns().map(|ns| ns as f64 / 1e6)
}

/// Each variant's figures from its frames (`names` and `measured` in the same order).
/// `kept`: per technique, the frames it kept in flight and where it skinned.
pub fn summarise(names: &[String], kept: &[(usize, Skinning)], measured: &[Vec<LoopFrame>]) -> Vec<LoopResult> {
    let bootstrap = Bootstrap::DEFAULT;
    let first: Vec<f64> = measured.first().map(|f| f.iter().map(LoopFrame::frame_ms).collect()).unwrap_or_default();
    names
        .iter()
        .zip(measured)
        .enumerate()
        .map(|(index, (name, frames))| {
            let played: u32 = frames.iter().map(|f| f.frames).sum();
            let count = f64::from(played.max(1));
            let mean = |value: &dyn Fn(&LoopFrame) -> f64| frames.iter().map(value).sum::<f64>() / count;
            let wall: Vec<f64> = frames.iter().map(LoopFrame::frame_ms).collect();
            let total_ms: f64 = frames.iter().map(|f| f.wall_ms).sum();
            LoopResult {
                technique: name.clone(),
                frames_in_flight: kept.get(index).map_or(1, |k| k.0),
                skinning: kept.get(index).map_or(Skinning::Cpu, |k| k.1),
                frames: played as usize,
                frames_per_second: if total_ms > 0.0 { f64::from(played) / (total_ms / 1e3) } else { 0.0 },
                frame_ms: mean(&|f| f.wall_ms),
                cpu_ms: mean(&|f| f.cpu_ms()),
                jobs_cpu_ms: mean(&|f| f.activity.job_ns as f64 / 1e6),
                pool_reset_cpu_ms: mean(&|f| f.activity.pool_reset_ns as f64 / 1e6),
                wait_ms: mean(&|f| f.activity.wait_ns as f64 / 1e6),
                commands_per_frame: mean(&|f| f.activity.commands as f64),
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
            "{} | {} | {}x{} | {}x | {} warm-up + {} turns of {} frame(s) of each, in turn, the scene animated, \
             frames kept on the GPU\n",
            self.device,
            self.scene,
            self.width,
            self.height,
            self.samples,
            self.warmup,
            self.results.first().map_or(0, |r| r.frames) / self.turn.max(1) as usize,
            self.turn,
        );
        let header = [
            "technique",
            "in flight",
            "skinning",
            "frames/s",
            "x [95% CI]",
            "frame ms",
            "CPU ms",
            "jobs ms",
            "commands",
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
                    r.frames_in_flight.to_string(),
                    r.skinning.to_string(),
                    format!("{:.1}", r.frames_per_second),
                    r.throughput_ratio.map_or("1.00".into(), |ratio| ratio.brief()),
                    format!("{:.2}", r.frame_ms),
                    format!("{:.2}", r.cpu_ms),
                    format!("{:.2}", r.jobs_cpu_ms),
                    format!("{:.0}", r.commands_per_frame),
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
            "x: throughput over the first technique's (median over the turns of its frame time / this one's, \
             bootstrap interval); in flight: frames submitted before the oldest is waited for (a turn's last \
             frames are finished at its end, within its time); CPU ms: the render thread's CPU time a frame \
             (without its waits for the GPU); jobs ms: the CPU time a frame's jobs took on other threads \
             (shadow volumes built on other cores, the frame slot's command pool reset); commands: state and draw commands a frame recorded \
             (binds, pushes, scissors, draws); allocs: memory allocations made (gpu-allocator's and dedicated); waits: host waits on a \
             fence\n",
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(wall_ms: f64) -> LoopFrame {
        LoopFrame { frames: 1, wall_ms, thread_cpu_ms: None, activity: Activity::default() }
    }

    #[test]
    fn a_frame_without_waits_is_all_cpu_time() {
        assert_eq!(frame(4.0).cpu_ms(), 4.0);
    }

    #[test]
    fn throughput_is_frames_over_their_time_and_its_ratio_is_to_the_first() {
        let names = ["a".to_owned(), "b".to_owned()];
        let measured = vec![vec![frame(10.0); 4], vec![frame(20.0); 4]];
        let results = summarise(&names, &[(1, Skinning::Cpu); 2], &measured);
        assert!((results[0].frames_per_second - 100.0).abs() < 1e-9);
        assert!((results[1].frames_per_second - 50.0).abs() < 1e-9);
        assert!(results[0].throughput_ratio.is_none());
        let ratio = results[1].throughput_ratio.expect("a ratio to the first");
        assert!((ratio.median - 0.5).abs() < 1e-9, "{ratio:?}");
    }
}
