//! A render pass's attachments as data, and what a tile-based GPU moves for each: the rule
//! nostencil's own profile and the fill-rate layer both apply (`tile_traffic`).

use ash::vk;

use crate::formats::texel_bytes;

/// The Vulkan flag of `samples` samples per pixel (1, 2, 4 or 8; anything else is one).
pub fn sample_count_flags(samples: u32) -> vk::SampleCountFlags {
    match samples {
        2 => vk::SampleCountFlags::TYPE_2,
        4 => vk::SampleCountFlags::TYPE_4,
        8 => vk::SampleCountFlags::TYPE_8,
        _ => vk::SampleCountFlags::TYPE_1,
    }
}

/// One attachment of a render pass: what it holds, how it is loaded and stored, where it ends.
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
