//! One-off submissions (uploads, bakes, read-backs): record into a fresh primary command
//! buffer, submit, wait on a fence. A frame's submissions reuse their slot's command buffer
//! and fence instead (`frame_submission`).

use ash::vk;

use super::context::Gpu;
use super::live_objects::ObjectKind;
use crate::error::{Result, VkContext};

/// One primary command buffer from the GPU's pool (freed by the caller, into the same pool).
pub fn allocate_primary(gpu: &Gpu) -> Result<vk::CommandBuffer> {
    let pool = gpu.command_pool();
    let info = vk::CommandBufferAllocateInfo::default()
        .command_pool(*pool)
        .level(vk::CommandBufferLevel::PRIMARY)
        .command_buffer_count(1);
    // SAFETY: the pool belongs to this device and is locked while it allocates; `info` asks for
    // exactly one buffer, so `[0]` exists.
    let cmd = unsafe { gpu.raw().allocate_command_buffers(&info) }.vk("vkAllocateCommandBuffers")?[0];
    gpu.created(ObjectKind::CommandBuffer);
    Ok(cmd)
}

/// Frees a command buffer from `allocate_primary`.
pub fn free_primary(gpu: &Gpu, cmd: vk::CommandBuffer) {
    let pool = gpu.command_pool();
    // SAFETY: `cmd` came from this pool (`allocate_primary`) and the caller has made sure it is
    // not pending.
    unsafe { gpu.raw().free_command_buffers(*pool, &[cmd]) };
    gpu.destroyed(ObjectKind::CommandBuffer);
}

/// Records `record` into a one-time command buffer, submits it and waits for completion.
pub fn submit_and_wait<T>(gpu: &Gpu, record: impl FnOnce(vk::CommandBuffer) -> Result<T>) -> Result<T> {
    submit_and_wait_timed(gpu, record).map(|(value, _)| value)
}

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

fn submit_and_wait_timed<T>(
    gpu: &Gpu,
    record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
) -> Result<(T, CpuPhases)> {
    let device = gpu.raw();
    let cmd = allocate_primary(gpu)?;
    let start = std::time::Instant::now();
    let since = |at: std::time::Instant| at.duration_since(start).as_secs_f64() * 1e3;
    let mut phases = CpuPhases::default();

    let result = (|| {
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: `cmd` is a fresh primary buffer of `device`, begun and ended once here. For
        // this and the calls below: a `Gpu` is driven from one thread at a time (nothing in the
        // crate shares one across threads), the external synchronisation pool and queue need.
        unsafe { device.begin_command_buffer(cmd, &begin) }.vk("vkBeginCommandBuffer")?;
        let value = record(cmd)?;
        // SAFETY: `cmd` is recording (begun above).
        unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
        phases.record = (0.0, since(std::time::Instant::now()));

        // SAFETY: a plain unsignalled fence of `device`.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")?;
        gpu.created(ObjectKind::Fence);
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        let submit_start = since(std::time::Instant::now());
        // SAFETY: `cmd` is ended, `fence` unsignalled and unused; `submit` outlives the call.
        let submitted = unsafe { device.queue_submit(gpu.device.queue, &submit, fence) }.vk("vkQueueSubmit");
        let wait_start = since(std::time::Instant::now());
        phases.submit = (submit_start, wait_start - submit_start);
        let wait_began = std::time::Instant::now();
        // SAFETY: `fence` is alive.
        let waited =
            submitted.and_then(|_| unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }.vk("vkWaitForFences"));
        gpu.waited(wait_began.elapsed());
        phases.wait = (wait_start, since(std::time::Instant::now()) - wait_start);
        // SAFETY: the fence is signalled, or was never submitted, or the device is lost.
        unsafe { device.destroy_fence(fence, None) };
        gpu.destroyed(ObjectKind::Fence);
        waited.map(|_| (value, phases))
    })();
    // `cmd` is not pending: it was never submitted, or the fence wait returned (a failed wait
    // means the device is lost).
    free_primary(gpu, cmd);
    result
}
