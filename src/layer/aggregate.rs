//! Mean, min and max of each render pass over the measured frames, matching passes across
//! frames by their position in the frame and their key (render area, attachment formats/ops).

use std::collections::BTreeMap;

use super::report::{AggregateRow, Counters, RenderPassRow};

#[derive(Debug, Clone)]
struct Accumulator {
    frames: u64,
    label: Option<String>,
    sum: Counters<f64>,
    /// How many frames had each optional counter (a mean over frames that lack one is null).
    optional_frames: [u64; 5],
    min: Counters,
    max: Counters,
}

#[derive(Debug, Default)]
pub struct Aggregator {
    passes: BTreeMap<(u32, String), Accumulator>,
}

fn add_opt(sum: &mut Option<f64>, value: Option<f64>, seen: &mut u64) {
    if let Some(v) = value {
        *sum = Some(sum.unwrap_or(0.0) + v);
        *seen += 1;
    }
}

fn pick<T: Copy>(a: Option<T>, b: Option<T>, better: fn(T, T) -> T) -> Option<T> {
    match (a, b) {
        (Some(a), Some(b)) => Some(better(a, b)),
        (a, b) => a.or(b),
    }
}

fn combine(a: &Counters, b: &Counters, int: fn(u64, u64) -> u64, float: fn(f64, f64) -> f64) -> Counters {
    Counters {
        draws: int(a.draws, b.draws),
        vertex_invocations: pick(a.vertex_invocations, b.vertex_invocations, int),
        clipping_primitives: pick(a.clipping_primitives, b.clipping_primitives, int),
        fragment_invocations: pick(a.fragment_invocations, b.fragment_invocations, int),
        fragments_per_pixel: pick(a.fragments_per_pixel, b.fragments_per_pixel, float),
        samples_passed: int(a.samples_passed, b.samples_passed),
        overdraw: float(a.overdraw, b.overdraw),
        gpu_ms: pick(a.gpu_ms, b.gpu_ms, float),
        bytes_loaded: int(a.bytes_loaded, b.bytes_loaded),
        bytes_stored: int(a.bytes_stored, b.bytes_stored),
    }
}

impl Aggregator {
    /// Adds one finished frame's measured passes.
    pub fn add_frame(&mut self, passes: &[RenderPassRow]) {
        for (position, row) in passes.iter().enumerate() {
            let Some(c) = &row.counters else { continue };
            let key = (position as u32, row.key());
            let f = |v: Option<u64>| v.map(|v| v as f64);
            match self.passes.get_mut(&key) {
                None => {
                    let mut acc = Accumulator {
                        frames: 1,
                        label: row.label.clone(),
                        sum: Counters {
                            draws: c.draws as f64,
                            vertex_invocations: None,
                            clipping_primitives: None,
                            fragment_invocations: None,
                            fragments_per_pixel: None,
                            samples_passed: c.samples_passed as f64,
                            overdraw: c.overdraw,
                            gpu_ms: None,
                            bytes_loaded: c.bytes_loaded as f64,
                            bytes_stored: c.bytes_stored as f64,
                        },
                        optional_frames: [0; 5],
                        min: *c,
                        max: *c,
                    };
                    let (s, n) = (&mut acc.sum, &mut acc.optional_frames);
                    add_opt(&mut s.vertex_invocations, f(c.vertex_invocations), &mut n[0]);
                    add_opt(&mut s.clipping_primitives, f(c.clipping_primitives), &mut n[1]);
                    add_opt(&mut s.fragment_invocations, f(c.fragment_invocations), &mut n[2]);
                    add_opt(&mut s.fragments_per_pixel, c.fragments_per_pixel, &mut n[3]);
                    add_opt(&mut s.gpu_ms, c.gpu_ms, &mut n[4]);
                    self.passes.insert(key, acc);
                }
                Some(acc) => {
                    acc.frames += 1;
                    acc.label = row.label.clone();
                    let (s, n) = (&mut acc.sum, &mut acc.optional_frames);
                    s.draws += c.draws as f64;
                    s.samples_passed += c.samples_passed as f64;
                    s.overdraw += c.overdraw;
                    s.bytes_loaded += c.bytes_loaded as f64;
                    s.bytes_stored += c.bytes_stored as f64;
                    add_opt(&mut s.vertex_invocations, f(c.vertex_invocations), &mut n[0]);
                    add_opt(&mut s.clipping_primitives, f(c.clipping_primitives), &mut n[1]);
                    add_opt(&mut s.fragment_invocations, f(c.fragment_invocations), &mut n[2]);
                    add_opt(&mut s.fragments_per_pixel, c.fragments_per_pixel, &mut n[3]);
                    add_opt(&mut s.gpu_ms, c.gpu_ms, &mut n[4]);
                    acc.min = combine(&acc.min, c, u64::min, f64::min);
                    acc.max = combine(&acc.max, c, u64::max, f64::max);
                }
            }
        }
    }

    /// One row per (position, key), in position order.
    pub fn rows(&self) -> Vec<AggregateRow> {
        self.passes
            .iter()
            .map(|((position, key), acc)| {
                let frames = acc.frames as f64;
                let n = &acc.optional_frames;
                let s = &acc.sum;
                // A counter some frames lacked has no honest mean.
                let mean = |v: Option<f64>, seen: u64| v.filter(|_| seen == acc.frames).map(|v| v / frames);
                AggregateRow {
                    position: *position,
                    key: key.clone(),
                    frames: acc.frames,
                    label: acc.label.clone(),
                    mean: Counters {
                        draws: s.draws / frames,
                        vertex_invocations: mean(s.vertex_invocations, n[0]),
                        clipping_primitives: mean(s.clipping_primitives, n[1]),
                        fragment_invocations: mean(s.fragment_invocations, n[2]),
                        fragments_per_pixel: mean(s.fragments_per_pixel, n[3]),
                        samples_passed: s.samples_passed / frames,
                        overdraw: s.overdraw / frames,
                        gpu_ms: mean(s.gpu_ms, n[4]),
                        bytes_loaded: s.bytes_loaded / frames,
                        bytes_stored: s.bytes_stored / frames,
                    },
                    min: acc.min,
                    max: acc.max,
                }
            })
            .collect()
    }
}

#[cfg(test)]
pub mod tests {
    use super::*;
    use crate::layer::report::{RawCounters, RenderArea};

    pub fn row(width: u32, samples_passed: u64, gpu_ns: Option<f64>) -> RenderPassRow {
        let area = RenderArea { x: 0, y: 0, width, height: 10 };
        let raw = RawCounters {
            draws: 2,
            vertex_invocations: Some(6),
            clipping_primitives: Some(2),
            fragment_invocations: Some(samples_passed * 2),
            samples_passed,
            gpu_ns,
        };
        RenderPassRow {
            per_draw: Vec::new(),
            index: 0,
            label: None,
            api: "vkCmdBeginRenderPass".into(),
            render_area: area,
            samples: 1,
            attachments: Vec::new(),
            counters: Some(Counters::new(&raw, &area, 1, &[])),
            not_measured: None,
        }
    }

    #[test]
    fn passes_match_by_position_and_key_with_mean_min_max() {
        let mut agg = Aggregator::default();
        agg.add_frame(&[row(10, 100, Some(1e6)), row(20, 50, Some(2e6))]);
        agg.add_frame(&[row(10, 300, Some(3e6)), row(20, 70, None)]);
        // Another size at position 0: another pass.
        agg.add_frame(&[row(30, 30, Some(1e6))]);
        let rows = agg.rows();
        assert_eq!(rows.len(), 3);
        let first = rows.iter().find(|r| r.position == 0 && r.key.starts_with("10x10")).expect("pass 0");
        assert_eq!(first.frames, 2);
        assert_eq!((first.mean.samples_passed, first.min.samples_passed, first.max.samples_passed), (200.0, 100, 300));
        assert_eq!(first.mean.fragment_invocations, Some(400.0));
        assert_eq!(first.mean.gpu_ms, Some(2.0));
        assert_eq!((first.min.gpu_ms, first.max.gpu_ms), (Some(1.0), Some(3.0)));
        assert_eq!(first.mean.overdraw, 2.0);
        // A frame without timestamps: no mean GPU time, min/max of the frames that had one.
        let second = rows.iter().find(|r| r.position == 1).expect("pass 1");
        assert_eq!((second.mean.gpu_ms, second.max.gpu_ms), (None, Some(2.0)));
        assert_eq!(second.mean.samples_passed, 60.0);
    }
}
