//! The canary: a deliberately wrong command sequence that synchronisation validation must report.
//! A transfer writes a buffer and the next transfer reads it with no barrier between them: a
//! read-after-write hazard that the core checks cannot see (every command is valid on its own)
//! and only synchronisation validation can. If the layer stops running it (switched off in
//! src/gpu/validation.rs, or the feature no longer reaches the layer), this test fails, so a
//! green suite really means "no hazard found" rather than "nobody looked".
//!
//! The same sequence with the barrier must stay silent: the message is about the missing barrier,
//! not about anything else in the sequence.

use crate::common;

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use nostencil::gpu::commands::submit_and_wait;
use nostencil::gpu::memory::Buffer;
use nostencil::Gpu;

const SIZE: u64 = 256;

/// Fills `source`, then copies it into `destination`, with or without the barrier that makes
/// the fill's writes visible to the copy's reads.
fn fill_then_copy(gpu: &Arc<Gpu>, with_barrier: bool) {
    let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
    let source = Buffer::new(gpu, "canary source", SIZE, usage, MemoryLocation::GpuOnly).expect("source buffer");
    let destination =
        Buffer::new(gpu, "canary destination", SIZE, usage, MemoryLocation::GpuOnly).expect("destination buffer");
    let device = gpu.raw();
    submit_and_wait(gpu, |cmd| {
        // SAFETY: both buffers are alive until after the wait; the regions are inside them.
        unsafe {
            device.cmd_fill_buffer(cmd, source.raw, 0, SIZE, 0x5eed_5eed);
            if with_barrier {
                let written = vk::MemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                    .dst_access_mask(vk::AccessFlags::TRANSFER_READ);
                device.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::DependencyFlags::empty(),
                    &[written],
                    &[],
                    &[],
                );
            }
            let region = vk::BufferCopy::default().size(SIZE);
            device.cmd_copy_buffer(cmd, source.raw, destination.raw, &[region]);
        }
        Ok(())
    })
    .expect("submit the canary");
}

#[test]
fn a_read_after_a_write_without_a_barrier_is_reported_as_a_sync_hazard() {
    let gpu = common::gpu();
    fill_then_copy(&gpu, false);
    let messages = gpu.validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("SYNC-HAZARD-READ-AFTER-WRITE")),
        "synchronisation validation did not report the missing barrier: is it on? messages: {messages:?}"
    );
    assert!(messages.iter().all(|m| m.contains("SYNC-HAZARD-")), "only the hazard was expected, got: {messages:?}");
}

#[test]
fn the_same_sequence_with_its_barrier_is_silent() {
    let gpu = common::gpu();
    fill_then_copy(&gpu, true);
    common::assert_no_validation_messages(&gpu);
}
