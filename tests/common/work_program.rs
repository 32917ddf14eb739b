//! A headless Vulkan program of the tests' own that does only work outside render passes, for
//! the fill-rate layer's compute and transfer rows: each submission (one command buffer, a
//! fence, a host wait) fills two storage buffers, runs `add_to_words.comp` as three dispatch
//! groups, copies the buffers out, clears an image, blits it into a larger one, copies that out,
//! updates a small buffer and runs a secondary command buffer that fills one more. It checks what it computed on the host, every submission, and
//! returns the expected rows (invocations, workgroups and bytes exact) for the layer's report.

use std::ffi::CStr;

use ash::vk;

/// Invocations per workgroup of `add_to_words.comp` (8 x 4 x 1).
pub const LOCAL: u64 = 32;
/// The small image cleared, and the larger one it is blitted into (RGBA8).
pub const SMALL: u32 = 16;
pub const LARGE: u32 = 32;
/// Bytes vkCmdUpdateBuffer writes.
pub const UPDATE: u64 = 16;
/// Bytes the secondary command buffer fills.
pub const SPARE: u64 = 16;

/// How the program runs.
#[derive(Debug, Clone, Copy)]
pub struct WorkOptions {
    /// Workgroups along x of the big dispatches (at least 2): the grid is 8 x `groups` words wide.
    pub groups: u32,
    pub submissions: u32,
    /// Chain a VkFrameBoundaryEXT (FRAME_END) to every `n`th submission (VK_EXT_frame_boundary
    /// enabled on the device), 0 for none.
    pub boundary_every: u32,
}

/// One row the layer should report: kind, command, label, commands, workgroups, invocations,
/// bytes read, bytes written.
pub type ExpectedRow = (&'static str, &'static str, Option<&'static str>, u64, Option<u64>, Option<u64>, u64, u64);

/// The rows of one submission, in recording order.
pub fn expected_rows(options: WorkOptions) -> Vec<ExpectedRow> {
    let g = options.groups as u64;
    let words = words(options) as u64 * 4;
    let small = (SMALL * SMALL * 4) as u64;
    let large = (LARGE * LARGE * 4) as u64;
    vec![
        ("transfer", "vkCmdFillBuffer", None, 1, None, None, 0, words),
        ("transfer", "vkCmdFillBuffer", None, 1, None, None, 0, words),
        ("compute", "vkCmdDispatch", Some("add"), 2, Some(4 * g), Some(4 * g * LOCAL), 0, 0),
        // Read back by the layer from the program's argument buffer.
        ("compute", "vkCmdDispatchIndirect", None, 1, Some(g), Some(g * LOCAL), 0, 0),
        ("compute", "vkCmdDispatchBase", None, 1, Some(1), Some(LOCAL), 0, 0),
        ("transfer", "vkCmdCopyBuffer", None, 1, None, None, words, words),
        ("transfer", "vkCmdCopyBuffer", None, 1, None, None, words, words),
        ("transfer", "vkCmdClearColorImage", None, 1, None, None, 0, small),
        ("transfer", "vkCmdBlitImage", None, 1, None, None, small, large),
        ("transfer", "vkCmdCopyImageToBuffer", None, 1, None, None, large, large),
        ("transfer", "vkCmdUpdateBuffer", None, 1, None, None, 0, UPDATE),
        // The fill in the secondary command buffer, where the primary executes it.
        ("transfer", "vkCmdFillBuffer", None, 1, None, None, 0, SPARE),
    ]
}

fn width(options: WorkOptions) -> u32 {
    8 * options.groups
}

/// Words of each storage buffer: the grid is `width` wide and 8 high.
fn words(options: WorkOptions) -> u32 {
    width(options) * 8
}

/// What buffer X and Y must hold after a submission (see `record`).
fn expected_words(options: WorkOptions) -> (Vec<u32>, Vec<u32>) {
    let w = width(options);
    let x = (0..words(options))
        .map(|i| {
            let (col, row) = (i % w, i / w);
            1 + if (8..16).contains(&col) && (4..8).contains(&row) { 4 } else { 0 }
        })
        .collect();
    let y = (0..words(options)).map(|i| 2 + if i / w < 4 { 8 } else { 0 }).collect();
    (x, y)
}

struct Objects {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    sets: [vk::DescriptorSet; 2],
    storage: [vk::Buffer; 2],
    indirect: vk::Buffer,
    host: vk::Buffer,
    host_mapped: *const u8,
    small_buffer: vk::Buffer,
    images: [vk::Image; 2],
    /// A secondary command buffer that fills `spare` (a row where the primary executes it).
    secondary: vk::CommandBuffer,
    spare: vk::Buffer,
}

/// A buffer of `size` bytes with `usage` in memory with `flags`, bound; the memory is returned
/// to be freed.
unsafe fn buffer(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    device: &ash::Device,
    size: u64,
    usage: vk::BufferUsageFlags,
    flags: vk::MemoryPropertyFlags,
) -> (vk::Buffer, vk::DeviceMemory) {
    let buffer = device.create_buffer(&vk::BufferCreateInfo::default().size(size).usage(usage), None).expect("buffer");
    let requirements = device.get_buffer_memory_requirements(buffer);
    let memory = allocate(instance, physical, device, requirements, flags);
    device.bind_buffer_memory(buffer, memory, 0).expect("bind");
    (buffer, memory)
}

unsafe fn allocate(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    device: &ash::Device,
    requirements: vk::MemoryRequirements,
    flags: vk::MemoryPropertyFlags,
) -> vk::DeviceMemory {
    let props = instance.get_physical_device_memory_properties(physical);
    let index = (0..props.memory_type_count)
        .find(|&i| {
            requirements.memory_type_bits & (1 << i) != 0
                && props.memory_types[i as usize].property_flags.contains(flags)
        })
        .expect("memory type");
    let info = vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(index);
    device.allocate_memory(&info, None).expect("memory")
}

fn colour_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

fn colour_layers() -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    }
}

/// A global memory barrier from `src` to `dst` (sync2).
unsafe fn barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
    images: &[vk::ImageMemoryBarrier2<'_>],
) {
    let memory = [vk::MemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)];
    device.cmd_pipeline_barrier2(
        cmd,
        &vk::DependencyInfo::default().memory_barriers(&memory).image_memory_barriers(images),
    );
}

fn image_barrier(
    image: vk::Image,
    (old, new): (vk::ImageLayout, vk::ImageLayout),
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .image(image)
        .old_layout(old)
        .new_layout(new)
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)
        .subresource_range(colour_range())
}

/// Records one submission's work (the rows of [`expected_rows`], in order).
unsafe fn record(
    (device, debug): (&ash::Device, &ash::ext::debug_utils::Device),
    cmd: vk::CommandBuffer,
    o: &Objects,
    options: WorkOptions,
) {
    let bytes = words(options) as u64 * 4;
    let transfer =
        (vk::PipelineStageFlags2::ALL_TRANSFER, vk::AccessFlags2::TRANSFER_WRITE | vk::AccessFlags2::TRANSFER_READ);
    let compute = (
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
    );
    let indirect = (vk::PipelineStageFlags2::DRAW_INDIRECT, vk::AccessFlags2::INDIRECT_COMMAND_READ);
    device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default()).expect("begin");
    // What the previous submission did is complete (its fence was waited for); the barrier
    // still orders this one's transfers after it for the synchronisation checks.
    // Graphics dynamic state set and no graphics pipeline ever bound: lavapipe flushes graphics
    // state at vkCmdBeginQuery (recording.rs), which the layer's query before the first dispatch
    // must survive.
    let viewport = vk::Viewport { x: 0.0, y: 0.0, width: 8.0, height: 8.0, min_depth: 0.0, max_depth: 1.0 };
    device.cmd_set_viewport(cmd, 0, &[viewport]);
    device.cmd_set_scissor(
        cmd,
        0,
        &[vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: 8, height: 8 } }],
    );
    device.cmd_set_blend_constants(cmd, &[0.0; 4]);
    device.cmd_set_stencil_reference(cmd, vk::StencilFaceFlags::FRONT_AND_BACK, 1);
    barrier(device, cmd, transfer, transfer, &[]);
    device.cmd_fill_buffer(cmd, o.storage[0], 0, vk::WHOLE_SIZE, 0);
    device.cmd_fill_buffer(cmd, o.storage[1], 0, bytes, 0);
    barrier(device, cmd, transfer, compute, &[]);
    device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, o.pipeline);
    let push = |value: u32| {
        let words = [width(options), value];
        device.cmd_push_constants(cmd, o.layout, vk::ShaderStageFlags::COMPUTE, 0, bytemuck::cast_slice(&words));
    };
    let bind = |set: usize| {
        device.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, o.layout, 0, &[o.sets[set]], &[]);
    };
    // One group of two dispatches into different buffers (no hazard between them), labelled.
    let label = vk::DebugUtilsLabelEXT::default().label_name(c"add");
    debug.cmd_begin_debug_utils_label(cmd, &label);
    bind(0);
    push(1);
    device.cmd_dispatch(cmd, options.groups, 2, 1);
    bind(1);
    push(2);
    device.cmd_dispatch(cmd, options.groups, 2, 1);
    debug.cmd_end_debug_utils_label(cmd);
    barrier(device, cmd, compute, (compute.0 | indirect.0, compute.1 | indirect.1), &[]);
    bind(1);
    push(8);
    device.cmd_dispatch_indirect(cmd, o.indirect, 0);
    // The base dispatch last: lavapipe (Mesa 22.3) keeps a dispatch base for a later indirect
    // dispatch in the same command buffer.
    barrier(device, cmd, compute, compute, &[]);
    bind(0);
    push(4);
    device.cmd_dispatch_base(cmd, 1, 1, 0, 1, 1, 1);
    let to_dst = (vk::ImageLayout::UNDEFINED, vk::ImageLayout::TRANSFER_DST_OPTIMAL);
    let images = [
        image_barrier(o.images[0], to_dst, transfer, transfer),
        image_barrier(o.images[1], to_dst, transfer, transfer),
    ];
    barrier(device, cmd, compute, transfer, &images);
    device.cmd_copy_buffer(cmd, o.storage[0], o.host, &[vk::BufferCopy { src_offset: 0, dst_offset: 0, size: bytes }]);
    device.cmd_copy_buffer(
        cmd,
        o.storage[1],
        o.host,
        &[vk::BufferCopy { src_offset: 0, dst_offset: bytes, size: bytes }],
    );
    // Exact in 8 bits: 51, 102, 153, 255.
    let colour = vk::ClearColorValue { float32: [0.2, 0.4, 0.6, 1.0] };
    device.cmd_clear_color_image(cmd, o.images[0], vk::ImageLayout::TRANSFER_DST_OPTIMAL, &colour, &[colour_range()]);
    let to_src = (vk::ImageLayout::TRANSFER_DST_OPTIMAL, vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
    barrier(device, cmd, transfer, transfer, &[image_barrier(o.images[0], to_src, transfer, transfer)]);
    let corner = |size: u32| [vk::Offset3D::default(), vk::Offset3D { x: size as i32, y: size as i32, z: 1 }];
    let blit = vk::ImageBlit {
        src_subresource: colour_layers(),
        src_offsets: corner(SMALL),
        dst_subresource: colour_layers(),
        dst_offsets: corner(LARGE),
    };
    device.cmd_blit_image(
        cmd,
        o.images[0],
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        o.images[1],
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        &[blit],
        vk::Filter::NEAREST,
    );
    barrier(device, cmd, transfer, transfer, &[image_barrier(o.images[1], to_src, transfer, transfer)]);
    let region = vk::BufferImageCopy {
        buffer_offset: 2 * bytes,
        image_subresource: colour_layers(),
        image_extent: vk::Extent3D { width: LARGE, height: LARGE, depth: 1 },
        ..Default::default()
    };
    device.cmd_copy_image_to_buffer(cmd, o.images[1], vk::ImageLayout::TRANSFER_SRC_OPTIMAL, o.host, &[region]);
    device.cmd_update_buffer(cmd, o.small_buffer, 0, &[7u8; UPDATE as usize]);
    // A fill in a secondary command buffer: a row of its own where the primary executes it.
    let inheritance = vk::CommandBufferInheritanceInfo::default();
    let begin = vk::CommandBufferBeginInfo::default().inheritance_info(&inheritance);
    device.begin_command_buffer(o.secondary, &begin).expect("begin secondary");
    device.cmd_fill_buffer(o.secondary, o.spare, 0, vk::WHOLE_SIZE, 1);
    device.end_command_buffer(o.secondary).expect("end secondary");
    device.cmd_execute_commands(cmd, &[o.secondary]);
    let host = (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ);
    barrier(device, cmd, transfer, host, &[]);
    device.end_command_buffer(cmd).expect("end");
}

/// Runs the program on a device of its own; panics if what it computed is wrong.
///
/// # Safety
/// Plain Vulkan use; the process's environment decides the layers.
pub unsafe fn run(name: &CStr, options: WorkOptions) {
    let raw = super::raw_vulkan::raw_instance(name);
    let (instance, physical, family) = (&raw.instance, raw.physical, raw.family);
    let priorities = [1.0];
    let queues = [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default().synchronization2(true);
    let mut boundary = vk::PhysicalDeviceFrameBoundaryFeaturesEXT::default().frame_boundary(true);
    let extensions = [c"VK_EXT_frame_boundary".as_ptr()];
    let mut info = vk::DeviceCreateInfo::default().queue_create_infos(&queues).push_next(&mut v13);
    if options.boundary_every > 0 {
        info = info.enabled_extension_names(&extensions).push_next(&mut boundary);
    }
    let device = instance.create_device(physical, &info, None).expect("device");
    let queue = device.get_device_queue(family, 0);

    let bytes = words(options) as u64 * 4;
    let local = vk::MemoryPropertyFlags::DEVICE_LOCAL;
    let visible = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
    let storage_usage =
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC;
    let (x, x_memory) = buffer(instance, physical, &device, bytes, storage_usage, local);
    let (y, y_memory) = buffer(instance, physical, &device, bytes, storage_usage, local);
    let (indirect, indirect_memory) =
        buffer(instance, physical, &device, 12, vk::BufferUsageFlags::INDIRECT_BUFFER, visible);
    let mapped = device.map_memory(indirect_memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()).expect("map");
    std::ptr::copy_nonoverlapping([options.groups, 1, 1].as_ptr(), mapped.cast::<u32>(), 3);
    device.unmap_memory(indirect_memory);
    let host_size = 2 * bytes + (LARGE * LARGE * 4) as u64;
    let (host, host_memory) =
        buffer(instance, physical, &device, host_size, vk::BufferUsageFlags::TRANSFER_DST, visible);
    let host_mapped = device.map_memory(host_memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()).expect("map");
    let (small_buffer, small_memory) =
        buffer(instance, physical, &device, UPDATE, vk::BufferUsageFlags::TRANSFER_DST, local);
    let image = |size: u32| {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(vk::Format::R8G8B8A8_UNORM)
            .extent(vk::Extent3D { width: size, height: size, depth: 1 })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST);
        let image = device.create_image(&info, None).expect("image");
        let memory = allocate(instance, physical, &device, device.get_image_memory_requirements(image), local);
        device.bind_image_memory(image, memory, 0).expect("bind");
        (image, memory)
    };
    let (small_image, small_image_memory) = image(SMALL);
    let (large_image, large_image_memory) = image(LARGE);

    let binding = [vk::DescriptorSetLayoutBinding::default()
        .binding(0)
        .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
        .descriptor_count(1)
        .stage_flags(vk::ShaderStageFlags::COMPUTE)];
    let set_layout = device
        .create_descriptor_set_layout(&vk::DescriptorSetLayoutCreateInfo::default().bindings(&binding), None)
        .expect("set layout");
    let ranges = [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 8 }];
    let set_layouts = [set_layout];
    let layout = device
        .create_pipeline_layout(
            &vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts).push_constant_ranges(&ranges),
            None,
        )
        .expect("layout");
    let module = super::raw_vulkan::shader(&device, super::raw_vulkan::ADD_TO_WORDS_COMP);
    let stage =
        vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::COMPUTE).module(module).name(c"main");
    let pipeline = device
        .create_compute_pipelines(
            vk::PipelineCache::null(),
            &[vk::ComputePipelineCreateInfo::default()
                .stage(stage)
                .layout(layout)
                .flags(vk::PipelineCreateFlags::DISPATCH_BASE)],
            None,
        )
        .map_err(|(_, e)| e)
        .expect("compute pipeline")[0];
    device.destroy_shader_module(module, None);
    let sizes = [vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 2 }];
    let pool = device
        .create_descriptor_pool(&vk::DescriptorPoolCreateInfo::default().max_sets(2).pool_sizes(&sizes), None)
        .expect("descriptor pool");
    let both = [set_layout, set_layout];
    let sets = device
        .allocate_descriptor_sets(&vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&both))
        .expect("sets");
    for (set, buffer) in sets.iter().zip([x, y]) {
        let info = [vk::DescriptorBufferInfo { buffer, offset: 0, range: vk::WHOLE_SIZE }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(*set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .buffer_info(&info);
        device.update_descriptor_sets(&[write], &[]);
    }
    let (spare, spare_memory) = buffer(instance, physical, &device, SPARE, vk::BufferUsageFlags::TRANSFER_DST, local);
    let objects = Objects {
        pipeline,
        layout,
        sets: [sets[0], sets[1]],
        storage: [x, y],
        indirect,
        host,
        host_mapped: host_mapped as *const u8,
        small_buffer,
        images: [small_image, large_image],
        secondary: vk::CommandBuffer::null(),
        spare,
    };

    let command_pool = device
        .create_command_pool(
            &vk::CommandPoolCreateInfo::default()
                .queue_family_index(family)
                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
            None,
        )
        .expect("command pool");
    let cmd = device
        .allocate_command_buffers(
            &vk::CommandBufferAllocateInfo::default().command_pool(command_pool).command_buffer_count(1),
        )
        .expect("command buffer")[0];
    let debug = ash::ext::debug_utils::Device::new(instance, &device);
    let secondary = device
        .allocate_command_buffers(
            &vk::CommandBufferAllocateInfo::default()
                .command_pool(command_pool)
                .level(vk::CommandBufferLevel::SECONDARY)
                .command_buffer_count(1),
        )
        .expect("secondary command buffer")[0];
    let objects = Objects { secondary, ..objects };
    let fence = device.create_fence(&vk::FenceCreateInfo::default(), None).expect("fence");
    let (want_x, want_y) = expected_words(options);
    for submission in 0..options.submissions {
        record((&device, &debug), cmd, &objects, options);
        let buffers = [cmd];
        let mut frame_end =
            vk::FrameBoundaryEXT::default().flags(vk::FrameBoundaryFlagsEXT::FRAME_END).frame_id(submission as u64);
        let mut submit = vk::SubmitInfo::default().command_buffers(&buffers);
        if options.boundary_every > 0 && (submission + 1) % options.boundary_every == 0 {
            submit = submit.push_next(&mut frame_end);
        }
        device.queue_submit(queue, &[submit], fence).expect("submit");
        device.wait_for_fences(&[fence], true, u64::MAX).expect("wait");
        device.reset_fences(&[fence]).expect("reset fence");
        let words = std::slice::from_raw_parts(objects.host_mapped.cast::<u32>(), 2 * want_x.len());
        assert_eq!(&words[..want_x.len()], &want_x[..], "buffer X after submission {submission}");
        assert_eq!(&words[want_x.len()..], &want_y[..], "buffer Y after submission {submission}");
        let pixels =
            std::slice::from_raw_parts(objects.host_mapped.add(2 * bytes as usize), (LARGE * LARGE * 4) as usize);
        assert!(pixels.chunks(4).all(|p| p == [51, 102, 153, 255]), "the blitted image after submission {submission}");
    }

    device.destroy_fence(fence, None);
    device.destroy_command_pool(command_pool, None);
    device.destroy_descriptor_pool(pool, None);
    device.destroy_pipeline(pipeline, None);
    device.destroy_pipeline_layout(layout, None);
    device.destroy_descriptor_set_layout(set_layout, None);
    for (image, memory) in [(small_image, small_image_memory), (large_image, large_image_memory)] {
        device.destroy_image(image, None);
        device.free_memory(memory, None);
    }
    let buffers = [
        (x, x_memory),
        (y, y_memory),
        (indirect, indirect_memory),
        (host, host_memory),
        (small_buffer, small_memory),
        (spare, spare_memory),
    ];
    for (buffer, memory) in buffers {
        device.destroy_buffer(buffer, None);
        device.free_memory(memory, None);
    }
    device.destroy_device(None);
    raw.destroy();
}
