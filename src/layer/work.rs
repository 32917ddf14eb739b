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

use super::recording::Recording;
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
    /// Workgroups as recorded; None once an indirect dispatch joined (its count is on the GPU).
    pub workgroups: Option<u64>,
    pub moved: Moved,
    pub statistics: Option<Slot>,
    pub timestamps: Option<(Slot, Slot)>,
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

impl Recording {
    /// A dispatch (`groups`: its workgroups, None for an indirect one): joins the open group
    /// or opens one. Returns the commands to record before the application's call.
    pub fn dispatch(
        &mut self,
        api: &'static str,
        groups: Option<u64>,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
    ) -> Vec<QueryCmd> {
        let mut before = Vec::new();
        if self.secondary || self.in_pass() {
            return before;
        }
        if let Some(index) = self.work.open {
            let group = &mut self.work.list[index];
            group.commands += 1;
            group.workgroups = group.workgroups.zip(groups).map(|(a, b)| a + b);
            return before;
        }
        let statistics = if self.support.statistics && !self.app_statistics_active() {
            self.work.compute.reserve(1, create, &mut before).then(|| self.work.compute.take()).flatten()
        } else {
            None
        };
        let timestamps = self.work_timestamps(create, &mut before);
        if let Some((begin, _)) = timestamps {
            before.push(QueryCmd::Timestamp { slot: begin, stage: vk::PipelineStageFlags::TOP_OF_PIPE });
        }
        if let Some(slot) = statistics {
            before.push(QueryCmd::Begin { slot, precise: false });
        }
        self.work.list.push(RecordedWork {
            kind: WorkKind::Compute,
            api,
            label: self.label_now(),
            commands: 1,
            workgroups: groups,
            moved: Moved::default(),
            statistics,
            timestamps,
        });
        self.work.open = Some(self.work.list.len() - 1);
        before
    }

    /// Closes the open dispatch group, if any: the commands to record before whatever closes it.
    pub fn close_work(&mut self) -> Vec<QueryCmd> {
        let mut before = Vec::new();
        let Some(index) = self.work.open.take() else { return before };
        let group = &self.work.list[index];
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
        api: &'static str,
        moved: Moved,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
    ) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let (mut before, mut after) = (Vec::new(), Vec::new());
        if self.secondary || self.in_pass() {
            return (before, after);
        }
        before.extend(self.close_work());
        let timestamps = self.work_timestamps(create, &mut before);
        if let Some((begin, end)) = timestamps {
            before.push(QueryCmd::Timestamp { slot: begin, stage: vk::PipelineStageFlags::TOP_OF_PIPE });
            after.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
        }
        self.work.list.push(RecordedWork {
            kind: WorkKind::Transfer,
            api,
            label: self.label_now(),
            commands: 1,
            workgroups: None,
            moved,
            statistics: None,
            timestamps,
        });
        (before, after)
    }

    /// Two fresh timestamp slots for a work row, when the queue family writes timestamps.
    fn work_timestamps(
        &mut self,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
        before: &mut Vec<QueryCmd>,
    ) -> Option<(Slot, Slot)> {
        if !self.support.timestamps || !self.timestamps.reserve(2, create, before) {
            return None;
        }
        self.timestamps.take().zip(self.timestamps.take())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layer::recording::QuerySupport;
    use ash::vk::Handle;

    fn recording() -> (Recording, impl FnMut(QueryKind) -> Option<vk::QueryPool>) {
        let mut next = 100u64;
        let create = move |kind: QueryKind| {
            next += 1;
            Some(vk::QueryPool::from_raw(next * 10 + kind as u64))
        };
        (Recording::new(false, QuerySupport { statistics: true, precise: true, timestamps: true }), create)
    }

    #[test]
    fn consecutive_dispatches_are_one_group_until_something_closes_it() {
        let (mut rec, mut create) = recording();
        let before = rec.dispatch("vkCmdDispatch", Some(4), &mut create);
        assert!(matches!(before.last(), Some(QueryCmd::Begin { precise: false, .. })), "{before:?}");
        assert!(before.iter().any(|c| matches!(c, QueryCmd::Timestamp { .. })));
        assert!(rec.dispatch("vkCmdDispatch", Some(6), &mut create).is_empty(), "joins the group");
        let close = rec.close_work();
        assert_eq!(close.len(), 2, "ends the statistics query and writes the end timestamp: {close:?}");
        assert!(rec.close_work().is_empty(), "closed once");
        rec.dispatch("vkCmdDispatchIndirect", None, &mut create);
        rec.dispatch("vkCmdDispatch", Some(1), &mut create);
        let (before, after) = rec.transfer("vkCmdCopyBuffer", Moved { read: 8, written: 8, note: None }, &mut create);
        assert!(matches!(before[0], QueryCmd::End { .. }), "a transfer closes the group: {before:?}");
        assert_eq!(after.len(), 1);
        let work = &rec.work.list;
        assert_eq!(work.len(), 3);
        assert_eq!((work[0].commands, work[0].workgroups), (2, Some(10)));
        assert_eq!((work[1].commands, work[1].workgroups), (2, None), "an indirect dispatch's count is unknown");
        assert_eq!((work[2].kind, work[2].moved.read), (WorkKind::Transfer, 8));
        assert!(work[2].statistics.is_none() && work[2].timestamps.is_some());
    }

    #[test]
    fn labels_name_groups_and_work_inside_a_pass_or_a_secondary_buffer_is_not_recorded() {
        let (mut rec, mut create) = recording();
        rec.push_label("blur".into());
        rec.dispatch("vkCmdDispatch", Some(1), &mut create);
        rec.close_work();
        assert_eq!(rec.work.list[0].label.as_deref(), Some("blur"));
        let mut secondary = Recording::new(true, rec.support);
        assert!(secondary.dispatch("vkCmdDispatch", Some(1), &mut create).is_empty());
        assert!(secondary.work.list.is_empty());
    }
}
