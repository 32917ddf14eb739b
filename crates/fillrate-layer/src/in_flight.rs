//! What the layer keeps per submission until the GPU is proven done with it: the copy of a
//! submission's query results (`copies`) and the fences that prove submissions done (`proofs`).
//! Plain data, below the device state that holds it, so that the modules that make and read
//! them can import that state without a circle.

use std::collections::HashMap;

use ash::vk;

use super::slots::Slot;

/// Bytes per copied query: up to three statistics and the availability word.
pub(super) const STRIDE: u64 = 32;

/// One submission's copy: the layer's command buffer and the memory it copies into.
#[derive(Debug)]
pub struct SubmissionCopy {
    pub command_buffer: vk::CommandBuffer,
    pub(super) pool: vk::CommandPool,
    pub(super) buffer: vk::Buffer,
    pub(super) memory: vk::DeviceMemory,
    /// The mapped memory (an address: the state is shared between threads).
    pub(super) mapped: usize,
    /// Each slot's index in the buffer.
    pub(super) index: HashMap<Slot, usize>,
    /// Where each indirect dispatch's arguments (buffer, offset) were copied: bytes from the
    /// start of the mapping.
    pub(super) indirect: HashMap<(vk::Buffer, u64), usize>,
}

impl SubmissionCopy {
    /// The `words` values of `slot` as this submission left them.
    pub fn read(&self, slot: Slot, words: usize) -> Result<Vec<u64>, String> {
        let index = *self.index.get(&slot).ok_or("query not copied")?;
        let base = self.mapped + index * STRIDE as usize;
        // SAFETY: the mapping covers every slot's STRIDE bytes; the submission that wrote them is
        // complete (the caller's proof) and the memory is host-coherent; `words` + 1 <= 4.
        let values: Vec<u64> =
            (0..=words).map(|i| unsafe { std::ptr::read_volatile((base + i * 8) as *const u64) }).collect();
        if values[words] == 0 {
            return Err("query results not available when read".into());
        }
        Ok(values[..words].to_vec())
    }

    /// The workgroups of the indirect dispatch whose arguments are at (`buffer`, `offset`), as
    /// they were when the submission's batch ended; None when they were not copied.
    pub fn workgroups(&self, buffer: vk::Buffer, offset: u64) -> Option<u64> {
        let at = *self.indirect.get(&(buffer, offset))?;
        // SAFETY: the mapping covers the copied arguments (three u32 at `at`, 4-aligned); the
        // submission is complete (the caller's proof) and the memory host-coherent.
        let counts: Vec<u64> = (0..3)
            .map(|i| unsafe { std::ptr::read_volatile((self.mapped + at + 4 * i) as *const u32) } as u64)
            .collect();
        Some(counts.iter().product())
    }

    /// Frees the command buffer and the memory (the submission is complete or never ran).
    pub fn release(self, device: &ash::Device) {
        // SAFETY: the layer's own objects, made on `device`; the submission using them is complete.
        unsafe {
            device.free_command_buffers(self.pool, &[self.command_buffer]);
            device.destroy_buffer(self.buffer, None);
            device.free_memory(self.memory, None);
        }
    }
}

/// A proof in flight: its fence signals when `queue`'s submissions up to `sequence` are done.
#[derive(Debug, Clone, Copy)]
pub struct Proof {
    pub(super) fence: vk::Fence,
    pub(super) queue: vk::Queue,
    pub(super) sequence: u64,
}

/// A timeline semaphore signal in a batch: once the semaphore reaches `value`, `queue`'s
/// submissions up to `sequence` are complete (a signal's first scope holds every command before
/// it on its queue, and a valid program's timeline values only grow).
#[derive(Debug, Clone, Copy)]
pub struct TimelineSignal {
    pub(super) semaphore: vk::Semaphore,
    pub(super) value: u64,
    pub(super) queue: vk::Queue,
    pub(super) sequence: u64,
}
