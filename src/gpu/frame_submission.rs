//! A frame slot's submission: a command pool with one command buffer, and a fence, made once
//! and used frame after frame, as a game's frames in flight use theirs. Submitting does not
//! wait; `wait` waits for the slot's last submission, the one wait a steady-state frame makes
//! (on the slot it is about to reuse), and hands the reset of the slot's pool to a worker
//! thread, which frees what the last frame recorded while the next one is prepared.

use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Instant;

use ash::vk;

use super::context::Gpu;
use super::faults::{self, Submission};
use super::live_objects::ObjectKind;
use super::thread_time::thread_cpu_ns;
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
    /// The slot's own pool (one per frame in flight, as Vulkan's guides have it), holding
    /// `cmd` alone: reset whole between frames, which frees at once whatever the frame recorded.
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// What the pending submission does ("the frame's passes: ..."), for a failed wait; None
    /// when nothing is pending.
    pending: Option<String>,
    /// Where the reset of `pool` stands, shared with the worker running it.
    reset: Arc<PoolReset>,
}

/// A command pool's reset, handed to a worker thread once the slot's submission finished:
/// lavapipe frees every command a frame recorded one by one (thousands on a heavy frame), which
/// is then off the render thread's path, as an engine resets its frame's pools off the main
/// thread. Its CPU time is counted on the device's activity, as a job's.
#[derive(Default)]
struct PoolReset {
    state: Mutex<ResetState>,
    finished: Condvar,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
enum ResetState {
    /// Ready to record: a new pool, or one reset since its last recording.
    #[default]
    Ready,
    /// Recorded into and not reset: reset it before recording again.
    Used,
    /// A worker is resetting it.
    Running,
    /// The worker's reset failed.
    Failed(vk::Result),
}

impl PoolReset {
    fn state(&self) -> MutexGuard<'_, ResetState> {
        // A poisoned lock means a worker panicked mid-reset; the state it left is still one of
        // the four, and the next `submit` acts on it.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Waits until no worker is resetting the pool; the state it left.
    fn joined(&self) -> ResetState {
        let mut state = self.state();
        while *state == ResetState::Running {
            state = self.finished.wait(state).unwrap_or_else(|p| p.into_inner());
        }
        *state
    }
}

impl SubmitSlot {
    pub fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let device = gpu.raw();
        // Its buffer is recorded again every frame: transient.
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.device.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        // SAFETY: `gpu` holds the device, and `queue_family` is its queue's family.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        gpu.created(ObjectKind::CommandPool);
        // Owns the pool from here: a failure below destroys it with what it made.
        let mut slot = SubmitSlot {
            gpu: gpu.clone(),
            pool,
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            pending: None,
            reset: Arc::default(),
        };
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is this device's, used by this thread alone; one buffer asked, so
        // `[0]` exists.
        slot.cmd = unsafe { device.allocate_command_buffers(&info) }.vk("vkAllocateCommandBuffers")?[0];
        gpu.created(ObjectKind::CommandBuffer);
        // SAFETY: `gpu` holds the device; a plain unsignalled fence.
        slot.fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")?;
        gpu.created(ObjectKind::Fence);
        Ok(slot)
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
            return Err(Error::Internal(
                "a frame slot was submitted again before its last frame was waited for".into(),
            ));
        }
        let device = self.gpu.raw();
        let start = Instant::now();
        let since = |at: Instant| at.duration_since(start).as_secs_f64() * 1e3;
        let mut phases = CpuPhases::default();
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        match self.reset.joined() {
            ResetState::Ready => {}
            // Never handed to a worker (its last submission was not waited for through `wait`).
            // SAFETY: nothing of the pool is pending (no submission is, checked above), and no
            // worker holds it (joined); this thread is the pool's only user.
            ResetState::Used => unsafe { device.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty()) }
                .vk("vkResetCommandPool")?,
            ResetState::Running => return Err(Error::Internal("a frame slot's reset was still running".into())),
            ResetState::Failed(result) => return Err(Error::Vulkan { call: "vkResetCommandPool", result }),
        }
        *self.reset.state() = ResetState::Used;
        // SAFETY: the command buffer is in its initial state (its pool reset, or new), and this
        // thread is its pool's only user. A `Gpu` is driven from one thread at a time, the
        // external synchronisation the queue needs.
        unsafe { device.begin_command_buffer(self.cmd, &begin) }.vk("vkBeginCommandBuffer")?;
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
        self.reset_elsewhere();
        Ok(Some(took.as_secs_f64() * 1e3))
    }

    /// Hands the reset of the slot's pool, whose submission has finished, to a worker thread;
    /// the next `submit` waits for it before recording.
    fn reset_elsewhere(&mut self) {
        let mut state = self.reset.state();
        if *state != ResetState::Used {
            return;
        }
        *state = ResetState::Running;
        drop(state);
        let (gpu, reset, pool) = (self.gpu.clone(), self.reset.clone(), self.pool);
        rayon::spawn(move || {
            let start = thread_cpu_ns();
            // SAFETY: nothing of the pool is pending (its one buffer's fence signalled) and the
            // slot touches the pool only once this reset is joined (`submit`, `drop`): this
            // worker is its only user meanwhile.
            let result = unsafe { gpu.raw().reset_command_pool(pool, vk::CommandPoolResetFlags::empty()) };
            if let (Some(start), Some(end)) = (start, thread_cpu_ns()) {
                gpu.counted_pool_reset_cpu(end.saturating_sub(start));
            }
            *reset.state() = match result {
                Ok(()) => ResetState::Ready,
                Err(result) => ResetState::Failed(result),
            };
            reset.finished.notify_all();
        });
    }
}

impl Drop for SubmitSlot {
    fn drop(&mut self) {
        // A failed wait means the device is lost: nothing runs any more either way.
        let _ = self.wait();
        self.reset.joined();
        let device = self.gpu.raw();
        // SAFETY: nothing is pending (waited above) and no worker holds the pool (joined); each
        // handle is destroyed once, the null ones of a slot whose making failed skipped.
        unsafe {
            if self.fence != vk::Fence::null() {
                device.destroy_fence(self.fence, None);
                self.gpu.destroyed(ObjectKind::Fence);
            }
            if self.cmd != vk::CommandBuffer::null() {
                device.free_command_buffers(self.pool, &[self.cmd]);
                self.gpu.destroyed(ObjectKind::CommandBuffer);
            }
            device.destroy_command_pool(self.pool, None);
        }
        self.gpu.destroyed(ObjectKind::CommandPool);
    }
}
