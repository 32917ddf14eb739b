//! One command buffer's recording as the layer sees it: the render pass instances it began,
//! their draws and label, the query slots that measure them, and the application's own queries.
//! Pure bookkeeping: each step returns the query commands to record, so it is tested without a
//! GPU. Vulkan rules it follows:
//! - a query begun inside a render pass ends in the same subpass: the layer's queries are split
//!   into segments at every vkCmdNextSubpass, summed at read back;
//! - a segment begins right before a draw, never right after the render pass begins: only a
//!   draw guarantees the application has bound a graphics pipeline, and lavapipe (Mesa 22.3)
//!   flushes the graphics state at vkCmdBeginQuery, dereferencing the missing pipeline's shaders
//!   when dynamic state was set first (vkd3d's clears: SIGSEGV in its queue thread). Fragments
//!   and samples come only from draws, so nothing is lost; a pass with no draw counts zero;
//! - two queries of one type cannot be active at once: when the application begins its own
//!   occlusion or statistics query inside a measured pass, the layer's segment of that type ends
//!   and the application's query covers the gap (read back from its pool and added); a new
//!   segment begins when the application's query ends;
//! - an application query of those types already active when a pass begins: the pass is not
//!   measured (the layer cannot begin its own), and said so.
//!
//! Sections: a debug-utils label begun or ended inside a pass splits it. The layer's active
//! segments end at the label call (ending a query needs no pipeline) and the next draw begins
//! new ones, so every segment, gap and per-draw query falls in exactly one section: a section is
//! where its lists begin in the pass's lists, and the pass's counters are the sum of its
//! sections' exactly. Each section opened by a label call also gets two timestamps of its own.
//! An application query is counted in the section it began in.

use std::collections::HashMap;

use ash::vk;

use super::report::{AttachmentRow, RenderArea};
use super::slots::{QueryCmd, QueryKind, Slot, SlotPool, CHUNK};

/// Occlusion and statistics segments one render pass may use.
pub const SEGMENTS_PER_PASS: u32 = 64;

/// Draws one pass may have when each draw is measured alone (`per_draw`).
pub const DRAWS_PER_PASS: u32 = 256;

/// Sections of one pass that get timestamps of their own (later ones have no GPU time): with
/// the pass's own two, one pool chunk.
pub const TIMED_SECTIONS_PER_PASS: u32 = 31;

/// A part of a render pass instance between two debug-utils label calls made inside it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Section {
    /// The labels begun inside the pass and open here, outermost first, joined by " / ".
    pub label: Option<String>,
    /// Where this section's entries begin in the pass's `occlusion`, `statistics`, `gaps` and
    /// `draw_slots` (they end where the next section's begin).
    pub from: [usize; 4],
    pub draws: u64,
    /// (begin, end) timestamps: sections opened by a label call.
    pub timestamps: Option<(Slot, Slot)>,
    /// Its end timestamp is written (early, where a subpass that runs secondary command
    /// buffers begins: the primary may record no timestamp inside it).
    pub ended: bool,
}

impl Section {
    /// Its end timestamp, when it has one not yet written.
    fn end_due(&self) -> Option<Slot> {
        self.timestamps.filter(|_| !self.ended).map(|(_, end)| end)
    }
}

/// The queries of one draw measured alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrawSlots {
    pub occlusion: Option<Slot>,
    pub statistics: Option<Slot>,
    pub timestamps: Option<(Slot, Slot)>,
}

/// An application query inside a measured pass, whose result fills the layer's gap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AppGap {
    pub kind: QueryKind,
    pub pool: vk::QueryPool,
    pub query: u32,
    /// Occlusion: the application asked for PRECISE.
    pub precise: bool,
    /// Statistics: the application pool's statistic bits.
    pub statistics: vk::QueryPipelineStatisticFlags,
    /// Still active (not yet ended by the application).
    pub open: bool,
}

/// What the layer knows of a render pass instance when it begins.
#[derive(Debug, Clone, PartialEq)]
pub struct PassDesc {
    pub api: &'static str,
    pub area: RenderArea,
    pub samples: u32,
    pub attachments: Vec<AttachmentRow>,
    /// Why it cannot be measured, decided at begin (a suspended dynamic pass, ...).
    pub not_measured: Option<String>,
    /// Its first subpass's contents are recorded in secondary command buffers.
    pub secondary_contents: bool,
    /// A multiview pass: the views each subpass renders (empty outside multiview).
    pub view_counts: Vec<u32>,
}

impl PassDesc {
    /// The most views any subpass renders (1 outside multiview).
    pub fn views(&self) -> u32 {
        self.view_counts.iter().copied().max().unwrap_or(1)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct RecordedPass {
    pub desc: PassDesc,
    pub label: Option<String>,
    pub draws: u64,
    pub occlusion: Vec<Slot>,
    pub statistics: Vec<Slot>,
    /// (begin, end) timestamps.
    pub timestamps: Option<(Slot, Slot)>,
    pub gaps: Vec<AppGap>,
    /// The indices of multiview queries past each run's first (`occlusion`, `statistics` hold
    /// them too): one a driver may leave unavailable reads as 0 (readback.rs).
    pub view_extras: Vec<Slot>,
    /// `per_draw`: each draw's own queries.
    pub draw_slots: Vec<DrawSlots>,
    /// At least one; more when labels were begun or ended inside the pass.
    pub sections: Vec<Section>,
    /// Labels open when the pass began (those inside it name its sections).
    label_base: usize,
    active_occlusion: Option<Slot>,
    active_statistics: Option<Slot>,
    measuring: bool,
    /// The current subpass runs secondary command buffers: the primary may record nothing but
    /// vkCmdExecuteCommands there, so the layer's timestamps go outside the pass.
    secondary_now: bool,
    /// A secondary command buffer's part of its executor's pass (RENDER_PASS_CONTINUE): no
    /// timestamps of its own, its resets made ahead of the submission.
    continued: bool,
    /// The current subpass, from 0.
    subpass: usize,
}

impl RecordedPass {
    /// Views the current subpass renders: each query of the layer's takes as many indices.
    fn views_now(&self) -> u32 {
        self.desc.view_counts.get(self.subpass).copied().unwrap_or(1).max(1)
    }

    /// A multiview pass: a timestamp inside it would write one query per view, so its pass
    /// timestamps are taken outside it and it has no section or per-draw timestamps.
    fn multiview(&self) -> bool {
        !self.desc.view_counts.is_empty()
    }

    /// The layer's timestamps cannot be written inside the pass now.
    fn stamps_outside(&self) -> bool {
        self.secondary_now || self.multiview()
    }

    pub fn not_measured(&self) -> Option<&str> {
        self.desc.not_measured.as_deref()
    }

    /// Whether a label call inside the pass split it into sections.
    pub fn split(&self) -> bool {
        self.sections.len() > 1
    }

    /// Section `index`'s ranges in the pass's occlusion, statistics, gaps and draw_slots lists.
    pub fn section_ranges(&self, index: usize) -> [std::ops::Range<usize>; 4] {
        let ends = [self.occlusion.len(), self.statistics.len(), self.gaps.len(), self.draw_slots.len()];
        let from = self.sections.get(index).map_or(ends, |s| s.from);
        let to = self.sections.get(index + 1).map_or(ends, |s| s.from);
        [0, 1, 2, 3].map(|i| from[i]..to[i].max(from[i]))
    }
}

/// The device's query support, as the layer enabled it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QuerySupport {
    pub statistics: bool,
    pub precise: bool,
    /// The command buffer's queue family writes timestamps.
    pub timestamps: bool,
}

#[derive(Debug)]
pub struct Recording {
    pub secondary: bool,
    /// Each draw gets segments and timestamps of its own (NOSTENCIL_FILLRATE_PER_DRAW).
    pub per_draw: bool,
    /// Begun with SIMULTANEOUS_USE.
    pub simultaneous: bool,
    pub passes: Vec<RecordedPass>,
    open: Option<usize>,
    labels: Vec<String>,
    inserted_label: Option<String>,
    /// Application queries active outside any pass: (pool, query) -> kind.
    app_active: HashMap<(vk::QueryPool, u32), QueryKind>,
    /// Query ranges the application resets in this recording.
    pub app_resets: Vec<(vk::QueryPool, u32, u32)>,
    pub support: QuerySupport,
    pub occlusion: SlotPool,
    pub statistics: SlotPool,
    pub timestamps: SlotPool,
    /// Dispatch groups and transfers outside render passes (work.rs).
    pub work: super::work::WorkState,
    /// Resets of slots used inside a render pass this recording did not begin (its own, as a
    /// secondary continuing its executor's pass, or those of the secondaries it executed): the
    /// layer records them in a command buffer of its own, ahead of the submission (copies.rs).
    pub deferred_resets: Vec<QueryCmd>,
    /// Secondary command buffers executed by this recording: their queries are in its passes
    /// and work.
    pub executed: Vec<vk::CommandBuffer>,
}

impl Recording {
    pub fn new(secondary: bool, support: QuerySupport) -> Self {
        Recording {
            secondary,
            per_draw: false,
            simultaneous: false,
            passes: Vec::new(),
            open: None,
            labels: Vec::new(),
            inserted_label: None,
            app_active: HashMap::new(),
            app_resets: Vec::new(),
            support,
            occlusion: SlotPool::new(QueryKind::Occlusion),
            statistics: SlotPool::new(QueryKind::Statistics),
            timestamps: SlotPool::new(QueryKind::Timestamp),
            work: Default::default(),
            deferred_resets: Vec::new(),
            executed: Vec::new(),
        }
    }

    /// vkBeginCommandBuffer / a reset: a fresh recording, keeping the pools.
    pub fn restart(&mut self, simultaneous: bool) {
        self.simultaneous = simultaneous;
        self.passes.clear();
        self.open = None;
        self.labels.clear();
        self.inserted_label = None;
        self.app_active.clear();
        self.app_resets.clear();
        self.occlusion.restart();
        self.statistics.restart();
        self.timestamps.restart();
        self.work.restart();
        self.deferred_resets.clear();
        self.executed.clear();
    }

    /// Every pool this recording created (to destroy with the command buffer).
    pub fn pools(&self) -> impl Iterator<Item = vk::QueryPool> + '_ {
        [&self.occlusion, &self.statistics, &self.timestamps, &self.work.compute]
            .into_iter()
            .flat_map(|s| s.pools.iter().copied())
    }

    /// An application statistics query is active outside any pass (a dispatch group then has
    /// no statistics of the layer's: two cannot be active at once).
    pub fn app_statistics_active(&self) -> bool {
        self.app_active.values().any(|k| *k == QueryKind::Statistics)
    }

    /// What the work bookkeeping (work.rs) needs to know now, and the work state itself.
    fn work_context(&mut self) -> (super::work::Context<'_>, &mut super::work::WorkState) {
        // The open label only: an inserted label names the next render pass, not work.
        let label = self.labels.last().cloned();
        let statistics = self.support.statistics && !self.app_statistics_active();
        let cx = super::work::Context {
            skip: self.open.is_some(),
            statistics,
            timestamps: self.support.timestamps.then_some(&mut self.timestamps),
            label,
        };
        (cx, &mut self.work)
    }

    /// A dispatch outside a render pass (work.rs): commands before the application's call.
    pub fn dispatch(
        &mut self,
        api: &'static str,
        groups: super::work::Workgroups,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
    ) -> Vec<QueryCmd> {
        let (cx, work) = self.work_context();
        work.dispatch(cx, api, groups, create)
    }

    /// A transfer outside a render pass (work.rs): commands before and after the call.
    pub fn transfer(
        &mut self,
        api: &'static str,
        moved: super::work::Moved,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
    ) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let (cx, work) = self.work_context();
        work.transfer(cx, api, moved, create)
    }

    /// Closes the open dispatch group: commands before whatever closes it.
    pub fn close_work(&mut self) -> Vec<QueryCmd> {
        self.work.close()
    }

    /// vkCmdBeginDebugUtilsLabelEXT: inside a pass, a new section begins (commands before and
    /// after the application's call).
    pub fn push_label(&mut self, label: String) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        // A label also ends a dispatch group (work.rs).
        let closed = self.close_work();
        self.labels.push(label);
        let (mut before, after) = self.split_section();
        before.splice(0..0, closed);
        (before, after)
    }

    /// vkCmdEndDebugUtilsLabelEXT: ending a label begun inside the pass begins a new section.
    pub fn pop_label(&mut self) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let closed = self.close_work();
        if !closed.is_empty() {
            // Outside any pass (a dispatch group was open): nothing of a pass's to split.
            self.labels.pop();
            return (closed, Vec::new());
        }
        self.labels.pop();
        let depth = self.labels.len();
        match self.open {
            Some(index) if depth < self.passes[index].label_base => {
                // A label begun before the pass ended inside it: nothing of the pass's closes.
                self.passes[index].label_base = depth;
                Default::default()
            }
            Some(_) => self.split_section(),
            None => Default::default(),
        }
    }

    /// Closes the open pass's current section and opens the next, named by the labels begun
    /// inside the pass that are open now.
    fn split_section(&mut self) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let (mut before, mut after) = (Vec::new(), Vec::new());
        let Some(index) = self.open else { return (before, after) };
        self.end_segments(None, &mut before);
        let base = self.passes[index].label_base.min(self.labels.len());
        let label = (base < self.labels.len()).then(|| self.labels[base..].join(" / "));
        let pass = &self.passes[index];
        if let Some(end) = pass.sections.last().and_then(Section::end_due) {
            before.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
        }
        let timed = pass.measuring
            && !pass.stamps_outside()
            && self.support.timestamps
            && pass.sections.len() <= TIMED_SECTIONS_PER_PASS as usize;
        let timestamps = if timed { self.timestamps.take().zip(self.timestamps.take()) } else { None };
        if let Some((begin, _)) = timestamps {
            after.push(QueryCmd::Timestamp { slot: begin, stage: vk::PipelineStageFlags::TOP_OF_PIPE });
        }
        let pass = &mut self.passes[index];
        let from = [pass.occlusion.len(), pass.statistics.len(), pass.gaps.len(), pass.draw_slots.len()];
        pass.sections.push(Section { label, from, draws: 0, timestamps, ended: false });
        (before, after)
    }

    /// The label a pass beginning now is named by (as `begin_pass` names it).
    pub fn label_now(&self) -> Option<String> {
        self.labels.last().cloned().or_else(|| self.inserted_label.clone())
    }

    pub fn insert_label(&mut self, label: String) {
        self.inserted_label = Some(label);
    }

    /// A draw command making `draws` draws (a multi-draw or an indirect draw makes several):
    /// counted in the open pass; returns the commands to record before and after it (the
    /// layer's segments begin here, see the module notes; with `per_draw` each draw command has
    /// segments and timestamps of its own, ended right after it).
    pub fn draw(&mut self, draws: u64) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let (mut before, mut after) = (Vec::new(), Vec::new());
        let Some(index) = self.open else { return (before, after) };
        self.passes[index].draws += draws;
        if let Some(section) = self.passes[index].sections.last_mut() {
            section.draws += draws;
        }
        if self.per_draw && self.passes[index].measuring && !self.passes[index].multiview() {
            self.end_segments(None, &mut before);
            let timestamps =
                if self.support.timestamps { self.timestamps.take().zip(self.timestamps.take()) } else { None };
            if let Some((begin, _)) = timestamps {
                before.push(QueryCmd::Timestamp { slot: begin, stage: vk::PipelineStageFlags::TOP_OF_PIPE });
            }
            self.begin_segment(QueryKind::Occlusion, &mut before);
            self.begin_segment(QueryKind::Statistics, &mut before);
            let pass = &mut self.passes[index];
            let slots = DrawSlots { occlusion: pass.active_occlusion, statistics: pass.active_statistics, timestamps };
            pass.draw_slots.push(slots);
            self.end_segments(None, &mut after);
            if let Some((_, end)) = timestamps {
                after.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
            }
            return (before, after);
        }
        self.begin_segment(QueryKind::Occlusion, &mut before);
        self.begin_segment(QueryKind::Statistics, &mut before);
        (before, after)
    }

    pub fn in_pass(&self) -> bool {
        self.open.is_some()
    }

    /// A render pass instance begins: (commands before the application's begin call, commands
    /// after it). `desc.not_measured` set: recorded but not measured.
    pub fn begin_pass(
        &mut self,
        desc: PassDesc,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
    ) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        self.open_pass_with(desc, create, false)
    }

    fn open_pass_with(
        &mut self,
        mut desc: PassDesc,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
        continued: bool,
    ) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let label = self.labels.last().cloned().or_else(|| self.inserted_label.take());
        if desc.not_measured.is_none() {
            // Occlusion named first when both are active (one reason per pass, the same each run).
            let active = |kind| self.app_active.values().any(|k| *k == kind);
            if active(QueryKind::Occlusion) {
                desc.not_measured = Some("application occlusion query active across the pass".into());
            } else if active(QueryKind::Statistics) {
                desc.not_measured = Some("application pipeline statistics query active across the pass".into());
            }
        }
        // A render pass ends a dispatch group (work.rs).
        let mut before = self.close_work();
        if desc.not_measured.is_none() {
            let support = self.support;
            // Resets go outside the pass: every slot the pass may use is reset before it.
            let sections = 2 * TIMED_SECTIONS_PER_PASS;
            let (mut segments, timestamps) = if self.per_draw {
                (DRAWS_PER_PASS, 2 + 2 * DRAWS_PER_PASS + sections)
            } else {
                (SEGMENTS_PER_PASS, 2 + sections)
            };
            let views = desc.views();
            if views > 1 {
                // A run of `views` slots per segment, and what runs skip at pool ends.
                segments = SEGMENTS_PER_PASS * views + CHUNK;
            }
            let mut ok = self.occlusion.reserve(segments, create, &mut before);
            if support.statistics {
                ok &= self.statistics.reserve(segments, create, &mut before);
            }
            if support.timestamps {
                ok &= self.timestamps.reserve(timestamps, create, &mut before);
            }
            if !ok {
                desc.not_measured = Some("the layer could not create a query pool".into());
            }
        }
        let measuring = desc.not_measured.is_none();
        let secondary_now = desc.secondary_contents;
        let outside = secondary_now || !desc.view_counts.is_empty();
        self.passes.push(RecordedPass {
            desc,
            label,
            draws: 0,
            occlusion: Vec::new(),
            statistics: Vec::new(),
            timestamps: None,
            gaps: Vec::new(),
            view_extras: Vec::new(),
            draw_slots: Vec::new(),
            sections: vec![Section { label: None, from: [0; 4], draws: 0, timestamps: None, ended: false }],
            label_base: self.labels.len(),
            active_occlusion: None,
            active_statistics: None,
            measuring,
            secondary_now,
            continued,
            subpass: 0,
        });
        self.open = Some(self.passes.len() - 1);
        let mut after = Vec::new();
        if measuring && !continued && self.support.timestamps {
            if let (Some(begin), Some(end)) = (self.timestamps.take(), self.timestamps.take()) {
                let stamp = QueryCmd::Timestamp { slot: begin, stage: vk::PipelineStageFlags::TOP_OF_PIPE };
                // Inside a subpass of secondary contents the primary records nothing but
                // vkCmdExecuteCommands, and inside a multiview pass a timestamp writes one query
                // per view: the pass is timed from before its begin.
                if outside {
                    before.push(stamp);
                } else {
                    after.push(stamp);
                }
                self.open_pass().timestamps = Some((begin, end));
            }
        }
        (before, after)
    }

    fn open_pass(&mut self) -> &mut RecordedPass {
        let index = self.open.unwrap_or(self.passes.len() - 1);
        &mut self.passes[index]
    }

    /// Begins a new layer segment of `kind` in the open pass, unless one is active or an
    /// application query of that kind is.
    fn begin_segment(&mut self, kind: QueryKind, out: &mut Vec<QueryCmd>) {
        let (support, precise) = (self.support, self.support.precise);
        let Some(index) = self.open else { return };
        let pass = &self.passes[index];
        let active = match kind {
            QueryKind::Occlusion => pass.active_occlusion.is_some(),
            _ => pass.active_statistics.is_some(),
        };
        if !pass.measuring || active || pass.gaps.iter().any(|g| g.open && g.kind == kind) {
            return;
        }
        let views = pass.views_now();
        let slot = match kind {
            QueryKind::Occlusion => self.occlusion.take_run(views),
            QueryKind::Statistics if support.statistics => self.statistics.take_run(views),
            _ => return,
        };
        let pass = &mut self.passes[index];
        let Some(slot) = slot else {
            pass.measuring = false;
            pass.desc.not_measured = Some(format!("more than {SEGMENTS_PER_PASS} query segments in one render pass"));
            return;
        };
        // Every index of the run is read back and summed: how a multiview query spreads its
        // results over the views' indices is the implementation's choice.
        let run = (0..views).map(|v| Slot { pool: slot.pool, query: slot.query + v });
        pass.view_extras.extend(run.clone().skip(1));
        match kind {
            QueryKind::Occlusion => {
                pass.occlusion.extend(run);
                pass.active_occlusion = Some(slot);
                out.push(QueryCmd::Begin { slot, precise });
            }
            _ => {
                pass.statistics.extend(run);
                pass.active_statistics = Some(slot);
                out.push(QueryCmd::Begin { slot, precise: false });
            }
        }
    }

    /// Ends the open pass's active layer segments (of `kind`, or both when None).
    fn end_segments(&mut self, kind: Option<QueryKind>, out: &mut Vec<QueryCmd>) {
        let Some(index) = self.open else { return };
        let pass = &mut self.passes[index];
        if kind != Some(QueryKind::Occlusion) {
            if let Some(slot) = pass.active_statistics.take() {
                out.push(QueryCmd::End { slot });
            }
        }
        if kind != Some(QueryKind::Statistics) {
            if let Some(slot) = pass.active_occlusion.take() {
                out.push(QueryCmd::End { slot });
            }
        }
    }

    /// vkCmdNextSubpass: (before, after); the next segments begin at the next draw.
    /// `secondary_contents`: the next subpass runs secondary command buffers (measured where
    /// they are executed); the section's end timestamp, if due, is written before the call.
    pub fn next_subpass(&mut self, secondary_contents: bool) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let mut before = Vec::new();
        let after = Vec::new();
        let Some(index) = self.open else { return (before, after) };
        self.end_segments(None, &mut before);
        let pass = &mut self.passes[index];
        if secondary_contents && !pass.stamps_outside() {
            if let Some(section) = pass.sections.last_mut() {
                if let Some(end) = section.end_due() {
                    before.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
                    section.ended = true;
                }
            }
        }
        pass.secondary_now = secondary_contents;
        pass.subpass += 1;
        (before, after)
    }

    /// The application ends the render pass instance: commands before its end call, and after it
    /// (the pass's end timestamp, where its last subpass ran secondary command buffers).
    pub fn end_pass(&mut self) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
        let (mut before, mut after) = (Vec::new(), Vec::new());
        let Some(index) = self.open else { return (before, after) };
        self.end_segments(None, &mut before);
        let pass = &mut self.passes[index];
        let stamps = if pass.stamps_outside() { &mut after } else { &mut before };
        if let Some(end) = pass.sections.last().and_then(Section::end_due) {
            stamps.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
        }
        if let Some((_, end)) = pass.timestamps {
            // The timestamps were taken when the pass began measuring; write the end one even if
            // the pass stopped measuring since, so the slot is never left unwritten.
            stamps.push(QueryCmd::Timestamp { slot: end, stage: vk::PipelineStageFlags::BOTTOM_OF_PIPE });
        }
        if pass.gaps.iter().any(|g| g.open) {
            pass.measuring = false;
            pass.desc.not_measured = Some("application query left active at the end of the pass".into());
        }
        self.open = None;
        (before, after)
    }

    /// The application begins a query of `kind`: commands before its call.
    pub fn app_begin_query(
        &mut self,
        kind: QueryKind,
        pool: vk::QueryPool,
        query: u32,
        precise: bool,
        statistics: vk::QueryPipelineStatisticFlags,
    ) -> Vec<QueryCmd> {
        let mut before = Vec::new();
        if kind == QueryKind::Timestamp {
            return before;
        }
        let Some(index) = self.open else {
            // The application's query must not overlap a dispatch group's.
            before.extend(self.close_work());
            self.app_active.insert((pool, query), kind);
            return before;
        };
        if !self.passes[index].measuring {
            return before;
        }
        self.end_segments(Some(kind), &mut before);
        let pass = &mut self.passes[index];
        pass.gaps.push(AppGap { kind, pool, query, precise, statistics, open: true });
        if kind == QueryKind::Occlusion && self.support.precise && !precise {
            pass.measuring = false;
            pass.desc.not_measured = Some("application imprecise occlusion query inside the pass".into());
            self.end_segments(None, &mut before);
        }
        before
    }

    /// The application ends a query: commands after its call (none: the next segment of that
    /// kind begins at the next draw).
    pub fn app_end_query(&mut self, pool: vk::QueryPool, query: u32) -> Vec<QueryCmd> {
        let after = Vec::new();
        if self.app_active.remove(&(pool, query)).is_some() {
            return after;
        }
        let Some(index) = self.open else { return after };
        let pass = &mut self.passes[index];
        let Some(gap) = pass.gaps.iter_mut().find(|g| g.open && g.pool == pool && g.query == query) else {
            return after;
        };
        gap.open = false;
        after
    }
}

mod secondaries;
pub use secondaries::Executed;

#[cfg(test)]
mod tests;
