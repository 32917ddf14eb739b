//! Hooks for work outside render passes (work.rs): dispatches, transfers, and the commands that
//! close a dispatch group (barriers, event waits, secondary buffers, the end of the buffer).
//! Each records the layer's queries around the application's call and passes the call on:
//! through the tiler check's hook (image_use.rs) when the check is on, which notes the images
//! read and written, and straight to the next layer otherwise.

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::commands::{around, create_pool, measuring};
use super::image_use as t;
use super::objects::device_and;
use super::slots::QueryCmd;
use super::state::{guard, DeviceData, DeviceState};
use super::transfer_bytes as bytes;
use super::work::{Moved, Workgroups};

type Cmds = (Vec<QueryCmd>, Vec<QueryCmd>);

/// A dispatch of `groups` workgroups on `cmd`.
fn dispatch(
    device: &DeviceData,
    st: &mut DeviceState,
    cmd: vk::CommandBuffer,
    api: &'static str,
    groups: Workgroups,
) -> Cmds {
    if !measuring(st) || in_secondary(st, cmd) {
        return Default::default();
    }
    let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
    (data.recording.dispatch(api, groups, &mut |kind| create_pool(device, kind)), Vec::new())
}

/// Work recorded in a secondary command buffer is not measured (its queries would have to run
/// wherever the buffer is executed); it is named, once per recorded command.
fn in_secondary(st: &mut DeviceState, cmd: vk::CommandBuffer) -> bool {
    let secondary = st.buffers.get(&cmd).is_some_and(|b| b.recording.secondary);
    if secondary {
        st.count_not_measured(SECONDARY_WORK);
    }
    secondary
}

/// The reason [`in_secondary`] names.
pub const SECONDARY_WORK: &str = "dispatch or transfer recorded in a secondary command buffer";

/// A transfer on `cmd`; `moved` works out its bytes from the device's images and buffers.
fn transfer(
    device: &DeviceData,
    st: &mut DeviceState,
    cmd: vk::CommandBuffer,
    api: &'static str,
    moved: impl FnOnce(&DeviceState) -> Moved,
) -> Cmds {
    if !measuring(st) || in_secondary(st, cmd) {
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
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_dispatch(cmd, x, y, z) }
            } else if let Some(next) = d.next.cmd_dispatch {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, x, y, z) }
            }
        },
        |d, st| dispatch(d, st, cmd, "vkCmdDispatch", groups(x, y, z)),
    );
}

pub(super) unsafe extern "system" fn cmd_dispatch_indirect(cmd: vk::CommandBuffer, buffer: vk::Buffer, offset: u64) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_dispatch_indirect(cmd, buffer, offset) }
            } else if let Some(next) = d.next.cmd_dispatch_indirect {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, buffer, offset) }
            }
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

pub(super) unsafe extern "system" fn cmd_copy_buffer(
    cmd: vk::CommandBuffer,
    src: vk::Buffer,
    dst: vk::Buffer,
    count: u32,
    regions: *const vk::BufferCopy,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_copy_buffer {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, src, dst, count, regions) }
            }
        },
        // SAFETY: the application's `count` regions.
        |d, st| transfer(d, st, cmd, "vkCmdCopyBuffer", |_| bytes::copy_buffer(unsafe { app_array(regions, count) })),
    );
}

/// The `*2` copy of buffers and its KHR alias.
unsafe fn copy_buffer2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCmdCopyBuffer2>,
    cmd: vk::CommandBuffer,
    info: *const vk::CopyBufferInfo2<'_>,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = pick(d) {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, info) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdCopyBuffer2", |_| {
                // SAFETY: the application's valid info with its regions.
                let regions = unsafe { app_array((*info).p_regions, (*info).region_count) };
                let plain: Vec<vk::BufferCopy> = regions
                    .iter()
                    .map(|r| vk::BufferCopy { src_offset: r.src_offset, dst_offset: r.dst_offset, size: r.size })
                    .collect();
                bytes::copy_buffer(&plain)
            })
        },
    );
}

pub(super) unsafe extern "system" fn cmd_copy_buffer2(cmd: vk::CommandBuffer, info: *const vk::CopyBufferInfo2<'_>) {
    // SAFETY: the application's arguments.
    unsafe { copy_buffer2_with(|d| d.next.cmd_copy_buffer2, cmd, info) }
}

pub(super) unsafe extern "system" fn cmd_copy_buffer2_khr(cmd: vk::CommandBuffer, info: *const vk::CopyBufferInfo2<'_>) {
    // SAFETY: the application's arguments.
    unsafe { copy_buffer2_with(|d| d.next.cmd_copy_buffer2_khr, cmd, info) }
}

pub(super) unsafe extern "system" fn cmd_fill_buffer(
    cmd: vk::CommandBuffer,
    buffer: vk::Buffer,
    offset: u64,
    size: u64,
    value: u32,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_fill_buffer {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, buffer, offset, size, value) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdFillBuffer", |st| {
                bytes::fill_buffer(st.buffer_sizes.get(&buffer).copied(), offset, size)
            })
        },
    );
}

pub(super) unsafe extern "system" fn cmd_update_buffer(
    cmd: vk::CommandBuffer,
    buffer: vk::Buffer,
    offset: u64,
    size: u64,
    data: *const std::ffi::c_void,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_update_buffer {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, buffer, offset, size, data) }
            }
        },
        |d, st| transfer(d, st, cmd, "vkCmdUpdateBuffer", |_| Moved { read: 0, written: size, note: None }),
    );
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_copy_image(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    src_layout: vk::ImageLayout,
    dst: vk::Image,
    dst_layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::ImageCopy,
) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_copy_image(cmd, src, src_layout, dst, dst_layout, count, regions) }
            } else if let Some(next) = d.next.cmd_copy_image {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, src, src_layout, dst, dst_layout, count, regions) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdCopyImage", |st| {
                // SAFETY: the application's `count` regions.
                bytes::copy_image(st.images.get(&src), st.images.get(&dst), unsafe { app_array(regions, count) })
            })
        },
    );
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_blit_image(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    src_layout: vk::ImageLayout,
    dst: vk::Image,
    dst_layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::ImageBlit,
    filter: vk::Filter,
) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_blit_image(cmd, src, src_layout, dst, dst_layout, count, regions, filter) }
            } else if let Some(next) = d.next.cmd_blit_image {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, src, src_layout, dst, dst_layout, count, regions, filter) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdBlitImage", |st| {
                // SAFETY: the application's `count` regions.
                bytes::blit_image(st.images.get(&src), st.images.get(&dst), unsafe { app_array(regions, count) })
            })
        },
    );
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_resolve_image(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    src_layout: vk::ImageLayout,
    dst: vk::Image,
    dst_layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::ImageResolve,
) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_resolve_image(cmd, src, src_layout, dst, dst_layout, count, regions) }
            } else if let Some(next) = d.next.cmd_resolve_image {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, src, src_layout, dst, dst_layout, count, regions) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdResolveImage", |st| {
                // SAFETY: the application's `count` regions.
                bytes::resolve_image(st.images.get(&src), st.images.get(&dst), unsafe { app_array(regions, count) })
            })
        },
    );
}

pub(super) unsafe extern "system" fn cmd_copy_image_to_buffer(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    layout: vk::ImageLayout,
    buffer: vk::Buffer,
    count: u32,
    regions: *const vk::BufferImageCopy,
) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_copy_image_to_buffer(cmd, src, layout, buffer, count, regions) }
            } else if let Some(next) = d.next.cmd_copy_image_to_buffer {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, src, layout, buffer, count, regions) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdCopyImageToBuffer", |st| {
                // SAFETY: the application's `count` regions.
                bytes::buffer_image(st.images.get(&src), unsafe { app_array(regions, count) }, false)
            })
        },
    );
}

pub(super) unsafe extern "system" fn cmd_copy_buffer_to_image(
    cmd: vk::CommandBuffer,
    buffer: vk::Buffer,
    dst: vk::Image,
    layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::BufferImageCopy,
) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_copy_buffer_to_image(cmd, buffer, dst, layout, count, regions) }
            } else if let Some(next) = d.next.cmd_copy_buffer_to_image {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, buffer, dst, layout, count, regions) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdCopyBufferToImage", |st| {
                // SAFETY: the application's `count` regions.
                bytes::buffer_image(st.images.get(&dst), unsafe { app_array(regions, count) }, true)
            })
        },
    );
}

pub(super) unsafe extern "system" fn cmd_clear_color_image(
    cmd: vk::CommandBuffer,
    image: vk::Image,
    layout: vk::ImageLayout,
    colour: *const vk::ClearColorValue,
    count: u32,
    ranges: *const vk::ImageSubresourceRange,
) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_clear_color_image(cmd, image, layout, colour, count, ranges) }
            } else if let Some(next) = d.next.cmd_clear_color_image {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, image, layout, colour, count, ranges) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdClearColorImage", |st| {
                // SAFETY: the application's `count` ranges.
                bytes::clear_image(st.images.get(&image), unsafe { app_array(ranges, count) })
            })
        },
    );
}

pub(super) unsafe extern "system" fn cmd_clear_depth_stencil_image(
    cmd: vk::CommandBuffer,
    image: vk::Image,
    layout: vk::ImageLayout,
    value: *const vk::ClearDepthStencilValue,
    count: u32,
    ranges: *const vk::ImageSubresourceRange,
) {
    around(
        cmd,
        |d| {
            if d.config.tiler {
                // SAFETY: the application's arguments, passed on through the check.
                unsafe { t::cmd_clear_depth_stencil_image(cmd, image, layout, value, count, ranges) }
            } else if let Some(next) = d.next.cmd_clear_depth_stencil_image {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, image, layout, value, count, ranges) }
            }
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdClearDepthStencilImage", |st| {
                // SAFETY: the application's `count` ranges.
                bytes::clear_image(st.images.get(&image), unsafe { app_array(ranges, count) })
            })
        },
    );
}

/// The `*2` image transfers and their KHR aliases: `$tiler` is the check's hook, `$moved`
/// works out the bytes from the state and the info.
macro_rules! transfer2_hook {
    ($name:ident, $field:ident, $tiler:path, $info:ty, $api:literal, |$st:ident, $i:ident| $moved:expr) => {
        pub(super) unsafe extern "system" fn $name(cmd: vk::CommandBuffer, info: *const $info) {
            around(
                cmd,
                |d| {
                    if d.config.tiler {
                        // SAFETY: the application's arguments, passed on through the check.
                        unsafe { $tiler(cmd, info) }
                    } else if let Some(next) = d.next.$field {
                        // SAFETY: the application's arguments, passed on.
                        unsafe { next(cmd, info) }
                    }
                },
                |d, st| {
                    transfer(d, st, cmd, $api, |$st| {
                        // SAFETY: the application's valid info.
                        let $i = unsafe { &*info };
                        $moved
                    })
                },
            );
        }
    };
}

fn image_copies(i: &vk::CopyImageInfo2<'_>) -> Vec<vk::ImageCopy> {
    // SAFETY: the application's valid info with its regions.
    let regions = unsafe { app_array(i.p_regions, i.region_count) };
    regions
        .iter()
        .map(|r| vk::ImageCopy {
            src_subresource: r.src_subresource,
            src_offset: r.src_offset,
            dst_subresource: r.dst_subresource,
            dst_offset: r.dst_offset,
            extent: r.extent,
        })
        .collect()
}

fn image_blits(i: &vk::BlitImageInfo2<'_>) -> Vec<vk::ImageBlit> {
    // SAFETY: the application's valid info with its regions.
    let regions = unsafe { app_array(i.p_regions, i.region_count) };
    regions
        .iter()
        .map(|r| vk::ImageBlit {
            src_subresource: r.src_subresource,
            src_offsets: r.src_offsets,
            dst_subresource: r.dst_subresource,
            dst_offsets: r.dst_offsets,
        })
        .collect()
}

fn image_resolves(i: &vk::ResolveImageInfo2<'_>) -> Vec<vk::ImageResolve> {
    // SAFETY: the application's valid info with its regions.
    let regions = unsafe { app_array(i.p_regions, i.region_count) };
    regions
        .iter()
        .map(|r| vk::ImageResolve {
            src_subresource: r.src_subresource,
            src_offset: r.src_offset,
            dst_subresource: r.dst_subresource,
            dst_offset: r.dst_offset,
            extent: r.extent,
        })
        .collect()
}

/// # Safety
/// `pointer` holds `count` valid regions.
unsafe fn buffer_image_copies(pointer: *const vk::BufferImageCopy2<'_>, count: u32) -> Vec<vk::BufferImageCopy> {
    // SAFETY: the caller's contract.
    let regions = unsafe { app_array(pointer, count) };
    regions
        .iter()
        .map(|r| vk::BufferImageCopy {
            buffer_offset: r.buffer_offset,
            buffer_row_length: r.buffer_row_length,
            buffer_image_height: r.buffer_image_height,
            image_subresource: r.image_subresource,
            image_offset: r.image_offset,
            image_extent: r.image_extent,
        })
        .collect()
}

transfer2_hook!(cmd_copy_image2, cmd_copy_image2, t::cmd_copy_image2, vk::CopyImageInfo2<'_>, "vkCmdCopyImage2", |st, i| {
    bytes::copy_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_copies(i))
});
transfer2_hook!(
    cmd_copy_image2_khr,
    cmd_copy_image2_khr,
    t::cmd_copy_image2_khr,
    vk::CopyImageInfo2<'_>,
    "vkCmdCopyImage2",
    |st, i| bytes::copy_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_copies(i))
);
transfer2_hook!(cmd_blit_image2, cmd_blit_image2, t::cmd_blit_image2, vk::BlitImageInfo2<'_>, "vkCmdBlitImage2", |st, i| {
    bytes::blit_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_blits(i))
});
transfer2_hook!(
    cmd_blit_image2_khr,
    cmd_blit_image2_khr,
    t::cmd_blit_image2_khr,
    vk::BlitImageInfo2<'_>,
    "vkCmdBlitImage2",
    |st, i| bytes::blit_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_blits(i))
);
transfer2_hook!(
    cmd_resolve_image2,
    cmd_resolve_image2,
    t::cmd_resolve_image2,
    vk::ResolveImageInfo2<'_>,
    "vkCmdResolveImage2",
    |st, i| bytes::resolve_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_resolves(i))
);
transfer2_hook!(
    cmd_resolve_image2_khr,
    cmd_resolve_image2_khr,
    t::cmd_resolve_image2_khr,
    vk::ResolveImageInfo2<'_>,
    "vkCmdResolveImage2",
    |st, i| bytes::resolve_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_resolves(i))
);
transfer2_hook!(
    cmd_copy_image_to_buffer2,
    cmd_copy_image_to_buffer2,
    t::cmd_copy_image_to_buffer2,
    vk::CopyImageToBufferInfo2<'_>,
    "vkCmdCopyImageToBuffer2",
    // SAFETY: the info's regions.
    |st, i| bytes::buffer_image(st.images.get(&i.src_image), &unsafe { buffer_image_copies(i.p_regions, i.region_count) }, false)
);
transfer2_hook!(
    cmd_copy_image_to_buffer2_khr,
    cmd_copy_image_to_buffer2_khr,
    t::cmd_copy_image_to_buffer2_khr,
    vk::CopyImageToBufferInfo2<'_>,
    "vkCmdCopyImageToBuffer2",
    // SAFETY: the info's regions.
    |st, i| bytes::buffer_image(st.images.get(&i.src_image), &unsafe { buffer_image_copies(i.p_regions, i.region_count) }, false)
);
transfer2_hook!(
    cmd_copy_buffer_to_image2,
    cmd_copy_buffer_to_image2,
    t::cmd_copy_buffer_to_image2,
    vk::CopyBufferToImageInfo2<'_>,
    "vkCmdCopyBufferToImage2",
    // SAFETY: the info's regions.
    |st, i| bytes::buffer_image(st.images.get(&i.dst_image), &unsafe { buffer_image_copies(i.p_regions, i.region_count) }, true)
);
transfer2_hook!(
    cmd_copy_buffer_to_image2_khr,
    cmd_copy_buffer_to_image2_khr,
    t::cmd_copy_buffer_to_image2_khr,
    vk::CopyBufferToImageInfo2<'_>,
    "vkCmdCopyBufferToImage2",
    // SAFETY: the info's regions.
    |st, i| bytes::buffer_image(st.images.get(&i.dst_image), &unsafe { buffer_image_copies(i.p_regions, i.region_count) }, true)
);

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
                unsafe {
                    next(cmd, src, dst, flags, memory_count, memory, buffer_count, buffers, image_count, images)
                }
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

pub(super) unsafe extern "system" fn cmd_pipeline_barrier2(cmd: vk::CommandBuffer, info: *const vk::DependencyInfo<'_>) {
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
        |_, st| close(st, cmd),
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
        |_, st| close(st, cmd),
    );
    result
}

/// Whether a pNext chain holds a struct of type `ty`.
///
/// # Safety
/// `p_next` is a valid pNext chain.
unsafe fn chain_has(mut p_next: *const std::ffi::c_void, ty: vk::StructureType) -> bool {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure<'_>;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (node, next) = unsafe { ((*base).s_type, (*base).p_next.cast()) };
        if node == ty {
            return true;
        }
        p_next = next;
    }
    false
}

pub(super) unsafe extern "system" fn create_buffer(
    device: vk::Device,
    info: *const vk::BufferCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    buffer: *mut vk::Buffer,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.create_buffer) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's valid create info.
    let Some(app_info) = (unsafe { info.as_ref() }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    // An indirect-argument buffer may also be copied from, so the layer can read back what an
    // indirect dispatch ran (copies.rs); nothing else of the buffer changes.
    // (Not when VK_KHR_maintenance5's usage struct in the chain replaces `usage`.)
    // SAFETY: the application's valid chain.
    let usage2 = unsafe { chain_has(app_info.p_next, vk::StructureType::BUFFER_USAGE_FLAGS_2_CREATE_INFO_KHR) };
    let indirect = data.active() && !usage2 && app_info.usage.contains(vk::BufferUsageFlags::INDIRECT_BUFFER);
    let mut ours = *app_info;
    if indirect {
        ours.usage |= vk::BufferUsageFlags::TRANSFER_SRC;
    }
    // SAFETY: the application's create info, at most one usage bit added.
    let result = unsafe { next(device, &ours, allocator, buffer) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: the new handle (the call succeeded).
            let handle = unsafe { *buffer };
            let mut st = data.state();
            st.buffer_sizes.insert(handle, app_info.size);
            if indirect {
                st.indirect_buffers.insert(handle);
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn destroy_buffer(
    device: vk::Device,
    buffer: vk::Buffer,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.destroy_buffer) else { return };
    guard((), || {
        let mut st = data.state();
        st.buffer_sizes.remove(&buffer);
        st.indirect_buffers.remove(&buffer);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, buffer, allocator) }
}

/// vkCreateSwapchainKHR: its format and extent are kept for its images (through the capture's
/// hook when capturing, which adds a usage bit).
pub(super) unsafe extern "system" fn create_swapchain(
    device: vk::Device,
    info: *const vk::SwapchainCreateInfoKHR<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    swapchain: *mut vk::SwapchainKHR,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.create_swapchain_khr) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let result = if data.config.capture.is_some() {
        // SAFETY: the application's arguments, passed on through the capture.
        unsafe { super::capture::create_swapchain(device, info, allocator, swapchain) }
    } else {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(device, info, allocator, swapchain) }
    };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info and the new handle (the call succeeded).
            let (info, handle) = unsafe { (&*info, *swapchain) };
            data.state().swapchains.insert(handle, (info.image_format, info.image_extent));
        });
    }
    result
}

/// vkGetSwapchainImagesKHR: the images are noted as a swapchain's (a full-frame copy or blit
/// into one is named).
pub(super) unsafe extern "system" fn get_swapchain_images(
    device: vk::Device,
    swapchain: vk::SwapchainKHR,
    count: *mut u32,
    images: *mut vk::Image,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.get_swapchain_images_khr) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, swapchain, count, images) };
    if result == vk::Result::SUCCESS && !images.is_null() {
        guard((), || {
            // SAFETY: the call filled `*count` images.
            let handles = unsafe { app_array(images, *count) };
            let mut st = data.state();
            let Some(&(format, extent)) = st.swapchains.get(&swapchain) else { return };
            for &image in handles {
                let info = bytes::ImageInfo {
                    format,
                    extent: vk::Extent3D { width: extent.width, height: extent.height, depth: 1 },
                    mip_levels: 1,
                    array_layers: 1,
                    samples: 1,
                    swapchain: true,
                };
                st.images.insert(image, info);
            }
        });
    }
    result
}
