//! Mean, min and max of each render pass over the measured frames, matching passes across
//! frames by their position in the frame and their key (render area, attachment formats/ops);
//! a pass's sections matched by their position in the pass and their label.

use std::collections::BTreeMap;

use crate::report::{
    AggregateRow, AggregateSection, Counters, FillrateReport, FrameRows, JournalLine, RenderPassRow, FILLRATE_SCHEMA,
    KEPT_FRAMES,
};

/// Sums, minima and maxima of one pass's (or section's) counters over frames.
#[derive(Debug, Clone)]
struct Stats {
    frames: u64,
    sum: Counters<f64>,
    /// How many frames had each optional counter (a mean over frames that lack one is null).
    optional_frames: [u64; 5],
    min: Counters,
    max: Counters,
}

impl Stats {
    fn new(c: &Counters) -> Self {
        let zero = Counters {
            draws: 0.0,
            vertex_invocations: None,
            clipping_primitives: None,
            fragment_invocations: None,
            fragments_per_pixel: None,
            samples_passed: 0.0,
            overdraw: 0.0,
            gpu_ms: None,
            bytes_loaded: 0.0,
            bytes_stored: 0.0,
            tiler_bytes: 0.0,
            immediate_bytes: 0.0,
        };
        let mut stats = Stats { frames: 0, sum: zero, optional_frames: [0; 5], min: *c, max: *c };
        stats.add(c);
        stats
    }

    fn add(&mut self, c: &Counters) {
        if self.frames > 0 {
            self.min = combine(&self.min, c, u64::min, f64::min);
            self.max = combine(&self.max, c, u64::max, f64::max);
        }
        self.frames += 1;
        let f = |v: Option<u64>| v.map(|v| v as f64);
        let (s, n) = (&mut self.sum, &mut self.optional_frames);
        s.draws += c.draws as f64;
        s.samples_passed += c.samples_passed as f64;
        s.overdraw += c.overdraw;
        s.bytes_loaded += c.bytes_loaded as f64;
        s.bytes_stored += c.bytes_stored as f64;
        s.tiler_bytes += c.tiler_bytes as f64;
        s.immediate_bytes += c.immediate_bytes as f64;
        add_opt(&mut s.vertex_invocations, f(c.vertex_invocations), &mut n[0]);
        add_opt(&mut s.clipping_primitives, f(c.clipping_primitives), &mut n[1]);
        add_opt(&mut s.fragment_invocations, f(c.fragment_invocations), &mut n[2]);
        add_opt(&mut s.fragments_per_pixel, c.fragments_per_pixel, &mut n[3]);
        add_opt(&mut s.gpu_ms, c.gpu_ms, &mut n[4]);
    }

    fn mean(&self) -> Counters<f64> {
        let frames = self.frames as f64;
        let n = &self.optional_frames;
        let s = &self.sum;
        // A counter some frames lacked has no honest mean.
        let mean = |v: Option<f64>, seen: u64| v.filter(|_| seen == self.frames).map(|v| v / frames);
        Counters {
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
            tiler_bytes: s.tiler_bytes / frames,
            immediate_bytes: s.immediate_bytes / frames,
        }
    }
}

#[derive(Debug, Clone)]
struct Accumulator {
    label: Option<String>,
    stats: Stats,
    /// Sections by (position in the pass, label): the same section of the same pass.
    sections: BTreeMap<(u32, Option<String>), Stats>,
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
        tiler_bytes: int(a.tiler_bytes, b.tiler_bytes),
        immediate_bytes: int(a.immediate_bytes, b.immediate_bytes),
    }
}

impl Aggregator {
    /// Adds one finished frame's measured passes, and their measured sections.
    pub fn add_frame(&mut self, passes: &[RenderPassRow]) {
        for (position, row) in passes.iter().enumerate() {
            let Some(c) = &row.counters else { continue };
            let key = (position as u32, row.key());
            let acc = match self.passes.entry(key) {
                std::collections::btree_map::Entry::Vacant(e) => {
                    e.insert(Accumulator { label: None, stats: Stats::new(c), sections: BTreeMap::new() })
                }
                std::collections::btree_map::Entry::Occupied(e) => {
                    let acc = e.into_mut();
                    acc.stats.add(c);
                    acc
                }
            };
            acc.label = row.label.clone();
            for (index, section) in row.sections.iter().enumerate() {
                let Some(c) = &section.counters else { continue };
                match acc.sections.get_mut(&(index as u32, section.label.clone())) {
                    Some(stats) => stats.add(c),
                    None => {
                        acc.sections.insert((index as u32, section.label.clone()), Stats::new(c));
                    }
                }
            }
        }
    }

    /// One row per (position, key), in position order, with its sections in theirs.
    pub fn rows(&self) -> Vec<AggregateRow> {
        self.passes
            .iter()
            .map(|((position, key), acc)| AggregateRow {
                position: *position,
                key: key.clone(),
                frames: acc.stats.frames,
                label: acc.label.clone(),
                mean: acc.stats.mean(),
                min: acc.stats.min,
                max: acc.stats.max,
                sections: acc
                    .sections
                    .iter()
                    .map(|((index, label), stats)| AggregateSection {
                        index: *index,
                        label: label.clone(),
                        frames: stats.frames,
                        mean: stats.mean(),
                        min: stats.min,
                        max: stats.max,
                    })
                    .collect(),
            })
            .collect()
    }
}

/// The report the journal's text holds: every frame it lists (the last [`KEPT_FRAMES`]
/// kept) and their aggregate; None without a whole line. A torn last line (the program died
/// while it was written) is left out.
pub fn report_from_journal(text: &str, keep_all: bool) -> Option<FillrateReport> {
    let lines: Vec<JournalLine> = text.lines().filter_map(|l| serde_json::from_str(l).ok()).collect();
    let last = lines.last()?.clone();
    let mut aggregate = Aggregator::default();
    let mut work = crate::work_aggregate::WorkAggregator::default();
    for line in &lines {
        aggregate.add_frame(&line.frame.render_passes);
        work.add_frame(&line.frame.work);
    }
    let mut frames: Vec<FrameRows> = lines.into_iter().map(|l| l.frame).collect();
    if !keep_all && frames.len() > KEPT_FRAMES {
        frames.drain(..frames.len() - KEPT_FRAMES);
    }
    Some(FillrateReport {
        schema: FILLRATE_SCHEMA.into(),
        application: last.application,
        device: last.device,
        counters: last.counters,
        frames_measured: last.frames_measured,
        not_measured: last.not_measured,
        frames,
        aggregate: aggregate.rows(),
        work_aggregate: work.rows(),
        run: None,
        hidden_extensions: Vec::new(),
        tiler_check: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::row;

    #[test]
    fn the_journal_gives_every_frame_and_their_aggregate_and_drops_a_torn_line() {
        use crate::report::{CounterSupport, FrameRows, JournalLine};
        let line = |index: u64| JournalLine {
            application: "app".into(),
            device: "gpu".into(),
            counters: CounterSupport::default(),
            frames_measured: index + 1,
            not_measured: Vec::new(),
            frame: FrameRows { index, render_passes: vec![row(10, 100 * (index + 1), None)], work: Vec::new() },
        };
        let mut text: String =
            (0..3).map(|i| serde_json::to_string(&line(i)).expect("json") + "\n").collect::<String>();
        let torn = serde_json::to_string(&line(3)).expect("json");
        text += &torn[..torn.len() / 2];
        let report = report_from_journal(&text, false).expect("a report");
        assert_eq!((report.frames_measured, report.frames.len()), (3, 3));
        assert_eq!(report.aggregate[0].frames, 3);
        assert_eq!(report.aggregate[0].mean.samples_passed, 200.0);
        assert_eq!(report_from_journal("", false), None);
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
