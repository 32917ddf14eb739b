//! What a render pass instance's attachments are (role, format, samples, load/store ops), from
//! a render pass object or a `VkRenderingInfo`, and their tile traffic over the render area by
//! `nostencil profile`'s own rule (`AttachmentDesc::tile_traffic`).

use ash::vk;

use super::arrays::app_array;
use super::report::{AttachmentRow, RenderArea};
use nostencil_tiler::attachment::AttachmentDesc;
use nostencil_tiler::formats::format_has_stencil;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AttachmentInfo {
    pub role: &'static str,
    pub format: vk::Format,
    pub samples: u32,
    pub load: vk::AttachmentLoadOp,
    pub store: vk::AttachmentStoreOp,
    pub stencil_load: vk::AttachmentLoadOp,
    pub stencil_store: vk::AttachmentStoreOp,
    /// The render pass begins from the UNDEFINED layout: old contents are not kept, whatever
    /// the load op (the tiler check's concern).
    pub initial_undefined: bool,
}

/// A render pass object as the layer keeps it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderPassInfo {
    pub attachments: Vec<AttachmentInfo>,
    /// Each subpass's uses of the attachments (the tiler check poisons the first and last's).
    pub subpasses: Vec<SubpassUses>,
    /// Some subpass has a non-zero view mask.
    pub multiview: bool,
    /// Each subpass's view mask (empty when no subpass has one).
    pub view_masks: Vec<u32>,
}

impl RenderPassInfo {
    /// Views each subpass renders (1 each outside multiview): a multiview pass's queries take
    /// that many consecutive indices in the subpass.
    pub fn view_counts(&self) -> Vec<u32> {
        self.view_masks.iter().map(|m| m.count_ones().max(1)).collect()
    }
}

pub fn has_depth(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::D16_UNORM
            | vk::Format::X8_D24_UNORM_PACK32
            | vk::Format::D32_SFLOAT
            | vk::Format::D16_UNORM_S8_UINT
            | vk::Format::D24_UNORM_S8_UINT
            | vk::Format::D32_SFLOAT_S8_UINT
    )
}

/// "depth", "stencil" or "depth_stencil" by the format's aspects.
fn depth_role(format: vk::Format) -> &'static str {
    match (has_depth(format), format_has_stencil(format)) {
        (true, true) => "depth_stencil",
        (false, true) => "stencil",
        _ => "depth",
    }
}

/// The attachment indices one subpass uses, by kind.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SubpassUses {
    pub colour: Vec<u32>,
    pub resolve: Vec<u32>,
    pub depth: Option<u32>,
    pub input: Vec<u32>,
    /// The depth/stencil reference's layout is read-only (it cannot be cleared in the subpass).
    pub depth_read_only: bool,
    /// A depth/stencil resolve (VkSubpassDescriptionDepthStencilResolve) writes it out.
    pub depth_resolved: bool,
}

/// The role of each attachment index by its first use in the subpasses.
pub fn roles(count: usize, formats: &[vk::Format], subpasses: &[SubpassUses]) -> Vec<&'static str> {
    let mut roles = vec!["unused"; count];
    let mut set = |index: u32, role: &'static str| {
        if let Some(slot) = roles.get_mut(index as usize) {
            if *slot == "unused" {
                *slot = role;
            }
        }
    };
    for SubpassUses { colour, resolve, depth, input, .. } in subpasses {
        colour.iter().filter(|&&a| a != vk::ATTACHMENT_UNUSED).for_each(|&a| set(a, "colour"));
        resolve.iter().filter(|&&a| a != vk::ATTACHMENT_UNUSED).for_each(|&a| set(a, "resolve"));
        if let Some(a) = depth.filter(|&a| a != vk::ATTACHMENT_UNUSED) {
            set(a, depth_role(formats.get(a as usize).copied().unwrap_or_default()));
        }
        input.iter().filter(|&&a| a != vk::ATTACHMENT_UNUSED).for_each(|&a| set(a, "input"));
    }
    roles
}

fn sample_count(flags: vk::SampleCountFlags) -> u32 {
    flags.as_raw().max(1)
}

/// The attachment fields the layer reads, the same in `VkAttachmentDescription` and `2`.
trait AttachmentFields {
    fn info(&self, role: &'static str) -> AttachmentInfo;
    fn format(&self) -> vk::Format;
}

macro_rules! attachment_fields {
    ($t:ty) => {
        impl AttachmentFields for $t {
            fn info(&self, role: &'static str) -> AttachmentInfo {
                AttachmentInfo {
                    role,
                    format: self.format,
                    samples: sample_count(self.samples),
                    load: self.load_op,
                    store: self.store_op,
                    stencil_load: self.stencil_load_op,
                    stencil_store: self.stencil_store_op,
                    initial_undefined: self.initial_layout == vk::ImageLayout::UNDEFINED,
                }
            }
            fn format(&self) -> vk::Format {
                self.format
            }
        }
    };
}
attachment_fields!(vk::AttachmentDescription);
attachment_fields!(vk::AttachmentDescription2<'_>);

/// `VkAttachmentReference` and `2`: the attachment index.
trait AttachmentIndex {
    fn index(&self) -> u32;
    fn layout(&self) -> vk::ImageLayout;
}

impl AttachmentIndex for vk::AttachmentReference {
    fn index(&self) -> u32 {
        self.attachment
    }
    fn layout(&self) -> vk::ImageLayout {
        self.layout
    }
}

impl AttachmentIndex for vk::AttachmentReference2<'_> {
    fn index(&self) -> u32 {
        self.attachment
    }
    fn layout(&self) -> vk::ImageLayout {
        self.layout
    }
}

/// A depth/stencil layout in which the subpass may not write (or clear) the attachment.
fn read_only(layout: vk::ImageLayout) -> bool {
    matches!(
        layout,
        vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL
            | vk::ImageLayout::STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL
            | vk::ImageLayout::DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::READ_ONLY_OPTIMAL
            | vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL
    )
}

/// One subpass's attachment uses from its reference arrays.
///
/// # Safety
/// Each pointer is null or points at as many valid references as its count (`colour_count` for
/// colour and resolve, one for depth), as a valid subpass description's do.
unsafe fn subpass_uses<R: AttachmentIndex>(
    colour: *const R,
    resolve: *const R,
    colour_count: u32,
    depth: *const R,
    input: *const R,
    input_count: u32,
) -> SubpassUses {
    // SAFETY: the caller's contract, for each array.
    let indices = |p: *const R, n: u32| unsafe { app_array(p, n) }.iter().map(R::index).collect::<Vec<u32>>();
    // SAFETY: null or one valid reference.
    let depth_ref = unsafe { depth.as_ref() };
    SubpassUses {
        colour: indices(colour, colour_count),
        resolve: indices(resolve, colour_count),
        // SAFETY: null or one valid reference.
        depth: unsafe { depth.as_ref() }.map(R::index),
        input: indices(input, input_count),
        depth_read_only: depth_ref.is_some_and(|d| read_only(d.layout())),
        depth_resolved: false,
    }
}

/// `VkSubpassDescription` and `2`: the attachments a subpass uses.
trait SubpassFields {
    /// # Safety
    /// The description's arrays are valid for their counts (valid usage).
    unsafe fn uses(&self) -> SubpassUses;
}

macro_rules! subpass_fields {
    ($t:ty) => {
        impl SubpassFields for $t {
            unsafe fn uses(&self) -> SubpassUses {
                // SAFETY: the caller's contract.
                unsafe {
                    subpass_uses(
                        self.p_color_attachments,
                        self.p_resolve_attachments,
                        self.color_attachment_count,
                        self.p_depth_stencil_attachment,
                        self.p_input_attachments,
                        self.input_attachment_count,
                    )
                }
            }
        }
    };
}
subpass_fields!(vk::SubpassDescription<'_>);
subpass_fields!(vk::SubpassDescription2<'_>);

/// The render pass from its attachments and each subpass's uses of them.
fn render_pass_info<A: AttachmentFields>(descriptions: &[A], uses: &[SubpassUses], masks: Vec<u32>) -> RenderPassInfo {
    let formats: Vec<_> = descriptions.iter().map(A::format).collect();
    let roles = roles(descriptions.len(), &formats, uses);
    let attachments = descriptions.iter().zip(roles).map(|(d, role)| d.info(role)).collect();
    let multiview = masks.iter().any(|&m| m != 0);
    let view_masks = if multiview { masks } else { Vec::new() };
    RenderPassInfo { attachments, subpasses: uses.to_vec(), multiview, view_masks }
}

impl RenderPassInfo {
    /// # Safety
    /// `info` is a valid VkRenderPassCreateInfo (as passed to vkCreateRenderPass).
    pub unsafe fn from_create_info(info: &vk::RenderPassCreateInfo) -> Self {
        // SAFETY: here and below, the arrays are as long as their counts say (valid usage).
        let descriptions = unsafe { app_array(info.p_attachments, info.attachment_count) };
        // SAFETY: as above.
        let subpasses = unsafe { app_array(info.p_subpasses, info.subpass_count) };
        // SAFETY: a valid subpass description's arrays (valid usage).
        let uses: Vec<_> = subpasses.iter().map(|s| unsafe { s.uses() }).collect();
        // SAFETY: the pNext chain is valid; a multiview node is VkRenderPassMultiviewCreateInfo.
        let masks = unsafe { multiview_masks(info.p_next) };
        render_pass_info(descriptions, &uses, masks)
    }

    /// # Safety
    /// `info` is a valid VkRenderPassCreateInfo2 (as passed to vkCreateRenderPass2).
    pub unsafe fn from_create_info2(info: &vk::RenderPassCreateInfo2) -> Self {
        // SAFETY: the arrays are as long as their counts say (valid usage).
        let descriptions = unsafe { app_array(info.p_attachments, info.attachment_count) };
        // SAFETY: as above.
        let subpasses = unsafe { app_array(info.p_subpasses, info.subpass_count) };
        // SAFETY: a valid subpass description's arrays (valid usage).
        let mut uses: Vec<_> = subpasses.iter().map(|s| unsafe { s.uses() }).collect();
        for (subpass, uses) in subpasses.iter().zip(&mut uses) {
            // SAFETY: a valid subpass description's pNext chain.
            uses.depth_resolved = unsafe { depth_resolve(subpass.p_next) };
        }
        render_pass_info(descriptions, &uses, subpasses.iter().map(|s| s.view_mask).collect())
    }
}

/// Whether a VkSubpassDescriptionDepthStencilResolve in the chain resolves the depth/stencil.
///
/// # Safety
/// `p_next` is a valid pNext chain.
unsafe fn depth_resolve(mut p_next: *const std::ffi::c_void) -> bool {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next as *const std::ffi::c_void) };
        if ty == vk::StructureType::SUBPASS_DESCRIPTION_DEPTH_STENCIL_RESOLVE {
            // SAFETY: a node of this sType is VkSubpassDescriptionDepthStencilResolve.
            let resolve = unsafe { &*(p_next as *const vk::SubpassDescriptionDepthStencilResolve) };
            // SAFETY: null or one valid reference.
            let target = unsafe { resolve.p_depth_stencil_resolve_attachment.as_ref() };
            return target.is_some_and(|t| t.attachment != vk::ATTACHMENT_UNUSED);
        }
        p_next = next;
    }
    false
}

/// The subpasses' view masks of a VkRenderPassMultiviewCreateInfo in the chain (empty: none).
///
/// # Safety
/// `p_next` is a valid pNext chain.
unsafe fn multiview_masks(mut p_next: *const std::ffi::c_void) -> Vec<u32> {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next as *const std::ffi::c_void) };
        if ty == vk::StructureType::RENDER_PASS_MULTIVIEW_CREATE_INFO {
            // SAFETY: a node of this sType is VkRenderPassMultiviewCreateInfo.
            let multiview = unsafe { &*(p_next as *const vk::RenderPassMultiviewCreateInfo) };
            // SAFETY: pViewMasks holds subpassCount masks.
            return unsafe { app_array(multiview.p_view_masks, multiview.subpass_count) }.to_vec();
        }
        p_next = next;
    }
    Vec::new()
}

/// The attachments of a dynamic render pass instance; `view` gives an image view's
/// (format, samples), None for a view the layer did not see created.
///
/// # Safety
/// `info` is a valid VkRenderingInfo.
pub unsafe fn rendering_attachments(
    info: &vk::RenderingInfo,
    view: &dyn Fn(vk::ImageView) -> Option<(vk::Format, u32)>,
) -> Vec<AttachmentInfo> {
    let mut out = Vec::new();
    let unknown = (vk::Format::UNDEFINED, 1);
    let dont_care = (vk::AttachmentLoadOp::DONT_CARE, vk::AttachmentStoreOp::DONT_CARE);
    // SAFETY: pColorAttachments holds colorAttachmentCount entries (valid usage).
    for c in unsafe { app_array(info.p_color_attachments, info.color_attachment_count) } {
        if c.image_view != vk::ImageView::null() {
            let (format, samples) = view(c.image_view).unwrap_or(unknown);
            out.push(AttachmentInfo {
                role: "colour",
                format,
                samples,
                load: c.load_op,
                store: c.store_op,
                stencil_load: dont_care.0,
                stencil_store: dont_care.1,
                initial_undefined: false,
            });
        }
        if c.resolve_mode != vk::ResolveModeFlags::NONE && c.resolve_image_view != vk::ImageView::null() {
            let (format, samples) = view(c.resolve_image_view).unwrap_or(unknown);
            // The resolve writes every pixel of the area: a store, nothing loaded.
            out.push(AttachmentInfo {
                role: "resolve",
                format,
                samples,
                load: dont_care.0,
                store: vk::AttachmentStoreOp::STORE,
                stencil_load: dont_care.0,
                stencil_store: dont_care.1,
                initial_undefined: false,
            });
        }
    }
    // SAFETY: pDepthAttachment / pStencilAttachment are null or one valid struct each.
    let (depth, stencil) = unsafe { (info.p_depth_attachment.as_ref(), info.p_stencil_attachment.as_ref()) };
    let depth = depth.filter(|d| d.image_view != vk::ImageView::null());
    let stencil = stencil.filter(|s| s.image_view != vk::ImageView::null());
    match (depth, stencil) {
        (Some(d), Some(s)) if d.image_view == s.image_view => {
            let (format, samples) = view(d.image_view).unwrap_or(unknown);
            out.push(AttachmentInfo {
                role: "depth_stencil",
                format,
                samples,
                load: d.load_op,
                store: d.store_op,
                stencil_load: s.load_op,
                stencil_store: s.store_op,
                initial_undefined: false,
            });
        }
        (depth, stencil) => {
            if let Some(d) = depth {
                let (format, samples) = view(d.image_view).unwrap_or(unknown);
                out.push(AttachmentInfo {
                    role: "depth",
                    format,
                    samples,
                    load: d.load_op,
                    store: d.store_op,
                    stencil_load: dont_care.0,
                    stencil_store: dont_care.1,
                    initial_undefined: false,
                });
            }
            if let Some(s) = stencil {
                let (format, samples) = view(s.image_view).unwrap_or(unknown);
                out.push(AttachmentInfo {
                    role: "stencil",
                    format,
                    samples,
                    load: s.load_op,
                    store: s.store_op,
                    stencil_load: s.load_op,
                    stencil_store: s.store_op,
                    initial_undefined: false,
                });
            }
        }
    }
    out
}

/// The image view of each attachment [`rendering_attachments`] lists, in its order.
///
/// # Safety
/// `info` is a valid VkRenderingInfo.
pub unsafe fn rendering_views(info: &vk::RenderingInfo) -> Vec<Option<vk::ImageView>> {
    let mut out = Vec::new();
    // SAFETY: pColorAttachments holds colorAttachmentCount entries (valid usage).
    for c in unsafe { app_array(info.p_color_attachments, info.color_attachment_count) } {
        if c.image_view != vk::ImageView::null() {
            out.push(Some(c.image_view));
        }
        if c.resolve_mode != vk::ResolveModeFlags::NONE && c.resolve_image_view != vk::ImageView::null() {
            out.push(Some(c.resolve_image_view));
        }
    }
    // SAFETY: pDepthAttachment / pStencilAttachment are null or one valid struct each.
    let (depth, stencil) = unsafe { (info.p_depth_attachment.as_ref(), info.p_stencil_attachment.as_ref()) };
    let depth = depth.map(|d| d.image_view).filter(|&v| v != vk::ImageView::null());
    let stencil = stencil.map(|s| s.image_view).filter(|&v| v != vk::ImageView::null());
    match (depth, stencil) {
        (Some(d), Some(s)) if d == s => out.push(Some(d)),
        (depth, stencil) => out.extend([depth, stencil].into_iter().flatten().map(Some)),
    }
    out
}

fn op_name<T: std::fmt::Debug>(op: T) -> String {
    format!("{op:?}")
}

/// The report rows of `attachments` over `area`, with tile traffic by `nostencil profile`'s rule.
pub fn attachment_rows(attachments: &[AttachmentInfo], area: &RenderArea) -> Vec<AttachmentRow> {
    attachments
        .iter()
        .map(|a| {
            let stencil = format_has_stencil(a.format);
            // A stencil-only attachment carries its ops in the stencil aspect only.
            let depth_aspect = has_depth(a.format) || !stencil;
            let desc = AttachmentDesc {
                name: a.role,
                format: a.format,
                load: if depth_aspect { a.load } else { vk::AttachmentLoadOp::DONT_CARE },
                store: if depth_aspect { a.store } else { vk::AttachmentStoreOp::DONT_CARE },
                stencil_load: a.stencil_load,
                stencil_store: a.stencil_store,
                final_layout: vk::ImageLayout::UNDEFINED,
                transient: false,
                samples: a.samples,
            };
            let traffic = desc.tile_traffic(area.width, area.height);
            AttachmentRow {
                role: a.role.to_owned(),
                format: op_name(a.format),
                samples: a.samples,
                load_op: op_name(a.load),
                store_op: op_name(a.store),
                stencil_load_op: stencil.then(|| op_name(a.stencil_load)),
                stencil_store_op: stencil.then(|| op_name(a.stencil_store)),
                bytes_loaded: traffic.bytes_loaded,
                bytes_stored: traffic.bytes_stored,
                bytes_cleared: traffic.bytes_cleared,
                bytes_per_sample: traffic.bytes_per_sample,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attachment(role: &'static str, format: vk::Format, load: vk::AttachmentLoadOp) -> AttachmentInfo {
        AttachmentInfo {
            role,
            format,
            samples: 1,
            load,
            store: vk::AttachmentStoreOp::STORE,
            stencil_load: vk::AttachmentLoadOp::LOAD,
            stencil_store: vk::AttachmentStoreOp::DONT_CARE,
            initial_undefined: false,
        }
    }

    #[test]
    fn traffic_follows_profiles_rule_over_the_render_area() {
        let area = RenderArea { x: 0, y: 0, width: 10, height: 20 };
        let rows = attachment_rows(
            &[
                attachment("colour", vk::Format::B8G8R8A8_UNORM, vk::AttachmentLoadOp::CLEAR),
                attachment("depth_stencil", vk::Format::D24_UNORM_S8_UINT, vk::AttachmentLoadOp::LOAD),
                AttachmentInfo {
                    samples: 4,
                    store: vk::AttachmentStoreOp::DONT_CARE,
                    ..attachment("colour", vk::Format::R8G8B8A8_SRGB, vk::AttachmentLoadOp::LOAD)
                },
            ],
            &area,
        );
        // Cleared colour: nothing loaded, 4 bytes a pixel stored.
        assert_eq!((rows[0].bytes_loaded, rows[0].bytes_stored), (0, 4 * 200));
        assert_eq!(rows[0].format, "B8G8R8A8_UNORM");
        assert_eq!((rows[0].load_op.as_str(), rows[0].store_op.as_str()), ("CLEAR", "STORE"));
        assert_eq!(rows[0].stencil_load_op, None);
        // D24S8 loaded (depth 3 + stencil 1 bytes), depth stored, stencil discarded.
        assert_eq!((rows[1].bytes_loaded, rows[1].bytes_stored), (4 * 200, 3 * 200));
        assert_eq!(rows[1].stencil_load_op.as_deref(), Some("LOAD"));
        // 4 samples loaded, discarded.
        assert_eq!((rows[2].bytes_loaded, rows[2].bytes_stored), (4 * 4 * 200, 0));
    }

    #[test]
    fn roles_come_from_the_first_subpass_that_uses_each_attachment() {
        let formats = [
            vk::Format::R8G8B8A8_SRGB,
            vk::Format::D32_SFLOAT_S8_UINT,
            vk::Format::R8G8B8A8_SRGB,
            vk::Format::R8_UNORM,
        ];
        let subpasses = vec![
            SubpassUses { colour: vec![0], resolve: vec![2], depth: Some(1), ..SubpassUses::default() },
            SubpassUses { input: vec![0, 3], ..SubpassUses::default() },
        ];
        assert_eq!(roles(5, &formats, &subpasses), vec!["colour", "depth_stencil", "resolve", "input", "unused"]);
    }
}
