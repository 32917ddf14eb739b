//! Queue and synchronisation hooks: submissions record which measured passes ran, in order;
//! a present closes the frame; a fence, a queue or device idle, or a timeline semaphore reaching
//! a value a batch signals proves submissions complete, and their results are read back then.

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::capture;
use super::config::FrameOn;
use super::frame_boundary;
use super::frame_cuts;
use super::in_flight::TimelineSignal;
use super::objects::device_and;
use super::proofs;
use super::readback::{read_completed, write_if_due};
use super::state::{guard, DeviceData, DeviceState};

mod submitted;
use submitted::{submitted, Batch, LayerBuffers};

/// Drops the timeline signals that would prove nothing still pending.
fn forget_proven_signals(state: &mut DeviceState) {
    let pending = &state.pending;
    state.timeline_signals.retain(|s| pending.iter().any(|p| p.queue == s.queue && p.sequence <= s.sequence));
}

/// The signal values of a VkSubmitInfo's signal semaphores, from its
/// VkTimelineSemaphoreSubmitInfo (none without one: binary semaphores only).
///
/// # Safety
/// `info` is a valid VkSubmitInfo with its pNext chain.
unsafe fn signals_of(info: &vk::SubmitInfo<'_>) -> Vec<(vk::Semaphore, u64)> {
    let mut p_next = info.p_next;
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next.cast()) };
        if ty == vk::StructureType::TIMELINE_SEMAPHORE_SUBMIT_INFO {
            // SAFETY: the node is a VkTimelineSemaphoreSubmitInfo; its value array holds
            // signalSemaphoreValueCount values (equal to signalSemaphoreCount when not 0).
            let values = unsafe {
                let timeline = &*(p_next as *const vk::TimelineSemaphoreSubmitInfo<'_>);
                app_array(timeline.p_signal_semaphore_values, timeline.signal_semaphore_value_count)
            };
            // SAFETY: the batch's signal semaphores.
            let semaphores = unsafe { app_array(info.p_signal_semaphores, info.signal_semaphore_count) };
            return semaphores.iter().copied().zip(values.iter().copied()).collect();
        }
        p_next = next;
    }
    Vec::new()
}

/// `semaphore` has reached `value`: the batches whose signals it passed are complete, with
/// everything before them on their queues. Reads them back.
fn timeline_reached(device: &DeviceData, state: &mut DeviceState, semaphore: vk::Semaphore, value: u64) {
    let (reached, rest): (Vec<TimelineSignal>, Vec<TimelineSignal>) = std::mem::take(&mut state.timeline_signals)
        .into_iter()
        .partition(|s| s.semaphore == semaphore && s.value <= value);
    state.timeline_signals = rest;
    for signal in reached {
        read_completed(device, state, |p| p.queue == signal.queue && p.sequence <= signal.sequence);
    }
    forget_proven_signals(state);
}

/// vkWaitSemaphores and its KHR alias: a successful wait proves the batches that signal what it
/// waited for complete (with VK_SEMAPHORE_WAIT_ANY, those whose semaphore has got there).
unsafe fn wait_semaphores_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkWaitSemaphores>,
    device: vk::Device,
    info: *const vk::SemaphoreWaitInfo<'_>,
    timeout: u64,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), pick) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, timeout) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            if !data.active() {
                return;
            }
            // SAFETY: the application's valid wait info, with `semaphoreCount` of each array.
            let (info, semaphores, values) = unsafe {
                let info = &*info;
                (
                    info,
                    app_array(info.p_semaphores, info.semaphore_count),
                    app_array(info.p_values, info.semaphore_count),
                )
            };
            let any = info.flags.contains(vk::SemaphoreWaitFlags::ANY);
            let counter = data.next.get_semaphore_counter_value.or(data.next.get_semaphore_counter_value_khr);
            let mut st = data.state();
            for (&semaphore, &value) in semaphores.iter().zip(values) {
                let reached = if any {
                    let Some(counter) = counter else { continue };
                    let mut now = 0u64;
                    // SAFETY: a timeline semaphore of this device the application just waited on.
                    if unsafe { counter(device, semaphore, &mut now) } != vk::Result::SUCCESS {
                        continue;
                    }
                    now
                } else {
                    value
                };
                timeline_reached(&data, &mut st, semaphore, reached);
            }
            waited(&data, &mut st);
        });
    }
    result
}

/// A successful host wait: the frame ends here with `--frame-on wait`.
fn waited(device: &DeviceData, state: &mut DeviceState) {
    if frame_cuts::cuts_on(device, state, FrameOn::Wait) {
        frame_cuts::cut(device, state);
    }
}

pub(super) unsafe extern "system" fn wait_semaphores(
    device: vk::Device,
    info: *const vk::SemaphoreWaitInfo<'_>,
    timeout: u64,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { wait_semaphores_with(|d| d.next.wait_semaphores, device, info, timeout) }
}

pub(super) unsafe extern "system" fn wait_semaphores_khr(
    device: vk::Device,
    info: *const vk::SemaphoreWaitInfo<'_>,
    timeout: u64,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { wait_semaphores_with(|d| d.next.wait_semaphores_khr, device, info, timeout) }
}

/// vkGetSemaphoreCounterValue and its KHR alias: the value read proves its signals done.
unsafe fn get_semaphore_counter_value_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkGetSemaphoreCounterValue>,
    device: vk::Device,
    semaphore: vk::Semaphore,
    value: *mut u64,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), pick) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, semaphore, value) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            if data.active() {
                // SAFETY: the call succeeded, so `value` holds the counter.
                let reached = unsafe { *value };
                timeline_reached(&data, &mut data.state(), semaphore, reached);
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn get_semaphore_counter_value(
    device: vk::Device,
    semaphore: vk::Semaphore,
    value: *mut u64,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { get_semaphore_counter_value_with(|d| d.next.get_semaphore_counter_value, device, semaphore, value) }
}

pub(super) unsafe extern "system" fn get_semaphore_counter_value_khr(
    device: vk::Device,
    semaphore: vk::Semaphore,
    value: *mut u64,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { get_semaphore_counter_value_with(|d| d.next.get_semaphore_counter_value_khr, device, semaphore, value) }
}

/// vkDestroySemaphore: every batch that refers to the semaphore has completed (valid usage), so
/// its signals prove their submissions done; read them, then forget them (the handle may be
/// reused).
pub(super) unsafe extern "system" fn destroy_semaphore(
    device: vk::Device,
    semaphore: vk::Semaphore,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.destroy_semaphore) else { return };
    guard((), || {
        if data.active() {
            timeline_reached(&data, &mut data.state(), semaphore, u64::MAX);
        }
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, semaphore, allocator) }
}

/// Records the command buffers a submit sends (`gather` reads its batches from the application's
/// submit infos), so that their passes are read back once the submit is known complete; returns
/// the layer's command buffers to append to each batch.
fn note_submit(
    device: &DeviceData,
    queue: vk::Queue,
    fence: vk::Fence,
    gather: impl FnOnce() -> Vec<Batch>,
) -> Vec<LayerBuffers> {
    guard(Vec::new(), || {
        if !device.active() {
            return Vec::new();
        }
        submitted(device, &mut device.state(), queue, &gather(), fence)
    })
}

/// Whether a VkSubmitInfo's chain allows more command buffers: a device group's per-buffer
/// masks must match the count, and a protected batch takes no unprotected buffer.
///
/// # Safety
/// `p_next` is a valid pNext chain.
unsafe fn batch_extendable(mut p_next: *const std::ffi::c_void) -> bool {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next.cast()) };
        if ty == vk::StructureType::DEVICE_GROUP_SUBMIT_INFO || ty == vk::StructureType::PROTECTED_SUBMIT_INFO {
            return false;
        }
        p_next = next;
    }
    true
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
    // SAFETY: `submits` holds `count` valid submit infos, each with its buffer array.
    let infos = unsafe { app_array(submits, count) };
    let copies = note_submit(&device, queue, fence, || {
        infos
            .iter()
            .map(|s| Batch {
                // SAFETY: as above.
                buffers: unsafe { app_array(s.p_command_buffers, s.command_buffer_count) }.to_vec(),
                // SAFETY: as above.
                can_copy: unsafe { batch_extendable(s.p_next) },
                // SAFETY: as above.
                signals: unsafe { signals_of(s) },
                // SAFETY: as above.
                frame_end: unsafe { frame_cuts::frame_end(s.p_next) },
            })
            .collect()
    });
    // The batches' frame boundaries (read above) are kept from a driver that lacks them, and
    // put back after the call.
    let emulated = device.info.frame_boundary_emulated;
    // SAFETY: the application's infos, restored below.
    let unlinked =
        unsafe { frame_boundary::strip(emulated, submits, count, |s| std::ptr::addr_of_mut!((*s).p_next).cast()) };
    if copies.iter().all(LayerBuffers::is_empty) {
        // SAFETY: the application's arguments, passed on.
        let result = unsafe { next(queue, count, submits, fence) };
        // SAFETY: the same infos.
        unsafe { unlinked.restore() };
        return result;
    }
    let buffers: Vec<Vec<vk::CommandBuffer>> = infos
        .iter()
        .zip(&copies)
        .map(|(info, layer)| {
            let mut all = layer.first.clone();
            // SAFETY: as above.
            all.extend(unsafe { app_array(info.p_command_buffers, info.command_buffer_count) });
            all.extend(&layer.last);
            all
        })
        .collect();
    let mut batches = infos.to_vec();
    for (batch, buffers) in batches.iter_mut().zip(&buffers) {
        batch.command_buffer_count = buffers.len() as u32;
        batch.p_command_buffers = buffers.as_ptr();
    }
    // SAFETY: the application's batches, each with the layer's buffers around its own.
    let result = unsafe { next(queue, count, batches.as_ptr(), fence) };
    // SAFETY: the same infos.
    unsafe { unlinked.restore() };
    result
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
    // SAFETY: `submits` holds `count` valid VkSubmitInfo2, each with its buffer infos.
    let infos = unsafe { app_array(submits, count) };
    let copies = note_submit(&device, queue, fence, || {
        infos
            .iter()
            .map(|s| Batch {
                // SAFETY: as above.
                buffers: unsafe { app_array(s.p_command_buffer_infos, s.command_buffer_info_count) }
                    .iter()
                    .map(|info| info.command_buffer)
                    .collect(),
                can_copy: !s.flags.contains(vk::SubmitFlags::PROTECTED),
                // SAFETY: as above.
                signals: unsafe { app_array(s.p_signal_semaphore_infos, s.signal_semaphore_info_count) }
                    .iter()
                    .map(|info| (info.semaphore, info.value))
                    .collect(),
                // SAFETY: as above.
                frame_end: unsafe { frame_cuts::frame_end(s.p_next) },
            })
            .collect()
    });
    let emulated = device.info.frame_boundary_emulated;
    // SAFETY: the application's infos, restored below.
    let unlinked =
        unsafe { frame_boundary::strip(emulated, submits, count, |s| std::ptr::addr_of_mut!((*s).p_next).cast()) };
    if copies.iter().all(LayerBuffers::is_empty) {
        // SAFETY: the application's arguments, passed on.
        let result = unsafe { next(queue, count, submits, fence) };
        // SAFETY: the same infos.
        unsafe { unlinked.restore() };
        return result;
    }
    let buffers: Vec<Vec<vk::CommandBufferSubmitInfo>> = infos
        .iter()
        .zip(&copies)
        .map(|(info, layer)| {
            // SAFETY: as above.
            let own = unsafe { app_array(info.p_command_buffer_infos, info.command_buffer_info_count) };
            // The same device mask as the batch's first and last buffers (0: all devices).
            let mask_first = own.first().map_or(0, |b| b.device_mask);
            let mask_last = own.last().map_or(0, |b| b.device_mask);
            let info =
                |c: vk::CommandBuffer, mask| vk::CommandBufferSubmitInfo::default().command_buffer(c).device_mask(mask);
            let mut all: Vec<_> = layer.first.iter().map(|&c| info(c, mask_first)).collect();
            all.extend(own);
            all.extend(layer.last.iter().map(|&c| info(c, mask_last)));
            all
        })
        .collect();
    let mut batches = infos.to_vec();
    for (batch, buffers) in batches.iter_mut().zip(&buffers) {
        batch.command_buffer_info_count = buffers.len() as u32;
        batch.p_command_buffer_infos = buffers.as_ptr();
    }
    // SAFETY: the application's batches, each with the layer's buffers after its own.
    let result = unsafe { next(queue, count, batches.as_ptr(), fence) };
    // SAFETY: the same infos.
    unsafe { unlinked.restore() };
    result
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
    // SAFETY: the application's valid present info (or null), for the call.
    let app_info = unsafe { info.as_ref() };
    // SAFETY: as above; the queue is the caller's for the call.
    let capturing = guard(None, || app_info.and_then(|i| unsafe { capture::begin(&device, queue, i) }));
    // SAFETY: as above. The present's frame boundary, read here, is kept from a driver that
    // lacks it and put back right after the call.
    let boundary = app_info.is_some_and(|i| unsafe { frame_cuts::frame_end(i.p_next) });
    let emulated = device.info.frame_boundary_emulated;
    // SAFETY: the application's info, restored below.
    let unlinked = unsafe { frame_boundary::strip(emulated, info, 1, |i| std::ptr::addr_of_mut!((*i).p_next).cast()) };
    let result = match (&capturing, app_info) {
        // SAFETY: the application's present, waiting on the layer's copy instead (which waited
        // on the application's semaphores).
        (Some(c), Some(app_info)) => unsafe { next(queue, &c.patched(app_info)) },
        // SAFETY: the application's arguments, passed on.
        _ => unsafe { next(queue, info) },
    };
    // SAFETY: the same info.
    unsafe { unlinked.restore() };
    if let Some(capturing) = capturing {
        guard((), || capture::finish(&device, capturing));
    }
    guard((), || {
        if device.active() {
            let mut st = device.state();
            if device.config.tiler {
                st.tiler.check.end_frame();
            }
            if boundary {
                frame_cuts::boundary(&device, &mut st);
            } else if frame_cuts::cuts_on(&device, &st, FrameOn::Present) {
                st.frames().present();
            }
            proofs::poll(&device, &mut st);
            proofs::add(&device, &mut st, queue);
            if super::readback::finish_frames(&device, &mut st) > 0 {
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
            waited(&data, &mut st);
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
                let mut st = device.state();
                read_completed(&device, &mut st, |p| p.queue == queue);
                waited(&device, &mut st);
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
                let mut st = data.state();
                read_completed(&data, &mut st, |_| true);
                waited(&data, &mut st);
            }
        });
    }
    result
}
