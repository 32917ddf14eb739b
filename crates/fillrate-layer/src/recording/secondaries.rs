//! Secondary command buffers: a secondary that continues its executor's render pass measures
//! its own draws (its segments begin at its draws, its resets are kept for the submission), and
//! the buffer that executes it takes in its queries, its own passes and its work (recording.rs).

use ash::vk;

use super::{PassDesc, QueryCmd, QueryKind, RecordedPass, Recording};

/// What a secondary command buffer brings to the command buffer that executes it: its part of
/// the executor's pass, the passes it begins itself, its work, and its deferred resets.
#[derive(Debug, Clone, Default)]
pub struct Executed {
    pub continued: Option<RecordedPass>,
    pub passes: Vec<RecordedPass>,
    pub work: Vec<crate::work::RecordedWork>,
    pub resets: Vec<QueryCmd>,
    /// Why its figures cannot be used (begun without the layer, or not ended).
    pub unusable: Option<String>,
}

impl Recording {
    /// A secondary command buffer begun with RENDER_PASS_CONTINUE: its draws are part of the
    /// pass that executes it. Its segments begin at its draws as in any pass; its slots' resets
    /// cannot be recorded inside a render pass, so they are kept for the executor's submission
    /// (`deferred_resets`), and it takes no timestamps of its own (the executor's pass has them).
    pub fn begin_continued_pass(&mut self, desc: PassDesc, create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>) {
        let (resets, _) = self.open_pass_with(desc, create, true);
        self.deferred_resets.extend(resets.into_iter().filter(|c| matches!(c, QueryCmd::Reset { .. })));
    }

    /// vkEndCommandBuffer of a secondary that continued its executor's pass: its segments end
    /// before the buffer does (commands before the call).
    pub fn end_continued_pass(&mut self) -> Vec<QueryCmd> {
        match self.open {
            Some(index) if self.passes[index].continued => self.end_pass().0,
            _ => Vec::new(),
        }
    }

    /// What this recording, a secondary command buffer, brings to the buffer that executes it.
    pub fn executed_part(&self) -> Executed {
        let continued = self.passes.iter().find(|p| p.continued).cloned();
        let unusable = match (self.open, &continued) {
            (Some(_), _) => Some("secondary command buffer executed before it was ended".to_owned()),
            _ => None,
        };
        Executed {
            continued,
            passes: self.passes.iter().filter(|p| !p.continued).cloned().collect(),
            work: self.work.list.clone(),
            resets: self.deferred_resets.clone(),
            unusable,
        }
    }

    /// vkCmdExecuteCommands of `secondary`, whose part is `part`. Inside a pass, its continued
    /// part's segments, gaps and draws join the open pass (they sum into it at read-back);
    /// outside, its own passes and work join this recording's, in order. A secondary executed
    /// twice in one recording would reuse its queries before they are read: that pass (or that
    /// work) is not measured.
    pub fn execute(&mut self, secondary: vk::CommandBuffer, part: Executed) {
        let twice = self.executed.contains(&secondary);
        self.executed.push(secondary);
        const TWICE: &str = "secondary command buffer executed twice in one command buffer";
        let Some(index) = self.open else {
            // Outside a pass: the work rows and passes it recorded, where it is executed.
            let mut passes = part.passes;
            let mut work = part.work;
            if twice || part.unusable.is_some() {
                let why = part.unusable.clone().unwrap_or_else(|| TWICE.to_owned());
                for pass in &mut passes {
                    pass.measuring = false;
                    pass.desc.not_measured.get_or_insert_with(|| why.clone());
                }
                for w in &mut work {
                    w.statistics = None;
                    w.timestamps = None;
                    w.not_measured.get_or_insert_with(|| why.clone());
                }
            }
            self.passes.extend(passes);
            self.work.list.extend(work);
            self.deferred_resets.extend(part.resets);
            return;
        };
        let pass = &mut self.passes[index];
        if !pass.measuring {
            return;
        }
        let why = match (&part.continued, twice, &part.unusable) {
            (_, _, Some(why)) => Some(why.clone()),
            (_, true, _) => Some(TWICE.to_owned()),
            (None, _, _) => Some("secondary command buffer not begun to continue a render pass".to_owned()),
            (Some(p), _, _) => p.desc.not_measured.clone(),
        };
        if let Some(why) = why {
            pass.measuring = false;
            pass.desc.not_measured = Some(why);
            return;
        }
        let Some(inner) = part.continued else { return };
        pass.draws += inner.draws;
        if let Some(section) = pass.sections.last_mut() {
            section.draws += inner.draws;
        }
        pass.occlusion.extend(inner.occlusion);
        pass.statistics.extend(inner.statistics);
        pass.gaps.extend(inner.gaps);
        pass.view_extras.extend(inner.view_extras);
        pass.draw_slots.extend(inner.draw_slots);
        self.deferred_resets.extend(part.resets);
    }
}
