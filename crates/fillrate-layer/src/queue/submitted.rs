//! What a submission records: each command buffer's measured passes and work, in submission
//! order, with the layer's buffers around them (the resets of secondaries' queries first, the
//! result copies last); read back once the submission is proven complete (queue.rs).

use std::sync::Once;

use ash::vk;

use super::{forget_proven_signals, poll_fences};
use crate::config::FrameOn;
use crate::copies;
use crate::frame_cuts;
use crate::in_flight::TimelineSignal;
use crate::objects::{flush_buffer, spoil_gaps};
use crate::state::{DeviceData, DeviceState, Pending};

/// One batch of a submit call: its command buffers, and whether the layer may append buffers of
/// its own to it.
pub(super) struct Batch {
    pub(super) buffers: Vec<vk::CommandBuffer>,
    pub(super) can_copy: bool,
    /// The semaphores it signals with their values (a timeline's; a binary one's is ignored).
    pub(super) signals: Vec<(vk::Semaphore, u64)>,
    /// It ends a frame (VkFrameBoundaryEXT with FRAME_END in its chain).
    pub(super) frame_end: bool,
}

/// The layer's command buffers for one batch: those that reset the queries of secondary command
/// buffers (copies.rs), submitted first, and the result copies, submitted last.
#[derive(Default)]
pub(super) struct LayerBuffers {
    pub(super) first: Vec<vk::CommandBuffer>,
    pub(super) last: Vec<vk::CommandBuffer>,
}

impl LayerBuffers {
    pub(super) fn is_empty(&self) -> bool {
        self.first.is_empty() && self.last.is_empty()
    }
}

/// Notes the command buffers of one vkQueueSubmit(2) call, in submission order. Returns, per
/// batch, the layer's copy command buffers (copies.rs) to submit at the end of that batch: never
/// between two of the application's buffers, where a render pass may be suspended in one and
/// resumed in the next (a suspended render pass is resumed within its batch: VUID-VkSubmitInfo2-
/// commandBuffer-06010, VUID-VkSubmitInfo-pCommandBuffers-06193). Each batch gets its own: a
/// semaphore signalled by a batch, which the application may wait for and then free or reset the
/// batch's buffers, covers the batch's copies too, and no later batch's.
pub(super) fn submitted(
    device: &DeviceData,
    state: &mut DeviceState,
    queue: vk::Queue,
    batches: &[Batch],
    fence: vk::Fence,
) -> Vec<LayerBuffers> {
    if device.config.tiler {
        // The check reads the command stream in submission order (a resubmitted buffer runs,
        // and is read, again).
        for &buffer in batches.iter().flat_map(|b| &b.buffers) {
            let DeviceState { tiler, buffers, .. } = &mut *state;
            if let Some(data) = buffers.get(&buffer) {
                tiler.check.process(&data.tiler.events);
            }
        }
    }
    for &buffer in batches.iter().flat_map(|b| &b.buffers) {
        let simultaneous = state.buffers.get(&buffer).is_some_and(|b| b.recording.simultaneous);
        if simultaneous {
            // The earlier submission may still run: read it if a fence proves it done. With a
            // copy of its own on this queue it keeps its results; otherwise this submission is
            // about to overwrite them.
            if state.pending.iter().any(|p| p.buffer == buffer) {
                poll_fences(device, state);
            }
            for pending in state.pending.iter_mut().filter(|p| p.buffer == buffer) {
                let why = match (&pending.copy, pending.queue == queue) {
                    (Some(_), true) => continue,
                    (Some(_), false) => "command buffer resubmitted on another queue while in use (SIMULTANEOUS_USE)",
                    (None, _) => "command buffer resubmitted while in use (SIMULTANEOUS_USE)",
                };
                pending.spoiled.get_or_insert_with(|| why.into());
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
    let mut copies = Vec::new();
    // Where each submission of this call was noted in `state.pending`: (batch, position).
    let mut noted: Vec<(usize, usize)> = Vec::new();
    for (b, batch) in batches.iter().enumerate() {
        let mut batch_copies = Vec::new();
        let mut batch_resets = Vec::new();
        for &buffer in &batch.buffers {
            if !measuring {
                break;
            }
            let Some(data) = state.buffers.get(&buffer) else { continue };
            if data.recording.passes.is_empty() && data.recording.work.list.is_empty() {
                continue;
            }
            let passes = data.recording.passes.clone();
            let work = data.recording.work.list.clone();
            let secondaries = data.recording.executed.clone();
            let deferred = data.recording.deferred_resets.clone();
            let family = state.command_pools.get(&data.pool).copied().unwrap_or(0);
            let timestamp_bits = device.info.timestamp_bits.get(family as usize).copied().unwrap_or(0);
            let copy = if batch.can_copy {
                // Without a copy the results are read from the pools, as long as nothing
                // re-submits the buffer before (the spoiling above says so if it does).
                copies::make(device, state, family, &passes, &work).unwrap_or_else(|why| {
                    static ONCE: Once = Once::new();
                    ONCE.call_once(|| eprintln!("nostencil fill-rate layer: {why}; results read from the query pools"));
                    None
                })
            } else {
                None
            };
            batch_copies.extend(copy.as_ref().map(|c| c.command_buffer));
            // Queries used inside render passes this buffer did not begin (its secondaries'):
            // reset by a buffer of the layer's first in the batch.
            let (resets, unreset) = match (deferred.is_empty(), batch.can_copy) {
                (true, _) => (None, None),
                (false, false) => {
                    (None, Some("secondary command buffers in a batch the layer cannot add to".to_owned()))
                }
                (false, true) => match copies::make_resets(device, state, family, &deferred) {
                    Ok(resets) => (Some(resets), None),
                    Err(why) => (None, Some(why)),
                },
            };
            batch_resets.extend(resets.map(|(_, cmd)| cmd));
            state.sequence += 1;
            let frame = state.frames().submitted();
            noted.push((b, state.pending.len()));
            state.pending.push(Pending {
                queue,
                sequence: state.sequence,
                frame,
                buffer,
                passes,
                work,
                timestamp_bits,
                spoiled: unreset,
                copy,
                secondaries,
                resets,
            });
        }
        copies.push(LayerBuffers { first: batch_resets, last: batch_copies });
        if batch.frame_end {
            frame_cuts::boundary(device, state);
        }
        let sequence = state.sequence;
        if state.pending.iter().any(|p| p.queue == queue && p.sequence <= sequence) {
            let signals =
                batch.signals.iter().map(|&(semaphore, value)| TimelineSignal { semaphore, value, queue, sequence });
            state.timeline_signals.extend(signals);
        }
    }
    // A buffer submitted twice in one call (SIMULTANEOUS_USE): the second run overwrites the
    // first's queries before the first's copy (at the end of its batch) or read-back sees them.
    for (i, &(batch, at)) in noted.iter().enumerate() {
        let buffer = state.pending[at].buffer;
        let has_copy = state.pending[at].copy.is_some();
        let overwritten = noted[i + 1..]
            .iter()
            .any(|&(later_batch, later)| state.pending[later].buffer == buffer && (!has_copy || later_batch == batch));
        if overwritten {
            state.pending[at]
                .spoiled
                .get_or_insert_with(|| "command buffer submitted again before its results were copied".into());
        }
    }
    if fence != vk::Fence::null() {
        state.fences.insert(fence, (queue, state.sequence));
    }
    forget_proven_signals(state);
    if frame_cuts::cuts_on(device, state, FrameOn::Submit) {
        frame_cuts::cut(device, state);
    }
    copies
}
