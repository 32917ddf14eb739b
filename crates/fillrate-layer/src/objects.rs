//! Hooks that only learn about objects: render passes (attachments, multiview), images and
//! views (formats and samples, for dynamic rendering), command pools and buffers (queue family,
//! level; the layer's own pools live and die with them), and the application's query pools.

use std::sync::Arc;

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::attachments::RenderPassInfo;
use super::readback::read_completed;
use super::recording::{QuerySupport, Recording};
use super::state::{self, guard, CommandBufferData, DeviceData, DeviceState};

/// The device of `handle` and its next function `pick` chooses, or None (then the hook has
/// nothing to call: the loader only hands out hooks for functions the device has).
pub fn device_and<F>(handle: u64, pick: impl FnOnce(&DeviceData) -> Option<F>) -> Option<(Arc<DeviceData>, F)> {
    let device = guard(None, || state::device_of(handle))?;
    let f = pick(&device)?;
    Some((device, f))
}

/// Reads back `buffer`'s submissions: called where the application guarantees the buffer is no
/// longer pending (re-recording, reset, free, re-submission without SIMULTANEOUS_USE).
pub fn flush_buffer(device: &DeviceData, state: &mut DeviceState, buffer: vk::CommandBuffer) {
    let uses = |p: &super::state::Pending| p.buffer == buffer || p.secondaries.contains(&buffer);
    if state.pending.iter().any(uses) {
        read_completed(device, state, uses);
    }
}

/// Forgets `buffers` after reading them back, destroying the layer's pools they used.
fn drop_buffers(device: &DeviceData, state: &mut DeviceState, buffers: &[vk::CommandBuffer]) {
    for &buffer in buffers {
        flush_buffer(device, state, buffer);
        if let Some(data) = state.buffers.remove(&buffer) {
            for pool in data.recording.pools() {
                // SAFETY: the layer's own pool; the buffer that used it is not pending (read back
                // above) and is being freed.
                unsafe { device.fns.destroy_query_pool(pool, None) };
            }
        }
    }
}

pub(super) unsafe extern "system" fn create_render_pass(
    device: vk::Device,
    info: *const vk::RenderPassCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    render_pass: *mut vk::RenderPass,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.create_render_pass) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, render_pass) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info (the call succeeded with it) and the new handle.
            let (pass_info, handle) = unsafe { (RenderPassInfo::from_create_info(&*info), *render_pass) };
            dev.state().render_passes.insert(handle, pass_info);
        });
    }
    result
}

/// vkCreateRenderPass2 and its KHR alias.
unsafe fn create_render_pass2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCreateRenderPass2>,
    device: vk::Device,
    info: *const vk::RenderPassCreateInfo2<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    render_pass: *mut vk::RenderPass,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), pick) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, render_pass) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info and the new handle.
            let (pass_info, handle) = unsafe { (RenderPassInfo::from_create_info2(&*info), *render_pass) };
            dev.state().render_passes.insert(handle, pass_info);
        });
    }
    result
}

pub(super) unsafe extern "system" fn create_render_pass2(
    device: vk::Device,
    info: *const vk::RenderPassCreateInfo2<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    render_pass: *mut vk::RenderPass,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { create_render_pass2_with(|d| d.next.create_render_pass2, device, info, allocator, render_pass) }
}

pub(super) unsafe extern "system" fn create_render_pass2_khr(
    device: vk::Device,
    info: *const vk::RenderPassCreateInfo2<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    render_pass: *mut vk::RenderPass,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { create_render_pass2_with(|d| d.next.create_render_pass2_khr, device, info, allocator, render_pass) }
}

pub(super) unsafe extern "system" fn destroy_render_pass(
    device: vk::Device,
    render_pass: vk::RenderPass,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.destroy_render_pass) else { return };
    guard((), || {
        dev.state().render_passes.remove(&render_pass);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, render_pass, allocator) }
}

pub(super) unsafe extern "system" fn create_image(
    device: vk::Device,
    info: *const vk::ImageCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    image: *mut vk::Image,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.create_image) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, image) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info and the new handle.
            let (info, handle) = unsafe { (&*info, *image) };
            let mut st = dev.state();
            st.image_samples.insert(handle, info.samples.as_raw().max(1));
            let image = super::transfer_bytes::ImageInfo {
                format: info.format,
                extent: info.extent,
                mip_levels: info.mip_levels,
                array_layers: info.array_layers,
                samples: info.samples.as_raw().max(1),
                swapchain: false,
            };
            st.images.insert(handle, image);
            let tiler = super::tiler_state::TilerImage {
                transient: info.usage.contains(vk::ImageUsageFlags::TRANSIENT_ATTACHMENT),
                extent: (info.extent.width, info.extent.height),
                single: info.mip_levels == 1 && info.array_layers == 1,
            };
            st.tiler.images.insert(handle, tiler);
        });
    }
    result
}

pub(super) unsafe extern "system" fn destroy_image(
    device: vk::Device,
    image: vk::Image,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.destroy_image) else { return };
    guard((), || {
        let mut st = dev.state();
        st.image_samples.remove(&image);
        st.images.remove(&image);
        st.tiler.images.remove(&image);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, image, allocator) }
}

pub(super) unsafe extern "system" fn create_image_view(
    device: vk::Device,
    info: *const vk::ImageViewCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    view: *mut vk::ImageView,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.create_image_view) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, view) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info and the new handle.
            let (format, image, handle) = unsafe { ((*info).format, (*info).image, *view) };
            // SAFETY: as above.
            let range = unsafe { (*info).subresource_range };
            let mut st = dev.state();
            let key = super::tiler_check::ImageKey {
                image: image.as_raw(),
                mip: range.base_mip_level,
                layer: range.base_array_layer,
            };
            st.tiler.views.insert(handle, super::tiler_state::ViewTarget { image, key });
            // Swapchain images are not created through vkCreateImage: one sample.
            let samples = st.image_samples.get(&image).copied().unwrap_or(1);
            st.views.insert(handle, (format, samples));
        });
    }
    result
}

pub(super) unsafe extern "system" fn destroy_image_view(
    device: vk::Device,
    view: vk::ImageView,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.destroy_image_view) else { return };
    guard((), || {
        let mut st = dev.state();
        st.views.remove(&view);
        st.tiler.views.remove(&view);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, view, allocator) }
}

pub(super) unsafe extern "system" fn create_command_pool(
    device: vk::Device,
    info: *const vk::CommandPoolCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    pool: *mut vk::CommandPool,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.create_command_pool) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, pool) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info and the new handle.
            let (family, handle) = unsafe { ((*info).queue_family_index, *pool) };
            dev.state().command_pools.insert(handle, family);
        });
    }
    result
}

fn buffers_of(state: &DeviceState, pool: vk::CommandPool) -> Vec<vk::CommandBuffer> {
    state.buffers.iter().filter(|(_, b)| b.pool == pool).map(|(&h, _)| h).collect()
}

pub(super) unsafe extern "system" fn destroy_command_pool(
    device: vk::Device,
    pool: vk::CommandPool,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.destroy_command_pool) else { return };
    guard((), || {
        let mut st = dev.state();
        let buffers = buffers_of(&st, pool);
        drop_buffers(&dev, &mut st, &buffers);
        st.command_pools.remove(&pool);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, pool, allocator) }
}

pub(super) unsafe extern "system" fn reset_command_pool(
    device: vk::Device,
    pool: vk::CommandPool,
    flags: vk::CommandPoolResetFlags,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.reset_command_pool) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    guard((), || {
        let mut st = dev.state();
        for buffer in buffers_of(&st, pool) {
            flush_buffer(&dev, &mut st, buffer);
            if let Some(data) = st.buffers.get_mut(&buffer) {
                data.recording.restart(false);
                data.tiler.restart();
            }
        }
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, pool, flags) }
}

pub(super) unsafe extern "system" fn allocate_command_buffers(
    device: vk::Device,
    info: *const vk::CommandBufferAllocateInfo<'_>,
    buffers: *mut vk::CommandBuffer,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.allocate_command_buffers) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, buffers) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid allocate info; `buffers` now holds commandBufferCount handles.
            let (info, handles) = unsafe { (&*info, app_array(buffers, (*info).command_buffer_count)) };
            let mut st = dev.state();
            let family = st.command_pools.get(&info.command_pool).copied().unwrap_or(0);
            let support = QuerySupport {
                statistics: dev.info.support.pipeline_statistics,
                precise: dev.info.support.occlusion_precise,
                timestamps: dev.info.timestamp_bits.get(family as usize).is_some_and(|&b| b > 0),
            };
            let secondary = info.level == vk::CommandBufferLevel::SECONDARY;
            for &handle in handles {
                let mut recording = Recording::new(secondary, support);
                recording.per_draw = dev.config.per_draw;
                let tiler = Default::default();
                st.buffers.insert(handle, CommandBufferData { pool: info.command_pool, recording, tiler });
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn free_command_buffers(
    device: vk::Device,
    pool: vk::CommandPool,
    count: u32,
    buffers: *const vk::CommandBuffer,
) {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.free_command_buffers) else { return };
    guard((), || {
        // SAFETY: `buffers` holds `count` handles (null ones allowed, ignored by the lookups).
        let handles = unsafe { app_array(buffers, count) };
        let mut st = dev.state();
        drop_buffers(&dev, &mut st, handles);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, pool, count, buffers) }
}

pub(super) unsafe extern "system" fn create_query_pool(
    device: vk::Device,
    info: *const vk::QueryPoolCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    pool: *mut vk::QueryPool,
) -> vk::Result {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.create_query_pool) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, pool) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info and the new handle.
            let (ty, stats, handle) = unsafe { ((*info).query_type, (*info).pipeline_statistics, *pool) };
            dev.state().app_pools.insert(handle, (ty, stats));
        });
    }
    result
}

pub(super) unsafe extern "system" fn destroy_query_pool(
    device: vk::Device,
    pool: vk::QueryPool,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((dev, next)) = device_and(device.as_raw(), |d| d.next.destroy_query_pool) else { return };
    guard((), || {
        let mut st = dev.state();
        spoil_gaps(&mut st, pool, 0, u32::MAX, "application query pool destroyed before the layer read it");
        st.app_pools.remove(&pool);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, pool, allocator) }
}

/// Marks pending passes whose gaps read `pool` queries in [first, first + count) as unreadable.
pub fn spoil_gaps(state: &mut DeviceState, pool: vk::QueryPool, first: u32, count: u32, why: &str) {
    for pending in &mut state.pending {
        let hit = pending
            .passes
            .iter()
            .flat_map(|p| &p.gaps)
            .any(|g| g.pool == pool && g.query >= first && (g.query - first) < count);
        if hit && pending.spoiled.is_none() {
            pending.spoiled = Some(why.to_owned());
        }
    }
}

/// vkResetQueryPool (host) and its EXT alias: results the layer still has to read are lost.
unsafe fn reset_query_pool_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkResetQueryPool>,
    device: vk::Device,
    pool: vk::QueryPool,
    first: u32,
    count: u32,
) {
    let Some((dev, next)) = device_and(device.as_raw(), pick) else { return };
    guard((), || {
        spoil_gaps(&mut dev.state(), pool, first, count, "application reset its query before the layer read it");
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, pool, first, count) }
}

pub(super) unsafe extern "system" fn reset_query_pool(device: vk::Device, pool: vk::QueryPool, first: u32, count: u32) {
    // SAFETY: the application's arguments.
    unsafe { reset_query_pool_with(|d| d.next.reset_query_pool, device, pool, first, count) }
}

pub(super) unsafe extern "system" fn reset_query_pool_ext(
    device: vk::Device,
    pool: vk::QueryPool,
    first: u32,
    count: u32,
) {
    // SAFETY: the application's arguments.
    unsafe { reset_query_pool_with(|d| d.next.reset_query_pool_ext, device, pool, first, count) }
}
