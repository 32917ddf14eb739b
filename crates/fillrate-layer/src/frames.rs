//! Frames out of submissions: a frame is the render pass instances submitted between two
//! presents, in submission order. A frame is finished once it is closed (by a present, or by
//! vkDestroyDevice) and every submission in it has been read back.

use std::collections::{BTreeMap, VecDeque};

use super::aggregate::Aggregator;
use super::report::{FrameRows, RenderPassRow, WorkRow, KEPT_FRAMES};
use super::work_aggregate::WorkAggregator;

#[derive(Debug, Default)]
struct FrameBuild {
    closed: bool,
    /// Submissions not read back yet.
    pending: u32,
    /// (submission sequence, pass order in it, row).
    rows: Vec<(u64, u32, RenderPassRow)>,
    /// (submission sequence, order in it, row): dispatch groups and transfers.
    work: Vec<(u64, u32, WorkRow)>,
}

#[derive(Debug)]
pub struct FrameAssembler {
    /// The frame submissions go to now.
    current: u64,
    /// Measure frames below this index only.
    limit: Option<u64>,
    building: BTreeMap<u64, FrameBuild>,
    /// Finished frames kept for the report.
    pub kept: VecDeque<FrameRows>,
    pub aggregate: Aggregator,
    pub work_aggregate: WorkAggregator,
    pub frames_measured: u64,
}

impl FrameAssembler {
    pub fn new(limit: Option<u64>) -> Self {
        FrameAssembler {
            current: 0,
            limit,
            building: BTreeMap::new(),
            kept: VecDeque::new(),
            aggregate: Aggregator::default(),
            work_aggregate: WorkAggregator::default(),
            frames_measured: 0,
        }
    }

    pub fn current(&self) -> u64 {
        self.current
    }

    /// Whether the current frame is measured (`NOSTENCIL_FILLRATE_FRAMES`).
    pub fn measuring(&self) -> bool {
        !matches!(self.limit, Some(n) if self.current >= n)
    }

    /// All the limited frames are finished: nothing more will be measured.
    pub fn done(&self) -> bool {
        self.limit.is_some_and(|n| self.frames_measured >= n)
    }

    /// A submission with measured passes went to the current frame; returns its frame.
    pub fn submitted(&mut self) -> u64 {
        self.building.entry(self.current).or_default().pending += 1;
        self.current
    }

    /// A submission of `frame` was read back: its rows (in recording order).
    pub fn completed(&mut self, frame: u64, sequence: u64, rows: Vec<RenderPassRow>) {
        self.completed_with_work(frame, sequence, rows, Vec::new());
    }

    /// [`Self::completed`] with the submission's work rows too.
    pub fn completed_with_work(&mut self, frame: u64, sequence: u64, rows: Vec<RenderPassRow>, work: Vec<WorkRow>) {
        let build = self.building.entry(frame).or_default();
        build.pending = build.pending.saturating_sub(1);
        for (order, row) in rows.into_iter().enumerate() {
            build.rows.push((sequence, order as u32, row));
        }
        for (order, row) in work.into_iter().enumerate() {
            build.work.push((sequence, order as u32, row));
        }
    }

    /// Ends the current frame where frames are cut by submissions, host waits or frame
    /// boundaries: unlike a present, nothing happens unless something was submitted to it, so
    /// waits with nothing new in flight make no empty frames.
    pub fn cut(&mut self) {
        if self.building.contains_key(&self.current) {
            self.present();
        }
    }

    /// A present: closes the current frame (if it is measured) and starts the next.
    pub fn present(&mut self) {
        if self.measuring() {
            self.building.entry(self.current).or_default().closed = true;
        }
        self.current += 1;
    }

    /// The end of the device: closes the current frame if anything was submitted to it (an
    /// application that never presents has this one frame).
    pub fn close_last(&mut self) {
        if let Some(build) = self.building.get_mut(&self.current) {
            build.closed = true;
        }
    }

    /// Moves finished frames, oldest first, to `kept` and the aggregate; returns how many.
    pub fn finish_ready(&mut self) -> u64 {
        let mut finished = 0;
        while let Some((&index, build)) = self.building.iter().next() {
            if !build.closed || build.pending > 0 {
                break;
            }
            let Some(build) = self.building.remove(&index) else { break };
            let render_passes = in_submission_order(build.rows, |row: &mut RenderPassRow, i| row.index = i);
            let work = in_submission_order(build.work, |row: &mut WorkRow, i| row.index = i);
            self.aggregate.add_frame(&render_passes);
            self.work_aggregate.add_frame(&work);
            self.kept.push_back(FrameRows { index, render_passes, work });
            if self.limit.is_none() && self.kept.len() > KEPT_FRAMES {
                self.kept.pop_front();
            }
            self.frames_measured += 1;
            finished += 1;
        }
        finished
    }
}

/// Rows keyed by (submission sequence, order within it), sorted and numbered from 0 with
/// `number` in that order.
fn in_submission_order<R>(mut rows: Vec<(u64, u32, R)>, number: fn(&mut R, u32)) -> Vec<R> {
    rows.sort_by_key(|(sequence, order, _)| (*sequence, *order));
    rows.into_iter()
        .enumerate()
        .map(|(i, (_, _, mut row))| {
            number(&mut row, i as u32);
            row
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nostencil_fillrate_report::fixtures::row;

    #[test]
    fn frames_close_at_present_and_finish_when_read_back_in_submission_order() {
        let mut frames = FrameAssembler::new(None);
        let a = frames.submitted();
        let b = frames.submitted();
        frames.present();
        let c = frames.submitted();
        assert_eq!((a, b, c), (0, 0, 1));
        // The second submission reads back first: the frame waits for the first.
        frames.completed(0, 2, vec![row(20, 1, None)]);
        assert_eq!(frames.finish_ready(), 0);
        frames.completed(0, 1, vec![row(10, 1, None), row(10, 2, None)]);
        assert_eq!(frames.finish_ready(), 1);
        let frame = &frames.kept[0];
        let widths: Vec<_> = frame.render_passes.iter().map(|r| (r.index, r.render_area.width)).collect();
        assert_eq!(widths, vec![(0, 10), (1, 10), (2, 20)]);
        // Frame 1 is open until the device ends.
        frames.completed(1, 3, vec![row(10, 5, None)]);
        assert_eq!(frames.finish_ready(), 0);
        frames.close_last();
        assert_eq!(frames.finish_ready(), 1);
        assert_eq!(frames.frames_measured, 2);
        assert_eq!(frames.aggregate.rows().len(), 3);
    }

    #[test]
    fn a_frame_limit_stops_measuring_and_says_done() {
        let mut frames = FrameAssembler::new(Some(2));
        for frame in 0..4 {
            assert_eq!(frames.measuring(), frame < 2);
            if frames.measuring() {
                let f = frames.submitted();
                frames.completed(f, frame, vec![row(10, frame, None)]);
            }
            frames.present();
            frames.finish_ready();
        }
        assert!(frames.done());
        assert_eq!(frames.kept.len(), 2);
    }

    #[test]
    fn only_the_last_frames_are_kept_without_a_limit_but_all_are_aggregated() {
        let mut frames = FrameAssembler::new(None);
        for frame in 0..(KEPT_FRAMES as u64 + 6) {
            let f = frames.submitted();
            frames.completed(f, frame, vec![row(10, frame, None)]);
            frames.present();
            frames.finish_ready();
        }
        assert_eq!(frames.kept.len(), KEPT_FRAMES);
        assert_eq!(frames.kept[0].index, 6);
        assert_eq!(frames.aggregate.rows()[0].frames, KEPT_FRAMES as u64 + 6);
    }
}
