//! Work outside render passes: compute dispatches and transfers, as one command buffer's
//! recording sees them. Pure bookkeeping like recording.rs: each step returns the query
//! commands to record around the application's call.
//! - Consecutive dispatches form one group (a row), closed by anything that orders or splits
//!   the work: a barrier or event wait, a debug label call, a render pass, a transfer, an
//!   application query, the end of the command buffer. A group has one pipeline-statistics
//!   query (compute-shader invocations only) and two timestamps around it.
//! - Each transfer command is a row of its own with two timestamps around it; its bytes are
//!   worked out from its regions (transfer_bytes.rs), nothing is read from the GPU but time.
//!
//! Queries are reset right before the group or transfer that uses them: work is never inside a
//! render pass, where a reset is not allowed.

use ash::vk;

use super::slots::{QueryCmd, QueryKind, Slot, SlotPool};

/// The statistic the layer's compute pools count.
pub const COMPUTE_STATISTICS: vk::QueryPipelineStatisticFlags =
    vk::QueryPipelineStatisticFlags::COMPUTE_SHADER_INVOCATIONS;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorkKind {
    Compute,
    Transfer,
}

impl WorkKind {
    pub fn name(self) -> &'static str {
        match self {
            WorkKind::Compute => "compute",
            WorkKind::Transfer => "transfer",
        }
    }
}

/// What a transfer command moves: bytes read from and written to memory, and whether it
/// writes a swapchain image whole (`into_swapchain`: a note for the tiler check).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Moved {
    pub read: u64,
    pub written: u64,
    pub note: Option<String>,
}

/// A group of dispatches or one transfer command.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedWork {
    pub kind: WorkKind,
    /// The first command's name, e.g. "vkCmdDispatch", "vkCmdBlitImage".
    pub api: &'static str,
    /// The innermost debug label open at the first command.
    pub label: Option<String>,
    pub commands: u32,
    /// Workgroups as recorded (the direct dispatches'); None for a transfer.
    pub workgroups: Option<u64>,
    /// The indirect dispatches' argument locations (buffer, offset): their counts are read back
    /// at the end of the submission (copies.rs).
    pub indirect: Vec<(vk::Buffer, u64)>,
    pub moved: Moved,
    pub statistics: Option<Slot>,
    pub timestamps: Option<(Slot, Slot)>,
    /// Why its figures cannot be used (a secondary command buffer executed twice in one buffer).
    pub not_measured: Option<String>,
}

/// One command buffer's work, and the compute query slots it uses.
#[derive(Debug)]
pub struct WorkState {
    pub list: Vec<RecordedWork>,
    /// The dispatch group still open (its queries active), by index in `list`.
    open: Option<usize>,
    pub compute: SlotPool,
}

impl Default for WorkState {
    fn default() -> Self {
        WorkState { list: Vec::new(), open: None, compute: SlotPool::new(QueryKind::Compute) }
    }
}

impl WorkState {
    pub fn restart(&mut self) {
        self.list.clear();
        self.open = None;
        self.compute.restart();
    }
}

/// A dispatch's workgroups: as recorded, or in a buffer (an indirect dispatch's arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Workgroups {
    Recorded(u64),
    Indirect(vk::Buffer, u64),
}

/// What the command buffer's recording tells the work bookkeeping at each command.
pub struct Context<'a> {
    /// Not recorded: a secondary command buffer, or inside a render pass (where a dispatch or
    /// transfer is not valid anyway).
    pub skip: bool,
    /// The device counts pipeline statistics and no application statistics query is active.
    pub statistics: bool,
    /// The recording's timestamp slots; None when the queue family writes no timestamps.
    pub timestamps: Option<&'a mut SlotPool>,
    /// The label the work is named by.
    pub label: Option<String>,
}

impl Context<'_> {
    /// Two fresh timestamp slots for a work row.
    fn timestamps(
        &mut self,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
        before: &mut Vec<QueryCmd>,
    ) -> Option<(Slot, Slot)> {
        let pool = self.timestamps.as_mut()?;
        if !pool.reserve(2, create, before) {
            return None;
        }
        pool.take().zip(pool.take())
    }
}

impl WorkState {
    /// A dispatch: joins the open group or opens one. Returns the commands to record before the
    /// application's call.
    pub fn dispatch(
        &mut self,
        mut cx: Context<'_>,
        api: &'static str,
        groups: Workgroups,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
    ) -> Vec<QueryCmd> {
        let mut before = Vec::new();
        if cx.skip {
            return before;
        }
        if let Some(index) = self.open {
            let group = &mut self.list[index];
            group.commands += 1;
            match groups {
                Workgroups::Recorded(n) => group.workgroups = group.workgroups.map(|w| w + n),
                Workgroups::Indirect(buffer, offset) => group.indirect.push((buffer, offset)),
            }
            return before;
        }
        let statistics = if cx.statistics {
            self.compute.reserve(1, create, &mut before).then(|| self.compute.take()).flatten()
        } else {
            None
        };
        let timestamps = cx.timestamps(create, &mut before);
        if let Some((begin, _)) = timestamps {
            before.push(QueryCmd::Timestamp { slot: begin, stage: vk::PipelineStageFlags::TOP_OF_PIPE });
        }
        if let Some(slot) = statistics {
            before.push(QueryCmd::Begin { slot, precise: false });
        }
        self.list.push(RecordedWork {
            kind: WorkKind::Compute,
            api,
            label: cx.label,
            commands: 1,
            workgroups: Some(match groups {
                Workgroups::Recorded(n) => n,
                Workgroups::Indirect(..) => 0,
            }),
            indirect: match groups {
                Workgroups::Indirect(buffer, offset) => vec![(buffer, offset)],
                Workgroups::Recorded(_) => Vec::new(),
            },
            moved: Moved::default(),
            statistics,
            timestamps,
            not_measured: None,
        });
        self.open = Some(self.list.len() - 1);
        before
    }

    /// Closes the open dispatch group, if any: the commands to record before whatever closes it.
    pub fn close(&mut self) -> Vec<QueryCmd> {
        let mut before = Vec::new();
        let Some(index) = self.open.take() else { return before };
        let group = &self.list[index];
        if let Some(slot) = group.statistics {
            before.push(QueryCmd::End { slot });
        }
        if let Some((_, end)) = group.timestamps {
            before.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
        }
        before
    }

    /// A transfer command outside a render pass: a row of its own, timed. Returns the commands
    /// to record before and after the application's call.
    pub fn transfer(
        &mut self,
        mut cx: Context<'_>,
        api: &'static str,
        moved: Moved,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
    ) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let (mut before, mut after) = (Vec::new(), Vec::new());
        if cx.skip {
            return (before, after);
        }
        before.extend(self.close());
        let timestamps = cx.timestamps(create, &mut before);
        if let Some((begin, end)) = timestamps {
            before.push(QueryCmd::Timestamp { slot: begin, stage: vk::PipelineStageFlags::TOP_OF_PIPE });
            after.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
        }
        self.list.push(RecordedWork {
            kind: WorkKind::Transfer,
            api,
            label: cx.label,
            commands: 1,
            workgroups: None,
            indirect: Vec::new(),
            moved,
            statistics: None,
            timestamps,
            not_measured: None,
        });
        (before, after)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    fn create() -> impl FnMut(QueryKind) -> Option<vk::QueryPool> {
        let mut next = 100u64;
        move |kind: QueryKind| {
            next += 1;
            Some(vk::QueryPool::from_raw(next * 10 + kind as u64))
        }
    }

    fn cx(timestamps: &mut SlotPool) -> Context<'_> {
        Context { skip: false, statistics: true, timestamps: Some(timestamps), label: None }
    }

    #[test]
    fn consecutive_dispatches_are_one_group_until_something_closes_it() {
        let (mut work, mut stamps, mut create) = (WorkState::default(), SlotPool::new(QueryKind::Timestamp), create());
        let before = work.dispatch(cx(&mut stamps), "vkCmdDispatch", Workgroups::Recorded(4), &mut create);
        assert!(matches!(before.last(), Some(QueryCmd::Begin { precise: false, .. })), "{before:?}");
        assert!(before.iter().any(|c| matches!(c, QueryCmd::Timestamp { .. })));
        assert!(
            work.dispatch(cx(&mut stamps), "vkCmdDispatch", Workgroups::Recorded(6), &mut create).is_empty(),
            "joins"
        );
        let close = work.close();
        assert_eq!(close.len(), 2, "ends the statistics query and writes the end timestamp: {close:?}");
        assert!(work.close().is_empty(), "closed once");
        let args = vk::Buffer::from_raw(9);
        work.dispatch(cx(&mut stamps), "vkCmdDispatchIndirect", Workgroups::Indirect(args, 12), &mut create);
        work.dispatch(cx(&mut stamps), "vkCmdDispatch", Workgroups::Recorded(1), &mut create);
        let moved = Moved { read: 8, written: 8, note: None };
        let (before, after) = work.transfer(cx(&mut stamps), "vkCmdCopyBuffer", moved, &mut create);
        assert!(matches!(before[0], QueryCmd::End { .. }), "a transfer closes the group: {before:?}");
        assert_eq!(after.len(), 1);
        let list = &work.list;
        assert_eq!(list.len(), 3);
        assert_eq!((list[0].commands, list[0].workgroups), (2, Some(10)));
        assert_eq!((list[1].commands, list[1].workgroups), (2, Some(1)), "the recorded part");
        assert_eq!(list[1].indirect, [(args, 12)], "the indirect arguments, read back later");
        assert_eq!((list[2].kind, list[2].moved.read), (WorkKind::Transfer, 8));
        assert!(list[2].statistics.is_none() && list[2].timestamps.is_some());
    }

    #[test]
    fn skipped_work_is_not_recorded_and_no_timestamps_means_no_gpu_time() {
        let (mut work, mut create) = (WorkState::default(), create());
        let skip = Context { skip: true, statistics: true, timestamps: None, label: None };
        assert!(work.dispatch(skip, "vkCmdDispatch", Workgroups::Recorded(1), &mut create).is_empty());
        assert!(work.list.is_empty());
        let plain = Context { skip: false, statistics: false, timestamps: None, label: Some("blur".into()) };
        assert!(work.dispatch(plain, "vkCmdDispatch", Workgroups::Recorded(1), &mut create).is_empty());
        assert_eq!((work.list[0].statistics, work.list[0].timestamps), (None, None));
        assert_eq!(work.list[0].label.as_deref(), Some("blur"));
    }
}
