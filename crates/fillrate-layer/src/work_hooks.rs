//! Hooks for compute work outside render passes (work.rs): the dispatches, and the commands
//! that close a dispatch group (barriers, event waits, secondary buffers, the end of the
//! buffer); and the helpers transfer_hooks.rs shares. Each records the layer's queries around
//! the application's call and passes the call on: through the tiler check's hook
//! (image_use.rs) when the check is on, which notes the images read, and straight to the next
//! layer otherwise.

use ash::vk;

use super::commands::{around, create_pool, measuring, pass_on_through_check};
use super::recording::Executed;
use super::slots::QueryCmd;
use super::state::{DeviceData, DeviceState};
use super::work::{Moved, Workgroups};

pub(super) type Cmds = (Vec<QueryCmd>, Vec<QueryCmd>);

/// A dispatch of `groups` workgroups on `cmd`.
fn dispatch(
    device: &DeviceData,
    st: &mut DeviceState,
    cmd: vk::CommandBuffer,
    api: &'static str,
    groups: Workgroups,
) -> Cmds {
    if !measuring(st) {
        return Default::default();
    }
    let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
    (data.recording.dispatch(api, groups, &mut |kind| create_pool(device, kind)), Vec::new())
}

/// A transfer on `cmd`; `moved` works out its bytes from the device's images and buffers.
pub(super) fn transfer(
    device: &DeviceData,
    st: &mut DeviceState,
    cmd: vk::CommandBuffer,
    api: &'static str,
    moved: impl FnOnce(&DeviceState) -> Moved,
) -> Cmds {
    if !measuring(st) {
        return Default::default();
    }
    let moved = moved(st);
    let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
    data.recording.transfer(api, moved, &mut |kind| create_pool(device, kind))
}

/// Closes `cmd`'s open dispatch group before the application's call.
fn close(st: &mut DeviceState, cmd: vk::CommandBuffer) -> Cmds {
    let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
    (data.recording.close_work(), Vec::new())
}

fn groups(x: u32, y: u32, z: u32) -> Workgroups {
    Workgroups::Recorded(x as u64 * y as u64 * z as u64)
}

pub(super) unsafe extern "system" fn cmd_dispatch(cmd: vk::CommandBuffer, x: u32, y: u32, z: u32) {
    around(
        cmd,
        |d| {
            pass_on_through_check!(d, cmd_dispatch(cmd, x, y, z));
        },
        |d, st| dispatch(d, st, cmd, "vkCmdDispatch", groups(x, y, z)),
    );
}

pub(super) unsafe extern "system" fn cmd_dispatch_indirect(cmd: vk::CommandBuffer, buffer: vk::Buffer, offset: u64) {
    around(
        cmd,
        |d| {
            pass_on_through_check!(d, cmd_dispatch_indirect(cmd, buffer, offset));
        },
        |d, st| dispatch(d, st, cmd, "vkCmdDispatchIndirect", Workgroups::Indirect(buffer, offset)),
    );
}

macro_rules! dispatch_base_hook {
    ($name:ident, $field:ident) => {
        #[allow(clippy::too_many_arguments)]
        pub(super) unsafe extern "system" fn $name(
            cmd: vk::CommandBuffer,
            base_x: u32,
            base_y: u32,
            base_z: u32,
            x: u32,
            y: u32,
            z: u32,
        ) {
            around(
                cmd,
                |d| {
                    if let Some(next) = d.next.$field {
                        // SAFETY: the application's arguments, passed on.
                        unsafe { next(cmd, base_x, base_y, base_z, x, y, z) }
                    }
                },
                |d, st| dispatch(d, st, cmd, "vkCmdDispatchBase", groups(x, y, z)),
            );
        }
    };
}

dispatch_base_hook!(cmd_dispatch_base, cmd_dispatch_base);
dispatch_base_hook!(cmd_dispatch_base_khr, cmd_dispatch_base_khr);

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_pipeline_barrier(
    cmd: vk::CommandBuffer,
    src: vk::PipelineStageFlags,
    dst: vk::PipelineStageFlags,
    flags: vk::DependencyFlags,
    memory_count: u32,
    memory: *const vk::MemoryBarrier<'_>,
    buffer_count: u32,
    buffers: *const vk::BufferMemoryBarrier<'_>,
    image_count: u32,
    images: *const vk::ImageMemoryBarrier<'_>,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_pipeline_barrier {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, src, dst, flags, memory_count, memory, buffer_count, buffers, image_count, images) }
            }
        },
        |_, st| close(st, cmd),
    );
}

unsafe fn pipeline_barrier2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCmdPipelineBarrier2>,
    cmd: vk::CommandBuffer,
    info: *const vk::DependencyInfo<'_>,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = pick(d) {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, info) }
            }
        },
        |_, st| close(st, cmd),
    );
}

pub(super) unsafe extern "system" fn cmd_pipeline_barrier2(
    cmd: vk::CommandBuffer,
    info: *const vk::DependencyInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { pipeline_barrier2_with(|d| d.next.cmd_pipeline_barrier2, cmd, info) }
}

pub(super) unsafe extern "system" fn cmd_pipeline_barrier2_khr(
    cmd: vk::CommandBuffer,
    info: *const vk::DependencyInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { pipeline_barrier2_with(|d| d.next.cmd_pipeline_barrier2_khr, cmd, info) }
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_wait_events(
    cmd: vk::CommandBuffer,
    event_count: u32,
    events: *const vk::Event,
    src: vk::PipelineStageFlags,
    dst: vk::PipelineStageFlags,
    memory_count: u32,
    memory: *const vk::MemoryBarrier<'_>,
    buffer_count: u32,
    buffers: *const vk::BufferMemoryBarrier<'_>,
    image_count: u32,
    images: *const vk::ImageMemoryBarrier<'_>,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_wait_events {
                // SAFETY: the application's arguments, passed on.
                unsafe {
                    next(
                        cmd,
                        event_count,
                        events,
                        src,
                        dst,
                        memory_count,
                        memory,
                        buffer_count,
                        buffers,
                        image_count,
                        images,
                    )
                }
            }
        },
        |_, st| close(st, cmd),
    );
}

unsafe fn wait_events2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCmdWaitEvents2>,
    cmd: vk::CommandBuffer,
    count: u32,
    events: *const vk::Event,
    infos: *const vk::DependencyInfo<'_>,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = pick(d) {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, count, events, infos) }
            }
        },
        |_, st| close(st, cmd),
    );
}

pub(super) unsafe extern "system" fn cmd_wait_events2(
    cmd: vk::CommandBuffer,
    count: u32,
    events: *const vk::Event,
    infos: *const vk::DependencyInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { wait_events2_with(|d| d.next.cmd_wait_events2, cmd, count, events, infos) }
}

pub(super) unsafe extern "system" fn cmd_wait_events2_khr(
    cmd: vk::CommandBuffer,
    count: u32,
    events: *const vk::Event,
    infos: *const vk::DependencyInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { wait_events2_with(|d| d.next.cmd_wait_events2_khr, cmd, count, events, infos) }
}

pub(super) unsafe extern "system" fn cmd_execute_commands(
    cmd: vk::CommandBuffer,
    count: u32,
    buffers: *const vk::CommandBuffer,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_execute_commands {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, count, buffers) }
            }
        },
        |_, st| {
            let before = close(st, cmd).0;
            // SAFETY: the application's array of `count` buffers.
            let secondaries = unsafe { super::arrays::app_array(buffers, count) };
            for &secondary in secondaries {
                let part = match st.buffers.get(&secondary) {
                    Some(data) => data.recording.executed_part(),
                    None => Executed {
                        unusable: Some("secondary command buffer allocated before the layer saw it".into()),
                        ..Default::default()
                    },
                };
                if let Some(data) = st.buffers.get_mut(&cmd) {
                    data.recording.execute(secondary, part);
                }
            }
            (before, Vec::new())
        },
    );
}

/// vkEndCommandBuffer: the open dispatch group ends before the buffer does.
pub(super) unsafe extern "system" fn end_command_buffer(cmd: vk::CommandBuffer) -> vk::Result {
    let mut result = vk::Result::ERROR_INITIALIZATION_FAILED;
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.end_command_buffer {
                // SAFETY: the application's arguments, passed on.
                result = unsafe { next(cmd) };
            }
        },
        |_, st| {
            let (mut before, after) = close(st, cmd);
            if let Some(data) = st.buffers.get_mut(&cmd) {
                before.extend(data.recording.end_continued_pass());
            }
            (before, after)
        },
    );
    result
}
