//! Render passes as data. One small description says, per attachment, whether it is cleared,
//! kept or discarded at the start and end of the pass, and whether it may live in tile memory
//! only (transient); `build` writes the Vulkan render pass out from it. The load/store decision
//! lives here and nowhere else.

use ash::vk;

use crate::error::{Result, VkContext};
use crate::gpu::memory::sample_count_flags;

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

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AttachmentDesc {
    pub name: &'static str,
    pub format: vk::Format,
    pub load: vk::AttachmentLoadOp,
    pub store: vk::AttachmentStoreOp,
    pub stencil_load: vk::AttachmentLoadOp,
    pub stencil_store: vk::AttachmentStoreOp,
    pub final_layout: vk::ImageLayout,
    /// Lives only in tile memory on a tile-based GPU (TRANSIENT_ATTACHMENT, lazily allocated).
    pub transient: bool,
    /// Samples per pixel (1, 2 or 4).
    pub samples: u32,
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
}

/// The frame's colour: sRGB-encoded RGB as a phone's screen expects, blended in linear space by
/// the hardware. Its alpha is plain linear UNORM8 (the spec leaves alpha out of the sRGB
/// transfer), so the alpha counter's arithmetic is the same as on R8G8B8A8_UNORM.
pub const COLOUR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// The name of a multisampled frame's resolve attachment (what the bandwidth model resolves into).
pub const RESOLVED_NAME: &str = "colour (resolved)";

pub fn format_has_stencil(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::S8_UINT
            | vk::Format::D16_UNORM_S8_UINT
            | vk::Format::D24_UNORM_S8_UINT
            | vk::Format::D32_SFLOAT_S8_UINT
    )
}

impl RenderPassDesc {
    /// The frame with `samples` samples per pixel. One sample: colour cleared and stored (it is
    /// read back or presented); depth cleared, never stored and transient, since nothing reads
    /// it after the pass. Several (docs/design/msaa.md): colour and depth both transient, cleared
    /// and discarded in tile memory, and the colour resolved into a one-sample attachment, the
    /// only one stored. `keep_samples` stores the multisampled colour too (the per-sample test
    /// reads it back; never in a timed frame).
    pub fn frame(depth_format: vk::Format, colour_feedback: bool, samples: u32, keep_samples: bool) -> Self {
        let stencil = format_has_stencil(depth_format);
        let output = AttachmentDesc {
            name: "colour",
            format: COLOUR_FORMAT,
            load: vk::AttachmentLoadOp::CLEAR,
            store: vk::AttachmentStoreOp::STORE,
            stencil_load: vk::AttachmentLoadOp::DONT_CARE,
            stencil_store: vk::AttachmentStoreOp::DONT_CARE,
            final_layout: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
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
            return RenderPassDesc { colour: output, depth, resolve: None, colour_feedback };
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
        RenderPassDesc { colour: multisampled, depth, resolve: Some(resolved), colour_feedback }
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

impl AttachmentDesc {
    /// The Vulkan attachment description. Contents are undefined on entry (cleared or fully
    /// overwritten), except for a loaded attachment: it enters in its final layout, the one the
    /// same pass left it in (the atlas page, whose tiles not re-baked keep their texels).
    pub fn description(&self) -> vk::AttachmentDescription {
        let loaded = self.load == vk::AttachmentLoadOp::LOAD || self.stencil_load == vk::AttachmentLoadOp::LOAD;
        vk::AttachmentDescription::default()
            .format(self.format)
            .samples(sample_count_flags(self.samples))
            .load_op(self.load)
            .store_op(self.store)
            .stencil_load_op(self.stencil_load)
            .stencil_store_op(self.stencil_store)
            .initial_layout(if loaded { self.final_layout } else { vk::ImageLayout::UNDEFINED })
            .final_layout(self.final_layout)
    }

    /// Bytes a tile-based GPU loads from and stores to main memory for this attachment over a
    /// `width` x `height` render area: a full load only for LOAD, a full store only for STORE,
    /// of every sample.
    pub fn tile_traffic(&self, width: u32, height: u32) -> AttachmentTraffic {
        let pixels = width as u64 * height as u64 * self.samples as u64;
        let (depth_bytes, stencil_bytes) = texel_bytes(self.format);
        let loaded =
            |op: vk::AttachmentLoadOp, bytes: u64| if op == vk::AttachmentLoadOp::LOAD { bytes * pixels } else { 0 };
        let stored =
            |op: vk::AttachmentStoreOp, bytes: u64| if op == vk::AttachmentStoreOp::STORE { bytes * pixels } else { 0 };
        let cleared =
            |op: vk::AttachmentLoadOp, bytes: u64| if op == vk::AttachmentLoadOp::CLEAR { bytes * pixels } else { 0 };
        AttachmentTraffic {
            attachment: self.name,
            format: format!("{:?}", self.format),
            load_op: format!("{:?}", self.load),
            store_op: format!("{:?}", self.store),
            bytes_loaded: loaded(self.load, depth_bytes) + loaded(self.stencil_load, stencil_bytes),
            bytes_stored: stored(self.store, depth_bytes) + stored(self.stencil_store, stencil_bytes),
            bytes_cleared: cleared(self.load, depth_bytes) + cleared(self.stencil_load, stencil_bytes),
            bytes_per_sample: depth_bytes + stencil_bytes,
            transient: self.transient,
            samples: self.samples,
        }
    }
}

/// (colour-or-depth bytes, stencil bytes) per texel; 4 bytes for a format not listed.
pub fn texel_bytes(format: vk::Format) -> (u64, u64) {
    match format {
        vk::Format::R8_UNORM | vk::Format::R8_SNORM | vk::Format::R8_UINT | vk::Format::R8_SINT | vk::Format::R8_SRGB => {
            (1, 0)
        }
        vk::Format::R8G8_UNORM
        | vk::Format::R8G8_UINT
        | vk::Format::R16_UNORM
        | vk::Format::R16_SFLOAT
        | vk::Format::R16_UINT
        | vk::Format::R5G6B5_UNORM_PACK16
        | vk::Format::D16_UNORM => (2, 0),
        vk::Format::R16G16B16A16_SFLOAT
        | vk::Format::R16G16B16A16_UNORM
        | vk::Format::R16G16B16A16_UINT
        | vk::Format::R32G32_SFLOAT
        | vk::Format::R32G32_UINT => (8, 0),
        vk::Format::R32G32B32A32_SFLOAT | vk::Format::R32G32B32A32_UINT => (16, 0),
        vk::Format::D16_UNORM_S8_UINT => (2, 1),
        vk::Format::D24_UNORM_S8_UINT => (3, 1),
        vk::Format::D32_SFLOAT_S8_UINT => (4, 1),
        vk::Format::S8_UINT => (0, 1),
        _ => (4, 0),
    }
}

/// The traffic of the render pass instances one measured pass began (`count` alike ones: the
/// same targets, ops and size, such as one bake per model), or of the frame's render pass,
/// which spans the passes drawn into the frame (`pass` = "frame").
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RenderPassTraffic {
    pub pass: String,
    pub width: u32,
    pub height: u32,
    pub count: u32,
    pub attachments: Vec<AttachmentTraffic>,
}

impl RenderPassTraffic {
    pub fn bytes_loaded(&self) -> u64 {
        self.count as u64 * self.attachments.iter().map(|a| a.bytes_loaded).sum::<u64>()
    }

    pub fn bytes_stored(&self) -> u64 {
        self.count as u64 * self.attachments.iter().map(|a| a.bytes_stored).sum::<u64>()
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AttachmentTraffic {
    pub attachment: &'static str,
    pub format: String,
    pub load_op: String,
    pub store_op: String,
    pub bytes_loaded: u64,
    pub bytes_stored: u64,
    /// Bytes its CLEAR ops write over the render area, every sample (the immediate-mode cost).
    pub bytes_cleared: u64,
    /// Bytes of one sample, all aspects.
    pub bytes_per_sample: u64,
    pub transient: bool,
    pub samples: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn main_frame_has_no_stencil_aspect_anywhere() {
        for depth in [vk::Format::D32_SFLOAT, vk::Format::D16_UNORM] {
            for feedback in [false, true] {
                let desc = RenderPassDesc::frame(depth, feedback, 1, false);
                assert!(!desc.has_stencil());
                assert_eq!(desc.depth.stencil_load, vk::AttachmentLoadOp::DONT_CARE);
                assert_eq!(desc.depth.stencil_store, vk::AttachmentStoreOp::DONT_CARE);
            }
        }
        assert!(RenderPassDesc::frame(vk::Format::D32_SFLOAT_S8_UINT, false, 1, false).has_stencil());
    }

    #[test]
    fn tile_traffic_follows_load_store_ops() {
        let desc = RenderPassDesc::frame(vk::Format::D32_SFLOAT, false, 1, false);
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
            ..RenderPassDesc::frame(vk::Format::D32_SFLOAT_S8_UINT, false, 1, false).depth
        };
        let traffic = kept.tile_traffic(16, 16);
        assert_eq!((traffic.bytes_loaded, traffic.bytes_stored), (5 * 256, 5 * 256));
    }
}
