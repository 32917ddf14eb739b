//! Command-buffer hooks: the render pass instances (begin, next subpass, end) get the layer's
//! queries (draws, debug labels and the application's own queries: `draw_hooks`). The layer's
//! commands are recorded right after the application's begin returns and right before its end
//! is called, so the render pass the application set up is untouched; nothing is bound.

use ash::vk;
use ash::vk::Handle;

use super::attachments::{attachment_rows, rendering_attachments, rendering_views};
use super::objects::{device_and, flush_buffer};
use super::poison::PoisonClear;
use super::recording::PassDesc;
use super::report::RenderArea;
use super::slots::{QueryCmd, QueryKind, CHUNK};
use super::state::{guard, DeviceData, DeviceState};
use super::tiler_pass;

/// Records the layer's query commands into `cmd`.
pub(super) fn record(device: &DeviceData, cmd: vk::CommandBuffer, cmds: &[QueryCmd]) {
    for c in cmds {
        // SAFETY: `cmd` is recording (the application is inside a vkCmd* call on it); every
        // pool is the layer's, each query reset before use and begun/ended in one subpass, resets
        // only outside a render pass (see recording.rs).
        unsafe {
            match *c {
                QueryCmd::Reset { pool, first, count } => device.fns.cmd_reset_query_pool(cmd, pool, first, count),
                QueryCmd::Begin { slot, precise } => {
                    let flags = if precise { vk::QueryControlFlags::PRECISE } else { vk::QueryControlFlags::empty() };
                    device.fns.cmd_begin_query(cmd, slot.pool, slot.query, flags)
                }
                QueryCmd::End { slot } => device.fns.cmd_end_query(cmd, slot.pool, slot.query),
                QueryCmd::Timestamp { slot, stage } => {
                    device.fns.cmd_write_timestamp(cmd, stage, slot.pool, slot.query)
                }
            }
        }
    }
}

/// A new query pool of `kind` for the layer.
pub(super) fn create_pool(device: &DeviceData, kind: QueryKind) -> Option<vk::QueryPool> {
    let (ty, stats) = match kind {
        QueryKind::Occlusion => (vk::QueryType::OCCLUSION, vk::QueryPipelineStatisticFlags::empty()),
        QueryKind::Statistics => {
            let bits = super::readback::STATISTICS.iter().fold(vk::QueryPipelineStatisticFlags::empty(), |a, &b| a | b);
            (vk::QueryType::PIPELINE_STATISTICS, bits)
        }
        QueryKind::Timestamp => (vk::QueryType::TIMESTAMP, vk::QueryPipelineStatisticFlags::empty()),
        QueryKind::Compute => (vk::QueryType::PIPELINE_STATISTICS, super::work::COMPUTE_STATISTICS),
    };
    let info = vk::QueryPoolCreateInfo::default().query_type(ty).query_count(CHUNK).pipeline_statistics(stats);
    // SAFETY: the device is alive; statistics pools are made only when the device has (and the
    // layer enabled) pipelineStatisticsQuery.
    unsafe { device.fns.create_query_pool(&info, None) }.ok()
}

/// A command's call passed on down the chain, through the tiler check's own hook for it
/// (`image_use.rs`) when the check is on: `pass_on_through_check!(d, cmd_copy_image(cmd, ...))`.
/// Every hook of a command the check also watches passes its call on this way.
macro_rules! pass_on_through_check {
    ($d:expr, $name:ident($($arg:expr),* $(,)?)) => {
        if $d.config.tiler {
            // SAFETY: the application's arguments, passed on through the check.
            unsafe { super::image_use::$name($($arg),*) }
        } else if let Some(next) = $d.next.$name {
            // SAFETY: the application's arguments, passed on.
            unsafe { next($($arg),*) }
        }
    };
}
pub(super) use pass_on_through_check;

/// Runs `f` on `cmd`'s recording if the layer is measuring; records what it returns before and
/// after `call`, which makes the application's call.
pub(super) fn around(
    cmd: vk::CommandBuffer,
    call: impl FnOnce(&DeviceData),
    f: impl FnOnce(&DeviceData, &mut DeviceState) -> (Vec<QueryCmd>, Vec<QueryCmd>),
) {
    let Some(device) = guard(None, || super::state::device_of(cmd.as_raw())) else { return };
    let (before, after) = guard(Default::default(), || {
        if !device.active() {
            return Default::default();
        }
        f(&device, &mut device.state())
    });
    guard((), || record(&device, cmd, &before));
    call(&device);
    guard((), || record(&device, cmd, &after));
}

/// [`around`] for a render pass's begin or end: `f` also returns the tiler check's clears,
/// recorded right after the application's call (`after_call`, at a begin: before the layer's
/// timestamp, so the pass's GPU time leaves them out) or right before it (at an end: after the
/// layer's queries and timestamps).
fn around_pass(
    cmd: vk::CommandBuffer,
    after_call: bool,
    call: impl FnOnce(&DeviceData),
    f: impl FnOnce(&DeviceData, &mut DeviceState) -> (Vec<QueryCmd>, Vec<QueryCmd>, Vec<PoisonClear>),
) {
    let Some(device) = guard(None, || super::state::device_of(cmd.as_raw())) else { return };
    let (before, after, poison) = guard(Default::default(), || {
        if !device.active() {
            return Default::default();
        }
        f(&device, &mut device.state())
    });
    guard((), || record(&device, cmd, &before));
    if !after_call {
        guard((), || record_poison(&device, cmd, &poison));
    }
    call(&device);
    if after_call {
        guard((), || record_poison(&device, cmd, &poison));
    }
    guard((), || record(&device, cmd, &after));
}

/// Records the tiler check's pattern into `cmd`, inside its render pass.
fn record_poison(device: &DeviceData, cmd: vk::CommandBuffer, clears: &[PoisonClear]) {
    for clear in clears {
        // SAFETY: `cmd` is recording inside the render pass instance the plan was made for; each
        // attachment is one of the current subpass's (colour slot or depth/stencil aspects it
        // has, not read-only) and each rect lies in the render area, one layer.
        unsafe { device.fns.cmd_clear_attachments(cmd, &clear.attachments, &clear.rects) }
    }
}

/// The tiler check at a render pass object's begin: notes the pass, returns its first clears.
fn tiler_begin_render_pass(
    device: &DeviceData,
    st: &mut DeviceState,
    cmd: vk::CommandBuffer,
    begin: &vk::RenderPassBeginInfo,
    contents: vk::SubpassContents,
) -> Vec<PoisonClear> {
    if !device.config.tiler {
        return Vec::new();
    }
    let plan = {
        let Some(info) = st.render_passes.get(&begin.render_pass) else { return Vec::new() };
        // SAFETY: the application's valid begin info and its pNext chain.
        let views = unsafe { imageless_views(begin.p_next) }
            .or_else(|| st.tiler.framebuffers.get(&begin.framebuffer).cloned())
            .unwrap_or_default();
        tiler_pass::render_pass_plan(&st.tiler, info, &views, begin.render_area)
    };
    let Some(data) = st.buffers.get_mut(&cmd) else { return Vec::new() };
    let label = data.recording.label_now();
    data.tiler.pass_began();
    tiler_pass::begin(&mut data.tiler, label, plan, contents == vk::SubpassContents::INLINE)
}

/// The views of an imageless framebuffer, from VkRenderPassAttachmentBeginInfo.
///
/// # Safety
/// `p_next` is a valid pNext chain.
unsafe fn imageless_views(mut p_next: *const std::ffi::c_void) -> Option<Vec<vk::ImageView>> {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next as *const std::ffi::c_void) };
        if ty == vk::StructureType::RENDER_PASS_ATTACHMENT_BEGIN_INFO {
            // SAFETY: a node of this sType is VkRenderPassAttachmentBeginInfo, its array as long
            // as its count.
            let views = unsafe {
                let info = &*(p_next as *const vk::RenderPassAttachmentBeginInfo);
                super::arrays::app_array(info.p_attachments, info.attachment_count).to_vec()
            };
            return Some(views);
        }
        p_next = next;
    }
    None
}

/// Whether new passes are measured now (an output is set and the frame limit not reached).
pub(super) fn measuring(state: &mut DeviceState) -> bool {
    !state.finished && state.frames().measuring()
}

/// The render pass instance begins: the pass is noted and (if it can be) measured.
fn begin_pass(
    device: &DeviceData,
    state: &mut DeviceState,
    cmd: vk::CommandBuffer,
    desc: PassDesc,
) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
    if !measuring(state) {
        return Default::default();
    }
    let Some(data) = state.buffers.get_mut(&cmd) else { return Default::default() };
    data.recording.begin_pass(desc, &mut |kind| create_pool(device, kind))
}

fn pass_desc(
    state: &DeviceState,
    api: &'static str,
    begin: &vk::RenderPassBeginInfo,
    contents: vk::SubpassContents,
) -> PassDesc {
    let area = RenderArea {
        x: begin.render_area.offset.x,
        y: begin.render_area.offset.y,
        width: begin.render_area.extent.width,
        height: begin.render_area.extent.height,
    };
    let info = state.render_passes.get(&begin.render_pass);
    let attachments = info.map(|i| attachment_rows(&i.attachments, &area)).unwrap_or_default();
    let not_measured = info.is_none().then(|| "render pass created before the layer saw it".to_owned());
    let samples = attachments.iter().map(|a| a.samples).max().unwrap_or(1);
    let secondary_contents = contents == vk::SubpassContents::SECONDARY_COMMAND_BUFFERS;
    let view_counts = info.map(|i| i.view_counts()).unwrap_or_default();
    PassDesc { api, area, samples, attachments, not_measured, secondary_contents, view_counts }
}

pub(super) unsafe extern "system" fn cmd_begin_render_pass(
    cmd: vk::CommandBuffer,
    begin: *const vk::RenderPassBeginInfo<'_>,
    contents: vk::SubpassContents,
) {
    around_pass(
        cmd,
        true,
        |d| {
            if let Some(next) = d.next.cmd_begin_render_pass {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, begin, contents) }
            }
        },
        |d, st| {
            // SAFETY: the application's valid begin info.
            let begin = unsafe { &*begin };
            let poison = tiler_begin_render_pass(d, st, cmd, begin, contents);
            let desc = pass_desc(st, "vkCmdBeginRenderPass", begin, contents);
            let (before, after) = begin_pass(d, st, cmd, desc);
            (before, after, poison)
        },
    );
}

unsafe fn begin_render_pass2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCmdBeginRenderPass2>,
    cmd: vk::CommandBuffer,
    begin: *const vk::RenderPassBeginInfo<'_>,
    subpass: *const vk::SubpassBeginInfo<'_>,
) {
    around_pass(
        cmd,
        true,
        |d| {
            if let Some(next) = pick(d) {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, begin, subpass) }
            }
        },
        |d, st| {
            // SAFETY: the application's valid begin infos.
            let (begin, contents) = unsafe { (&*begin, (*subpass).contents) };
            let poison = tiler_begin_render_pass(d, st, cmd, begin, contents);
            let desc = pass_desc(st, "vkCmdBeginRenderPass2", begin, contents);
            let (before, after) = begin_pass(d, st, cmd, desc);
            (before, after, poison)
        },
    );
}

pub(super) unsafe extern "system" fn cmd_begin_render_pass2(
    cmd: vk::CommandBuffer,
    begin: *const vk::RenderPassBeginInfo<'_>,
    subpass: *const vk::SubpassBeginInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { begin_render_pass2_with(|d| d.next.cmd_begin_render_pass2, cmd, begin, subpass) }
}

pub(super) unsafe extern "system" fn cmd_begin_render_pass2_khr(
    cmd: vk::CommandBuffer,
    begin: *const vk::RenderPassBeginInfo<'_>,
    subpass: *const vk::SubpassBeginInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { begin_render_pass2_with(|d| d.next.cmd_begin_render_pass2_khr, cmd, begin, subpass) }
}

fn next_subpass(
    st: &mut DeviceState,
    cmd: vk::CommandBuffer,
    contents: vk::SubpassContents,
) -> (Vec<QueryCmd>, Vec<QueryCmd>) {
    let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
    // Only the first subpass's first draw is checked against the DONT_CARE loads.
    data.tiler.first_draw = None;
    data.tiler.inline = contents == vk::SubpassContents::INLINE;
    data.recording.next_subpass(contents == vk::SubpassContents::SECONDARY_COMMAND_BUFFERS)
}

pub(super) unsafe extern "system" fn cmd_next_subpass(cmd: vk::CommandBuffer, contents: vk::SubpassContents) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_next_subpass {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, contents) }
            }
        },
        |_, st| next_subpass(st, cmd, contents),
    );
}

unsafe fn next_subpass2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCmdNextSubpass2>,
    cmd: vk::CommandBuffer,
    begin: *const vk::SubpassBeginInfo<'_>,
    end: *const vk::SubpassEndInfo<'_>,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = pick(d) {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, begin, end) }
            }
        },
        // SAFETY: the application's valid subpass begin info.
        |_, st| next_subpass(st, cmd, unsafe { (*begin).contents }),
    );
}

pub(super) unsafe extern "system" fn cmd_next_subpass2(
    cmd: vk::CommandBuffer,
    begin: *const vk::SubpassBeginInfo<'_>,
    end: *const vk::SubpassEndInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { next_subpass2_with(|d| d.next.cmd_next_subpass2, cmd, begin, end) }
}

pub(super) unsafe extern "system" fn cmd_next_subpass2_khr(
    cmd: vk::CommandBuffer,
    begin: *const vk::SubpassBeginInfo<'_>,
    end: *const vk::SubpassEndInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { next_subpass2_with(|d| d.next.cmd_next_subpass2_khr, cmd, begin, end) }
}

fn end_pass(
    device: &DeviceData,
    st: &mut DeviceState,
    cmd: vk::CommandBuffer,
) -> (Vec<QueryCmd>, Vec<QueryCmd>, Vec<PoisonClear>) {
    let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
    let poison = if device.config.tiler { tiler_pass::end(&mut data.tiler) } else { Vec::new() };
    let (before, after) = data.recording.end_pass();
    (before, after, poison)
}

pub(super) unsafe extern "system" fn cmd_end_render_pass(cmd: vk::CommandBuffer) {
    around_pass(
        cmd,
        false,
        |d| {
            if let Some(next) = d.next.cmd_end_render_pass {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd) }
            }
        },
        |d, st| end_pass(d, st, cmd),
    );
}

unsafe fn end_render_pass2_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCmdEndRenderPass2>,
    cmd: vk::CommandBuffer,
    end: *const vk::SubpassEndInfo<'_>,
) {
    around_pass(
        cmd,
        false,
        |d| {
            if let Some(next) = pick(d) {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, end) }
            }
        },
        |d, st| end_pass(d, st, cmd),
    );
}

pub(super) unsafe extern "system" fn cmd_end_render_pass2(cmd: vk::CommandBuffer, end: *const vk::SubpassEndInfo<'_>) {
    // SAFETY: the application's arguments.
    unsafe { end_render_pass2_with(|d| d.next.cmd_end_render_pass2, cmd, end) }
}

pub(super) unsafe extern "system" fn cmd_end_render_pass2_khr(
    cmd: vk::CommandBuffer,
    end: *const vk::SubpassEndInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { end_render_pass2_with(|d| d.next.cmd_end_render_pass2_khr, cmd, end) }
}

unsafe fn begin_rendering_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCmdBeginRendering>,
    cmd: vk::CommandBuffer,
    info: *const vk::RenderingInfo<'_>,
) {
    around_pass(
        cmd,
        true,
        |d| {
            if let Some(next) = pick(d) {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, info) }
            }
        },
        |d, st| {
            // SAFETY: the application's valid rendering info.
            let info = unsafe { &*info };
            let poison = if d.config.tiler {
                let views = &st.views;
                // SAFETY: as above.
                let infos = unsafe { rendering_attachments(info, &|v| views.get(&v).copied()) };
                // SAFETY: as above.
                let pairs: Vec<_> = infos.into_iter().zip(unsafe { rendering_views(info) }).collect();
                let (flags, multiview) = (info.flags, info.view_mask != 0);
                let suspending = flags.contains(vk::RenderingFlags::SUSPENDING);
                let resuming = flags.contains(vk::RenderingFlags::RESUMING);
                let plan =
                    tiler_pass::rendering_plan(&st.tiler, &pairs, info.render_area, suspending, resuming, multiview);
                match st.buffers.get_mut(&cmd) {
                    Some(data) => {
                        let label = data.recording.label_now();
                        data.tiler.pass_began();
                        let inline = !flags.contains(vk::RenderingFlags::CONTENTS_SECONDARY_COMMAND_BUFFERS);
                        tiler_pass::begin(&mut data.tiler, label, plan, inline)
                    }
                    None => Vec::new(),
                }
            } else {
                Vec::new()
            };
            let area = RenderArea {
                x: info.render_area.offset.x,
                y: info.render_area.offset.y,
                width: info.render_area.extent.width,
                height: info.render_area.extent.height,
            };
            let views = &st.views;
            // SAFETY: as above.
            let attachments = unsafe { rendering_attachments(info, &|v| views.get(&v).copied()) };
            let attachments = attachment_rows(&attachments, &area);
            let flags = info.flags;
            let not_measured = flags
                .intersects(vk::RenderingFlags::SUSPENDING | vk::RenderingFlags::RESUMING)
                .then(|| "suspended or resumed dynamic render pass".to_owned());
            let view_counts = if info.view_mask != 0 { vec![info.view_mask.count_ones()] } else { Vec::new() };
            let samples = attachments.iter().map(|a| a.samples).max().unwrap_or(1);
            let secondary_contents = flags.contains(vk::RenderingFlags::CONTENTS_SECONDARY_COMMAND_BUFFERS);
            let api = "vkCmdBeginRendering";
            let desc = PassDesc { api, area, samples, attachments, not_measured, secondary_contents, view_counts };
            let (before, after) = begin_pass(d, st, cmd, desc);
            (before, after, poison)
        },
    );
}

pub(super) unsafe extern "system" fn cmd_begin_rendering(cmd: vk::CommandBuffer, info: *const vk::RenderingInfo<'_>) {
    // SAFETY: the application's arguments.
    unsafe { begin_rendering_with(|d| d.next.cmd_begin_rendering, cmd, info) }
}

pub(super) unsafe extern "system" fn cmd_begin_rendering_khr(
    cmd: vk::CommandBuffer,
    info: *const vk::RenderingInfo<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { begin_rendering_with(|d| d.next.cmd_begin_rendering_khr, cmd, info) }
}

pub(super) unsafe extern "system" fn cmd_end_rendering(cmd: vk::CommandBuffer) {
    around_pass(
        cmd,
        false,
        |d| {
            if let Some(next) = d.next.cmd_end_rendering {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd) }
            }
        },
        |d, st| end_pass(d, st, cmd),
    );
}

pub(super) unsafe extern "system" fn cmd_end_rendering_khr(cmd: vk::CommandBuffer) {
    around_pass(
        cmd,
        false,
        |d| {
            if let Some(next) = d.next.cmd_end_rendering_khr {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd) }
            }
        },
        |d, st| end_pass(d, st, cmd),
    );
}

pub(super) unsafe extern "system" fn begin_command_buffer(
    cmd: vk::CommandBuffer,
    info: *const vk::CommandBufferBeginInfo<'_>,
) -> vk::Result {
    let Some((device, next)) = device_and(cmd.as_raw(), |d| d.next.begin_command_buffer) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    guard((), || {
        if !device.active() {
            return;
        }
        // SAFETY: the application's valid begin info.
        let simultaneous = unsafe { (*info).flags }.contains(vk::CommandBufferUsageFlags::SIMULTANEOUS_USE);
        let mut st = device.state();
        // Re-recording: the buffer's last submission is complete (valid usage), read it now.
        flush_buffer(&device, &mut st, cmd);
        if let Some(data) = st.buffers.get_mut(&cmd) {
            data.recording.restart(simultaneous);
            data.tiler.restart();
        }
        // SAFETY: the application's valid begin info.
        let info = unsafe { &*info };
        if info.flags.contains(vk::CommandBufferUsageFlags::RENDER_PASS_CONTINUE) && measuring(&mut st) {
            // SAFETY: as above: a secondary's begin info has its inheritance info.
            let desc = unsafe { continued_desc(&st, info) };
            if let Some(data) = st.buffers.get_mut(&cmd).filter(|d| d.recording.secondary) {
                data.recording.begin_continued_pass(desc, &mut |kind| create_pool(&device, kind));
            }
        }
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(cmd, info) }
}

/// What the layer knows of the pass a secondary command buffer continues (its inheritance
/// info): the views its subpass renders (its queries take one index each), since its figures
/// join the executor's pass.
///
/// # Safety
/// `info` is a valid begin info whose pInheritanceInfo, with its pNext chain, is valid.
unsafe fn continued_desc(st: &DeviceState, info: &vk::CommandBufferBeginInfo<'_>) -> PassDesc {
    let area = RenderArea { x: 0, y: 0, width: 0, height: 0 };
    let mut desc = PassDesc {
        api: "vkBeginCommandBuffer",
        area,
        samples: 1,
        attachments: Vec::new(),
        not_measured: None,
        secondary_contents: false,
        view_counts: Vec::new(),
    };
    // SAFETY: the caller's contract.
    let Some(inheritance) = (unsafe { info.p_inheritance_info.as_ref() }) else { return desc };
    let pass = st.render_passes.get(&inheritance.render_pass);
    let mut mask = pass.and_then(|i| i.view_masks.get(inheritance.subpass as usize)).copied().unwrap_or(0);
    let mut p_next = inheritance.p_next;
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure; this one is, by its sType,
        // VkCommandBufferInheritanceRenderingInfo.
        unsafe {
            if (*base).s_type == vk::StructureType::COMMAND_BUFFER_INHERITANCE_RENDERING_INFO {
                mask |= (*(p_next as *const vk::CommandBufferInheritanceRenderingInfo<'_>)).view_mask;
            }
            p_next = (*base).p_next.cast();
        }
    }
    if mask != 0 {
        desc.view_counts = vec![mask.count_ones()];
    }
    desc
}

pub(super) unsafe extern "system" fn reset_command_buffer(
    cmd: vk::CommandBuffer,
    flags: vk::CommandBufferResetFlags,
) -> vk::Result {
    let Some((device, next)) = device_and(cmd.as_raw(), |d| d.next.reset_command_buffer) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    guard((), || {
        if !device.active() {
            return;
        }
        let mut st = device.state();
        flush_buffer(&device, &mut st, cmd);
        if let Some(data) = st.buffers.get_mut(&cmd) {
            data.recording.restart(false);
            data.tiler.restart();
        }
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(cmd, flags) }
}
