//! The tiler check's bookkeeping, as the device and each command buffer keep it: which image
//! each view and framebuffer names, which images each descriptor set holds and which sets a
//! command buffer has bound (a draw or dispatch reads them), which pipelines blend or
//! depth-test, and the events a command buffer's recording made (image_use.rs's hooks fill it).

use std::collections::{HashMap, HashSet};

use ash::vk;
use ash::vk::Handle;

use super::tiler_check::{Event, ImageKey, TilerCheck};

/// An image the layer saw created.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TilerImage {
    /// TRANSIENT_ATTACHMENT usage: it may live in tile memory only.
    pub transient: bool,
    pub extent: (u32, u32),
    /// One mip level and one layer: a clear of it replaces all of it.
    pub single: bool,
}

/// The image and subresource an image view names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ViewTarget {
    pub image: vk::Image,
    pub key: ImageKey,
}

/// Whether a pipeline's draws read the colour attachments (per slot: blending or a logic op)
/// and the depth (a depth test other than ALWAYS, known at creation).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PipelineReads {
    pub blends: Vec<bool>,
    pub depth_test: bool,
}

/// The device's part of the check.
#[derive(Debug, Default)]
pub struct TilerState {
    pub images: HashMap<vk::Image, TilerImage>,
    pub views: HashMap<vk::ImageView, ViewTarget>,
    pub framebuffers: HashMap<vk::Framebuffer, Vec<vk::ImageView>>,
    /// Sampled and storage images per descriptor set, by (binding, array element).
    pub sets: HashMap<vk::DescriptorSet, HashMap<(u32, u32), vk::Image>>,
    pub pipelines: HashMap<vk::Pipeline, PipelineReads>,
    /// Descriptor update templates' image entries (descriptor_templates.rs).
    pub templates: super::descriptor_templates::Templates,
    pub check: TilerCheck,
}

impl TilerState {
    fn transient(&self, image: vk::Image) -> bool {
        self.images.get(&image).is_some_and(|i| i.transient)
    }

    pub fn read(&self, image: vk::Image, how: &'static str) -> Event {
        Event::Read { image: image.as_raw(), how, transient: self.transient(image) }
    }

    pub fn overwrite(&self, image: vk::Image, how: &'static str, whole: bool) -> Event {
        let full = whole && self.images.get(&image).is_some_and(|i| i.single);
        Event::Overwrite { image: image.as_raw(), how, full, transient: self.transient(image) }
    }

    /// A clear command of `ranges` of `image`.
    pub fn cleared(&self, image: vk::Image, how: &'static str, ranges: &[vk::ImageSubresourceRange]) -> Event {
        let end = |base: u32, count: u32| if count == vk::REMAINING_MIP_LEVELS { u32::MAX } else { base + count };
        let ranges = ranges
            .iter()
            .map(|r| {
                (
                    r.base_mip_level..end(r.base_mip_level, r.level_count),
                    r.base_array_layer..end(r.base_array_layer, r.layer_count),
                )
            })
            .collect();
        Event::Cleared { image: image.as_raw(), how, ranges }
    }

    pub fn resolve(&self, src: vk::Image, dst: vk::Image) -> Event {
        Event::Resolve {
            src: src.as_raw(),
            dst: dst.as_raw(),
            src_transient: self.transient(src),
            dst_transient: self.transient(dst),
        }
    }
}

/// A pass's attachments its first draw must not read: (colour slot, attachment index in the
/// pass) and the depth/stencil attachment's index, loaded DONT_CARE.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FirstDraw {
    pub colour: Vec<(u32, usize)>,
    pub depth: Option<usize>,
}

/// One command buffer's part of the check.
#[derive(Debug, Default)]
pub struct CommandTiler {
    pub events: Vec<Event>,
    /// Bound descriptor sets by (bind point, set number).
    pub bound: HashMap<(i32, u32), vk::DescriptorSet>,
    /// Bind points whose sets changed (or a pass began) since a draw or dispatch last read them.
    pub dirty: HashSet<i32>,
    /// The graphics pipeline bound.
    pub pipeline: Option<vk::Pipeline>,
    pub first_draw: Option<FirstDraw>,
    pub end_poison: Vec<super::poison::PoisonClear>,
    /// The current subpass's commands are recorded inline (not in secondary command buffers).
    pub inline: bool,
}

impl CommandTiler {
    /// vkBeginCommandBuffer or a reset: nothing recorded, nothing bound.
    pub fn restart(&mut self) {
        *self = CommandTiler::default();
    }

    /// A pass begins: its first draw reads the bound sets again (a set bound before a pass that
    /// writes one of its images is read after that pass, not before).
    pub fn pass_began(&mut self) {
        self.dirty.extend([vk::PipelineBindPoint::GRAPHICS.as_raw(), vk::PipelineBindPoint::COMPUTE.as_raw()]);
    }

    /// A draw (`GRAPHICS`) or dispatch (`COMPUTE`): the images of the sets bound there are read;
    /// a pass's first draw is checked against its DONT_CARE loads.
    pub fn draw(&mut self, tiler: &TilerState, point: vk::PipelineBindPoint) {
        if self.dirty.remove(&point.as_raw()) {
            let mut images: Vec<vk::Image> = self
                .bound
                .iter()
                .filter(|((p, _), _)| *p == point.as_raw())
                .filter_map(|(_, set)| tiler.sets.get(set))
                .flat_map(|images| images.values().copied())
                .collect();
            images.sort_by_key(|i| i.as_raw());
            images.dedup();
            let how =
                if point == vk::PipelineBindPoint::COMPUTE { "a dispatch (descriptor)" } else { "a draw (descriptor)" };
            self.events.extend(images.into_iter().map(|i| tiler.read(i, how)));
        }
        if point != vk::PipelineBindPoint::GRAPHICS {
            return;
        }
        let Some(first) = self.first_draw.take() else { return };
        let reads = self.pipeline.and_then(|p| tiler.pipelines.get(&p)).cloned().unwrap_or_default();
        for (slot, attachment) in first.colour {
            if reads.blends.get(slot as usize).copied().unwrap_or(false) {
                self.events.push(Event::ReadUndefined { attachment, how: "blending" });
            }
        }
        if let (Some(attachment), true) = (first.depth, reads.depth_test) {
            self.events.push(Event::ReadUndefined { attachment, how: "the depth test" });
        }
    }
}
