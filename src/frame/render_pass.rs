//! Render passes as data. One small description says, per attachment, whether it is cleared,
//! kept or discarded at the start and end of the pass, and whether it may live in tile memory
//! only (transient); `build` writes the Vulkan render pass out from it. The load/store decision
//! lives here and nowhere else.

use ash::vk;
pub use nostencil_tiler::attachment::{AttachmentDesc, AttachmentTraffic, RenderPassTraffic};
pub use nostencil_tiler::formats::format_has_stencil;

use crate::error::{Result, VkContext};

crate::names::named_enum! {
    /// Whether the frame has a real stencil. The main frame never does; the reference does,
    /// only to prove the emulation right and to compare costs.
    pub enum StencilMode {
        /// No stencil aspect anywhere: stencil effects are emulated in the colour alpha channel.
        #[default]
        Emulated = "emulated",
        /// D32_SFLOAT_S8_UINT (or D24_UNORM_S8_UINT): the real-stencil reference path.
        Reference = "reference",
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderPassDesc {
    pub colour: AttachmentDesc,
    pub depth: AttachmentDesc,
    /// A multisampled frame's one-sample colour, written by the resolve at the end of the
    /// subpass (`pResolveAttachments`): the only attachment that leaves tile memory.
    pub resolve: Option<AttachmentDesc>,
    /// The colour attachment is also read as an input attachment by the same subpass
    /// (a by-region feedback loop, GENERAL layout): for the subpass normalisation path.
    pub colour_feedback: bool,
    pub destination: FrameDestination,
}

/// The frame's colour: sRGB-encoded RGB as a phone's screen expects, blended in linear space by
/// the hardware. Its alpha is plain linear UNORM8 (the spec leaves alpha out of the sRGB
/// transfer), so the alpha counter's arithmetic is the same as on R8G8B8A8_UNORM.
pub const COLOUR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// Where the frame's one-sample colour (the resolve target at several samples) goes when the
/// render pass ends.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum FrameDestination {
    /// An image of the renderer's own in [`COLOUR_FORMAT`], left in TRANSFER_SRC_OPTIMAL: read
    /// back, or kept on the GPU.
    #[default]
    Offscreen,
    /// The images of a swapchain of `format` (an 8-bit sRGB format with alpha, whose values are
    /// the same as [`COLOUR_FORMAT`]'s), left in PRESENT_SRC_KHR: presented as rendered, with no
    /// copy after the pass.
    Swapchain { format: vk::Format },
}

impl FrameDestination {
    /// The one-sample colour's format.
    pub fn format(self) -> vk::Format {
        match self {
            FrameDestination::Offscreen => COLOUR_FORMAT,
            FrameDestination::Swapchain { format } => format,
        }
    }

    /// The layout the render pass leaves the one-sample colour in.
    pub fn final_layout(self) -> vk::ImageLayout {
        match self {
            FrameDestination::Offscreen => vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            FrameDestination::Swapchain { .. } => vk::ImageLayout::PRESENT_SRC_KHR,
        }
    }
}

/// The name of a multisampled frame's resolve attachment (what the bandwidth model resolves into).
pub const RESOLVED_NAME: &str = "colour (resolved)";

impl RenderPassDesc {
    /// The frame with `samples` samples per pixel. One sample: colour cleared and stored (it is
    /// read back or presented); depth cleared, never stored and transient, since nothing reads
    /// it after the pass. Several (docs/design/msaa.md): colour and depth both transient, cleared
    /// and discarded in tile memory, and the colour resolved into a one-sample attachment, the
    /// only one stored. `keep_samples` stores the multisampled colour too (the per-sample test
    /// reads it back; never in a timed frame). `destination`: where the one-sample colour goes.
    pub fn frame(
        depth_format: vk::Format,
        colour_feedback: bool,
        samples: u32,
        keep_samples: bool,
        destination: FrameDestination,
    ) -> Self {
        let stencil = format_has_stencil(depth_format);
        let output = AttachmentDesc {
            name: "colour",
            format: destination.format(),
            load: vk::AttachmentLoadOp::CLEAR,
            store: vk::AttachmentStoreOp::STORE,
            stencil_load: vk::AttachmentLoadOp::DONT_CARE,
            stencil_store: vk::AttachmentStoreOp::DONT_CARE,
            final_layout: destination.final_layout(),
            transient: false,
            samples: 1,
        };
        let depth = AttachmentDesc {
            name: if stencil { "depth+stencil" } else { "depth" },
            format: depth_format,
            load: vk::AttachmentLoadOp::CLEAR,
            store: vk::AttachmentStoreOp::DONT_CARE,
            // The reference clears its stencil and discards it, like the depth.
            stencil_load: if stencil { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::DONT_CARE },
            stencil_store: vk::AttachmentStoreOp::DONT_CARE,
            final_layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            transient: true,
            samples,
        };
        if samples <= 1 {
            return RenderPassDesc { colour: output, depth, resolve: None, colour_feedback, destination };
        }
        let multisampled = AttachmentDesc {
            name: "colour (multisampled)",
            store: if keep_samples { vk::AttachmentStoreOp::STORE } else { vk::AttachmentStoreOp::DONT_CARE },
            // GENERAL where a shader reads it: the subpass input, or the per-sample read-back.
            final_layout: if colour_feedback || keep_samples {
                vk::ImageLayout::GENERAL
            } else {
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
            },
            transient: !keep_samples,
            samples,
            ..output
        };
        let resolved = AttachmentDesc { name: RESOLVED_NAME, load: vk::AttachmentLoadOp::DONT_CARE, ..output };
        RenderPassDesc { colour: multisampled, depth, resolve: Some(resolved), colour_feedback, destination }
    }

    /// Samples per pixel of the colour and depth attachments.
    pub fn samples(&self) -> u32 {
        self.colour.samples
    }

    pub fn has_stencil(&self) -> bool {
        format_has_stencil(self.colour.format) || format_has_stencil(self.depth.format)
    }

    fn colour_layout(&self) -> vk::ImageLayout {
        if self.colour_feedback {
            vk::ImageLayout::GENERAL
        } else {
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
        }
    }

    pub fn build(&self, device: &ash::Device) -> Result<vk::RenderPass> {
        let attachments: Vec<_> = self.attachments().iter().map(AttachmentDesc::description).collect();
        let colour_ref = [vk::AttachmentReference { attachment: 0, layout: self.colour_layout() }];
        let depth_ref =
            vk::AttachmentReference { attachment: 1, layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL };
        let resolve_ref =
            [vk::AttachmentReference { attachment: 2, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
        let mut subpass = vk::SubpassDescription::default()
            .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
            .color_attachments(&colour_ref)
            .depth_stencil_attachment(&depth_ref);
        if self.resolve.is_some() {
            // The resolve runs at the end of the (last and only) subpass, in tile memory.
            subpass = subpass.resolve_attachments(&resolve_ref);
        }
        if self.colour_feedback {
            subpass = subpass.input_attachments(&colour_ref);
        }
        let subpasses = [subpass];

        // Colour writes (the resolve's included) finish before the copy that reads the frame
        // back, and before the shader that reads kept samples back.
        let samples_read = self.resolve.is_some() && self.colour.store == vk::AttachmentStoreOp::STORE;
        let (mut dst_stage, mut dst_access) = (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::TRANSFER_READ);
        if samples_read {
            dst_stage |= vk::PipelineStageFlags::FRAGMENT_SHADER;
            dst_access |= vk::AccessFlags::SHADER_READ;
        }
        let mut dependencies = vec![vk::SubpassDependency {
            src_subpass: 0,
            dst_subpass: vk::SUBPASS_EXTERNAL,
            src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
            dst_stage_mask: dst_stage,
            src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            dst_access_mask: dst_access,
            dependency_flags: vk::DependencyFlags::empty(),
        }];
        // What the frame before used these attachments for is done before this one clears
        // them: with frames in flight the previous frame may still run (its colour and depth
        // writes, its input-attachment reads, its read-back copy). A swapchain frame's
        // submission waits for the acquired image at COLOR_ATTACHMENT_OUTPUT, which orders its
        // layout transition here too. This replaces the implicit dependency, which waits for
        // nothing.
        let fragment_tests = vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
        let attachment_stages = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | fragment_tests;
        dependencies.push(vk::SubpassDependency {
            src_subpass: vk::SUBPASS_EXTERNAL,
            dst_subpass: 0,
            src_stage_mask: attachment_stages
                | vk::PipelineStageFlags::FRAGMENT_SHADER
                | vk::PipelineStageFlags::TRANSFER,
            dst_stage_mask: attachment_stages,
            src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            dst_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_READ
                | vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            dependency_flags: vk::DependencyFlags::empty(),
        });
        if self.colour_feedback {
            // A full-screen pass reads the pixel that earlier draws of this subpass wrote.
            dependencies.push(vk::SubpassDependency {
                src_subpass: 0,
                dst_subpass: 0,
                src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                dst_stage_mask: vk::PipelineStageFlags::FRAGMENT_SHADER,
                src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                dst_access_mask: vk::AccessFlags::INPUT_ATTACHMENT_READ,
                dependency_flags: vk::DependencyFlags::BY_REGION,
            });
        }
        let info = vk::RenderPassCreateInfo::default()
            .attachments(&attachments)
            .subpasses(&subpasses)
            .dependencies(&dependencies);
        // SAFETY: `info` and the arrays it points at live until the call returns; the subpass
        // references attachments 0 and 1 (and 2 when resolving), all described.
        unsafe { device.create_render_pass(&info, None) }.vk("vkCreateRenderPass")
    }

    /// The attachments in framebuffer order: colour, depth, then the resolve target if any.
    pub fn attachments(&self) -> Vec<AttachmentDesc> {
        [Some(self.colour), Some(self.depth), self.resolve].into_iter().flatten().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn main_frame_has_no_stencil_aspect_anywhere() {
        for depth in [vk::Format::D32_SFLOAT, vk::Format::D16_UNORM] {
            for feedback in [false, true] {
                let desc = RenderPassDesc::frame(depth, feedback, 1, false, FrameDestination::Offscreen);
                assert!(!desc.has_stencil());
                assert_eq!(desc.depth.stencil_load, vk::AttachmentLoadOp::DONT_CARE);
                assert_eq!(desc.depth.stencil_store, vk::AttachmentStoreOp::DONT_CARE);
            }
        }
        assert!(RenderPassDesc::frame(vk::Format::D32_SFLOAT_S8_UINT, false, 1, false, FrameDestination::Offscreen)
            .has_stencil());
    }

    #[test]
    fn a_presented_frame_leaves_its_colour_in_the_swapchain_format_ready_to_present() {
        let format = vk::Format::B8G8R8A8_SRGB;
        let destination = FrameDestination::Swapchain { format };
        let one = RenderPassDesc::frame(vk::Format::D32_SFLOAT, false, 1, false, destination);
        assert_eq!((one.colour.format, one.colour.final_layout), (format, vk::ImageLayout::PRESENT_SRC_KHR));
        assert_eq!(one.colour.store, vk::AttachmentStoreOp::STORE);
        // At 4x the samples stay in tile memory and resolve into the swapchain image, whose
        // format the resolve requires of them too.
        let four = RenderPassDesc::frame(vk::Format::D32_SFLOAT, false, 4, false, destination);
        let resolve = four.resolve.expect("a resolve attachment");
        assert_eq!((resolve.format, resolve.final_layout), (format, vk::ImageLayout::PRESENT_SRC_KHR));
        assert_eq!(resolve.load, vk::AttachmentLoadOp::DONT_CARE);
        assert_eq!((four.colour.format, four.colour.store), (format, vk::AttachmentStoreOp::DONT_CARE));
        assert!(four.colour.transient);
        let offscreen = RenderPassDesc::frame(vk::Format::D32_SFLOAT, false, 4, false, FrameDestination::Offscreen);
        assert_eq!(offscreen.resolve.map(|r| r.final_layout), Some(vk::ImageLayout::TRANSFER_SRC_OPTIMAL));
    }

    #[test]
    fn tile_traffic_follows_load_store_ops() {
        let desc = RenderPassDesc::frame(vk::Format::D32_SFLOAT, false, 1, false, FrameDestination::Offscreen);
        let traffic = desc.attachments().iter().map(|a| a.tile_traffic(256, 256)).collect::<Vec<_>>();
        // Colour: cleared (nothing loaded), stored (4 bytes a pixel). Depth: nothing moves.
        assert_eq!(traffic[0].bytes_loaded, 0);
        assert_eq!(traffic[0].bytes_stored, 4 * 256 * 256);
        assert_eq!(traffic[1].bytes_loaded + traffic[1].bytes_stored, 0);
        // A loaded and stored depth-stencil attachment moves both aspects both ways.
        let kept = AttachmentDesc {
            load: vk::AttachmentLoadOp::LOAD,
            store: vk::AttachmentStoreOp::STORE,
            stencil_load: vk::AttachmentLoadOp::LOAD,
            stencil_store: vk::AttachmentStoreOp::STORE,
            ..RenderPassDesc::frame(vk::Format::D32_SFLOAT_S8_UINT, false, 1, false, FrameDestination::Offscreen).depth
        };
        let traffic = kept.tile_traffic(16, 16);
        assert_eq!((traffic.bytes_loaded, traffic.bytes_stored), (5 * 256, 5 * 256));
    }
}
