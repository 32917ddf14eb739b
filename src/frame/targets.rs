//! The frame's render targets: RGBA8 colour (alpha kept, it is the stencil's stand-in) and a
//! transient depth attachment, plus the render pass and framebuffer that bind them.

use std::sync::Arc;

use ash::vk;

use super::render_pass::{RenderPassDesc, StencilMode, COLOUR_FORMAT};
use crate::error::{Error, Result, VkContext};
use crate::gpu::memory::{Image, ImageDesc};
use crate::gpu::Gpu;

pub struct FrameTargets {
    gpu: Arc<Gpu>,
    pub extent: vk::Extent2D,
    pub stencil: StencilMode,
    pub desc: RenderPassDesc,
    pub colour: Image,
    pub depth: Image,
    pub render_pass: vk::RenderPass,
    pub framebuffer: vk::Framebuffer,
}

/// Depth formats in order of preference, per stencil mode.
fn depth_candidates(stencil: StencilMode) -> &'static [vk::Format] {
    match stencil {
        StencilMode::Emulated => &[vk::Format::D32_SFLOAT, vk::Format::D16_UNORM],
        StencilMode::Reference => &[vk::Format::D32_SFLOAT_S8_UINT, vk::Format::D24_UNORM_S8_UINT],
    }
}

pub fn choose_depth_format(gpu: &Gpu, stencil: StencilMode) -> Result<vk::Format> {
    depth_candidates(stencil)
        .iter()
        .copied()
        .find(|&format| {
            // SAFETY: the physical device was enumerated from this live instance.
            let props = unsafe { gpu.instance.raw.get_physical_device_format_properties(gpu.device.physical, format) };
            props.optimal_tiling_features.contains(vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT)
        })
        .ok_or_else(|| Error::Device(format!("the device has no usable depth format for the {} frame", stencil.name())))
}

impl FrameTargets {
    pub fn new(gpu: &Arc<Gpu>, width: u32, height: u32, stencil: StencilMode, colour_feedback: bool) -> Result<Self> {
        crate::gpu::mobile_profile::check_image_size("frame", width, height)?;
        let extent = vk::Extent2D { width, height };
        let depth_format = choose_depth_format(gpu, stencil)?;
        let desc = RenderPassDesc::frame(depth_format, colour_feedback);

        let colour = Image::new(
            gpu,
            &ImageDesc {
                name: "frame colour",
                format: COLOUR_FORMAT,
                extent,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::INPUT_ATTACHMENT,
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
            },
        )?;
        let depth_aspect = if desc.has_stencil() {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        } else {
            vk::ImageAspectFlags::DEPTH
        };
        let depth = Image::new(
            gpu,
            &ImageDesc {
                name: "frame depth",
                format: depth_format,
                extent,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                aspect: depth_aspect,
                mip_levels: 1,
            },
        )?;

        let device = gpu.raw();
        let render_pass = desc.build(device)?;
        let views = [colour.view, depth.view];
        let fb_info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(&views)
            .width(width)
            .height(height)
            .layers(1);
        // SAFETY: both views are alive (owned by `colour` and `depth`, kept with the framebuffer)
        // and match the render pass's two attachments, at the framebuffer's size.
        let framebuffer = match unsafe { device.create_framebuffer(&fb_info, None) }.vk("vkCreateFramebuffer") {
            Ok(fb) => fb,
            Err(e) => {
                // SAFETY: the render pass was just created and nothing uses it.
                unsafe { device.destroy_render_pass(render_pass, None) };
                return Err(e);
            }
        };
        Ok(FrameTargets { gpu: gpu.clone(), extent, stencil, desc, colour, depth, render_pass, framebuffer })
    }
}

impl Drop for FrameTargets {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: no pending command uses them (see `Buffer`'s drop); the framebuffer goes before
        // its render pass, and the images (fields) after both.
        unsafe {
            device.destroy_framebuffer(self.framebuffer, None);
            device.destroy_render_pass(self.render_pass, None);
        }
    }
}
