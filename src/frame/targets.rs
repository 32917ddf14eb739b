//! The frame's render targets: RGBA8 colour (alpha kept, it is the stencil's stand-in) and a
//! transient depth attachment, plus the render pass and framebuffer that bind them. A
//! multisampled frame draws into transient multisampled colour and depth and resolves into a
//! one-sample colour image, the one read back or presented.

use std::sync::Arc;

use ash::vk;

use super::render_pass::{FrameDestination, RenderPassDesc, StencilMode};
use crate::error::{Error, Result, VkContext};
use crate::gpu::live_objects::ObjectKind;
use crate::gpu::memory::{sample_count_flags, Image, ImageDesc};
use crate::gpu::Gpu;

pub struct FrameTargets {
    gpu: Arc<Gpu>,
    pub extent: vk::Extent2D,
    pub desc: RenderPassDesc,
    /// The frame as it leaves the render pass (one sample): read back, or presented.
    pub output: OutputImages,
    /// The multisampled colour the passes draw into, when the frame has several samples.
    pub multisampled: Option<Image>,
    pub depth: Image,
    pub render_pass: vk::RenderPass,
    /// One per output image (one offscreen; one per swapchain image once attached).
    framebuffers: Vec<vk::Framebuffer>,
    /// The output image the next frame is drawn into.
    current: usize,
}

/// The frame's one-sample colour images (`FrameDestination`).
pub enum OutputImages {
    /// The renderer's own image, left in TRANSFER_SRC_OPTIMAL.
    Own(Image),
    /// A swapchain's images (the swapchain's, not destroyed here) with a view of each made
    /// here, left in PRESENT_SRC_KHR; none until `attach_swapchain`.
    Swapchain { images: Vec<vk::Image>, views: Vec<vk::ImageView> },
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
) -> Result<(OutputImages, Option<Image>, Image)> {
    let multisampled_frame = desc.resolve.is_some();
    let depth_format = desc.depth.format;
    let mut colour_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    if !multisampled_frame {
        colour_usage |= vk::ImageUsageFlags::INPUT_ATTACHMENT;
    }
    let output = match desc.destination {
        FrameDestination::Offscreen => OutputImages::Own(Image::new(
            gpu,
            &ImageDesc {
                name: "frame colour",
                format: desc.destination.format(),
                extent,
                usage: colour_usage,
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
                samples: 1,
            },
        )?),
        FrameDestination::Swapchain { .. } => OutputImages::Swapchain { images: Vec::new(), views: Vec::new() },
    };
    let multisampled = if multisampled_frame {
        // Transient: it lives in tile memory and is resolved before it would leave it.
        let kept = if keep_samples { vk::ImageUsageFlags::SAMPLED } else { vk::ImageUsageFlags::TRANSIENT_ATTACHMENT };
        Some(Image::new(
            gpu,
            &ImageDesc {
                name: "frame colour (multisampled)",
                format: desc.destination.format(),
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
    Ok((output, multisampled, depth))
}

impl FrameTargets {
    /// A one-sample frame at `width` x `height`. `colour_feedback`: the colour is also an input
    /// attachment of its own subpass.
    #[cfg(test)]
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
        let frame = (width, height, samples);
        Self::build(gpu, frame, stencil, colour_feedback, keep_samples, FrameDestination::Offscreen)
    }

    /// A `width` x `height` frame of `samples` samples drawn into (or resolved into) the
    /// images of a swapchain of `format`, attached with [`FrameTargets::attach_swapchain`].
    /// A one-sample frame whose subpass reads its colour back (`colour_feedback`) cannot: its
    /// input attachment would change with every image.
    pub fn presenting(
        gpu: &Arc<Gpu>,
        (width, height, samples): (u32, u32, u32),
        stencil: StencilMode,
        colour_feedback: bool,
        format: vk::Format,
    ) -> Result<Self> {
        if colour_feedback && samples == 1 {
            return Err(Error::Internal(
                "a one-sample frame that reads its own colour is not drawn into swapchain images".into(),
            ));
        }
        let destination = FrameDestination::Swapchain { format };
        Self::build(gpu, (width, height, samples), stencil, colour_feedback, false, destination)
    }

    fn build(
        gpu: &Arc<Gpu>,
        (width, height, samples): (u32, u32, u32),
        stencil: StencilMode,
        colour_feedback: bool,
        keep_samples: bool,
        destination: FrameDestination,
    ) -> Result<Self> {
        crate::gpu::mobile_profile::check_image_size("frame", width, height)?;
        check_samples(gpu, stencil, samples)?;
        let extent = vk::Extent2D { width, height };
        let depth_format = choose_depth_format(gpu, stencil)?;
        check_frame_fits(gpu, width, height, samples, depth_format)?;
        let desc = RenderPassDesc::frame(depth_format, colour_feedback, samples, keep_samples, destination);
        let (output, multisampled, depth) = frame_images(gpu, &desc, extent, samples, keep_samples)?;

        let render_pass = desc.build(gpu.raw())?;
        gpu.created(ObjectKind::RenderPass);
        let mut targets = FrameTargets {
            gpu: gpu.clone(),
            extent,
            desc,
            output,
            multisampled,
            depth,
            render_pass,
            framebuffers: Vec::new(),
            current: 0,
        };
        // On failure `targets` is dropped, destroying the render pass.
        if let OutputImages::Own(colour) = &targets.output {
            let framebuffer = targets.framebuffer_for(colour.view)?;
            targets.framebuffers.push(framebuffer);
        }
        Ok(targets)
    }

    /// A framebuffer of the render pass with `output` as its one-sample colour.
    fn framebuffer_for(&self, output: vk::ImageView) -> Result<vk::Framebuffer> {
        let views = match &self.multisampled {
            Some(drawn) => vec![drawn.view, self.depth.view, output],
            None => vec![output, self.depth.view],
        };
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(self.render_pass)
            .attachments(&views)
            .width(self.extent.width)
            .height(self.extent.height)
            .layers(1);
        // SAFETY: the views are alive (owned by the images kept with the framebuffer, or made
        // for the attached swapchain's images and destroyed after it) and match the render
        // pass's attachments, in order, at the framebuffer's size.
        let framebuffer = unsafe { self.gpu.raw().create_framebuffer(&info, None) }.vk("vkCreateFramebuffer")?;
        self.gpu.created(ObjectKind::Framebuffer);
        Ok(framebuffer)
    }

    /// Draws the next frames into `images`, a swapchain's (at this frame's size and format),
    /// replacing those attached before; the caller makes sure no frame still uses the old ones.
    pub fn attach_swapchain(&mut self, images: &[vk::Image]) -> Result<()> {
        let FrameDestination::Swapchain { format } = self.desc.destination else {
            return Err(Error::Internal("an offscreen frame was given swapchain images".into()));
        };
        self.destroy_framebuffers();
        for &image in images {
            let info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format)
                .subresource_range(crate::gpu::regions::COLOUR_RANGE);
            // SAFETY: `image` is a live swapchain image of `format` (the caller's), one layer.
            let view = unsafe { self.gpu.raw().create_image_view(&info, None) }.vk("vkCreateImageView")?;
            self.gpu.created(ObjectKind::ImageView);
            if let OutputImages::Swapchain { images: kept, views } = &mut self.output {
                kept.push(image);
                views.push(view);
            }
            let framebuffer = self.framebuffer_for(view)?;
            self.framebuffers.push(framebuffer);
        }
        self.current = 0;
        Ok(())
    }

    /// The next frame is drawn into output image `index` (a swapchain image's index).
    pub fn select_output(&mut self, index: u32) -> Result<()> {
        if index as usize >= self.framebuffers.len() {
            return Err(Error::Internal(format!(
                "output image {index} of {}: attach the swapchain's images first",
                self.framebuffers.len()
            )));
        }
        self.current = index as usize;
        Ok(())
    }

    /// The framebuffer the next frame is drawn into.
    pub fn framebuffer(&self) -> Result<vk::Framebuffer> {
        self.framebuffers.get(self.current).copied().ok_or_else(|| {
            Error::Internal("a frame for swapchain images was drawn before the swapchain was attached".into())
        })
    }

    /// The renderer's own output image: None when frames go to a swapchain.
    pub fn colour(&self) -> Option<&Image> {
        match &self.output {
            OutputImages::Own(image) => Some(image),
            OutputImages::Swapchain { .. } => None,
        }
    }

    /// The one-sample image the next frame leaves the render pass in.
    pub fn output_image(&self) -> vk::Image {
        match &self.output {
            OutputImages::Own(image) => image.raw,
            OutputImages::Swapchain { images, .. } => images.get(self.current).copied().unwrap_or_default(),
        }
    }

    /// Whether frames are presented as rendered, into a swapchain's images.
    pub fn presents(&self) -> bool {
        matches!(self.desc.destination, FrameDestination::Swapchain { .. })
    }

    /// The colour image the passes draw into, if it is the renderer's own: the multisampled
    /// one, else the frame's colour (a subpass reads it as its input attachment).
    pub fn drawn_colour(&self) -> Option<&Image> {
        self.multisampled.as_ref().or_else(|| self.colour())
    }

    /// The colour image the passes of the next frame draw into.
    pub fn drawn_colour_image(&self) -> vk::Image {
        self.multisampled.as_ref().map_or_else(|| self.output_image(), |image| image.raw)
    }

    /// Samples per pixel.
    pub fn samples(&self) -> u32 {
        self.desc.samples()
    }

    fn destroy_framebuffers(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: no pending command uses them (the owner's drop or the caller of
        // `attach_swapchain` waited); each handle is destroyed once, framebuffers before views.
        unsafe {
            for framebuffer in self.framebuffers.drain(..) {
                device.destroy_framebuffer(framebuffer, None);
                self.gpu.destroyed(ObjectKind::Framebuffer);
            }
            if let OutputImages::Swapchain { images, views } = &mut self.output {
                images.clear();
                for view in views.drain(..) {
                    device.destroy_image_view(view, None);
                    self.gpu.destroyed(ObjectKind::ImageView);
                }
            }
        }
    }
}

impl Drop for FrameTargets {
    fn drop(&mut self) {
        self.destroy_framebuffers();
        // SAFETY: no pending command uses it (see `Buffer`'s drop); the framebuffers went
        // before it, and the images (fields) go after.
        unsafe { self.gpu.raw().destroy_render_pass(self.render_pass, None) };
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
