//! Sampled textures: an image uploaded through a staging buffer (optionally with a mip chain
//! built by blits), left in SHADER_READ_ONLY_OPTIMAL, with its sampler.

use std::ops::Range;
use std::sync::Arc;

use ash::vk;
use image::RgbaImage;

use super::barriers;
use super::commands::submit_and_wait;
use super::live_objects::ObjectKind;
use super::memory::{Buffer, Image, ImageDesc};
use super::Gpu;
use crate::error::{Error, Result, VkContext};

pub struct Sampler {
    gpu: Arc<Gpu>,
    pub raw: vk::Sampler,
}

impl Sampler {
    /// Linear or nearest filtering, trilinear when the image has mips; no anisotropy (the mobile
    /// profile keeps samplerAnisotropy off).
    pub fn new(gpu: &Arc<Gpu>, filter: vk::Filter, address: vk::SamplerAddressMode) -> Result<Self> {
        let mipmap =
            if filter == vk::Filter::LINEAR { vk::SamplerMipmapMode::LINEAR } else { vk::SamplerMipmapMode::NEAREST };
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(mipmap)
            .address_mode_u(address)
            .address_mode_v(address)
            .address_mode_w(address)
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: `gpu` holds the device; anisotropy stays off, as the profile requires.
        let raw = unsafe { gpu.raw().create_sampler(&info, None) }.vk("vkCreateSampler")?;
        gpu.created(ObjectKind::Sampler);
        Ok(Sampler { gpu: gpu.clone(), raw })
    }

    /// A depth-compare sampler (`sampler2DShadow`): LESS_OR_EQUAL against the reference,
    /// nearest texel, outside the map reads as lit (white border, depth 1).
    pub fn depth_compare(gpu: &Arc<Gpu>) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_BORDER)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_BORDER)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_BORDER)
            .border_color(vk::BorderColor::FLOAT_OPAQUE_WHITE)
            .compare_enable(true)
            .compare_op(vk::CompareOp::LESS_OR_EQUAL)
            // A shadow map has one mip: no clamp is needed (Arm's best practices flag one).
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: `gpu` holds the device; depth compare is core Vulkan and anisotropy stays off.
        let raw = unsafe { gpu.raw().create_sampler(&info, None) }.vk("vkCreateSampler")?;
        gpu.created(ObjectKind::Sampler);
        Ok(Sampler { gpu: gpu.clone(), raw })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: no pending command uses the sampler (see `Buffer`'s drop).
        unsafe { self.gpu.raw().destroy_sampler(self.raw, None) };
        self.gpu.destroyed(ObjectKind::Sampler);
    }
}

impl Sampler {
    /// Any sampler without anisotropy (the mobile profile keeps samplerAnisotropy off; the
    /// flag in `info` is ignored).
    pub fn from_info(gpu: &Arc<Gpu>, info: vk::SamplerCreateInfo) -> Result<Self> {
        let info = info.anisotropy_enable(false);
        // SAFETY: `gpu` holds the device; `info` points at nothing; anisotropy is off.
        let raw = unsafe { gpu.raw().create_sampler(&info, None) }.vk("vkCreateSampler")?;
        gpu.created(ObjectKind::Sampler);
        Ok(Sampler { gpu: gpu.clone(), raw })
    }
}

/// Whether the device can build a mip chain of `format` with linear blits (Vulkan requires it
/// for RGBA8 UNORM and sRGB, but a port should not assume it of every format).
pub fn can_blit_mips(gpu: &Gpu, format: vk::Format) -> bool {
    // SAFETY: the instance and physical device live as long as `gpu`.
    let props = unsafe { gpu.instance.raw.get_physical_device_format_properties(gpu.device.physical, format) };
    let needed = vk::FormatFeatureFlags::BLIT_SRC
        | vk::FormatFeatureFlags::BLIT_DST
        | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR;
    props.optimal_tiling_features.contains(needed)
}

/// Number of mip levels down to 1x1.
pub fn mip_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

pub struct Texture {
    pub image: Image,
    pub sampler: Sampler,
}

impl Texture {
    /// Uploads RGBA8 pixels (`format` is R8G8B8A8_UNORM or _SRGB); `mipmaps` builds the whole
    /// chain with linear blits.
    pub fn from_rgba8(
        gpu: &Arc<Gpu>,
        name: &str,
        pixels: &RgbaImage,
        format: vk::Format,
        mipmaps: bool,
        sampler: Sampler,
    ) -> Result<Self> {
        let (width, height, pixels) = (pixels.width(), pixels.height(), pixels.as_raw().as_slice());
        if pixels.len() as u64 != width as u64 * height as u64 * 4 {
            return Err(Error::InvalidInput(format!(
                "texture '{name}': {} bytes for {width}x{height} RGBA8",
                pixels.len()
            )));
        }
        let mip_levels = if mipmaps { mip_count(width, height) } else { 1 };
        let image = Image::new(
            gpu,
            &ImageDesc {
                name,
                format,
                extent: vk::Extent2D { width, height },
                usage: vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::TRANSFER_SRC,
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels,
                samples: 1,
            },
        )?;
        let staging = Buffer::with_data(gpu, &format!("{name} (staging)"), pixels, vk::BufferUsageFlags::TRANSFER_SRC)?;
        submit_and_wait(gpu, |cmd| {
            barriers::upload_destination(gpu.raw(), cmd, image.raw, 0..mip_levels);
            let region = vk::BufferImageCopy::default()
                .image_subresource(colour_layers(0))
                .image_extent(vk::Extent3D { width, height, depth: 1 });
            // SAFETY: `cmd` is recording; mip 0 is TRANSFER_DST_OPTIMAL (barrier above); the
            // staging buffer holds exactly width x height x 4 bytes (checked above) and both
            // live until `submit_and_wait` has waited.
            unsafe {
                gpu.raw().cmd_copy_buffer_to_image(
                    cmd,
                    staging.raw,
                    image.raw,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &[region],
                )
            };
            record_mip_chain(gpu, cmd, image.raw, width, height, mip_levels);
            Ok(())
        })?;
        Ok(Texture { image, sampler })
    }
}

fn colour_layers(mip: u32) -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: mip,
        base_array_layer: 0,
        layer_count: 1,
    }
}

/// Copies mip `mip` (`side` x `side`, RGBA8, SHADER_READ_ONLY_OPTIMAL) of a colour image to
/// the CPU, leaving it sampled again.
pub fn read_back_mip(gpu: &Arc<Gpu>, image: vk::Image, mip: u32, side: u32) -> Result<Vec<u8>> {
    read_back_square(gpu, image, mip, (0, 0), side)
}

/// As [`read_back_mip`], the `side` x `side` square of mip `mip` whose corner is `corner` (a
/// tile of an atlas page).
pub fn read_back_square(gpu: &Arc<Gpu>, image: vk::Image, mip: u32, corner: (u32, u32), side: u32) -> Result<Vec<u8>> {
    let readback = Buffer::new(
        gpu,
        "shadow texture readback",
        side as u64 * side as u64 * 4,
        vk::BufferUsageFlags::TRANSFER_DST,
        gpu_allocator::MemoryLocation::GpuToCpu,
    )?;
    submit_and_wait(gpu, |cmd| {
        barriers::sampled_to_read_back(gpu.raw(), cmd, image, mip);
        let region = vk::BufferImageCopy::default()
            .image_subresource(colour_layers(mip))
            .image_offset(vk::Offset3D { x: corner.0 as i32, y: corner.1 as i32, z: 0 })
            .image_extent(vk::Extent3D { width: side, height: side, depth: 1 });
        // SAFETY: `cmd` is recording; the barrier above made the mip TRANSFER_SRC_OPTIMAL, the
        // region lies inside it and the buffer holds side * side RGBA8 texels.
        unsafe {
            gpu.raw().cmd_copy_image_to_buffer(
                cmd,
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.raw,
                &[region],
            )
        };
        barriers::read_back_to_sampled(gpu.raw(), cmd, image, mip);
        // The copy's writes become visible to the host read after the fence wait.
        barriers::transfer_to_host(gpu.raw(), cmd, readback.raw);
        Ok(())
    })?;
    Ok(readback.read()?.to_vec())
}

/// Builds mips 1.. from mip 0 (which must be in TRANSFER_DST_OPTIMAL, the others too) with
/// linear blits, leaving every mip sampled (SHADER_READ_ONLY_OPTIMAL, for fragment shaders).
pub fn record_mip_chain(gpu: &Gpu, cmd: vk::CommandBuffer, image: vk::Image, width: u32, height: u32, mip_levels: u32) {
    blit_chain(gpu, cmd, image, (width, height), mip_levels, false);
}

/// As [`record_mip_chain`], from a mip 0 left ready for sampling (SHADER_READ_ONLY_OPTIMAL,
/// its writes made visible to transfers by the render pass that wrote it), which it keeps; the
/// other mips' old contents are dropped.
pub fn record_mip_chain_from_sampled(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    width: u32,
    height: u32,
    mip_levels: u32,
) {
    if mip_levels > 1 {
        barriers::upload_destination(gpu.raw(), cmd, image, 1..mip_levels);
        barriers::sampled_to_read_back(gpu.raw(), cmd, image, 0);
    }
    blit_chain(gpu, cmd, image, (width, height), mip_levels, true);
}

/// Blits each mip from the one before; `first_source_ready`: mip 0 is already a blit source.
fn blit_chain(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    (width, height): (u32, u32),
    mip_levels: u32,
    first_source_ready: bool,
) {
    if mip_levels == 0 || (first_source_ready && mip_levels == 1) {
        return; // nothing to build; a sampled mip 0 stays as it is
    }
    let device = gpu.raw();
    let (mut w, mut h) = (width as i32, height as i32);
    for mip in 1..mip_levels {
        if !(first_source_ready && mip == 1) {
            barriers::mip_to_blit_source(device, cmd, image, mip - 1);
        }
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let blit = vk::ImageBlit {
            src_subresource: colour_layers(mip - 1),
            src_offsets: [vk::Offset3D::default(), vk::Offset3D { x: w, y: h, z: 1 }],
            dst_subresource: colour_layers(mip),
            dst_offsets: [vk::Offset3D::default(), vk::Offset3D { x: nw, y: nh, z: 1 }],
        };
        // SAFETY: `cmd` is recording; mip - 1 is TRANSFER_SRC_OPTIMAL and mip TRANSFER_DST_OPTIMAL
        // (the caller's contract and the barrier above); both rectangles lie inside their mips;
        // the project's textures are RGBA8 (UNORM or sRGB), whose linear blits Vulkan requires.
        unsafe {
            gpu.raw().cmd_blit_image(
                cmd,
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[blit],
                vk::Filter::LINEAR,
            )
        };
        barriers::read_back_to_sampled(device, cmd, image, mip - 1);
        (w, h) = (nw, nh);
    }
    barriers::written_mip_to_sampled(device, cmd, image, mip_levels - 1..mip_levels);
}

/// Each of `images` left for sampling (SHADER_READ_ONLY) in one submission, its mips in the
/// range given cleared to `colour` and the others left as they are (undefined: a render pass
/// that clears or overwrites them comes first; clearing them here too would only move bytes, and
/// a tiler would read the clear back into tile memory). The images need TRANSFER_DST usage.
pub fn ready_for_sampling(gpu: &Arc<Gpu>, images: &[(&Image, Range<u32>)], colour: [f32; 4]) -> Result<()> {
    submit_and_wait(gpu, |cmd| {
        for (image, cleared) in images {
            let mips = 0..image.mip_levels;
            barriers::upload_destination(gpu.raw(), cmd, image.raw, mips.clone());
            if !cleared.is_empty() {
                let range = vk::ImageSubresourceRange {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    base_mip_level: cleared.start,
                    level_count: cleared.len() as u32,
                    base_array_layer: 0,
                    layer_count: 1,
                };
                let clear = vk::ClearColorValue { float32: colour };
                // SAFETY: `cmd` is recording; the barrier above made every mip TRANSFER_DST_OPTIMAL,
                // and the caller created the image with TRANSFER_DST usage and these mips.
                unsafe {
                    gpu.raw().cmd_clear_color_image(
                        cmd,
                        image.raw,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        &clear,
                        &[range],
                    )
                };
            }
            barriers::written_mip_to_sampled(gpu.raw(), cmd, image.raw, mips);
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn mip_count_reaches_one_pixel() {
        assert_eq!(super::mip_count(1, 1), 1);
        assert_eq!(super::mip_count(256, 256), 9);
        assert_eq!(super::mip_count(257, 3), 9);
    }
}
