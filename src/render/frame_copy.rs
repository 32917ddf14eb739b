//! The commands that put a rendered frame on screen when it was not drawn into the swapchain
//! image itself: the RGBA8 colour target is blitted (or copied) into the acquired swapchain
//! image, read back for a screenshot if asked, and the image is handed over to presentation.
//! A frame drawn into the swapchain image only needs the screenshot's read-back
//! (`record_screenshot`).

use ash::vk;

use crate::gpu::barriers::{self, BeforePresent, SwapchainFrame};
use crate::gpu::regions;
use crate::gpu::swapchain::{Swapchain, Transfer};

/// Records into `cmd` (recording) the copy of `colour`, the frame, into swapchain image
/// `index`; with `screenshot`, what will be presented is also copied into that buffer (sized
/// for the swapchain's extent). The image ends in PRESENT_SRC_KHR.
pub fn record(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    colour: vk::Image,
    swapchain: &Swapchain,
    index: u32,
    screenshot: Option<vk::Buffer>,
) {
    let extent = swapchain.extent;
    let image = swapchain.images[index as usize];
    let layers = regions::COLOUR_LAYER;
    barriers::frame_to_swapchain_copy(device, cmd, colour, image);
    let corner = vk::Offset3D { x: extent.width as i32, y: extent.height as i32, z: 1 };
    // SAFETY: `cmd` is recording (the presenter's begin and end surround this call); `colour`
    // is the live frame target in TRANSFER_SRC_OPTIMAL and `image` the acquired swapchain image,
    // just moved to TRANSFER_DST_OPTIMAL; both are at least `extent` in size, and the blit
    // source and destination formats support blitting (`Transfer::Blit` is only chosen then).
    unsafe {
        match swapchain.transfer {
            Transfer::Blit => {
                let region = vk::ImageBlit {
                    src_subresource: layers,
                    src_offsets: [vk::Offset3D::default(), corner],
                    dst_subresource: layers,
                    dst_offsets: [vk::Offset3D::default(), corner],
                };
                device.cmd_blit_image(
                    cmd,
                    colour,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    image,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &[region],
                    vk::Filter::NEAREST,
                );
            }
            Transfer::Copy => {
                let region = vk::ImageCopy {
                    src_subresource: layers,
                    src_offset: vk::Offset3D::default(),
                    dst_subresource: layers,
                    dst_offset: vk::Offset3D::default(),
                    extent: vk::Extent3D { width: extent.width, height: extent.height, depth: 1 },
                };
                device.cmd_copy_image(
                    cmd,
                    colour,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    image,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &[region],
                );
            }
        }
    }
    let mut before_present = BeforePresent::Copied;
    if let Some(buffer) = screenshot {
        // Read back what will be presented, from the swapchain image itself (or, where its
        // images cannot be read, from the frame it was copied from).
        let source = if swapchain.readable {
            barriers::swapchain_to_read_back(device, cmd, image, SwapchainFrame::Copied);
            before_present = BeforePresent::ReadBack;
            image
        } else {
            colour
        };
        let region = vk::BufferImageCopy::default().image_subresource(layers).image_extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        });
        // SAFETY: `cmd` is recording; `source` is in TRANSFER_SRC_OPTIMAL (the barrier above, or
        // the frame target's layout) and `buffer` is the presenter's screenshot buffer, sized for
        // `extent` in RGBA8 and alive until the slot's fence is waited for.
        unsafe {
            device.cmd_copy_image_to_buffer(cmd, source, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, buffer, &[region])
        };
        barriers::transfer_to_host(device, cmd, buffer);
    }
    barriers::swapchain_to_present(device, cmd, image, before_present);
}

/// Records into `cmd` (recording, after the frame's render pass) the read-back of swapchain
/// image `image`, which the pass drew into and left in PRESENT_SRC_KHR, into `buffer` (sized for
/// `extent` at 4 bytes a pixel); the image is left ready to present again.
pub fn record_screenshot(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent2D,
    buffer: vk::Buffer,
) {
    barriers::swapchain_to_read_back(device, cmd, image, SwapchainFrame::Drawn);
    // SAFETY: `cmd` is recording outside a render pass; `image` is in TRANSFER_SRC_OPTIMAL (the
    // barrier above) and `buffer` is the presenter's screenshot buffer, sized for `extent` in
    // 4-byte pixels and alive until the frame's fence is waited for.
    unsafe {
        device.cmd_copy_image_to_buffer(
            cmd,
            image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            buffer,
            &[regions::colour_to_buffer(extent)],
        )
    };
    barriers::transfer_to_host(device, cmd, buffer);
    barriers::swapchain_to_present(device, cmd, image, BeforePresent::ReadBack);
}
