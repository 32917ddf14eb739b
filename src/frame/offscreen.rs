//! Render passes for targets of a technique's own, drawn before the frame (shadow maps, shadow
//! textures): one attachment each, cleared or not, stored, left ready for sampling or transfer.
//! The handles destroy themselves on drop.

use std::sync::Arc;

use ash::vk;

use super::render_pass::AttachmentDesc;
use crate::error::{Error, Result, VkContext};
use crate::gpu::live_objects::ObjectKind;
use crate::gpu::memory::Image;
use crate::gpu::Gpu;

/// Vulkan handles destroyed on drop.
pub struct RenderPass {
    gpu: Arc<Gpu>,
    pub raw: vk::RenderPass,
    /// Its attachments, as the profile's tile-traffic table reads them.
    pub attachments: Vec<AttachmentDesc>,
}

impl Drop for RenderPass {
    fn drop(&mut self) {
        // SAFETY: no pending command uses the render pass (see `Buffer`'s drop).
        unsafe { self.gpu.raw().destroy_render_pass(self.raw, None) };
        self.gpu.destroyed(ObjectKind::RenderPass);
    }
}

pub struct Framebuffer {
    gpu: Arc<Gpu>,
    pub raw: vk::Framebuffer,
}

impl Framebuffer {
    pub fn new(gpu: &Arc<Gpu>, render_pass: &RenderPass, view: vk::ImageView, extent: vk::Extent2D) -> Result<Self> {
        Self::with_views(gpu, render_pass, &[view], extent)
    }

    /// A framebuffer of one view per attachment of `render_pass`, in its order.
    pub fn with_views(
        gpu: &Arc<Gpu>,
        render_pass: &RenderPass,
        views: &[vk::ImageView],
        extent: vk::Extent2D,
    ) -> Result<Self> {
        if views.len() != render_pass.attachments.len() {
            return Err(Error::Internal(format!(
                "a framebuffer of {} views for a render pass of {} attachments",
                views.len(),
                render_pass.attachments.len()
            )));
        }
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass.raw)
            .attachments(views)
            .width(extent.width)
            .height(extent.height)
            .layers(1);
        // SAFETY: `render_pass` is alive and has one attachment per view (checked above); each
        // view is the caller's single-mip view of an image at least `extent` large, kept alive as
        // long as this framebuffer.
        let raw = unsafe { gpu.raw().create_framebuffer(&info, None) }.vk("vkCreateFramebuffer")?;
        gpu.created(ObjectKind::Framebuffer);
        Ok(Framebuffer { gpu: gpu.clone(), raw })
    }
}

impl Drop for Framebuffer {
    fn drop(&mut self) {
        // SAFETY: no pending command uses the framebuffer (see `Buffer`'s drop).
        unsafe { self.gpu.raw().destroy_framebuffer(self.raw, None) };
        self.gpu.destroyed(ObjectKind::Framebuffer);
    }
}

pub struct ImageView {
    gpu: Arc<Gpu>,
    pub raw: vk::ImageView,
}

impl ImageView {
    /// A view of one mip (framebuffers take single-mip views).
    pub fn mip(gpu: &Arc<Gpu>, image: &Image, mip: u32) -> Result<Self> {
        if mip >= image.mip_levels {
            return Err(Error::Internal(format!("mip {mip} of an image with {} mips", image.mip_levels)));
        }
        Self::colour_mips(gpu, image, mip, 1)
    }

    /// A view of mips 0 to `levels` - 1 of a colour image: sampling through it clamps the LOD
    /// to those levels (a tile of the atlas page with fewer clean mips than the page).
    pub fn levels(gpu: &Arc<Gpu>, image: &Image, levels: u32) -> Result<Self> {
        if levels == 0 || levels > image.mip_levels {
            return Err(Error::Internal(format!("{levels} mips of an image with {}", image.mip_levels)));
        }
        Self::colour_mips(gpu, image, 0, levels)
    }

    /// A 2D colour view of `count` mips from `base` (the callers check the range).
    fn colour_mips(gpu: &Arc<Gpu>, image: &Image, base: u32, count: u32) -> Result<Self> {
        let info = vk::ImageViewCreateInfo::default()
            .image(image.raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(image.format)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                base_mip_level: base,
                level_count: count,
                base_array_layer: 0,
                layer_count: 1,
            });
        // SAFETY: `image` is alive (borrowed) and holds mips `base..base + count` (checked by
        // the callers); the view keeps its format and colour aspect.
        let raw = unsafe { gpu.raw().create_image_view(&info, None) }.vk("vkCreateImageView")?;
        gpu.created(ObjectKind::ImageView);
        Ok(ImageView { gpu: gpu.clone(), raw })
    }

    /// A 2D view of layer `layer` of an arrayed image, mip 0, aspect `aspect` (a framebuffer
    /// per shadow-map layer).
    pub fn layer(gpu: &Arc<Gpu>, image: &Image, layer: u32, aspect: vk::ImageAspectFlags) -> Result<Self> {
        if layer >= image.layers {
            return Err(Error::Internal(format!("layer {layer} of an image with {} layers", image.layers)));
        }
        let info = vk::ImageViewCreateInfo::default()
            .image(image.raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(image.format)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: aspect,
                base_mip_level: 0,
                level_count: 1,
                base_array_layer: layer,
                layer_count: 1,
            });
        // SAFETY: `image` is alive (borrowed) and `layer` one of its layers (checked above); the
        // caller names an aspect of its format.
        let raw = unsafe { gpu.raw().create_image_view(&info, None) }.vk("vkCreateImageView")?;
        gpu.created(ObjectKind::ImageView);
        Ok(ImageView { gpu: gpu.clone(), raw })
    }
}

impl Drop for ImageView {
    fn drop(&mut self) {
        // SAFETY: no pending command uses the view (see `Buffer`'s drop).
        unsafe { self.gpu.raw().destroy_image_view(self.raw, None) };
        self.gpu.destroyed(ObjectKind::ImageView);
    }
}

/// The dependencies every pre-pass render pass needs: its attachment is written after earlier
/// reads (shader, transfer) and read afterwards by shaders and transfers.
fn dependencies(
    attachment_stages: vk::PipelineStageFlags,
    attachment_write: vk::AccessFlags,
) -> [vk::SubpassDependency; 2] {
    let outside = vk::PipelineStageFlags::FRAGMENT_SHADER | vk::PipelineStageFlags::TRANSFER;
    [
        vk::SubpassDependency {
            src_subpass: vk::SUBPASS_EXTERNAL,
            dst_subpass: 0,
            src_stage_mask: outside,
            dst_stage_mask: attachment_stages,
            src_access_mask: vk::AccessFlags::SHADER_READ | vk::AccessFlags::TRANSFER_READ,
            dst_access_mask: attachment_write,
            dependency_flags: vk::DependencyFlags::empty(),
        },
        vk::SubpassDependency {
            src_subpass: 0,
            dst_subpass: vk::SUBPASS_EXTERNAL,
            src_stage_mask: attachment_stages,
            dst_stage_mask: outside,
            src_access_mask: attachment_write,
            dst_access_mask: vk::AccessFlags::SHADER_READ | vk::AccessFlags::TRANSFER_READ,
            dependency_flags: vk::DependencyFlags::empty(),
        },
    ]
}

/// Depth only: cleared, stored (unlike the frame's depth) and left ready for sampling.
pub fn depth_render_pass(gpu: &Arc<Gpu>, format: vk::Format) -> Result<RenderPass> {
    let attachment = AttachmentDesc {
        name: "depth",
        format,
        load: vk::AttachmentLoadOp::CLEAR,
        store: vk::AttachmentStoreOp::STORE,
        stencil_load: vk::AttachmentLoadOp::DONT_CARE,
        stencil_store: vk::AttachmentStoreOp::DONT_CARE,
        final_layout: vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
        transient: false,
        samples: 1,
    };
    let depth_ref =
        vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL };
    let subpasses = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .depth_stencil_attachment(&depth_ref)];
    let deps = dependencies(
        vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
        vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ,
    );
    build(gpu, attachment, &subpasses, &deps)
}

/// One colour attachment, cleared (`clear`) or not loaded, stored, left in `final_layout`.
pub fn colour_render_pass(
    gpu: &Arc<Gpu>,
    format: vk::Format,
    clear: bool,
    final_layout: vk::ImageLayout,
) -> Result<RenderPass> {
    let load = if clear { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::DONT_CARE };
    single_colour(gpu, format, load, final_layout, vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
}

/// One colour attachment loaded and stored, entering and leaving in `layout`: a target
/// updated in part (the atlas page's re-baked tiles), the rest kept.
pub fn colour_render_pass_loaded(gpu: &Arc<Gpu>, format: vk::Format, layout: vk::ImageLayout) -> Result<RenderPass> {
    // Loading reads the attachment: the write after the last pass's write is ordered too.
    let access = vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::COLOR_ATTACHMENT_READ;
    single_colour(gpu, format, vk::AttachmentLoadOp::LOAD, layout, access)
}

/// [`colour_render_pass_loaded`]'s first run: the same pass (compatible with it: the same
/// dependencies), cleared instead of loaded, for a target's first update, which has nothing to
/// keep (a tiler clears it in tile memory instead of reading it back).
pub fn colour_render_pass_loaded_first(
    gpu: &Arc<Gpu>,
    format: vk::Format,
    layout: vk::ImageLayout,
) -> Result<RenderPass> {
    let access = vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::COLOR_ATTACHMENT_READ;
    single_colour(gpu, format, vk::AttachmentLoadOp::CLEAR, layout, access)
}

/// A render pass of one stored colour attachment loaded by `load`, left in `final_layout`,
/// whose external dependencies order `access` against the shaders and transfers around it.
fn single_colour(
    gpu: &Arc<Gpu>,
    format: vk::Format,
    load: vk::AttachmentLoadOp,
    final_layout: vk::ImageLayout,
    access: vk::AccessFlags,
) -> Result<RenderPass> {
    let attachment = AttachmentDesc {
        name: "colour",
        format,
        load,
        store: vk::AttachmentStoreOp::STORE,
        stencil_load: vk::AttachmentLoadOp::DONT_CARE,
        stencil_store: vk::AttachmentStoreOp::DONT_CARE,
        final_layout,
        transient: false,
        samples: 1,
    };
    let colour_ref = [vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
    let subpasses = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&colour_ref)];
    let deps = dependencies(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT, access);
    build(gpu, attachment, &subpasses, &deps)
}

/// A colour attachment as [`colour_render_pass`] makes it (cleared, stored, left for
/// sampling) and a stencil attachment cleared to 0 and dropped: a mask drawn with a real
/// stencil (the outline blur's reference path). `stencil_format` has a stencil aspect; its
/// depth is neither loaded nor stored.
pub fn colour_stencil_render_pass(
    gpu: &Arc<Gpu>,
    format: vk::Format,
    stencil_format: vk::Format,
) -> Result<RenderPass> {
    let colour = AttachmentDesc {
        name: "colour",
        format,
        load: vk::AttachmentLoadOp::CLEAR,
        store: vk::AttachmentStoreOp::STORE,
        stencil_load: vk::AttachmentLoadOp::DONT_CARE,
        stencil_store: vk::AttachmentStoreOp::DONT_CARE,
        final_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        transient: false,
        samples: 1,
    };
    let stencil = AttachmentDesc {
        name: "stencil",
        format: stencil_format,
        load: vk::AttachmentLoadOp::DONT_CARE,
        store: vk::AttachmentStoreOp::DONT_CARE,
        stencil_load: vk::AttachmentLoadOp::CLEAR,
        stencil_store: vk::AttachmentStoreOp::DONT_CARE,
        final_layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        transient: true,
        samples: 1,
    };
    let colour_ref = [vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
    let stencil_ref =
        vk::AttachmentReference { attachment: 1, layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL };
    let subpasses = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&colour_ref)
        .depth_stencil_attachment(&stencil_ref)];
    let deps = dependencies(
        vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
            | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
        vk::AccessFlags::COLOR_ATTACHMENT_WRITE
            | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE
            | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ,
    );
    build_with(gpu, vec![colour, stencil], &subpasses, &deps)
}

fn build(
    gpu: &Arc<Gpu>,
    attachment: AttachmentDesc,
    subpasses: &[vk::SubpassDescription],
    deps: &[vk::SubpassDependency],
) -> Result<RenderPass> {
    build_with(gpu, vec![attachment], subpasses, deps)
}

fn build_with(
    gpu: &Arc<Gpu>,
    attachments: Vec<AttachmentDesc>,
    subpasses: &[vk::SubpassDescription],
    deps: &[vk::SubpassDependency],
) -> Result<RenderPass> {
    let descriptions = attachments.iter().map(AttachmentDesc::description).collect::<Vec<_>>();
    let info = vk::RenderPassCreateInfo::default().attachments(&descriptions).subpasses(subpasses).dependencies(deps);
    // SAFETY: `info` and the arrays it points at live until the call returns; the subpasses
    // reference only attachments of `descriptions`.
    let raw = unsafe { gpu.raw().create_render_pass(&info, None) }.vk("vkCreateRenderPass")?;
    gpu.created(ObjectKind::RenderPass);
    Ok(RenderPass { gpu: gpu.clone(), raw, attachments })
}
