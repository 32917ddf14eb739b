//! Per-submission results. A command buffer's query slots are fixed when it is recorded, so a
//! pre-recorded buffer submitted again (SIMULTANEOUS_USE: even while in flight) would overwrite
//! the results of its previous submission before the layer reads them. So each submission gets
//! a command buffer of the layer's, submitted right after the application's in the same batch,
//! that copies the slots' results into a host-visible buffer of that submission's own.
//! Query commands on one queue execute in submission order (Vulkan spec, "Queries": an implicit
//! execution dependency between query commands on the same query and queue), so the copy sees
//! exactly this submission's results; WAIT makes it wait for them on the GPU.

use ash::vk;
use ash::vk::Handle;

use super::in_flight::{SubmissionCopy, STRIDE};
use super::readback::STATISTICS;
use super::recording::RecordedPass;
use super::slots::{QueryCmd, Slot};
use super::state::{DeviceData, DeviceState};
use super::work::RecordedWork;

/// The slots of `passes` and `work` and how many values each has; the multiview queries'
/// later indices are copied without waiting, since a driver may never make them available
/// (readback.rs reads such a one as 0).
fn slots_of(passes: &[RecordedPass], work: &[RecordedWork]) -> Vec<(Slot, usize)> {
    let mut slots = Vec::new();
    for w in work {
        slots.extend(w.statistics.map(|s| (s, 1)));
        if let Some((begin, end)) = w.timestamps {
            slots.extend([(begin, 1), (end, 1)]);
        }
    }
    for pass in passes.iter().filter(|p| p.not_measured().is_none()) {
        slots.extend(pass.occlusion.iter().map(|&s| (s, 1)));
        slots.extend(pass.statistics.iter().map(|&s| (s, STATISTICS.len())));
        if let Some((begin, end)) = pass.timestamps {
            slots.extend([(begin, 1), (end, 1)]);
        }
        for (begin, end) in pass.draw_slots.iter().filter_map(|d| d.timestamps) {
            slots.extend([(begin, 1), (end, 1)]);
        }
        for (begin, end) in pass.sections.iter().filter_map(|s| s.timestamps) {
            slots.extend([(begin, 1), (end, 1)]);
        }
    }
    slots
}

pub(super) fn host_memory_type(device: &DeviceData, bits: u32) -> Option<u32> {
    let wanted = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
    let props = &device.info.memory;
    (0..props.memory_type_count)
        .find(|&i| bits & (1 << i) != 0 && props.memory_types[i as usize].property_flags.contains(wanted))
}

/// A copy for one submission of `passes` on a queue of `family`; Err says why there is none.
pub fn make(
    device: &DeviceData,
    state: &mut DeviceState,
    family: u32,
    passes: &[RecordedPass],
    work: &[RecordedWork],
) -> Result<Option<SubmissionCopy>, String> {
    let slots = slots_of(passes, work);
    // Indirect dispatches' arguments, where the layer made the buffer readable (work_hooks.rs).
    let mut indirect: Vec<Arguments> = work
        .iter()
        .flat_map(|w| w.indirect.iter().copied())
        .filter(|(b, _)| state.indirect_buffers.contains(b))
        .collect();
    indirect.sort_unstable();
    indirect.dedup();
    if slots.is_empty() && indirect.is_empty() {
        return Ok(None);
    }
    let set_loader_data = device.info.set_loader_data.ok_or("the loader gave no vkSetDeviceLoaderData")?;
    let failed = |what: &str, e: vk::Result| format!("the layer could not {what} ({e:?})");
    let pool = copy_pool(device, state, family).map_err(|e| failed("make a command pool", e))?;
    let indirect_base = slots.len() as u64 * STRIDE;
    let size = indirect_base + indirect.len() as u64 * INDIRECT_STRIDE;
    let info = vk::BufferCreateInfo::default().size(size).usage(vk::BufferUsageFlags::TRANSFER_DST);
    // SAFETY: plain object creation on the live device; every object is released on each
    // failure path below.
    unsafe {
        let buffer = device.fns.create_buffer(&info, None).map_err(|e| failed("make a buffer", e))?;
        let requirements = device.fns.get_buffer_memory_requirements(buffer);
        let Some(memory_type) = host_memory_type(device, requirements.memory_type_bits) else {
            device.fns.destroy_buffer(buffer, None);
            return Err("no host-visible memory for the layer's results".into());
        };
        let allocate =
            vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(memory_type);
        let memory = match device.fns.allocate_memory(&allocate, None) {
            Ok(memory) => memory,
            Err(e) => {
                device.fns.destroy_buffer(buffer, None);
                return Err(failed("allocate memory", e));
            }
        };
        let mapped = device
            .fns
            .bind_buffer_memory(buffer, memory, 0)
            .and_then(|()| device.fns.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()));
        let allocated = mapped.and_then(|mapped| {
            let info = vk::CommandBufferAllocateInfo::default()
                .command_pool(pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            let cmd = device.fns.allocate_command_buffers(&info)?[0];
            Ok((mapped, cmd))
        });
        let (mapped, cmd) = match allocated {
            Ok(pair) => pair,
            Err(e) => {
                device.fns.destroy_buffer(buffer, None);
                device.fns.free_memory(memory, None);
                return Err(failed("set up a result copy", e));
            }
        };
        let copy = SubmissionCopy {
            command_buffer: cmd,
            pool,
            buffer,
            memory,
            mapped: mapped as usize,
            index: slots.iter().enumerate().map(|(i, (slot, _))| (*slot, i)).collect(),
            indirect: indirect
                .iter()
                .enumerate()
                .map(|(i, &at)| (at, (indirect_base + i as u64 * INDIRECT_STRIDE) as usize))
                .collect(),
        };
        // The loader's dispatch pointer, which the layers below look the buffer up by.
        let result = set_loader_data(device.handle, cmd.as_raw() as usize as *mut std::ffi::c_void);
        if result != vk::Result::SUCCESS {
            copy.release(&device.fns);
            return Err(failed("register its command buffer with the loader", result));
        }
        let extras: Vec<Slot> = passes.iter().flat_map(|p| p.view_extras.iter().copied()).collect();
        if let Err(e) = record(device, &copy, (&slots, &indirect, &extras), buffer) {
            copy.release(&device.fns);
            return Err(failed("record its result copy", e));
        }
        Ok(Some(copy))
    }
}

/// A command buffer of the layer's that resets `resets` (queries a secondary command buffer
/// uses inside its executor's render pass, where no reset may be recorded), to submit first in
/// the batch: (its pool, the buffer).
pub fn make_resets(
    device: &DeviceData,
    state: &mut DeviceState,
    family: u32,
    resets: &[QueryCmd],
) -> Result<(vk::CommandPool, vk::CommandBuffer), String> {
    let set_loader_data = device.info.set_loader_data.ok_or("the loader gave no vkSetDeviceLoaderData")?;
    let failed = |what: &str, e: vk::Result| format!("the layer could not {what} ({e:?})");
    let pool = copy_pool(device, state, family).map_err(|e| failed("make a command pool", e))?;
    let info = vk::CommandBufferAllocateInfo::default()
        .command_pool(pool)
        .level(vk::CommandBufferLevel::PRIMARY)
        .command_buffer_count(1);
    // SAFETY: the layer's own pool on the live device, used under the state lock; the buffer is
    // registered with the loader before any call on it, and freed on every failure path.
    unsafe {
        let cmd = device.fns.allocate_command_buffers(&info).map_err(|e| failed("allocate a command buffer", e))?[0];
        let registered = set_loader_data(device.handle, cmd.as_raw() as usize as *mut std::ffi::c_void);
        let recorded = if registered == vk::Result::SUCCESS {
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.fns.begin_command_buffer(cmd, &begin).and_then(|()| {
                for reset in resets {
                    if let QueryCmd::Reset { pool, first, count } = *reset {
                        device.fns.cmd_reset_query_pool(cmd, pool, first, count);
                    }
                }
                device.fns.end_command_buffer(cmd)
            })
        } else {
            Err(registered)
        };
        if let Err(e) = recorded {
            device.fns.free_command_buffers(pool, &[cmd]);
            return Err(failed("record the resets of secondary command buffers' queries", e));
        }
        Ok((pool, cmd))
    }
}

/// The layer's command pool for queue family `family`.
fn copy_pool(device: &DeviceData, state: &mut DeviceState, family: u32) -> Result<vk::CommandPool, vk::Result> {
    if let Some(&pool) = state.copy_pools.get(&family) {
        return Ok(pool);
    }
    let info =
        vk::CommandPoolCreateInfo::default().queue_family_index(family).flags(vk::CommandPoolCreateFlags::TRANSIENT);
    // SAFETY: the device is alive; the pool is the layer's, used under the state lock.
    let pool = unsafe { device.fns.create_command_pool(&info, None) }?;
    state.copy_pools.insert(family, pool);
    Ok(pool)
}

/// Bytes per copied indirect dispatch's arguments (three u32, padded).
const INDIRECT_STRIDE: u64 = 16;

/// Where an indirect dispatch's arguments are: the program's buffer and the offset in it.
type Arguments = (vk::Buffer, u64);

/// Records the copy of every slot and of the indirect dispatches' arguments, then makes the
/// writes visible to the host.
///
/// # Safety
/// `copy.command_buffer` is the layer's, freshly allocated; `buffer` holds every slot and
/// argument; each argument buffer has TRANSFER_SRC usage.
unsafe fn record(
    device: &DeviceData,
    copy: &SubmissionCopy,
    (slots, indirect, extras): (&[(Slot, usize)], &[Arguments], &[Slot]),
    buffer: vk::Buffer,
) -> ash::prelude::VkResult<()> {
    let cmd = copy.command_buffer;
    let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
    // SAFETY: the caller's contract; every query was reset and written by the application's
    // command buffer submitted just before this one in the same batch.
    unsafe {
        device.fns.begin_command_buffer(cmd, &begin)?;
        if !indirect.is_empty() {
            // The arguments as the batch left them: after every write before this buffer.
            let barrier = [vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::MEMORY_WRITE)
                .dst_access_mask(vk::AccessFlags::TRANSFER_READ)];
            let (src, dst) = (vk::PipelineStageFlags::ALL_COMMANDS, vk::PipelineStageFlags::TRANSFER);
            device.fns.cmd_pipeline_barrier(cmd, src, dst, vk::DependencyFlags::empty(), &barrier, &[], &[]);
        }
        for (&(source, offset), &at) in indirect.iter().zip(indirect.iter().map(|k| &copy.indirect[k])) {
            let region = vk::BufferCopy { src_offset: offset, dst_offset: at as u64, size: 12 };
            device.fns.cmd_copy_buffer(cmd, source, buffer, &[region]);
        }
        let flags = vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WITH_AVAILABILITY;
        for (i, (slot, _)) in slots.iter().enumerate() {
            let flags = if extras.contains(slot) { flags } else { flags | vk::QueryResultFlags::WAIT };
            device.fns.cmd_copy_query_pool_results(
                cmd,
                slot.pool,
                slot.query,
                1,
                buffer,
                i as u64 * STRIDE,
                STRIDE,
                flags,
            );
        }
        let barrier = [vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
            .dst_access_mask(vk::AccessFlags::HOST_READ)];
        // ALL_COMMANDS too: later writes of the program's to the argument buffers wait for the
        // layer's reads of them.
        device.fns.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST | vk::PipelineStageFlags::ALL_COMMANDS,
            vk::DependencyFlags::empty(),
            &barrier,
            &[],
            &[],
        );
        device.fns.end_command_buffer(cmd)
    }
}
