//! The tiler check (`NOSTENCIL_FILLRATE_TILER=1`, `profile-app --tiler-check`) on a small Vulkan
//! program that does three things a tile-based GPU punishes and lavapipe forgives, all legal
//! Vulkan (the validation layer below the fill-rate layer stays silent):
//! - pass #0 loads its colour DONT_CARE and blends a half-transparent white over it (the image
//!   was cleared blue before: lavapipe keeps the blue, a tiler hands back garbage);
//! - pass #1 stores a 4x colour, then vkCmdResolveImage resolves it;
//! - pass #2 stores a depth image that nothing reads.
//!
//! Run twice in this process (its own test binary: it sets the loader's environment), with the
//! check and without: with it, each mistake is flagged by name and pass #0's image is the
//! pattern under the white; without it, the image is the clean blended blue.

mod common;

use std::path::Path;

use ash::vk;
use nostencil::layer::report::FillrateReport;

const SIZE: u32 = 64;
const COLOUR: vk::Format = vk::Format::R8G8B8A8_UNORM;
const DEPTH: vk::Format = vk::Format::D16_UNORM;

/// A render pass of one attachment (colour, or depth when `depth`), with the ops and layouts
/// given, and dependencies on everything before and after it.
unsafe fn one_attachment_pass(
    device: &ash::Device,
    format: vk::Format,
    samples: vk::SampleCountFlags,
    load: vk::AttachmentLoadOp,
    layouts: (vk::ImageLayout, vk::ImageLayout),
    depth: bool,
) -> vk::RenderPass {
    let attachment = [vk::AttachmentDescription::default()
        .format(format)
        .samples(samples)
        .load_op(load)
        .store_op(vk::AttachmentStoreOp::STORE)
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(layouts.0)
        .final_layout(layouts.1)];
    let colour = [vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
    let depth_ref =
        vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL };
    let subpass = vk::SubpassDescription::default().pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS);
    let subpass = if depth { subpass.depth_stencil_attachment(&depth_ref) } else { subpass.color_attachments(&colour) };
    let (all, graphics) = (vk::PipelineStageFlags::ALL_COMMANDS, vk::PipelineStageFlags::ALL_GRAPHICS);
    let memory = vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE;
    let dependencies = [
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(all)
            .dst_stage_mask(graphics)
            .src_access_mask(memory)
            .dst_access_mask(memory),
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(graphics)
            .dst_stage_mask(all)
            .src_access_mask(memory)
            .dst_access_mask(memory),
    ];
    let subpasses = [subpass];
    let info =
        vk::RenderPassCreateInfo::default().attachments(&attachment).subpasses(&subpasses).dependencies(&dependencies);
    device.create_render_pass(&info, None).expect("render pass")
}

/// `fullscreen.vert` + `solid.frag` blending its push-constant colour over the attachment.
unsafe fn blend_pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    render_pass: vk::RenderPass,
) -> vk::Pipeline {
    let attachments = [vk::PipelineColorBlendAttachmentState::default()
        .blend_enable(true)
        .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
        .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
        .color_blend_op(vk::BlendOp::ADD)
        .src_alpha_blend_factor(vk::BlendFactor::ONE)
        .dst_alpha_blend_factor(vk::BlendFactor::ZERO)
        .alpha_blend_op(vk::BlendOp::ADD)
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    common::raw_vulkan::fullscreen_pipeline(device, layout, render_pass, SIZE, "solid.frag", None, &attachments)
}

/// A `SIZE`-square image bound to device memory, and a view of it.
unsafe fn image(
    raw: &common::raw_vulkan::RawInstance,
    device: &ash::Device,
    format: vk::Format,
    samples: vk::SampleCountFlags,
    usage: vk::ImageUsageFlags,
) -> (vk::Image, vk::DeviceMemory, vk::ImageView) {
    let aspect = if format == DEPTH { vk::ImageAspectFlags::DEPTH } else { vk::ImageAspectFlags::COLOR };
    let range = vk::ImageSubresourceRange { aspect_mask: aspect, level_count: 1, layer_count: 1, ..Default::default() };
    let target = (&raw.instance, raw.physical, device);
    common::raw_vulkan::image_target(target, format, SIZE, samples, usage, range)
}

const COLOUR_RANGE: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

/// A layout transition of a colour image, everything before to everything after.
unsafe fn transition(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    from: vk::ImageLayout,
    to: vk::ImageLayout,
) {
    let barrier = vk::ImageMemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::MEMORY_WRITE)
        .dst_access_mask(vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE)
        .old_layout(from)
        .new_layout(to)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(COLOUR_RANGE);
    let all = vk::PipelineStageFlags::ALL_COMMANDS;
    device.cmd_pipeline_barrier(cmd, all, all, vk::DependencyFlags::empty(), &[], &[], &[barrier]);
}

/// The program: its three passes, then pass #0's colour and the resolved image read back.
/// Returns pass #0's pixels (RGBA8).
fn wrong_program() -> Vec<u8> {
    // SAFETY: the whole body is plain Vulkan use in order: every handle is created before use,
    // used only while alive, and destroyed after the fence wait that proves the GPU done with it.
    unsafe {
        let raw = common::raw_vulkan::raw_instance(c"tiler-mistakes");
        let priorities = [1.0];
        let queues =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(raw.family).queue_priorities(&priorities)];
        let device = raw
            .instance
            .create_device(raw.physical, &vk::DeviceCreateInfo::default().queue_create_infos(&queues), None)
            .expect("device");
        let queue = device.get_device_queue(raw.family, 0);
        let transfer = vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST;
        let attachment = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        let one = vk::SampleCountFlags::TYPE_1;
        let blended = image(&raw, &device, COLOUR, one, attachment | transfer);
        let multisampled = image(&raw, &device, COLOUR, vk::SampleCountFlags::TYPE_4, attachment | transfer);
        let resolved = image(&raw, &device, COLOUR, one, attachment | transfer);
        let depth = image(&raw, &device, DEPTH, one, vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT);

        use vk::ImageLayout as L;
        let dont_care = vk::AttachmentLoadOp::DONT_CARE;
        let clear = vk::AttachmentLoadOp::CLEAR;
        let blend_pass = one_attachment_pass(
            &device,
            COLOUR,
            one,
            dont_care,
            (L::TRANSFER_DST_OPTIMAL, L::TRANSFER_SRC_OPTIMAL),
            false,
        );
        let ms_pass = one_attachment_pass(
            &device,
            COLOUR,
            vk::SampleCountFlags::TYPE_4,
            clear,
            (L::UNDEFINED, L::TRANSFER_SRC_OPTIMAL),
            false,
        );
        let depth_pass =
            one_attachment_pass(&device, DEPTH, one, clear, (L::UNDEFINED, L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL), true);
        let framebuffer = |pass, view| {
            let views = [view];
            let info = vk::FramebufferCreateInfo::default()
                .render_pass(pass)
                .attachments(&views)
                .width(SIZE)
                .height(SIZE)
                .layers(1);
            device.create_framebuffer(&info, None).expect("framebuffer")
        };
        let framebuffers = [
            framebuffer(blend_pass, blended.2),
            framebuffer(ms_pass, multisampled.2),
            framebuffer(depth_pass, depth.2),
        ];
        let push = [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::FRAGMENT, offset: 0, size: 16 }];
        let layout = device
            .create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push), None)
            .expect("layout");
        let pipeline = blend_pipeline(&device, layout, blend_pass);

        let bytes = (SIZE * SIZE * 4) as u64;
        let buffer = device
            .create_buffer(
                &vk::BufferCreateInfo::default().size(2 * bytes).usage(vk::BufferUsageFlags::TRANSFER_DST),
                None,
            )
            .expect("buffer");
        let requirements = device.get_buffer_memory_requirements(buffer);
        let props = raw.instance.get_physical_device_memory_properties(raw.physical);
        let host = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let memory_type = (0..props.memory_type_count)
            .find(|&i| {
                requirements.memory_type_bits & (1 << i) != 0
                    && props.memory_types[i as usize].property_flags.contains(host)
            })
            .expect("host-visible memory");
        let buffer_memory = device
            .allocate_memory(
                &vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(memory_type),
                None,
            )
            .expect("memory");
        device.bind_buffer_memory(buffer, buffer_memory, 0).expect("bind");

        let pool = device
            .create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(raw.family), None)
            .expect("pool");
        let cmd = device
            .allocate_command_buffers(
                &vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(1),
            )
            .expect("command buffer")[0];
        device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default()).expect("begin");
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: SIZE, height: SIZE } };
        // The blue a desktop GPU keeps under the DONT_CARE load.
        transition(&device, cmd, blended.0, L::UNDEFINED, L::TRANSFER_DST_OPTIMAL);
        let blue = vk::ClearColorValue { float32: [0.0, 0.0, 1.0, 1.0] };
        device.cmd_clear_color_image(cmd, blended.0, L::TRANSFER_DST_OPTIMAL, &blue, &[COLOUR_RANGE]);
        // #0: DONT_CARE load, then half-transparent white blended over it.
        let begin =
            vk::RenderPassBeginInfo::default().render_pass(blend_pass).framebuffer(framebuffers[0]).render_area(area);
        device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        let white: [f32; 4] = [1.0, 1.0, 1.0, 0.5];
        let push_bytes: Vec<u8> = white.iter().flat_map(|v| v.to_le_bytes()).collect();
        device.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::FRAGMENT, 0, &push_bytes);
        device.cmd_draw(cmd, 3, 1, 0, 0);
        device.cmd_end_render_pass(cmd);
        // #1: a 4x colour cleared and stored, then resolved outside the pass.
        let clears = [vk::ClearValue { color: vk::ClearColorValue { float32: [1.0, 0.5, 0.0, 1.0] } }];
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(ms_pass)
            .framebuffer(framebuffers[1])
            .render_area(area)
            .clear_values(&clears);
        device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
        device.cmd_end_render_pass(cmd);
        transition(&device, cmd, resolved.0, L::UNDEFINED, L::TRANSFER_DST_OPTIMAL);
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let region = vk::ImageResolve {
            src_subresource: layers,
            src_offset: vk::Offset3D::default(),
            dst_subresource: layers,
            dst_offset: vk::Offset3D::default(),
            extent: vk::Extent3D { width: SIZE, height: SIZE, depth: 1 },
        };
        device.cmd_resolve_image(
            cmd,
            multisampled.0,
            L::TRANSFER_SRC_OPTIMAL,
            resolved.0,
            L::TRANSFER_DST_OPTIMAL,
            &[region],
        );
        transition(&device, cmd, resolved.0, L::TRANSFER_DST_OPTIMAL, L::TRANSFER_SRC_OPTIMAL);
        // #2: a depth cleared and stored that nothing reads.
        let clears = [vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } }];
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(depth_pass)
            .framebuffer(framebuffers[2])
            .render_area(area)
            .clear_values(&clears);
        device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
        device.cmd_end_render_pass(cmd);
        // Pass #0's colour and the resolved image read back.
        let copy = |offset: u64| vk::BufferImageCopy {
            buffer_offset: offset,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: layers,
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D { width: SIZE, height: SIZE, depth: 1 },
        };
        device.cmd_copy_image_to_buffer(cmd, blended.0, L::TRANSFER_SRC_OPTIMAL, buffer, &[copy(0)]);
        device.cmd_copy_image_to_buffer(cmd, resolved.0, L::TRANSFER_SRC_OPTIMAL, buffer, &[copy(bytes)]);
        device.end_command_buffer(cmd).expect("end");
        let fence = device.create_fence(&vk::FenceCreateInfo::default(), None).expect("fence");
        let cmds = [cmd];
        device.queue_submit(queue, &[vk::SubmitInfo::default().command_buffers(&cmds)], fence).expect("submit");
        device.wait_for_fences(&[fence], true, u64::MAX).expect("wait");
        let mapped = device.map_memory(buffer_memory, 0, bytes, vk::MemoryMapFlags::empty()).expect("map");
        let pixels = std::slice::from_raw_parts(mapped as *const u8, bytes as usize).to_vec();
        device.unmap_memory(buffer_memory);

        device.destroy_fence(fence, None);
        device.destroy_command_pool(pool, None);
        device.destroy_buffer(buffer, None);
        device.free_memory(buffer_memory, None);
        device.destroy_pipeline(pipeline, None);
        device.destroy_pipeline_layout(layout, None);
        for framebuffer in framebuffers {
            device.destroy_framebuffer(framebuffer, None);
        }
        for pass in [blend_pass, ms_pass, depth_pass] {
            device.destroy_render_pass(pass, None);
        }
        for (image, memory, view) in [blended, multisampled, resolved, depth] {
            device.destroy_image_view(view, None);
            device.destroy_image(image, None);
            device.free_memory(memory, None);
        }
        device.destroy_device(None);
        raw.destroy();
        pixels
    }
}

/// The program run once under the layer writing to `out`, with the check or without.
fn run(out: &Path, check: bool) -> (Vec<u8>, FillrateReport) {
    std::env::set_var("NOSTENCIL_FILLRATE_OUT", out);
    if check {
        std::env::set_var("NOSTENCIL_FILLRATE_TILER", "1");
    } else {
        std::env::remove_var("NOSTENCIL_FILLRATE_TILER");
    }
    let pixels = wrong_program();
    let messages = common::raw_vulkan::MESSAGES.lock().unwrap_or_else(|e| e.into_inner()).clone();
    assert!(messages.is_empty(), "validation messages (check {check}):\n{}", messages.join("\n"));
    let text = std::fs::read_to_string(out).expect("the layer's result");
    (pixels, FillrateReport::from_json(&text).expect("a fill-rate report"))
}

/// Blending (1, 1, 1, 0.5) over `under` in UNORM8, each channel within 2.
fn over(under: [u8; 3]) -> [u8; 3] {
    under.map(|c| ((c as f32 / 255.0 * 0.5 + 0.5) * 255.0).round() as u8)
}

fn near(a: &[u8], b: [u8; 3]) -> bool {
    a.iter().zip(b).all(|(&x, y)| x.abs_diff(y) <= 2)
}

#[test]
fn each_mistake_is_flagged_by_name_and_the_dont_care_load_shows_the_pattern() {
    let first = common::raw_vulkan::under_the_layer("tiler_check");
    let dir = first.parent().expect("scratch folder").to_path_buf();

    let (clean, report) = run(&dir.join("off.json"), false);
    assert!(report.tiler_check.is_none(), "no check asked for");
    assert!(
        clean.chunks(4).all(|p| near(p, over([0, 0, 255]))),
        "without the check the blended image is the clean blue under white: {:?}",
        &clean[..8]
    );

    let (poisoned, report) = run(&dir.join("on.json"), true);
    let check = report.tiler_check.clone().expect("the tiler check's report");
    let flags: Vec<(&str, u32, Option<&str>)> =
        check.flags.iter().map(|f| (f.kind.as_str(), f.pass, f.attachment.as_deref())).collect();
    let colour = Some("colour #0 (R8G8B8A8_UNORM)");
    let mut expected = vec![
        ("dont_care_load_read", 0, colour),
        ("multisampled_stored", 1, colour),
        ("resolve_outside_pass", 1, colour),
        ("stored_never_read", 2, Some("depth #0 (D16_UNORM)")),
        ("dead_pass", 2, None),
    ];
    let mut found = flags.clone();
    found.sort();
    expected.sort();
    assert_eq!(found, expected, "{:#?}", check.flags);
    assert!(check.flags.iter().all(|f| f.frame == 0 && f.count == 1 && !f.detail.is_empty()));
    assert_eq!(check.poisoned.len(), 1, "{:?}", check.poisoned);
    assert_eq!(check.poisoned[0].read_by.as_deref(), Some("the pass's first draw (blending)"));

    // Pass #0's image: the magenta and green checkerboard of 16-pixel cells under the white.
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: SIZE, height: SIZE } };
    let cell = nostencil::layer::poison::cell_size(area) as usize;
    assert_eq!(cell, 16);
    for (i, pixel) in poisoned.chunks(4).enumerate() {
        let (x, y) = (i % SIZE as usize, i / SIZE as usize);
        let under = if (x / cell + y / cell) % 2 == 1 { [0, 255, 0] } else { [255, 0, 255] };
        assert!(near(pixel, over(under)), "pixel ({x}, {y}) is {pixel:?}, not the pattern under white");
    }
    // The table's tiler lines, and both images side by side (docs/fillrate-layer.md shows them).
    let table = nostencil::layer::output::render(&report, nostencil::layer::config::OutputFormat::Table);
    assert!(table.contains("tiler check: 5 flag(s)") && table.contains("dead_pass: frame 0 pass #2"), "{table}");
    std::fs::write(dir.join("tiler-check.txt"), &table).expect("table written");
    // Each pixel four times as wide and high, so the cells show.
    let side_by_side = image::RgbaImage::from_fn(8 * SIZE, 4 * SIZE, |x, y| {
        let (x, y) = (x / 4, y / 4);
        let (source, x) = if x < SIZE { (&clean, x) } else { (&poisoned, x - SIZE) };
        let at = ((y * SIZE + x) * 4) as usize;
        image::Rgba([source[at], source[at + 1], source[at + 2], 255])
    });
    side_by_side.save(dir.join("tiler-check.png")).expect("picture written");

    // The check changed nothing but what a tiler would not have kept: the counters are alike.
    let counters = |r: &FillrateReport| -> Vec<u64> {
        r.frames.iter().flat_map(|f| &f.render_passes).filter_map(|p| p.counters).map(|c| c.samples_passed).collect()
    };
    let off = std::fs::read_to_string(dir.join("off.json")).expect("the first result");
    let off = FillrateReport::from_json(&off).expect("a fill-rate report");
    assert_eq!(counters(&report), counters(&off));
}
