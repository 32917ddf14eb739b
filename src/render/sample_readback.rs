//! Reads every sample of a multisampled frame back to the CPU, for tests that check a frame
//! before its resolve. The frame must have kept its samples (`RenderOptions.keep_samples`: the
//! multisampled colour stored, SAMPLED, left in GENERAL). One full-screen pass of its own
//! fetches sample i of pixel (x, y) (`texelFetch` on a `sampler2DMS`) into pixel (x * N + i, y)
//! of a one-sample image of the frame's format, then copies that to the CPU. It is a separate
//! submission, never part of a timed frame.
//!
//! The bytes are the stored ones: alpha is linear in R8G8B8A8_SRGB; the RGB that the fetch
//! decodes from sRGB is encoded again by the write to the sRGB target.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::pipeline_object::Pipeline;
use crate::error::{Error, Result};
use crate::frame::offscreen::{colour_render_pass, Framebuffer};
use crate::frame::FrameTargets;
use crate::gpu::barriers;
use crate::gpu::commands::submit_and_wait;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{sample_count_flags, Buffer, Image, ImageDesc};
use crate::gpu::regions;
use crate::gpu::texture::Sampler;
use crate::gpu::Gpu;
use crate::pipeline::{FixedFunction, PipelineDesc, VertexLayout};
use crate::shaders;

/// Every sample of a frame, as stored (RGBA8, the frame's format).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameSamples {
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    /// Row by row, pixel by pixel, sample by sample: 4 bytes each.
    pub bytes: Vec<u8>,
}

impl FrameSamples {
    /// Sample `i` of pixel (`x`, `y`).
    pub fn sample(&self, x: u32, y: u32, i: u32) -> [u8; 4] {
        let at = (((y * self.width + x) * self.samples + i) * 4) as usize;
        [self.bytes[at], self.bytes[at + 1], self.bytes[at + 2], self.bytes[at + 3]]
    }

    /// The samples of pixel (`x`, `y`), in sample order.
    pub fn pixel(&self, x: u32, y: u32) -> Vec<[u8; 4]> {
        (0..self.samples).map(|i| self.sample(x, y, i)).collect()
    }
}

fn readback_desc() -> PipelineDesc {
    PipelineDesc {
        name: "sample read-back",
        vertex_shader: shaders::FULLSCREEN_VERT,
        fragment_shader: shaders::SAMPLE_READBACK_FRAG,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction::FULLSCREEN,
        push_constant_bytes: 4,
    }
}

/// Every sample of the last frame drawn into `targets`, which must have kept them.
pub fn read_samples(gpu: &Arc<Gpu>, targets: &FrameTargets) -> Result<FrameSamples> {
    let samples = targets.samples();
    let kept = match &targets.multisampled {
        Some(image) if targets.desc.colour.store == vk::AttachmentStoreOp::STORE => image,
        _ => {
            return Err(Error::InvalidInput(format!(
                "read_samples: the {samples}-sample frame did not keep its samples (render it with keep_samples)"
            )))
        }
    };
    if !gpu.device.info.limits.sampled_image_color_sample_counts.contains(sample_count_flags(samples)) {
        return Err(Error::Device(format!("read_samples: the device cannot sample a {samples}-sample colour image")));
    }
    let format = targets.desc.destination.format();
    let extent = vk::Extent2D { width: targets.extent.width * samples, height: targets.extent.height };
    let target = Image::new(
        gpu,
        &ImageDesc {
            name: "sample read-back",
            format,
            extent,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            aspect: vk::ImageAspectFlags::COLOR,
            mip_levels: 1,
            samples: 1,
        },
    )?;
    let render_pass = colour_render_pass(gpu, format, false, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)?;
    let framebuffer = Framebuffer::new(gpu, &render_pass, target.view, extent)?;
    let sampler = Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
    let set = DescriptorSet::new(
        gpu,
        &[Binding::Texture {
            view: kept.view,
            sampler: sampler.raw,
            layout: vk::ImageLayout::GENERAL,
            stages: vk::ShaderStageFlags::FRAGMENT,
        }],
    )?;
    let pipeline = Pipeline::new(gpu, &readback_desc(), render_pass.raw, &[set.layout])?;
    let readback = Buffer::new(
        gpu,
        "sample read-back",
        extent.width as u64 * extent.height as u64 * 4,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;

    let device = gpu.raw();
    submit_and_wait(gpu, |cmd| {
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(render_pass.raw)
            .framebuffer(framebuffer.raw)
            .render_area(area);
        let viewport = regions::full_viewport(extent);
        let region = regions::colour_to_buffer(extent);
        // SAFETY: `cmd` is recording; every handle used belongs to this function and outlives
        // the submission `submit_and_wait` waits for. The kept samples are in GENERAL, where the
        // frame's render pass left them, its dependency making its writes visible to fragment
        // shaders; this render pass leaves `target` in TRANSFER_SRC_OPTIMAL for the copy, whose
        // buffer is sized for `extent` in RGBA8.
        unsafe {
            device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
            device.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.layout, 0, &[set.set], &[]);
            device.cmd_push_constants(
                cmd,
                pipeline.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                &(samples as i32).to_ne_bytes(),
            );
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
            device.cmd_draw(cmd, 3, 1, 0, 0);
            device.cmd_end_render_pass(cmd);
            device.cmd_copy_image_to_buffer(
                cmd,
                target.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.raw,
                &[region],
            );
        }
        barriers::transfer_to_host(device, cmd, readback.raw);
        Ok(())
    })?;
    Ok(FrameSamples {
        width: targets.extent.width,
        height: targets.extent.height,
        samples,
        bytes: readback.read()?.to_vec(),
    })
}
