//! The tiler check's hooks for what happens to images outside render passes: framebuffers,
//! descriptor set updates and binds, pipelines (whether their draws blend or depth-test),
//! dispatches and the transfer commands that read or overwrite images. Each notes [`Event`]s in
//! the command buffer's list (tiler_state.rs) and passes the call on; they are handed out only
//! when the check is on.

use std::sync::Arc;

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::state::{guard, DeviceData, DeviceState};
use super::tiler_check::Event;
use super::tiler_state::{PipelineReads, TilerState};

/// Runs `f` on the device's check state and `cmd`'s when the check is on; returns the device
/// to make the application's call with.
fn noting(cmd: vk::CommandBuffer, f: impl FnOnce(&mut DeviceState)) -> Option<Arc<DeviceData>> {
    let device = guard(None, || super::state::device_of(cmd.as_raw()))?;
    guard((), || {
        if device.active() && device.config.tiler {
            f(&mut device.state());
        }
    });
    Some(device)
}

/// Notes the events `f` makes from the device's check state in `cmd`'s list.
fn note_events(cmd: vk::CommandBuffer, f: impl FnOnce(&TilerState) -> Vec<Event>) -> Option<Arc<DeviceData>> {
    noting(cmd, |st| {
        let events = f(&st.tiler);
        if let Some(data) = st.buffers.get_mut(&cmd) {
            data.tiler.events.extend(events);
        }
    })
}

/// The device of `handle` when the check is on, and the next function `pick` chooses.
fn device_checking<F>(handle: u64, pick: impl FnOnce(&DeviceData) -> Option<F>) -> Option<(Arc<DeviceData>, F)> {
    super::objects::device_and(handle, pick)
}

pub(super) unsafe extern "system" fn create_framebuffer(
    device: vk::Device,
    info: *const vk::FramebufferCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    framebuffer: *mut vk::Framebuffer,
) -> vk::Result {
    let Some((dev, next)) = device_checking(device.as_raw(), |d| d.next.create_framebuffer) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, framebuffer) };
    if result == vk::Result::SUCCESS && dev.config.tiler {
        guard((), || {
            // SAFETY: a valid create info (the call succeeded with it) and the new handle.
            let (info, handle) = unsafe { (&*info, *framebuffer) };
            let views = if info.flags.contains(vk::FramebufferCreateFlags::IMAGELESS) {
                Vec::new()
            } else {
                // SAFETY: pAttachments holds attachmentCount views (valid usage).
                unsafe { app_array(info.p_attachments, info.attachment_count) }.to_vec()
            };
            dev.state().tiler.framebuffers.insert(handle, views);
        });
    }
    result
}

pub(super) unsafe extern "system" fn destroy_framebuffer(
    device: vk::Device,
    framebuffer: vk::Framebuffer,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((dev, next)) = device_checking(device.as_raw(), |d| d.next.destroy_framebuffer) else { return };
    guard((), || {
        dev.state().tiler.framebuffers.remove(&framebuffer);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, framebuffer, allocator) }
}

/// The descriptor types whose images a draw or dispatch reads from memory (an input
/// attachment is read in its pass, from tile memory).
fn reads_image(ty: vk::DescriptorType) -> bool {
    super::descriptor_templates::reads_image(ty)
}

/// The images `write` puts in its set, by (binding, array element).
///
/// # Safety
/// `write` is a valid VkWriteDescriptorSet.
unsafe fn written_images(tiler: &TilerState, write: &vk::WriteDescriptorSet) -> Vec<((u32, u32), Option<vk::Image>)> {
    if !reads_image(write.descriptor_type) {
        return Vec::new();
    }
    // SAFETY: pImageInfo holds descriptorCount entries for these types (valid usage).
    let infos = unsafe { app_array(write.p_image_info, write.descriptor_count) };
    infos
        .iter()
        .enumerate()
        .map(|(i, info)| {
            let image = tiler.views.get(&info.image_view).map(|v| v.image);
            ((write.dst_binding, write.dst_array_element + i as u32), image)
        })
        .collect()
}

pub(super) unsafe extern "system" fn update_descriptor_sets(
    device: vk::Device,
    write_count: u32,
    writes: *const vk::WriteDescriptorSet<'_>,
    copy_count: u32,
    copies: *const vk::CopyDescriptorSet<'_>,
) {
    let Some((dev, next)) = device_checking(device.as_raw(), |d| d.next.update_descriptor_sets) else { return };
    if dev.config.tiler {
        guard((), || {
            let mut st = dev.state();
            let tiler = &mut st.tiler;
            // SAFETY: the arrays hold their counts (valid usage).
            for write in unsafe { app_array(writes, write_count) } {
                // SAFETY: a valid write.
                let images = unsafe { written_images(tiler, write) };
                let set = tiler.sets.entry(write.dst_set).or_default();
                for (slot, image) in images {
                    match image {
                        Some(image) => set.insert(slot, image),
                        None => set.remove(&slot),
                    };
                }
            }
            // SAFETY: as above.
            for copy in unsafe { app_array(copies, copy_count) } {
                let from = tiler.sets.get(&copy.src_set).cloned().unwrap_or_default();
                let to = tiler.sets.entry(copy.dst_set).or_default();
                for i in 0..copy.descriptor_count {
                    let source = from.get(&(copy.src_binding, copy.src_array_element + i)).copied();
                    let slot = (copy.dst_binding, copy.dst_array_element + i);
                    match source {
                        Some(image) => to.insert(slot, image),
                        None => to.remove(&slot),
                    };
                }
            }
        });
    }
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, write_count, writes, copy_count, copies) }
}

/// What a pipeline's draws read of the attachments, from its create info.
///
/// # Safety
/// `info` is a valid VkGraphicsPipelineCreateInfo.
unsafe fn pipeline_reads(info: &vk::GraphicsPipelineCreateInfo) -> PipelineReads {
    // SAFETY: each state pointer is null or valid, its arrays as long as their counts.
    unsafe {
        let dynamic: Vec<vk::DynamicState> = info
            .p_dynamic_state
            .as_ref()
            .map(|d| app_array(d.p_dynamic_states, d.dynamic_state_count).to_vec())
            .unwrap_or_default();
        let blends = match info.p_color_blend_state.as_ref() {
            Some(b) => {
                let logic = b.logic_op_enable != 0;
                app_array(b.p_attachments, b.attachment_count).iter().map(|a| logic || a.blend_enable != 0).collect()
            }
            None => Vec::new(),
        };
        // A depth test set dynamically is not known here: not counted.
        let dynamic_depth = dynamic
            .iter()
            .any(|&d| d == vk::DynamicState::DEPTH_TEST_ENABLE || d == vk::DynamicState::DEPTH_COMPARE_OP);
        let depth_test = !dynamic_depth
            && info
                .p_depth_stencil_state
                .as_ref()
                .is_some_and(|d| d.depth_test_enable != 0 && d.depth_compare_op != vk::CompareOp::ALWAYS);
        PipelineReads { blends, depth_test }
    }
}

pub(super) unsafe extern "system" fn create_graphics_pipelines(
    device: vk::Device,
    cache: vk::PipelineCache,
    count: u32,
    infos: *const vk::GraphicsPipelineCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    pipelines: *mut vk::Pipeline,
) -> vk::Result {
    let Some((dev, next)) = device_checking(device.as_raw(), |d| d.next.create_graphics_pipelines) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, cache, count, infos, allocator, pipelines) };
    if result == vk::Result::SUCCESS && dev.config.tiler {
        guard((), || {
            // SAFETY: `count` valid create infos and as many new handles.
            let (infos, handles) = unsafe { (app_array(infos, count), app_array(pipelines, count)) };
            let mut st = dev.state();
            for (info, &handle) in infos.iter().zip(handles) {
                // SAFETY: a valid create info.
                let reads = unsafe { pipeline_reads(info) };
                st.tiler.pipelines.insert(handle, reads);
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn cmd_bind_pipeline(
    cmd: vk::CommandBuffer,
    point: vk::PipelineBindPoint,
    pipeline: vk::Pipeline,
) {
    let Some(device) = noting(cmd, |st| {
        if let Some(data) = st.buffers.get_mut(&cmd).filter(|_| point == vk::PipelineBindPoint::GRAPHICS) {
            data.tiler.pipeline = Some(pipeline);
        }
    }) else {
        return;
    };
    if let Some(next) = device.next.cmd_bind_pipeline {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, point, pipeline) }
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_bind_descriptor_sets(
    cmd: vk::CommandBuffer,
    point: vk::PipelineBindPoint,
    layout: vk::PipelineLayout,
    first: u32,
    count: u32,
    sets: *const vk::DescriptorSet,
    dynamic_count: u32,
    dynamic_offsets: *const u32,
) {
    let Some(device) = noting(cmd, |st| {
        let Some(data) = st.buffers.get_mut(&cmd) else { return };
        // SAFETY: pDescriptorSets holds descriptorSetCount sets (valid usage).
        for (i, &set) in unsafe { app_array(sets, count) }.iter().enumerate() {
            data.tiler.bound.insert((point.as_raw(), first + i as u32), set);
        }
        data.tiler.dirty.insert(point.as_raw());
    }) else {
        return;
    };
    if let Some(next) = device.next.cmd_bind_descriptor_sets {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, point, layout, first, count, sets, dynamic_count, dynamic_offsets) }
    }
}

pub(super) unsafe extern "system" fn cmd_push_descriptor_set(
    cmd: vk::CommandBuffer,
    point: vk::PipelineBindPoint,
    layout: vk::PipelineLayout,
    set: u32,
    count: u32,
    writes: *const vk::WriteDescriptorSet<'_>,
) {
    // Pushed images are counted as read at the push, the draw that reads them being near.
    let Some(device) = note_events(cmd, |tiler| {
        // SAFETY: pDescriptorWrites holds descriptorWriteCount valid writes (valid usage).
        let writes = unsafe { app_array(writes, count) };
        // SAFETY: each a valid write.
        let images = writes.iter().flat_map(|w| unsafe { written_images(tiler, w) }).filter_map(|(_, i)| i);
        images.map(|i| tiler.read(i, "a pushed descriptor")).collect()
    }) else {
        return;
    };
    if let Some(next) = device.next.cmd_push_descriptor_set {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, point, layout, set, count, writes) }
    }
}

/// vkUpdateDescriptorSetWithTemplate and its KHR alias: the images the template's entries name
/// in the program's data go into the set, as a vkUpdateDescriptorSets write's would
/// (descriptor_templates.rs). A template the layer did not see created stops the flags that
/// need every read.
unsafe fn update_with_template(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkUpdateDescriptorSetWithTemplate>,
    device: vk::Device,
    set: vk::DescriptorSet,
    template: vk::DescriptorUpdateTemplate,
    data: *const std::ffi::c_void,
) {
    let Some((dev, next)) = device_checking(device.as_raw(), pick) else { return };
    if dev.config.tiler {
        guard((), || {
            let mut st = dev.state();
            let tiler = &mut st.tiler;
            // SAFETY: the program's data for this template (valid usage).
            match unsafe { tiler.templates.written_views(template, data) } {
                Some(views) => {
                    let images: Vec<_> =
                        views.into_iter().map(|(slot, view)| (slot, tiler.views.get(&view).map(|v| v.image))).collect();
                    let written = tiler.sets.entry(set).or_default();
                    for (slot, image) in images {
                        match image {
                            Some(image) => written.insert(slot, image),
                            None => written.remove(&slot),
                        };
                    }
                }
                None => tiler
                    .check
                    .reads_unknown("descriptor sets updated with templates created before the layer saw them"),
            }
        });
    }
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, set, template, data) }
}

unsafe fn create_template_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkCreateDescriptorUpdateTemplate>,
    device: vk::Device,
    info: *const vk::DescriptorUpdateTemplateCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    template: *mut vk::DescriptorUpdateTemplate,
) -> vk::Result {
    let Some((dev, next)) = device_checking(device.as_raw(), pick) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, info, allocator, template) };
    if result == vk::Result::SUCCESS && dev.config.tiler {
        // SAFETY: a valid create info; the new handle written.
        guard((), || unsafe { dev.state().tiler.templates.created(*template, &*info) });
    }
    result
}

pub(super) unsafe extern "system" fn create_descriptor_update_template(
    device: vk::Device,
    info: *const vk::DescriptorUpdateTemplateCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    template: *mut vk::DescriptorUpdateTemplate,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { create_template_with(|d| d.next.create_descriptor_update_template, device, info, allocator, template) }
}

pub(super) unsafe extern "system" fn create_descriptor_update_template_khr(
    device: vk::Device,
    info: *const vk::DescriptorUpdateTemplateCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    template: *mut vk::DescriptorUpdateTemplate,
) -> vk::Result {
    // SAFETY: the application's arguments.
    unsafe { create_template_with(|d| d.next.create_descriptor_update_template_khr, device, info, allocator, template) }
}

unsafe fn destroy_template_with(
    pick: fn(&DeviceData) -> Option<vk::PFN_vkDestroyDescriptorUpdateTemplate>,
    device: vk::Device,
    template: vk::DescriptorUpdateTemplate,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((dev, next)) = device_checking(device.as_raw(), pick) else { return };
    if dev.config.tiler {
        guard((), || dev.state().tiler.templates.destroyed(template));
    }
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, template, allocator) }
}

pub(super) unsafe extern "system" fn destroy_descriptor_update_template(
    device: vk::Device,
    template: vk::DescriptorUpdateTemplate,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { destroy_template_with(|d| d.next.destroy_descriptor_update_template, device, template, allocator) }
}

pub(super) unsafe extern "system" fn destroy_descriptor_update_template_khr(
    device: vk::Device,
    template: vk::DescriptorUpdateTemplate,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { destroy_template_with(|d| d.next.destroy_descriptor_update_template_khr, device, template, allocator) }
}

/// vkCmdPushDescriptorSetWithTemplateKHR: the images pushed are read, as with a plain push.
pub(super) unsafe extern "system" fn cmd_push_descriptor_set_with_template(
    cmd: vk::CommandBuffer,
    template: vk::DescriptorUpdateTemplate,
    layout: vk::PipelineLayout,
    set: u32,
    data: *const std::ffi::c_void,
) {
    let Some(device) = noting(cmd, |st| {
        // SAFETY: the program's data for this template (valid usage).
        let events = match unsafe { st.tiler.templates.written_views(template, data) } {
            Some(views) => views
                .into_iter()
                .filter_map(|(_, view)| st.tiler.views.get(&view).map(|v| v.image))
                .map(|image| st.tiler.read(image, "a pushed descriptor"))
                .collect(),
            None => {
                st.tiler.check.reads_unknown("descriptors pushed with templates created before the layer saw them");
                Vec::new()
            }
        };
        if let Some(data) = st.buffers.get_mut(&cmd) {
            data.tiler.events.extend(events);
        }
    }) else {
        return;
    };
    if let Some(next) = device.next.cmd_push_descriptor_set_with_template {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, template, layout, set, data) }
    }
}

pub(super) unsafe extern "system" fn update_descriptor_set_with_template(
    device: vk::Device,
    set: vk::DescriptorSet,
    template: vk::DescriptorUpdateTemplate,
    data: *const std::ffi::c_void,
) {
    // SAFETY: the application's arguments.
    unsafe { update_with_template(|d| d.next.update_descriptor_set_with_template, device, set, template, data) }
}

pub(super) unsafe extern "system" fn update_descriptor_set_with_template_khr(
    device: vk::Device,
    set: vk::DescriptorSet,
    template: vk::DescriptorUpdateTemplate,
    data: *const std::ffi::c_void,
) {
    // SAFETY: the application's arguments.
    unsafe { update_with_template(|d| d.next.update_descriptor_set_with_template_khr, device, set, template, data) }
}

/// A dispatch reads the images of the compute sets bound.
fn dispatch(cmd: vk::CommandBuffer) -> Option<Arc<DeviceData>> {
    noting(cmd, |st| {
        let DeviceState { tiler, buffers, .. } = st;
        if let Some(data) = buffers.get_mut(&cmd) {
            data.tiler.draw(tiler, vk::PipelineBindPoint::COMPUTE);
        }
    })
}

pub(super) unsafe extern "system" fn cmd_dispatch(cmd: vk::CommandBuffer, x: u32, y: u32, z: u32) {
    if let Some(next) = dispatch(cmd).and_then(|d| d.next.cmd_dispatch) {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, x, y, z) }
    }
}

pub(super) unsafe extern "system" fn cmd_dispatch_indirect(cmd: vk::CommandBuffer, buffer: vk::Buffer, offset: u64) {
    if let Some(next) = dispatch(cmd).and_then(|d| d.next.cmd_dispatch_indirect) {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, buffer, offset) }
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_copy_image(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    src_layout: vk::ImageLayout,
    dst: vk::Image,
    dst_layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::ImageCopy,
) {
    let how = "vkCmdCopyImage";
    let Some(d) = note_events(cmd, |t| vec![t.read(src, how), t.overwrite(dst, how, false)]) else { return };
    if let Some(next) = d.next.cmd_copy_image {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, src, src_layout, dst, dst_layout, count, regions) }
    }
}

pub(super) unsafe extern "system" fn cmd_copy_image_to_buffer(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    layout: vk::ImageLayout,
    buffer: vk::Buffer,
    count: u32,
    regions: *const vk::BufferImageCopy,
) {
    let Some(d) = note_events(cmd, |t| vec![t.read(src, "vkCmdCopyImageToBuffer")]) else { return };
    if let Some(next) = d.next.cmd_copy_image_to_buffer {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, src, layout, buffer, count, regions) }
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_blit_image(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    src_layout: vk::ImageLayout,
    dst: vk::Image,
    dst_layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::ImageBlit,
    filter: vk::Filter,
) {
    let how = "vkCmdBlitImage";
    let Some(d) = note_events(cmd, |t| vec![t.read(src, how), t.overwrite(dst, how, false)]) else { return };
    if let Some(next) = d.next.cmd_blit_image {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, src, src_layout, dst, dst_layout, count, regions, filter) }
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) unsafe extern "system" fn cmd_resolve_image(
    cmd: vk::CommandBuffer,
    src: vk::Image,
    src_layout: vk::ImageLayout,
    dst: vk::Image,
    dst_layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::ImageResolve,
) {
    let Some(d) = note_events(cmd, |t| vec![t.resolve(src, dst)]) else { return };
    if let Some(next) = d.next.cmd_resolve_image {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, src, src_layout, dst, dst_layout, count, regions) }
    }
}

pub(super) unsafe extern "system" fn cmd_clear_color_image(
    cmd: vk::CommandBuffer,
    image: vk::Image,
    layout: vk::ImageLayout,
    colour: *const vk::ClearColorValue,
    count: u32,
    ranges: *const vk::ImageSubresourceRange,
) {
    let how = "vkCmdClearColorImage";
    // SAFETY: the application's array of `count` ranges.
    let cleared = unsafe { super::arrays::app_array(ranges, count) };
    let Some(d) = note_events(cmd, |t| vec![t.overwrite(image, how, true), t.cleared(image, how, cleared)]) else {
        return;
    };
    if let Some(next) = d.next.cmd_clear_color_image {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, image, layout, colour, count, ranges) }
    }
}

pub(super) unsafe extern "system" fn cmd_clear_depth_stencil_image(
    cmd: vk::CommandBuffer,
    image: vk::Image,
    layout: vk::ImageLayout,
    value: *const vk::ClearDepthStencilValue,
    count: u32,
    ranges: *const vk::ImageSubresourceRange,
) {
    let how = "vkCmdClearDepthStencilImage";
    // SAFETY: the application's array of `count` ranges.
    let cleared = unsafe { super::arrays::app_array(ranges, count) };
    let Some(d) = note_events(cmd, |t| vec![t.overwrite(image, how, true), t.cleared(image, how, cleared)]) else {
        return;
    };
    if let Some(next) = d.next.cmd_clear_depth_stencil_image {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, image, layout, value, count, ranges) }
    }
}

pub(super) unsafe extern "system" fn cmd_copy_buffer_to_image(
    cmd: vk::CommandBuffer,
    buffer: vk::Buffer,
    dst: vk::Image,
    layout: vk::ImageLayout,
    count: u32,
    regions: *const vk::BufferImageCopy,
) {
    let Some(d) = note_events(cmd, |t| vec![t.overwrite(dst, "vkCmdCopyBufferToImage", false)]) else { return };
    if let Some(next) = d.next.cmd_copy_buffer_to_image {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, buffer, dst, layout, count, regions) }
    }
}

/// The hooks of a `*2` transfer command (one info struct naming the images) under each of its
/// names, core and KHR alias, which note the same image uses.
macro_rules! transfer2_hook {
    ([$($name:ident),+], $info:ty, |$t:ident, $i:ident| $events:expr) => {$(
        pub(super) unsafe extern "system" fn $name(cmd: vk::CommandBuffer, info: *const $info) {
            let Some(d) = note_events(cmd, |$t| {
                // SAFETY: the application's valid info.
                let $i = unsafe { &*info };
                $events
            }) else {
                return;
            };
            if let Some(next) = d.next.$name {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, info) }
            }
        }
    )+};
}

transfer2_hook!([cmd_copy_image2, cmd_copy_image2_khr], vk::CopyImageInfo2<'_>, |t, i| vec![
    t.read(i.src_image, "vkCmdCopyImage2"),
    t.overwrite(i.dst_image, "vkCmdCopyImage2", false)
]);
transfer2_hook!(
    [cmd_copy_image_to_buffer2, cmd_copy_image_to_buffer2_khr],
    vk::CopyImageToBufferInfo2<'_>,
    |t, i| vec![t.read(i.src_image, "vkCmdCopyImageToBuffer2")]
);
transfer2_hook!([cmd_blit_image2, cmd_blit_image2_khr], vk::BlitImageInfo2<'_>, |t, i| vec![
    t.read(i.src_image, "vkCmdBlitImage2"),
    t.overwrite(i.dst_image, "vkCmdBlitImage2", false)
]);
transfer2_hook!([cmd_resolve_image2, cmd_resolve_image2_khr], vk::ResolveImageInfo2<'_>, |t, i| vec![
    t.resolve(i.src_image, i.dst_image)
]);
transfer2_hook!(
    [cmd_copy_buffer_to_image2, cmd_copy_buffer_to_image2_khr],
    vk::CopyBufferToImageInfo2<'_>,
    |t, i| vec![t.overwrite(i.dst_image, "vkCmdCopyBufferToImage2", false)]
);
