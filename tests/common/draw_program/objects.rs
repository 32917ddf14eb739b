//! The objects the draw program is made of: its targets, buffers, render passes, pipelines and
//! command buffers (draw_program.rs).

use ash::vk;

use super::super::raw_vulkan;
use super::{Target, FORMAT, SIZE};

pub(super) fn colour_range(layers: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: layers,
    }
}

/// A SIZE-square RGBA8 target of `layers` layers and its view (2D, or 2D array when layered).
pub(super) unsafe fn target(
    objects: (&ash::Instance, vk::PhysicalDevice, &ash::Device),
    layers: u32,
    usage: vk::ImageUsageFlags,
) -> Target {
    let one_sample = vk::SampleCountFlags::TYPE_1;
    let (image, memory, view) =
        raw_vulkan::layered_target(objects, (FORMAT, SIZE, layers), one_sample, usage, colour_range(layers));
    Target { image, memory, view }
}

/// A buffer of `size` bytes with `usage`, host-visible or device-local.
pub(super) unsafe fn buffer(
    (instance, physical, device): (&ash::Instance, vk::PhysicalDevice, &ash::Device),
    size: u64,
    usage: vk::BufferUsageFlags,
    host: bool,
) -> (vk::Buffer, vk::DeviceMemory) {
    let buffer = device.create_buffer(&vk::BufferCreateInfo::default().size(size).usage(usage), None).expect("buffer");
    let requirements = device.get_buffer_memory_requirements(buffer);
    let props = instance.get_physical_device_memory_properties(physical);
    let wanted = if host {
        vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT
    } else {
        vk::MemoryPropertyFlags::DEVICE_LOCAL
    };
    let memory_type = raw_vulkan::memory_type(&props, requirements.memory_type_bits, wanted).expect("a memory type");
    let allocate = vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(memory_type);
    let memory = device.allocate_memory(&allocate, None).expect("memory");
    device.bind_buffer_memory(buffer, memory, 0).expect("bind");
    (buffer, memory)
}

/// A one-subpass render pass on the RGBA8 target, loading with `load` from `initial`, storing,
/// left ready to draw into again; `view_mask` non-zero: multiview.
pub(super) unsafe fn render_pass(
    device: &ash::Device,
    load: vk::AttachmentLoadOp,
    initial: vk::ImageLayout,
    view_mask: u32,
) -> vk::RenderPass {
    let attachments = [vk::AttachmentDescription::default()
        .format(FORMAT)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(load)
        .store_op(vk::AttachmentStoreOp::STORE)
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(initial)
        .final_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let colour = [vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
    let subpasses = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&colour)];
    // The earlier pass's (or submission's copy's) use of the target comes first.
    let dependencies = [vk::SubpassDependency {
        src_subpass: vk::SUBPASS_EXTERNAL,
        dst_subpass: 0,
        src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags::TRANSFER,
        dst_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
        src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::TRANSFER_READ,
        dst_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::COLOR_ATTACHMENT_READ,
        dependency_flags: vk::DependencyFlags::empty(),
    }];
    let masks = [view_mask];
    let mut multiview = vk::RenderPassMultiviewCreateInfo::default().view_masks(&masks);
    let mut info =
        vk::RenderPassCreateInfo::default().attachments(&attachments).subpasses(&subpasses).dependencies(&dependencies);
    if view_mask != 0 {
        info = info.push_next(&mut multiview);
    }
    device.create_render_pass(&info, None).expect("render pass")
}

/// `rect.vert` + `solid.frag` for `pass` (null: dynamic rendering of one RGBA8 attachment).
pub(super) unsafe fn pipeline(device: &ash::Device, layout: vk::PipelineLayout, pass: vk::RenderPass) -> vk::Pipeline {
    let blends = [vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA)];
    let target = raw_vulkan::Target { render_pass: pass, size: SIZE, depth: None, colour_formats: &[FORMAT] };
    raw_vulkan::pipeline(device, layout, (raw_vulkan::RECT_VERT, raw_vulkan::SOLID_FRAG), target, &blends)
}

pub(super) unsafe fn allocate(
    device: &ash::Device,
    pool: vk::CommandPool,
    level: vk::CommandBufferLevel,
) -> vk::CommandBuffer {
    let info = vk::CommandBufferAllocateInfo::default().command_pool(pool).level(level).command_buffer_count(1);
    device.allocate_command_buffers(&info).expect("command buffer")[0]
}
