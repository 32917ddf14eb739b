//! The commands that put a rendered frame on screen: the RGBA8 colour target is blitted (or
//! copied) into the acquired swapchain image, read back for a screenshot if asked, and the
//! image is handed over to presentation.

use ash::vk;

use super::swapchain::{Swapchain, Transfer};

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
    let range = vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    };
    let layers = vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    let barrier = |image, old, new, src_access, dst_access| {
        vk::ImageMemoryBarrier::default()
            .src_access_mask(src_access)
            .dst_access_mask(dst_access)
            .old_layout(old)
            .new_layout(new)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(image)
            .subresource_range(range)
    };
    unsafe {
        // The frame's render pass left the colour target in TRANSFER_SRC_OPTIMAL; the
        // acquired image's old contents do not matter.
        let to_transfer = [
            barrier(
                colour,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                vk::AccessFlags::TRANSFER_READ,
            ),
            barrier(
                image,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::AccessFlags::empty(),
                vk::AccessFlags::TRANSFER_WRITE,
            ),
        ];
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::TRANSFER,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &to_transfer,
        );
        let corner = vk::Offset3D { x: extent.width as i32, y: extent.height as i32, z: 1 };
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
        let mut present_from = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
        let mut present_access = vk::AccessFlags::TRANSFER_WRITE;
        if let Some(buffer) = screenshot {
            // Read back what will be presented, from the swapchain image itself (or, where
            // its images cannot be read, from the frame it was copied from).
            let (source, layout) = if swapchain.readable {
                device.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::DependencyFlags::empty(),
                    &[],
                    &[],
                    &[barrier(
                        image,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        vk::AccessFlags::TRANSFER_WRITE,
                        vk::AccessFlags::TRANSFER_READ,
                    )],
                );
                present_from = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                present_access = vk::AccessFlags::empty();
                (image, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            } else {
                (colour, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            };
            let region = vk::BufferImageCopy::default().image_subresource(layers).image_extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            });
            device.cmd_copy_image_to_buffer(cmd, source, layout, buffer, &[region]);
            crate::gpu::barriers::transfer_to_host(device, cmd, buffer);
        }
        // Presentation waits on the semaphore, which orders it after this command buffer.
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &[barrier(image, present_from, vk::ImageLayout::PRESENT_SRC_KHR, present_access, vk::AccessFlags::empty())],
        );
    }
}
