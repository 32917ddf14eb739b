//! What a frame's recording leaves beside its commands: the measured passes with what each
//! drew and bound, the render pass instances and their tile traffic, and the commands counted.
//! Kept apart from `recorder`, whose calls record the commands and tell this what they did.

use super::instances::RenderPassInstance;
use crate::frame::render_pass::{AttachmentDesc, RenderPassTraffic};

pub(crate) struct PassRecord {
    pub name: String,
    /// What the technique drew in it itself (`DrawKind::describe` of its own draw kind), for
    /// [`FrameCounters::drawing`](super::counters::FrameCounters::drawing).
    pub own_draw: Option<&'static str>,
    /// The light the plan drew the pass for (`PlannedPass::light`).
    pub light: Option<u8>,
    pub draws: u32,
    /// State and draw commands it recorded (binds, pushes, scissors, draws, clears).
    pub commands: u32,
    /// Labels of the pipelines bound in the pass, in first-bound order (the plan test compares
    /// them with the plan).
    pub pipelines: Vec<&'static str>,
    /// The render pass instances its draws went into (`FrameRecord::instances`).
    pub instances: Vec<u32>,
}

/// One frame's bookkeeping, filled in as it is recorded.
#[derive(Default)]
pub(crate) struct FrameRecord {
    pub(crate) passes: Vec<PassRecord>,
    /// What each render pass begun moves to and from main memory on a tile-based GPU.
    pub(crate) render_passes: Vec<RenderPassTraffic>,
    /// Every render pass instance begun, in order, with the measured passes drawn into it.
    pub(crate) instances: Vec<RenderPassInstance>,
    /// The render pass instance open now, if any.
    open_instance: Option<u32>,
    /// A measured pass is open (the last of `passes`).
    open: bool,
    /// State and draw commands recorded so far (`Activity::commands`).
    pub(crate) commands: u64,
}

impl FrameRecord {
    /// Whether a measured pass is open.
    pub(crate) fn pass_open(&self) -> bool {
        self.open
    }

    /// The measured pass open now.
    fn open_pass(&mut self) -> Option<&mut PassRecord> {
        self.passes.last_mut().filter(|_| self.open)
    }

    /// Opens measured pass `name`: drawn into the render pass instance open now, if any (the
    /// frame's render pass).
    pub(crate) fn begin_pass(&mut self, name: &str) {
        let instances: Vec<u32> = self.open_instance.into_iter().collect();
        if let Some(instance) = self.open_instance.and_then(|i| self.instances.get_mut(i as usize)) {
            instance.passes.push(name.to_owned());
        }
        self.passes.push(PassRecord {
            name: name.to_owned(),
            own_draw: None,
            light: None,
            draws: 0,
            commands: 0,
            pipelines: Vec::new(),
            instances,
        });
        self.open = true;
    }

    pub(crate) fn end_pass(&mut self) {
        self.open = false;
    }

    /// Notes that the open pass bound the pipeline labelled `name`.
    pub(crate) fn bound(&mut self, name: &'static str) {
        if let Some(pass) = self.open_pass() {
            if !pass.pipelines.contains(&name) {
                pass.pipelines.push(name);
            }
        }
    }

    /// Counts a draw recorded: in the last pass's draws, and as a command.
    pub(crate) fn count_draw(&mut self) {
        self.count_commands(1);
        if let Some(pass) = self.passes.last_mut() {
            pass.draws += 1;
        }
    }

    /// Counts `count` state and draw commands recorded: the frame's, and the open pass's.
    pub(crate) fn count_commands(&mut self, count: u64) {
        self.commands += count;
        if let Some(pass) = self.open_pass() {
            pass.commands += count as u32;
        }
    }

    /// Notes a render pass begun over a `width` x `height` area, its attachments
    /// `attachments`: its tile traffic (under the open measured pass, else under "frame") and
    /// its instance, which the open measured pass (a prepass) draws into.
    pub(crate) fn begin_render_pass(&mut self, attachments: &[AttachmentDesc], (width, height): (u32, u32)) {
        let pass = match (self.open, self.passes.last()) {
            (true, Some(p)) => p.name.clone(),
            _ => "frame".to_owned(),
        };
        let traffic = RenderPassTraffic {
            pass,
            width,
            height,
            count: 1,
            attachments: attachments.iter().map(|a| a.tile_traffic(width, height)).collect(),
        };
        let same = |t: &&mut RenderPassTraffic| {
            (&t.pass, t.width, t.height, &t.attachments)
                == (&traffic.pass, traffic.width, traffic.height, &traffic.attachments)
        };
        let index = self.instances.len() as u32;
        let mut instance = RenderPassInstance {
            index,
            width,
            height,
            samples: attachments.iter().map(|a| a.samples).max().unwrap_or(1),
            attachments: traffic.attachments.clone(),
            passes: Vec::new(),
        };
        if let Some(pass) = self.open_pass() {
            pass.instances.push(index);
            instance.passes.push(pass.name.clone());
        }
        self.instances.push(instance);
        self.open_instance = Some(index);
        match self.render_passes.iter_mut().find(same) {
            Some(alike) => alike.count += 1,
            None => self.render_passes.push(traffic),
        }
    }

    pub(crate) fn end_render_pass(&mut self) {
        self.open_instance = None;
    }
}
