//! The one place that records and submits command buffers: record into a fresh primary
//! command buffer, submit, wait on a fence. Offscreen rendering needs nothing more elaborate.

use ash::vk;

use super::context::Gpu;
use crate::error::{Result, VkContext};

/// Records `record` into a one-time command buffer, submits it and waits for completion.
pub fn submit_and_wait<T>(gpu: &Gpu, record: impl FnOnce(vk::CommandBuffer) -> Result<T>) -> Result<T> {
    let device = gpu.raw();
    let cmd = {
        let pool = gpu.command_pool();
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        unsafe { device.allocate_command_buffers(&info) }.vk("vkAllocateCommandBuffers")?[0]
    };
    let free = || {
        let pool = gpu.command_pool();
        unsafe { device.free_command_buffers(*pool, &[cmd]) };
    };

    let result = (|| {
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        unsafe { device.begin_command_buffer(cmd, &begin) }.vk("vkBeginCommandBuffer")?;
        let value = record(cmd)?;
        unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;

        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")?;
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        let submitted = unsafe { device.queue_submit(gpu.device.queue, &submit, fence) }.vk("vkQueueSubmit");
        let waited =
            submitted.and_then(|_| unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }.vk("vkWaitForFences"));
        unsafe { device.destroy_fence(fence, None) };
        waited.map(|_| value)
    })();
    free();
    result
}
