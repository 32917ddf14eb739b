//! The targets the shadow techniques render into before the frame: the lights' shadow maps
//! (a depth array, a layer per light, stored for sampling) and per-model shadow textures (colour, with mips).

use std::sync::Arc;

use ash::vk;

use crate::error::Result;
pub use crate::frame::offscreen::{Framebuffer, ImageView, RenderPass};
use crate::gpu::memory::{Image, ImageDesc};
use crate::gpu::Gpu;

/// Depth format of the shadow map: D16_UNORM supports depth attachment and sampling on every
/// Vulkan device.
pub const SHADOW_MAP_FORMAT: vk::Format = vk::Format::D16_UNORM;
pub const SHADOW_TEXTURE_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The shadow map's render pass: depth only, cleared, stored and left ready for sampling.
pub fn shadow_map_render_pass(gpu: &Arc<Gpu>) -> Result<RenderPass> {
    crate::frame::offscreen::depth_render_pass(gpu, SHADOW_MAP_FORMAT)
}

/// A shadow-texture render pass (see `offscreen::colour_render_pass`).
pub fn colour_render_pass(gpu: &Arc<Gpu>, clear: bool, final_layout: vk::ImageLayout) -> Result<RenderPass> {
    crate::frame::offscreen::colour_render_pass(gpu, SHADOW_TEXTURE_FORMAT, clear, final_layout)
}

/// The lights' shadow maps: one layer per shadowing light (at least one, bound even unused).
pub fn shadow_map_image(gpu: &Arc<Gpu>, size: u32, layers: u32) -> Result<Image> {
    Image::new_layered(
        gpu,
        &ImageDesc {
            name: "shadow maps",
            format: SHADOW_MAP_FORMAT,
            extent: vk::Extent2D { width: size, height: size },
            usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            aspect: vk::ImageAspectFlags::DEPTH,
            mip_levels: 1,
            samples: 1,
        },
        layers,
    )
}

/// A shadow texture (or the bake's raw target when `mip_levels` is 1).
pub fn shadow_texture_image(gpu: &Arc<Gpu>, name: &str, size: u32, mip_levels: u32) -> Result<Image> {
    shadow_texture_page(gpu, name, vk::Extent2D { width: size, height: size }, mip_levels)
}

/// The atlas page (or its raw bake when `mip_levels` is 1): every model's shadow texture as a
/// tile of one image.
pub fn shadow_texture_page(gpu: &Arc<Gpu>, name: &str, extent: vk::Extent2D, mip_levels: u32) -> Result<Image> {
    Image::new(
        gpu,
        &ImageDesc {
            name,
            format: SHADOW_TEXTURE_FORMAT,
            extent,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
            mip_levels,
            samples: 1,
        },
    )
}
