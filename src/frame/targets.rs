//! The frame's render targets: RGBA8 colour (alpha kept, it is the stencil's stand-in) and a
//! transient depth attachment, plus the render pass and framebuffer that bind them. A
//! multisampled frame draws into transient multisampled colour and depth and resolves into a
//! one-sample colour image, the one read back or presented.

use std::sync::Arc;

use ash::vk;

use super::render_pass::{RenderPassDesc, StencilMode, COLOUR_FORMAT};
use crate::error::{Error, Result, VkContext};
use crate::gpu::live_objects::ObjectKind;
use crate::gpu::memory::{sample_count_flags, Image, ImageDesc};
use crate::gpu::Gpu;

pub struct FrameTargets {
    gpu: Arc<Gpu>,
    pub extent: vk::Extent2D,
    pub stencil: StencilMode,
    pub desc: RenderPassDesc,
    /// The frame as it leaves the render pass (one sample; TRANSFER_SRC_OPTIMAL): read back,
    /// presented.
    pub colour: Image,
    /// The multisampled colour the passes draw into, when the frame has several samples.
    pub multisampled: Option<Image>,
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

/// The sample counts the device offers for the frame's colour and depth (and stencil, in the
/// reference path) attachments at once.
pub fn frame_sample_counts(gpu: &Gpu, stencil: StencilMode) -> vk::SampleCountFlags {
    let limits = &gpu.device.info.limits;
    let mut counts = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
    if stencil == StencilMode::Reference {
        counts &= limits.framebuffer_stencil_sample_counts;
    }
    counts
}

/// The samples per pixel (of 1, 2, 4, 8) the device offers for the frame in `stencil`'s path.
pub fn offered_samples(gpu: &Gpu, stencil: StencilMode) -> Vec<u32> {
    let counts = frame_sample_counts(gpu, stencil);
    [1u32, 2, 4, 8].into_iter().filter(|&n| counts.contains(sample_count_flags(n))).collect()
}

/// What a frame of `samples` samples needs from the device: an error naming the counts it has.
pub fn check_samples(gpu: &Gpu, stencil: StencilMode, samples: u32) -> Result<()> {
    let offered = offered_samples(gpu, stencil);
    if offered.contains(&samples) {
        return Ok(());
    }
    let offered: Vec<String> = offered.iter().map(u32::to_string).collect();
    Err(Error::Device(format!(
        "--samples {samples}: the device offers {} samples per pixel for the {} frame",
        offered.join(", "),
        stencil.name()
    )))
}

/// The frame's images for `desc`: the one-sample colour (the resolve target at several samples,
/// read back and fed back as an input attachment at one), the multisampled colour at several
/// samples (transient unless `keep_samples`), and the depth (transient: it never leaves tile
/// memory).
fn frame_images(
    gpu: &Arc<Gpu>,
    desc: &RenderPassDesc,
    extent: vk::Extent2D,
    samples: u32,
    keep_samples: bool,
) -> Result<(Image, Option<Image>, Image)> {
    let multisampled_frame = desc.resolve.is_some();
    let depth_format = desc.depth.format;
    let mut colour_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    if !multisampled_frame {
        colour_usage |= vk::ImageUsageFlags::INPUT_ATTACHMENT;
    }
    let colour = Image::new(
        gpu,
        &ImageDesc {
            name: "frame colour",
            format: COLOUR_FORMAT,
            extent,
            usage: colour_usage,
            aspect: vk::ImageAspectFlags::COLOR,
            mip_levels: 1,
            samples: 1,
        },
    )?;
    let multisampled = if multisampled_frame {
        // Transient: it lives in tile memory and is resolved before it would leave it.
        let kept = if keep_samples { vk::ImageUsageFlags::SAMPLED } else { vk::ImageUsageFlags::TRANSIENT_ATTACHMENT };
        Some(Image::new(
            gpu,
            &ImageDesc {
                name: "frame colour (multisampled)",
                format: COLOUR_FORMAT,
                extent,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::INPUT_ATTACHMENT | kept,
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
                samples,
            },
        )?)
    } else {
        None
    };
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
            samples,
        },
    )?;
    Ok((colour, multisampled, depth))
}

impl FrameTargets {
    /// A one-sample frame at `width` x `height`. `colour_feedback`: the colour is also an input
    /// attachment of its own subpass.
    pub fn new(gpu: &Arc<Gpu>, width: u32, height: u32, stencil: StencilMode, colour_feedback: bool) -> Result<Self> {
        Self::with_samples(gpu, width, height, stencil, colour_feedback, 1, false)
    }

    /// As [`FrameTargets::new`] with `samples` samples per pixel. `keep_samples` stores the
    /// multisampled colour for a per-sample read-back instead of leaving it in tile memory.
    pub fn with_samples(
        gpu: &Arc<Gpu>,
        width: u32,
        height: u32,
        stencil: StencilMode,
        colour_feedback: bool,
        samples: u32,
        keep_samples: bool,
    ) -> Result<Self> {
        crate::gpu::mobile_profile::check_image_size("frame", width, height)?;
        check_samples(gpu, stencil, samples)?;
        let extent = vk::Extent2D { width, height };
        let depth_format = choose_depth_format(gpu, stencil)?;
        check_frame_fits(gpu, width, height, samples, depth_format)?;
        let desc = RenderPassDesc::frame(depth_format, colour_feedback, samples, keep_samples);
        let (colour, multisampled, depth) = frame_images(gpu, &desc, extent, samples, keep_samples)?;

        let device = gpu.raw();
        let render_pass = desc.build(device)?;
        gpu.created(ObjectKind::RenderPass);
        let views = match &multisampled {
            Some(drawn) => vec![drawn.view, depth.view, colour.view],
            None => vec![colour.view, depth.view],
        };
        let fb_info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(&views)
            .width(width)
            .height(height)
            .layers(1);
        // SAFETY: the views are alive (owned by the images kept with the framebuffer) and match
        // the render pass's attachments, in order, at the framebuffer's size.
        let framebuffer = match unsafe { device.create_framebuffer(&fb_info, None) }.vk("vkCreateFramebuffer") {
            Ok(fb) => {
                gpu.created(ObjectKind::Framebuffer);
                fb
            }
            Err(e) => {
                // SAFETY: the render pass was just created and nothing uses it.
                unsafe { device.destroy_render_pass(render_pass, None) };
                gpu.destroyed(ObjectKind::RenderPass);
                return Err(e);
            }
        };
        Ok(FrameTargets {
            gpu: gpu.clone(),
            extent,
            stencil,
            desc,
            colour,
            multisampled,
            depth,
            render_pass,
            framebuffer,
        })
    }

    /// The colour image the passes draw into (and a subpass reads as its input attachment):
    /// the multisampled one, else the frame's colour.
    pub fn drawn_colour(&self) -> &Image {
        self.multisampled.as_ref().unwrap_or(&self.colour)
    }

    /// Samples per pixel.
    pub fn samples(&self) -> u32 {
        self.desc.samples()
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
        self.gpu.destroyed(ObjectKind::Framebuffer);
        self.gpu.destroyed(ObjectKind::RenderPass);
    }
}

/// Refuses a frame whose targets (colour, multisampled colour, depth) and read-back buffer
/// together exceed the device's largest heap, naming the size and sample count to lower.
fn check_frame_fits(gpu: &Gpu, width: u32, height: u32, samples: u32, depth_format: vk::Format) -> Result<()> {
    let pixels = width as u64 * height as u64;
    let depth_bytes = match depth_format {
        vk::Format::D32_SFLOAT_S8_UINT => 8,
        _ => 4,
    };
    let multisampled = if samples > 1 { 4 * samples as u64 } else { 0 };
    // Colour, its read-back buffer, the multisampled colour, depth per sample.
    let bytes = pixels * (4 + 4 + multisampled + depth_bytes * samples as u64);
    crate::gpu::memory::check_fits_in_heap(
        gpu,
        &format!("a {width}x{height} frame at {samples}x MSAA"),
        bytes,
        ": choose a smaller --size or fewer --samples",
    )
}
