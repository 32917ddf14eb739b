//! A frame slot's submission: a command buffer and a fence made once and used frame after
//! frame, as a game's frames in flight use theirs. Submitting does not wait; `wait` waits for
//! the slot's last submission, the one wait a steady-state frame makes (on the slot it is about
//! to reuse).

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use super::commands::{allocate_primary, free_primary};
use super::context::Gpu;
use super::faults::{self, Submission};
use super::live_objects::ObjectKind;
use crate::error::{Error, Result, VkContext};

/// What a frame's submission waits on and signals besides its fence: for a frame drawn into a
/// swapchain image, the image's acquire and its present.
#[derive(Debug, Clone, Copy, Default)]
pub struct FrameSync {
    /// Waited on before the given stages run.
    pub wait: Option<(vk::Semaphore, vk::PipelineStageFlags)>,
    /// Signalled when the frame's commands complete.
    pub signal: Option<vk::Semaphore>,
}

/// Where the CPU spent a submission's time: (start, duration) in milliseconds from the start of
/// its recording, for recording (begin to end of the command buffer), vkQueueSubmit and the
/// fence wait (`--trace`'s CPU track).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct CpuPhases {
    pub record: (f64, f64),
    pub submit: (f64, f64),
    pub wait: (f64, f64),
}

pub struct SubmitSlot {
    gpu: Arc<Gpu>,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// What the pending submission does ("the frame's passes: ..."), for a failed wait; None
    /// when nothing is pending.
    pending: Option<String>,
}

impl SubmitSlot {
    pub fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let cmd = allocate_primary(gpu)?;
        // SAFETY: `gpu` holds the device; a plain unsignalled fence.
        let fence = match unsafe { gpu.raw().create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence") {
            Ok(fence) => fence,
            Err(e) => {
                free_primary(gpu, cmd);
                return Err(e);
            }
        };
        gpu.created(ObjectKind::Fence);
        Ok(SubmitSlot { gpu: gpu.clone(), cmd, fence, pending: None })
    }

    /// Whether a submission of this slot may still be running.
    pub fn is_pending(&self) -> bool {
        self.pending.is_some()
    }

    /// Records `record` into the slot's command buffer and submits it with `sync`, without
    /// waiting. The slot must not be pending (`wait` first). `work` names what the recording
    /// returned (its passes), for a failed submit now or a failed wait later.
    pub fn submit<T>(
        &mut self,
        sync: FrameSync,
        work: impl Fn(&T) -> String,
        record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
    ) -> Result<(T, CpuPhases)> {
        if self.pending.is_some() {
            return Err(Error::Internal("a frame slot was submitted again before its last frame was waited for".into()));
        }
        let device = self.gpu.raw();
        let start = Instant::now();
        let since = |at: Instant| at.duration_since(start).as_secs_f64() * 1e3;
        let mut phases = CpuPhases::default();
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the command buffer is not pending (no submission is, checked above); its pool
        // allows resetting one buffer. A `Gpu` is driven from one thread at a time, the external
        // synchronisation the pool and queue need.
        unsafe {
            device.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty()).vk("vkResetCommandBuffer")?;
            device.begin_command_buffer(self.cmd, &begin).vk("vkBeginCommandBuffer")?;
        }
        let value = record(self.cmd)?;
        let described = work(&value);
        let injected = faults::submit_fault(Submission::Frame);
        // SAFETY: the command buffer is recording (begun above).
        unsafe { device.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")?;
        phases.record = (0.0, since(Instant::now()));

        let cmds = [self.cmd];
        let mut info = vk::SubmitInfo::default().command_buffers(&cmds);
        // Set only when there are some: an empty slice would still pass a pointer.
        let (wait, stage) = (sync.wait.map(|(s, _)| [s]), sync.wait.map(|(_, stage)| [stage]));
        if let (Some(wait), Some(stage)) = (&wait, &stage) {
            info = info.wait_semaphores(wait).wait_dst_stage_mask(stage);
        }
        let signal = sync.signal.map(|s| [s]);
        if let Some(signal) = &signal {
            info = info.signal_semaphores(signal);
        }
        let submit_start = since(Instant::now());
        // SAFETY: the fence is not pending (nothing is), so it may be reset.
        unsafe { device.reset_fences(&[self.fence]) }.vk("vkResetFences")?;
        let submitted = match injected {
            Some(result) => Err(result),
            // SAFETY: the command buffer is ended, the fence unsignalled and unused; `info` and
            // the arrays it points at outlive the call.
            None => unsafe { device.queue_submit(self.gpu.device.queue, &[info], self.fence) },
        };
        phases.submit = (submit_start, since(Instant::now()) - submit_start);
        submitted.map_err(|result| Error::Submit { work: described.clone(), call: "vkQueueSubmit", result })?;
        self.pending = Some(described);
        Ok((value, phases))
    }

    /// Waits for the slot's last submission, if one is pending: how long it waited, in ms.
    pub fn wait(&mut self) -> Result<Option<f64>> {
        let Some(work) = self.pending.take() else { return Ok(None) };
        let began = Instant::now();
        // SAFETY: the fence is alive and was submitted with the pending submission.
        let waited = unsafe { self.gpu.raw().wait_for_fences(&[self.fence], true, u64::MAX) };
        let took = began.elapsed();
        self.gpu.waited(took);
        waited.map_err(|result| Error::Submit { work, call: "vkWaitForFences", result })?;
        Ok(Some(took.as_secs_f64() * 1e3))
    }
}

impl Drop for SubmitSlot {
    fn drop(&mut self) {
        // A failed wait means the device is lost: nothing runs any more either way.
        let _ = self.wait();
        // SAFETY: nothing is pending (waited above); each handle is destroyed once.
        unsafe { self.gpu.raw().destroy_fence(self.fence, None) };
        self.gpu.destroyed(ObjectKind::Fence);
        free_primary(&self.gpu, self.cmd);
    }
}
