//! Mean, min and max of each work row (work.rs) over the measured frames, matched by position
//! among the frame's work, kind, command and label.

use std::collections::BTreeMap;

use crate::report::{AggregateWork, WorkCounters, WorkRow};

#[derive(Debug, Clone)]
struct Stats {
    frames: u64,
    sum: WorkCounters<f64>,
    /// Frames that had workgroups, invocations and GPU time (a mean over fewer is null).
    optional_frames: [u64; 3],
    min: WorkCounters,
    max: WorkCounters,
}

fn pick(a: Option<u64>, b: Option<u64>, f: fn(u64, u64) -> u64) -> Option<u64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(f(a, b)),
        (a, b) => a.or(b),
    }
}

fn pick_f(a: Option<f64>, b: Option<f64>, f: fn(f64, f64) -> f64) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(f(a, b)),
        (a, b) => a.or(b),
    }
}

fn combine(a: &WorkCounters, b: &WorkCounters, u: fn(u64, u64) -> u64, f: fn(f64, f64) -> f64) -> WorkCounters {
    WorkCounters {
        commands: u(a.commands, b.commands),
        workgroups: pick(a.workgroups, b.workgroups, u),
        compute_invocations: pick(a.compute_invocations, b.compute_invocations, u),
        bytes_read: u(a.bytes_read, b.bytes_read),
        bytes_written: u(a.bytes_written, b.bytes_written),
        gpu_ms: pick_f(a.gpu_ms, b.gpu_ms, f),
    }
}

impl Stats {
    fn new(c: &WorkCounters) -> Self {
        let zero = WorkCounters {
            commands: 0.0,
            workgroups: None,
            compute_invocations: None,
            bytes_read: 0.0,
            bytes_written: 0.0,
            gpu_ms: None,
        };
        let mut stats = Stats { frames: 0, sum: zero, optional_frames: [0; 3], min: *c, max: *c };
        stats.add(c);
        stats
    }

    fn add(&mut self, c: &WorkCounters) {
        if self.frames > 0 {
            self.min = combine(&self.min, c, u64::min, f64::min);
            self.max = combine(&self.max, c, u64::max, f64::max);
        }
        self.frames += 1;
        let s = &mut self.sum;
        s.commands += c.commands as f64;
        s.bytes_read += c.bytes_read as f64;
        s.bytes_written += c.bytes_written as f64;
        let optional = [c.workgroups.map(|v| v as f64), c.compute_invocations.map(|v| v as f64), c.gpu_ms];
        let sums = [&mut s.workgroups, &mut s.compute_invocations, &mut s.gpu_ms];
        for ((sum, value), seen) in sums.into_iter().zip(optional).zip(&mut self.optional_frames) {
            if let Some(v) = value {
                *sum = Some(sum.unwrap_or(0.0) + v);
                *seen += 1;
            }
        }
    }

    fn mean(&self) -> WorkCounters<f64> {
        let frames = self.frames as f64;
        let s = &self.sum;
        // A figure some frames lacked has no honest mean.
        let mean = |v: Option<f64>, seen: u64| v.filter(|_| seen == self.frames).map(|v| v / frames);
        WorkCounters {
            commands: s.commands / frames,
            workgroups: mean(s.workgroups, self.optional_frames[0]),
            compute_invocations: mean(s.compute_invocations, self.optional_frames[1]),
            bytes_read: s.bytes_read / frames,
            bytes_written: s.bytes_written / frames,
            gpu_ms: mean(s.gpu_ms, self.optional_frames[2]),
        }
    }
}

/// Work rows over frames, matched by position among the frame's work, kind, command and label.
#[derive(Debug, Default)]
pub struct WorkAggregator {
    rows: BTreeMap<(u32, String, String, Option<String>), Stats>,
}

impl WorkAggregator {
    pub fn add_frame(&mut self, work: &[WorkRow]) {
        for row in work {
            let Some(counters) = &row.counters else { continue };
            let key = (row.index, row.kind.clone(), row.api.clone(), row.label.clone());
            match self.rows.get_mut(&key) {
                Some(stats) => stats.add(counters),
                None => {
                    self.rows.insert(key, Stats::new(counters));
                }
            }
        }
    }

    pub fn rows(&self) -> Vec<AggregateWork> {
        self.rows
            .iter()
            .map(|((position, kind, api, label), stats)| AggregateWork {
                position: *position,
                kind: kind.clone(),
                api: api.clone(),
                label: label.clone(),
                frames: stats.frames,
                mean: stats.mean(),
                min: stats.min,
                max: stats.max,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(index: u32, invocations: Option<u64>, gpu_ms: Option<f64>) -> WorkRow {
        WorkRow {
            index,
            kind: "compute".into(),
            api: "vkCmdDispatch".into(),
            label: None,
            counters: Some(WorkCounters {
                commands: 1,
                workgroups: Some(2),
                compute_invocations: invocations,
                bytes_read: 0,
                bytes_written: 0,
                gpu_ms,
            }),
            not_measured: None,
            note: None,
        }
    }

    #[test]
    fn work_is_aggregated_by_position_with_honest_means() {
        let mut aggregate = WorkAggregator::default();
        aggregate.add_frame(&[row(0, Some(64), Some(1.0)), row(1, Some(8), None)]);
        aggregate.add_frame(&[row(0, Some(128), Some(3.0)), row(1, Some(8), Some(2.0))]);
        let rows = aggregate.rows();
        assert_eq!(rows.len(), 2);
        assert_eq!((rows[0].frames, rows[0].mean.compute_invocations, rows[0].mean.gpu_ms), (2, Some(96.0), Some(2.0)));
        assert_eq!((rows[0].min.compute_invocations, rows[0].max.compute_invocations), (Some(64), Some(128)));
        assert_eq!(rows[1].mean.gpu_ms, None, "one frame had no GPU time");
        assert_eq!(rows[1].max.gpu_ms, Some(2.0));
    }
}
