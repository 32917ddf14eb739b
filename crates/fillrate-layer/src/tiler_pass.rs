//! The tiler check at a render pass instance's begin and end: which images its attachments
//! are, what it does with their contents ([`PassAttachment`]), which of them to fill with the
//! pattern (poison.rs) right after it begins and right before it ends, and which its first draw
//! must not read (loaded DONT_CARE).
//!
//! Only the first subpass's attachments are poisoned at the begin and the last's at the end:
//! vkCmdClearAttachments reaches the current subpass's attachments only. An attachment the last
//! subpass resolves is not poisoned at the end (the resolve would copy the pattern), nor a
//! depth/stencil attachment the subpass uses read-only, nor a multiview pass's.

use ash::vk;

use super::attachments::{has_depth, AttachmentInfo, RenderPassInfo, SubpassUses};
use super::poison::{pattern, ColourClass, PoisonClear, Target};
use super::tiler_check::{Event, Load, PassAttachment, Store};
use super::tiler_state::{CommandTiler, FirstDraw, TilerState};
use nostencil_tiler::formats::format_has_stencil;

/// The ops of the aspect that names an attachment: depth if it has one, else stencil, colour's.
fn primary_ops(a: &AttachmentInfo) -> (vk::AttachmentLoadOp, vk::AttachmentStoreOp) {
    if format_has_stencil(a.format) && !has_depth(a.format) {
        (a.stencil_load, a.stencil_store)
    } else {
        (a.load, a.store)
    }
}

fn load_of(op: vk::AttachmentLoadOp, undefined: bool) -> Load {
    match op {
        vk::AttachmentLoadOp::LOAD if undefined => Load::DontCare,
        vk::AttachmentLoadOp::LOAD => Load::Load,
        vk::AttachmentLoadOp::CLEAR => Load::Clear,
        vk::AttachmentLoadOp::DONT_CARE => Load::DontCare,
        _ => Load::Keep,
    }
}

fn store_of(op: vk::AttachmentStoreOp) -> Store {
    match op {
        vk::AttachmentStoreOp::STORE => Store::Store,
        vk::AttachmentStoreOp::DONT_CARE => Store::DontCare,
        _ => Store::Keep,
    }
}

/// The aspects of a depth/stencil attachment whose load op (from `undefined` layout or not)
/// leaves them undefined.
fn undefined_aspects(a: &AttachmentInfo, load: bool) -> vk::ImageAspectFlags {
    let mut aspects = vk::ImageAspectFlags::empty();
    let undefined_load = |op| load_of(op, a.initial_undefined) == Load::DontCare;
    let dropped = |op| op == vk::AttachmentStoreOp::DONT_CARE;
    if has_depth(a.format) && if load { undefined_load(a.load) } else { dropped(a.store) } {
        aspects |= vk::ImageAspectFlags::DEPTH;
    }
    let stencil = if load { undefined_load(a.stencil_load) } else { dropped(a.stencil_store) };
    if format_has_stencil(a.format) && stencil {
        aspects |= vk::ImageAspectFlags::STENCIL;
    }
    aspects
}

/// What the begin hook records and the recording keeps for one pass.
pub struct PassPlan {
    pub attachments: Vec<PassAttachment>,
    pub begin_poison: Vec<PoisonClear>,
    pub end_poison: Vec<PoisonClear>,
    pub first_draw: FirstDraw,
}

/// The attachment as the check names and places it: `view` is its image view.
fn pass_attachment(
    tiler: &TilerState,
    name: String,
    a: &AttachmentInfo,
    view: Option<vk::ImageView>,
    area: vk::Rect2D,
) -> PassAttachment {
    let target = view.and_then(|v| tiler.views.get(&v));
    let image = target.and_then(|t| tiler.images.get(&t.image));
    let (load, store) = primary_ops(a);
    let covers = image.zip(target).is_some_and(|(i, t)| {
        let (w, h) = ((i.extent.0 >> t.key.mip).max(1), (i.extent.1 >> t.key.mip).max(1));
        area.offset.x <= 0 && area.offset.y <= 0 && area.extent.width >= w && area.extent.height >= h
    });
    PassAttachment {
        name,
        key: target.map(|t| t.key),
        samples: a.samples,
        load: load_of(load, a.initial_undefined),
        store: store_of(store),
        covers_image: covers,
        // A view the layer saw made of an image it did not see created: a swapchain image.
        external: target.is_some() && image.is_none(),
        poisoned_before: false,
        poisoned_after: false,
    }
}

fn name_of(role: &str, index: usize, format: vk::Format) -> String {
    format!("{role} #{index} ({format:?})")
}

/// The poison targets of `subpass` among `attachments` (`before`: undefined loads; else
/// dropped stores), with the attachment indices they cover.
fn subpass_targets(attachments: &[AttachmentInfo], subpass: &SubpassUses, before: bool) -> Vec<(usize, Target)> {
    let mut targets = Vec::new();
    for (slot, &index) in subpass.colour.iter().enumerate() {
        let Some(a) = attachments.get(index as usize) else { continue };
        let resolved = subpass.resolve.get(slot).is_some_and(|&r| r != vk::ATTACHMENT_UNUSED);
        let poison = if before {
            load_of(a.load, a.initial_undefined) == Load::DontCare
        } else {
            a.store == vk::AttachmentStoreOp::DONT_CARE && !resolved
        };
        if poison {
            targets.push((index as usize, Target::Colour { slot: slot as u32, class: ColourClass::of(a.format) }));
        }
    }
    let depth = subpass.depth.filter(|&d| d != vk::ATTACHMENT_UNUSED);
    if let Some(a) = depth.and_then(|d| attachments.get(d as usize)) {
        let aspects = undefined_aspects(a, before);
        let blocked = subpass.depth_read_only || (!before && subpass.depth_resolved);
        if !aspects.is_empty() && !blocked {
            targets.push((depth.unwrap_or_default() as usize, Target::DepthStencil { aspects }));
        }
    }
    targets
}

/// A render pass object's instance: `views` are the framebuffer's (or the begin info's, for an
/// imageless framebuffer), in attachment order.
pub fn render_pass_plan(
    tiler: &TilerState,
    info: &RenderPassInfo,
    views: &[vk::ImageView],
    area: vk::Rect2D,
) -> PassPlan {
    let mut attachments: Vec<PassAttachment> = info
        .attachments
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let mut pass = pass_attachment(tiler, name_of(a.role, i, a.format), a, views.get(i).copied(), area);
            if a.role == "resolve" {
                // Written whole by the resolve, never loaded.
                pass.load = Load::Clear;
            }
            pass
        })
        .collect();
    let mut plan = PassPlan {
        attachments: Vec::new(),
        begin_poison: Vec::new(),
        end_poison: Vec::new(),
        first_draw: FirstDraw::default(),
    };
    if let (Some(first), Some(last), false) = (info.subpasses.first(), info.subpasses.last(), info.multiview) {
        let before = subpass_targets(&info.attachments, first, true);
        let after = subpass_targets(&info.attachments, last, false);
        for &(index, target) in &before {
            attachments[index].poisoned_before = true;
            match target {
                Target::Colour { slot, .. } => plan.first_draw.colour.push((slot, index)),
                Target::DepthStencil { .. } => plan.first_draw.depth = Some(index),
            }
        }
        for &(index, _) in &after {
            attachments[index].poisoned_after = true;
        }
        plan.begin_poison = pattern(&before.iter().map(|t| t.1).collect::<Vec<_>>(), area);
        plan.end_poison = pattern(&after.iter().map(|t| t.1).collect::<Vec<_>>(), area);
    }
    // Unused attachments are neither loaded nor stored by any subpass.
    for (pass, a) in attachments.iter_mut().zip(&info.attachments) {
        if a.role == "unused" {
            (pass.load, pass.store) = (Load::Keep, Store::Keep);
        }
    }
    plan.attachments = attachments;
    plan
}

/// A dynamic render pass instance (`VkRenderingInfo`), whose attachments `rendering` lists as
/// attachments.rs reads them (colour, its resolve, then depth/stencil), with their views.
pub fn rendering_plan(
    tiler: &TilerState,
    rendering: &[(AttachmentInfo, Option<vk::ImageView>)],
    area: vk::Rect2D,
    suspending: bool,
    resuming: bool,
    multiview: bool,
) -> PassPlan {
    let mut plan = PassPlan {
        attachments: Vec::new(),
        begin_poison: Vec::new(),
        end_poison: Vec::new(),
        first_draw: FirstDraw::default(),
    };
    let (mut before, mut after) = (Vec::new(), Vec::new());
    let mut slot = 0u32;
    for (i, (a, view)) in rendering.iter().enumerate() {
        let role_index = if a.role == "colour" || a.role == "resolve" { slot as usize } else { 0 };
        let mut pass = pass_attachment(tiler, name_of(a.role, role_index, a.format), a, *view, area);
        let resolved = rendering.get(i + 1).is_some_and(|(next, _)| next.role == "resolve") && a.role == "colour";
        match a.role {
            "resolve" => {
                pass.load = Load::Clear;
                slot += 1;
            }
            "colour" => {
                let class = ColourClass::of(a.format);
                if pass.load == Load::DontCare && !resuming && !multiview {
                    before.push(Target::Colour { slot, class });
                    pass.poisoned_before = true;
                    plan.first_draw.colour.push((slot, i));
                }
                if pass.store == Store::DontCare && !resolved && !suspending && !multiview {
                    after.push(Target::Colour { slot, class });
                    pass.poisoned_after = true;
                }
                if !resolved {
                    slot += 1;
                }
            }
            _ => {
                let (load, store) = (undefined_aspects(a, true), undefined_aspects(a, false));
                if !load.is_empty() && !resuming && !multiview {
                    before.push(Target::DepthStencil { aspects: load });
                    pass.poisoned_before = true;
                    plan.first_draw.depth = Some(i);
                }
                if !store.is_empty() && !suspending && !multiview {
                    after.push(Target::DepthStencil { aspects: store });
                    pass.poisoned_after = true;
                }
            }
        }
        plan.attachments.push(pass);
    }
    plan.begin_poison = pattern(&before, area);
    plan.end_poison = pattern(&after, area);
    plan
}

/// Notes the pass's begin in `buffer`'s events and keeps what its end and first draw need;
/// returns the clears to record right after the application's begin call. `inline`: the first
/// subpass's commands are recorded here, not in secondary command buffers (where the layer can
/// neither clear nor see the draws).
pub fn begin(buffer: &mut CommandTiler, label: Option<String>, mut plan: PassPlan, inline: bool) -> Vec<PoisonClear> {
    if !inline {
        plan.begin_poison.clear();
        plan.attachments.iter_mut().for_each(|a| a.poisoned_before = false);
    }
    buffer.events.push(Event::PassBegin { label, attachments: plan.attachments });
    buffer.end_poison = plan.end_poison;
    buffer.first_draw = inline.then_some(plan.first_draw);
    buffer.inline = inline;
    plan.begin_poison
}

/// Notes the pass's end; returns the clears to record right before the application's end call
/// (none when the last subpass runs secondary command buffers: a clear may not be recorded
/// there).
pub fn end(buffer: &mut CommandTiler) -> Vec<PoisonClear> {
    buffer.first_draw = None;
    let poison = std::mem::take(&mut buffer.end_poison);
    if !buffer.inline {
        if let Some(Event::PassBegin { attachments, .. }) =
            buffer.events.iter_mut().rev().find(|e| matches!(e, Event::PassBegin { .. }))
        {
            attachments.iter_mut().for_each(|a| a.poisoned_after = false);
        }
        buffer.events.push(Event::PassEnd);
        return Vec::new();
    }
    buffer.events.push(Event::PassEnd);
    poison
}
