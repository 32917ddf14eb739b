//! Fences of the layer's own that prove submissions complete. A program may never wait on a fence
//! the layer sees (timeline semaphores, vkd3d's fence thread, a program that only presents), and
//! then its frames would never be read back. At each present the layer submits an empty batch
//! with a fence of its own to that queue (vkQueueSubmit with no batch: the fence signals once all
//! work submitted to the queue before it completes); later presents poll those fences without
//! waiting and read back what they prove done.

use ash::vk;

use super::in_flight::Proof;
use super::readback::read_completed;
use super::state::{DeviceData, DeviceState};

/// Reads back what signalled proofs show complete, recycling their fences; never waits.
pub fn poll(device: &DeviceData, state: &mut DeviceState) {
    let proofs = std::mem::take(&mut state.proofs);
    for proof in proofs {
        // SAFETY: the layer's own fence on the live device.
        let signalled = unsafe { device.fns.get_fence_status(proof.fence) }.unwrap_or(false);
        if !signalled {
            state.proofs.push(proof);
            continue;
        }
        read_completed(device, state, |p| p.queue == proof.queue && p.sequence <= proof.sequence);
        // SAFETY: the fence is signalled and no longer used by any submission.
        if unsafe { device.fns.reset_fences(&[proof.fence]) }.is_ok() {
            state.spare_fences.push(proof.fence);
        } else {
            // SAFETY: as above; a fence that cannot be reset is not reused.
            unsafe { device.fns.destroy_fence(proof.fence, None) };
        }
    }
}

/// Submits a proof for `queue` if it has submissions waiting to be read back that no proof
/// covers yet. Called from the application's vkQueuePresentKHR on `queue`, which the
/// application synchronises externally for the call.
pub fn add(device: &DeviceData, state: &mut DeviceState, queue: vk::Queue) {
    let Some(latest) = state.pending.iter().filter(|p| p.queue == queue).map(|p| p.sequence).max() else { return };
    if state.proofs.iter().any(|p| p.queue == queue && p.sequence >= latest) {
        return;
    }
    let Some(submit) = device.next.queue_submit else { return };
    let fence = match state.spare_fences.pop() {
        Some(fence) => fence,
        // SAFETY: plain fence creation on the live device.
        None => match unsafe { device.fns.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(fence) => fence,
            Err(_) => return,
        },
    };
    // SAFETY: no batch, only the layer's unsignalled fence; the queue is held by the caller.
    if unsafe { submit(queue, 0, std::ptr::null(), fence) } == vk::Result::SUCCESS {
        state.proofs.push(Proof { fence, queue, sequence: latest });
    } else {
        state.spare_fences.push(fence);
    }
}

/// Destroys every fence of the layer's (at vkDestroyDevice, after the application's own wait).
pub fn destroy(device: &DeviceData, state: &mut DeviceState) {
    let fences = state.proofs.drain(..).map(|p| p.fence).chain(state.spare_fences.drain(..));
    for fence in fences.collect::<Vec<_>>() {
        // SAFETY: the layer's own fences; the application waited for its work before destroying
        // the device, and an empty batch has nothing else to finish.
        unsafe { device.fns.destroy_fence(fence, None) };
    }
}
