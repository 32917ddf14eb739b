//! Queue and synchronisation hooks: submissions record which measured passes ran, in order;
//! a present closes the frame; a fence, a queue or device idle proves submissions complete, and
//! their results are read back then.

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::objects::{device_and, flush_buffer, spoil_gaps};
use super::readback::{read_completed, write_if_due};
use super::state::{guard, DeviceData, DeviceState, Pending};

/// Notes the command buffers of one vkQueueSubmit(2) call, in submission order.
fn submitted(
    device: &DeviceData,
    state: &mut DeviceState,
    queue: vk::Queue,
    buffers: &[vk::CommandBuffer],
    fence: vk::Fence,
) {
    for &buffer in buffers {
        let simultaneous = state.buffers.get(&buffer).is_some_and(|b| b.recording.simultaneous);
        if simultaneous {
            // The earlier submission may still run: read it if a fence proves it done, else its
            // results are about to be overwritten by this one.
            if state.pending.iter().any(|p| p.buffer == buffer) {
                poll_fences(device, state);
            }
            for pending in state.pending.iter_mut().filter(|p| p.buffer == buffer) {
                pending
                    .spoiled
                    .get_or_insert_with(|| "command buffer resubmitted while in use (SIMULTANEOUS_USE)".into());
            }
        } else {
            // Without SIMULTANEOUS_USE the buffer's last submission has completed (valid usage).
            flush_buffer(device, state, buffer);
        }
        // The application's resets in this buffer may overwrite queries the layer still reads.
        let resets = state.buffers.get(&buffer).map(|b| b.recording.app_resets.clone()).unwrap_or_default();
        for (pool, first, count) in resets {
            spoil_gaps(state, pool, first, count, "application reset its query before the layer read it");
        }
    }
    let measuring = !state.finished && state.frames().measuring();
    for &buffer in buffers {
        if !measuring {
            break;
        }
        let Some(data) = state.buffers.get(&buffer) else { continue };
        if data.recording.passes.is_empty() {
            continue;
        }
        let passes = data.recording.passes.clone();
        let family = state.command_pools.get(&data.pool).copied().unwrap_or(0);
        let timestamp_bits = device.info.timestamp_bits.get(family as usize).copied().unwrap_or(0);
        state.sequence += 1;
        let frame = state.frames().submitted();
        state.pending.push(Pending {
            queue,
            sequence: state.sequence,
            frame,
            buffer,
            passes,
            timestamp_bits,
            spoiled: None,
        });
    }
    if fence != vk::Fence::null() {
        state.fences.insert(fence, (queue, state.sequence));
    }
}

/// Records the command buffers a submit sends (`gather` reads them from the application's
/// submit infos), so that their passes are read back once the submit is known complete.
fn note_submit(
    device: &DeviceData,
    queue: vk::Queue,
    fence: vk::Fence,
    gather: impl FnOnce() -> Vec<vk::CommandBuffer>,
) {
    guard((), || {
        if device.active() {
            submitted(device, &mut device.state(), queue, &gather(), fence);
        }
    });
}

pub(super) unsafe extern "system" fn queue_submit(
    queue: vk::Queue,
    count: u32,
    submits: *const vk::SubmitInfo<'_>,
    fence: vk::Fence,
) -> vk::Result {
    let Some((device, next)) = device_and(queue.as_raw(), |d| d.next.queue_submit) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    note_submit(&device, queue, fence, || {
        // SAFETY: `submits` holds `count` valid submit infos, each with its buffer array.
        let submits = unsafe { app_array(submits, count) };
        // SAFETY: as above.
        submits
            .iter()
            .flat_map(|s| unsafe { app_array(s.p_command_buffers, s.command_buffer_count) })
            .copied()
            .collect()
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(queue, count, submits, fence) }
}

unsafe fn queue_submit2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkQueueSubmit2>,
    queue: vk::Queue,
    count: u32,
    submits: *const vk::SubmitInfo2<'_>,
    fence: vk::Fence,
) -> vk::Result {
    let Some((device, next)) = device_and(queue.as_raw(), pick) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    note_submit(&device, queue, fence, || {
        // SAFETY: `submits` holds `count` valid VkSubmitInfo2, each with its buffer infos.
        let submits = unsafe { app_array(submits, count) };
        submits
            .iter()
            // SAFETY: as above.
            .flat_map(|s| unsafe { app_array(s.p_command_buffer_infos, s.command_buffer_info_count) })
            .map(|info| info.command_buffer)
            .collect()
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(queue, count, submits, fence) }
}

pub(super) unsafe extern "system" fn queue_submit2(
    queue: vk::Queue,
    count: u32,
    submits: *const vk::SubmitInfo2<'_>,
    fence: vk::Fence,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { queue_submit2_with(|d| d.next.queue_submit2, queue, count, submits, fence) }
}

pub(super) unsafe extern "system" fn queue_submit2_khr(
    queue: vk::Queue,
    count: u32,
    submits: *const vk::SubmitInfo2<'_>,
    fence: vk::Fence,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { queue_submit2_with(|d| d.next.queue_submit2_khr, queue, count, submits, fence) }
}

pub(super) unsafe extern "system" fn queue_present(
    queue: vk::Queue,
    info: *const vk::PresentInfoKHR<'_>,
) -> vk::Result {
    let Some((device, next)) = device_and(queue.as_raw(), |d| d.next.queue_present) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(queue, info) };
    guard((), || {
        if device.active() {
            let mut st = device.state();
            st.frames().present();
            if st.frames().finish_ready() > 0 {
                write_if_due(&device, &mut st, false);
            }
        }
    });
    result
}

/// Reads back what any fence the application submitted with proves complete, asking the fences'
/// status (no waiting).
fn poll_fences(device: &DeviceData, state: &mut DeviceState) {
    let Some(status) = device.next.get_fence_status else { return };
    let fences: Vec<(vk::Fence, vk::Queue, u64)> = state
        .fences
        .iter()
        .filter(|(_, (queue, sequence))| state.pending.iter().any(|p| p.queue == *queue && p.sequence <= *sequence))
        .map(|(&fence, &(queue, sequence))| (fence, queue, sequence))
        .collect();
    for (fence, queue, sequence) in fences {
        // SAFETY: a fence of this device the application submitted (a destroyed one would be an
        // application error: it may not destroy a fence a pending submission signals).
        if unsafe { status(device.handle, fence) } == vk::Result::SUCCESS {
            read_completed(device, state, |p| p.queue == queue && p.sequence <= sequence);
        }
    }
}

/// `fence` has signalled: its submission and everything before it on its queue are complete.
fn fence_signalled(device: &DeviceData, state: &mut DeviceState, fence: vk::Fence) {
    if let Some(&(queue, sequence)) = state.fences.get(&fence) {
        read_completed(device, state, |p| p.queue == queue && p.sequence <= sequence);
    }
}

pub(super) unsafe extern "system" fn wait_for_fences(
    device: vk::Device,
    count: u32,
    fences: *const vk::Fence,
    wait_all: vk::Bool32,
    timeout: u64,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.wait_for_fences) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, count, fences, wait_all, timeout) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            if !data.active() {
                return;
            }
            // SAFETY: `fences` holds `count` handles.
            let fences = unsafe { app_array(fences, count) };
            let mut st = data.state();
            for &fence in fences {
                let signalled = wait_all == vk::TRUE
                    // SAFETY: a fence of this device, which the application just waited on.
                    || data.next.get_fence_status.is_some_and(|status| unsafe { status(device, fence) } == vk::Result::SUCCESS);
                if signalled {
                    fence_signalled(&data, &mut st, fence);
                }
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn get_fence_status(device: vk::Device, fence: vk::Fence) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.get_fence_status) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, fence) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            if data.active() {
                fence_signalled(&data, &mut data.state(), fence);
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn queue_wait_idle(queue: vk::Queue) -> vk::Result {
    let Some((device, next)) = device_and(queue.as_raw(), |d| d.next.queue_wait_idle) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(queue) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            if device.active() {
                read_completed(&device, &mut device.state(), |p| p.queue == queue);
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn device_wait_idle(device: vk::Device) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.device_wait_idle) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            if data.active() {
                read_completed(&data, &mut data.state(), |_| true);
            }
        });
    }
    result
}
