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
    submit_and_wait_once(gpu, record)
}

fn submit_and_wait_once<T>(gpu: &Gpu, record: impl FnOnce(vk::CommandBuffer) -> Result<T>) -> Result<T> {
    let device = gpu.raw();
    let cmd = allocate_primary(gpu)?;
    let result = (|| {
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: `cmd` is a fresh primary buffer of `device`, begun and ended once here. For
        // this and the calls below: a `Gpu` is driven from one thread at a time (nothing in the
        // crate shares one across threads), the external synchronisation pool and queue need.
        unsafe { device.begin_command_buffer(cmd, &begin) }.vk("vkBeginCommandBuffer")?;
        let value = record(cmd)?;
        // SAFETY: `cmd` is recording (begun above).
        unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;

        // SAFETY: a plain unsignalled fence of `device`.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")?;
        gpu.created(ObjectKind::Fence);
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: `cmd` is ended, `fence` unsignalled and unused; `submit` outlives the call.
        let submitted = unsafe { device.queue_submit(gpu.device.queue, &submit, fence) }.vk("vkQueueSubmit");
        let wait_began = std::time::Instant::now();
        // SAFETY: `fence` is alive.
        let waited =
            submitted.and_then(|_| unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }.vk("vkWaitForFences"));
        gpu.waited(wait_began.elapsed());
        // SAFETY: the fence is signalled, or was never submitted, or the device is lost.
        unsafe { device.destroy_fence(fence, None) };
        gpu.destroyed(ObjectKind::Fence);
        waited.map(|_| value)
    })();
    // `cmd` is not pending: it was never submitted, or the fence wait returned (a failed wait
    // means the device is lost).
    free_primary(gpu, cmd);
    result
}
