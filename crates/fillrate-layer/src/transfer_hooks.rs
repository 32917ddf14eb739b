//! Hooks for the transfer commands outside render passes (work.rs): each is a row of its own,
//! timed, with the bytes it reads and writes worked out from its regions (transfer_bytes.rs).
//! The call goes on through the tiler check's hook (image_use.rs) when the check is on.

use ash::vk;

use super::arrays::app_array;
use super::commands::{around, pass_on_through_check};
use super::image_use as t;
use super::state::DeviceData;
use super::transfer_bytes as bytes;
use super::work::Moved;
use super::work_hooks::transfer;

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

pub(super) unsafe extern "system" fn cmd_copy_buffer2_khr(
    cmd: vk::CommandBuffer,
    info: *const vk::CopyBufferInfo2<'_>,
) {
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
            pass_on_through_check!(d, cmd_copy_image(cmd, src, src_layout, dst, dst_layout, count, regions));
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
            pass_on_through_check!(d, cmd_blit_image(cmd, src, src_layout, dst, dst_layout, count, regions, filter));
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
            pass_on_through_check!(d, cmd_resolve_image(cmd, src, src_layout, dst, dst_layout, count, regions));
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
            pass_on_through_check!(d, cmd_copy_image_to_buffer(cmd, src, layout, buffer, count, regions));
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
            pass_on_through_check!(d, cmd_copy_buffer_to_image(cmd, buffer, dst, layout, count, regions));
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
            pass_on_through_check!(d, cmd_clear_color_image(cmd, image, layout, colour, count, ranges));
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
            pass_on_through_check!(d, cmd_clear_depth_stencil_image(cmd, image, layout, value, count, ranges));
        },
        |d, st| {
            transfer(d, st, cmd, "vkCmdClearDepthStencilImage", |st| {
                // SAFETY: the application's `count` ranges.
                bytes::clear_image(st.images.get(&image), unsafe { app_array(ranges, count) })
            })
        },
    );
}

/// The hooks of a `*2` image transfer under each of its names, core and KHR alias: each passes
/// on to the tiler check's hook of its name (`t::`) or the next layer's, and `$moved` works out
/// the bytes from the state and the info.
macro_rules! transfer2_hook {
    ([$($name:ident),+], $info:ty, $api:literal, |$st:ident, $i:ident| $moved:expr) => {$(
        pub(super) unsafe extern "system" fn $name(cmd: vk::CommandBuffer, info: *const $info) {
            around(
                cmd,
                |d| {
                    if d.config.tiler {
                        // SAFETY: the application's arguments, passed on through the check.
                        unsafe { t::$name(cmd, info) }
                    } else if let Some(next) = d.next.$name {
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
    )+};
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

transfer2_hook!([cmd_copy_image2, cmd_copy_image2_khr], vk::CopyImageInfo2<'_>, "vkCmdCopyImage2", |st, i| {
    bytes::copy_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_copies(i))
});
transfer2_hook!([cmd_blit_image2, cmd_blit_image2_khr], vk::BlitImageInfo2<'_>, "vkCmdBlitImage2", |st, i| {
    bytes::blit_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_blits(i))
});
transfer2_hook!(
    [cmd_resolve_image2, cmd_resolve_image2_khr],
    vk::ResolveImageInfo2<'_>,
    "vkCmdResolveImage2",
    |st, i| bytes::resolve_image(st.images.get(&i.src_image), st.images.get(&i.dst_image), &image_resolves(i))
);
transfer2_hook!(
    [cmd_copy_image_to_buffer2, cmd_copy_image_to_buffer2_khr],
    vk::CopyImageToBufferInfo2<'_>,
    "vkCmdCopyImageToBuffer2",
    // SAFETY: the info's regions.
    |st, i| bytes::buffer_image(
        st.images.get(&i.src_image),
        &unsafe { buffer_image_copies(i.p_regions, i.region_count) },
        false
    )
);
transfer2_hook!(
    [cmd_copy_buffer_to_image2, cmd_copy_buffer_to_image2_khr],
    vk::CopyBufferToImageInfo2<'_>,
    "vkCmdCopyBufferToImage2",
    // SAFETY: the info's regions.
    |st, i| bytes::buffer_image(
        st.images.get(&i.dst_image),
        &unsafe { buffer_image_copies(i.p_regions, i.region_count) },
        true
    )
);
