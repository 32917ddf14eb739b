//! The tiler check (`NOSTENCIL_FILLRATE_TILER=1`, `profile-app --tiler-check`) on small Vulkan
//! programs that do what a tile-based GPU punishes and lavapipe forgives. The first does six
//! such things, all legal Vulkan (the validation layer below the fill-rate layer stays silent):
//! - pass #0 loads its colour DONT_CARE and blends a half-transparent white over it (the image
//!   was cleared blue before: lavapipe keeps the blue, a tiler hands back garbage);
//! - pass #1 stores a 4x colour, then vkCmdResolveImage resolves it;
//! - pass #2 stores a depth image that nothing reads;
//! - pass #3 stores a colour that pass #4 clears whole before anything read it;
//! - pass #5 clears a colour and leaves it DONT_CARE, and pass #6 LOADs it.
//!
//! The second copies an image made for tile memory only (TRANSIENT_ATTACHMENT) after its pass:
//! not valid Vulkan (a transient image may have attachment usages only), which is why a tiler
//! cannot run it; the validation layer says exactly that, and nothing else.
//!
//! Run in this process (its own test binary: it sets the loader's environment), the first with
//! the check and without: with it, each mistake is flagged by name and pass #0's and pass #6's
//! images are the pattern (under the white for #0); without it, they are the clean colours.

use crate::common;

use std::ffi::CStr;
use std::path::Path;

use ash::vk;
use common::raw_vulkan::RawInstance;
use nostencil_fillrate_report::report::FillrateReport;

const SIZE: u32 = 64;
const COLOUR: vk::Format = vk::Format::R8G8B8A8_UNORM;
const DEPTH: vk::Format = vk::Format::D16_UNORM;
/// Bytes of one read-back image (RGBA8).
const BYTES: u64 = (SIZE * SIZE * 4) as u64;
/// The colour pass #5 clears to and drops (what lavapipe keeps for pass #6's LOAD).
const YELLOW: [f32; 4] = [1.0, 1.0, 0.0, 1.0];

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
    common::raw_vulkan::fullscreen_pipeline(
        device,
        layout,
        render_pass,
        SIZE,
        common::raw_vulkan::SOLID_FRAG,
        None,
        &attachments,
    )
}

/// An image and its memory and view, as `raw_vulkan::image_target` makes them.
type Target = (vk::Image, vk::DeviceMemory, vk::ImageView);

/// One small program: a device with one queue, a command buffer being recorded, a host-visible
/// buffer its images are copied into, and every object it made, destroyed together.
struct Program {
    raw: RawInstance,
    device: ash::Device,
    queue: vk::Queue,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    readback: (vk::Buffer, vk::DeviceMemory),
    images: Vec<Target>,
    passes: Vec<vk::RenderPass>,
    framebuffers: Vec<vk::Framebuffer>,
    pipelines: Vec<(vk::Pipeline, vk::PipelineLayout)>,
}

impl Program {
    /// The instance named `name`, its device, and room for `images` read-back images.
    ///
    /// # Safety
    /// Plain Vulkan use; the caller ends with [`Program::finish`] and [`Program::destroy`].
    unsafe fn new(name: &CStr, images: u64) -> Self {
        let raw = common::raw_vulkan::raw_instance(name);
        let priorities = [1.0];
        let queues =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(raw.family).queue_priorities(&priorities)];
        let device = raw
            .instance
            .create_device(raw.physical, &vk::DeviceCreateInfo::default().queue_create_infos(&queues), None)
            .expect("device");
        let queue = device.get_device_queue(raw.family, 0);
        let readback = common::raw_vulkan::host_buffer((&raw.instance, raw.physical, &device), images * BYTES);
        let pool = device
            .create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(raw.family), None)
            .expect("pool");
        let allocate = vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(1);
        let cmd = device.allocate_command_buffers(&allocate).expect("command buffer")[0];
        device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default()).expect("begin");
        let (images, passes, framebuffers, pipelines) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        Program { raw, device, queue, pool, cmd, readback, images, passes, framebuffers, pipelines }
    }

    /// A `SIZE`-square image bound to device memory, and a view of it.
    unsafe fn image(
        &mut self,
        format: vk::Format,
        samples: vk::SampleCountFlags,
        usage: vk::ImageUsageFlags,
    ) -> Target {
        let aspect = if format == DEPTH { vk::ImageAspectFlags::DEPTH } else { vk::ImageAspectFlags::COLOR };
        let range =
            vk::ImageSubresourceRange { aspect_mask: aspect, level_count: 1, layer_count: 1, ..Default::default() };
        let target = (&self.raw.instance, self.raw.physical, &self.device);
        let image = common::raw_vulkan::image_target(target, format, SIZE, samples, usage, range);
        self.images.push(image);
        image
    }

    /// A render pass of one attachment (colour, or depth when `depth`), with the load and store
    /// ops and layouts given, and dependencies on everything before and after it.
    unsafe fn pass(
        &mut self,
        (format, samples): (vk::Format, vk::SampleCountFlags),
        (load, store): (vk::AttachmentLoadOp, vk::AttachmentStoreOp),
        layouts: (vk::ImageLayout, vk::ImageLayout),
        depth: bool,
    ) -> vk::RenderPass {
        let attachment = [vk::AttachmentDescription::default()
            .format(format)
            .samples(samples)
            .load_op(load)
            .store_op(store)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(layouts.0)
            .final_layout(layouts.1)];
        let colour = [vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
        let depth_ref =
            vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL };
        let subpass = vk::SubpassDescription::default().pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS);
        let subpass =
            if depth { subpass.depth_stencil_attachment(&depth_ref) } else { subpass.color_attachments(&colour) };
        let (all, graphics) = (vk::PipelineStageFlags::ALL_COMMANDS, vk::PipelineStageFlags::ALL_GRAPHICS);
        let memory = vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE;
        let dependency = vk::SubpassDependency::default().src_access_mask(memory).dst_access_mask(memory);
        let dependencies = [
            dependency.src_subpass(vk::SUBPASS_EXTERNAL).dst_subpass(0).src_stage_mask(all).dst_stage_mask(graphics),
            dependency.src_subpass(0).dst_subpass(vk::SUBPASS_EXTERNAL).src_stage_mask(graphics).dst_stage_mask(all),
        ];
        let subpasses = [subpass];
        let info = vk::RenderPassCreateInfo::default()
            .attachments(&attachment)
            .subpasses(&subpasses)
            .dependencies(&dependencies);
        let pass = self.device.create_render_pass(&info, None).expect("render pass");
        self.passes.push(pass);
        pass
    }

    unsafe fn framebuffer(&mut self, pass: vk::RenderPass, view: vk::ImageView) -> vk::Framebuffer {
        let framebuffer = common::raw_vulkan::framebuffer(&self.device, pass, view, SIZE);
        self.framebuffers.push(framebuffer);
        framebuffer
    }

    /// Begins `pass` on `view` over the whole image, clearing to `clears`.
    unsafe fn begin(&mut self, pass: vk::RenderPass, view: vk::ImageView, clears: &[vk::ClearValue]) {
        let framebuffer = self.framebuffer(pass, view);
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: SIZE, height: SIZE } };
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(pass)
            .framebuffer(framebuffer)
            .render_area(area)
            .clear_values(clears);
        self.device.cmd_begin_render_pass(self.cmd, &begin, vk::SubpassContents::INLINE);
    }

    /// A pass that clears `format` (1 sample) and ends, with the store op and layouts given.
    unsafe fn clear_pass(
        &mut self,
        view: vk::ImageView,
        store: vk::AttachmentStoreOp,
        layouts: (vk::ImageLayout, vk::ImageLayout),
        colour: [f32; 4],
    ) {
        let one = (COLOUR, vk::SampleCountFlags::TYPE_1);
        let pass = self.pass(one, (vk::AttachmentLoadOp::CLEAR, store), layouts, false);
        self.begin(pass, view, &[vk::ClearValue { color: vk::ClearColorValue { float32: colour } }]);
        self.device.cmd_end_render_pass(self.cmd);
    }

    /// Copies colour `image` (in TRANSFER_SRC_OPTIMAL) into read-back slot `slot`.
    unsafe fn copy_out(&self, image: vk::Image, slot: u64) {
        let copy = vk::BufferImageCopy {
            buffer_offset: slot * BYTES,
            image_subresource: LAYERS,
            image_extent: vk::Extent3D { width: SIZE, height: SIZE, depth: 1 },
            ..Default::default()
        };
        let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        self.device.cmd_copy_image_to_buffer(self.cmd, image, layout, self.readback.0, &[copy]);
    }

    /// Ends the command buffer, submits it, waits for it and returns the read-back bytes.
    unsafe fn finish(&self) -> Vec<u8> {
        self.device.end_command_buffer(self.cmd).expect("end");
        let fence = self.device.create_fence(&vk::FenceCreateInfo::default(), None).expect("fence");
        let cmds = [self.cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        self.device.queue_submit(self.queue, &submit, fence).expect("submit");
        self.device.wait_for_fences(&[fence], true, u64::MAX).expect("wait");
        self.device.destroy_fence(fence, None);
        let memory = self.readback.1;
        let mapped = self.device.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()).expect("map");
        let size = self.device.get_buffer_memory_requirements(self.readback.0).size;
        let bytes = std::slice::from_raw_parts(mapped as *const u8, size as usize).to_vec();
        self.device.unmap_memory(memory);
        bytes
    }

    /// Destroys everything, after [`Program::finish`] proved the GPU done with it.
    unsafe fn destroy(self) {
        let device = &self.device;
        device.destroy_command_pool(self.pool, None);
        device.destroy_buffer(self.readback.0, None);
        device.free_memory(self.readback.1, None);
        for (pipeline, layout) in self.pipelines {
            device.destroy_pipeline(pipeline, None);
            device.destroy_pipeline_layout(layout, None);
        }
        for framebuffer in self.framebuffers {
            device.destroy_framebuffer(framebuffer, None);
        }
        for pass in self.passes {
            device.destroy_render_pass(pass, None);
        }
        for (image, memory, view) in self.images {
            device.destroy_image_view(view, None);
            device.destroy_image(image, None);
            device.free_memory(memory, None);
        }
        device.destroy_device(None);
        self.raw.destroy();
    }
}

const COLOUR_RANGE: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

const LAYERS: vk::ImageSubresourceLayers = vk::ImageSubresourceLayers {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    mip_level: 0,
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

const TRANSFER: vk::ImageUsageFlags = vk::ImageUsageFlags::from_raw(
    vk::ImageUsageFlags::TRANSFER_SRC.as_raw() | vk::ImageUsageFlags::TRANSFER_DST.as_raw(),
);
const ONE: vk::SampleCountFlags = vk::SampleCountFlags::TYPE_1;

/// #0: an image cleared blue, then a pass that loads it DONT_CARE and blends a
/// half-transparent white over it (`fullscreen.vert` + `solid.frag`); read back into slot 0.
unsafe fn blend_over_dont_care(p: &mut Program) {
    use vk::ImageLayout as L;
    let blended = p.image(COLOUR, ONE, vk::ImageUsageFlags::COLOR_ATTACHMENT | TRANSFER);
    let ops = (vk::AttachmentLoadOp::DONT_CARE, vk::AttachmentStoreOp::STORE);
    let pass = p.pass((COLOUR, ONE), ops, (L::TRANSFER_DST_OPTIMAL, L::TRANSFER_SRC_OPTIMAL), false);
    let push = [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::FRAGMENT, offset: 0, size: 16 }];
    let info = vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push);
    let layout = p.device.create_pipeline_layout(&info, None).expect("layout");
    let pipeline = blend_pipeline(&p.device, layout, pass);
    p.pipelines.push((pipeline, layout));
    // The blue a desktop GPU keeps under the DONT_CARE load.
    transition(&p.device, p.cmd, blended.0, L::UNDEFINED, L::TRANSFER_DST_OPTIMAL);
    let blue = vk::ClearColorValue { float32: [0.0, 0.0, 1.0, 1.0] };
    p.device.cmd_clear_color_image(p.cmd, blended.0, L::TRANSFER_DST_OPTIMAL, &blue, &[COLOUR_RANGE]);
    p.begin(pass, blended.2, &[]);
    p.device.cmd_bind_pipeline(p.cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
    let white: [f32; 4] = [1.0, 1.0, 1.0, 0.5];
    let push_bytes: Vec<u8> = white.iter().flat_map(|v| v.to_le_bytes()).collect();
    p.device.cmd_push_constants(p.cmd, layout, vk::ShaderStageFlags::FRAGMENT, 0, &push_bytes);
    p.device.cmd_draw(p.cmd, 3, 1, 0, 0);
    p.device.cmd_end_render_pass(p.cmd);
    p.copy_out(blended.0, 0);
}

/// #1: a 4x colour cleared and stored, then resolved outside the pass; read back into slot 1.
unsafe fn resolve_outside_the_pass(p: &mut Program) {
    use vk::ImageLayout as L;
    let four = vk::SampleCountFlags::TYPE_4;
    let multisampled = p.image(COLOUR, four, vk::ImageUsageFlags::COLOR_ATTACHMENT | TRANSFER);
    let resolved = p.image(COLOUR, ONE, vk::ImageUsageFlags::COLOR_ATTACHMENT | TRANSFER);
    let ops = (vk::AttachmentLoadOp::CLEAR, vk::AttachmentStoreOp::STORE);
    let pass = p.pass((COLOUR, four), ops, (L::UNDEFINED, L::TRANSFER_SRC_OPTIMAL), false);
    p.begin(pass, multisampled.2, &[vk::ClearValue { color: vk::ClearColorValue { float32: [1.0, 0.5, 0.0, 1.0] } }]);
    p.device.cmd_end_render_pass(p.cmd);
    transition(&p.device, p.cmd, resolved.0, L::UNDEFINED, L::TRANSFER_DST_OPTIMAL);
    let region = vk::ImageResolve {
        src_subresource: LAYERS,
        src_offset: vk::Offset3D::default(),
        dst_subresource: LAYERS,
        dst_offset: vk::Offset3D::default(),
        extent: vk::Extent3D { width: SIZE, height: SIZE, depth: 1 },
    };
    let (src, dst) = ((multisampled.0, L::TRANSFER_SRC_OPTIMAL), (resolved.0, L::TRANSFER_DST_OPTIMAL));
    p.device.cmd_resolve_image(p.cmd, src.0, src.1, dst.0, dst.1, &[region]);
    transition(&p.device, p.cmd, resolved.0, L::TRANSFER_DST_OPTIMAL, L::TRANSFER_SRC_OPTIMAL);
    p.copy_out(resolved.0, 1);
}

/// #2: a depth cleared and stored that nothing reads.
unsafe fn unread_depth(p: &mut Program) {
    let depth = p.image(DEPTH, ONE, vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT);
    let ops = (vk::AttachmentLoadOp::CLEAR, vk::AttachmentStoreOp::STORE);
    let layouts = (vk::ImageLayout::UNDEFINED, vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let pass = p.pass((DEPTH, ONE), ops, layouts, true);
    p.begin(pass, depth.2, &[vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } }]);
    p.device.cmd_end_render_pass(p.cmd);
}

/// #3 clears and stores a colour, #4 clears all of it again before anything read it; read back
/// into slot 2.
unsafe fn overwrite_unread(p: &mut Program) {
    use vk::ImageLayout as L;
    let image = p.image(COLOUR, ONE, vk::ImageUsageFlags::COLOR_ATTACHMENT | TRANSFER);
    let store = vk::AttachmentStoreOp::STORE;
    p.clear_pass(image.2, store, (L::UNDEFINED, L::TRANSFER_SRC_OPTIMAL), [1.0, 0.0, 0.0, 1.0]);
    p.clear_pass(image.2, store, (L::TRANSFER_SRC_OPTIMAL, L::TRANSFER_SRC_OPTIMAL), [0.0, 1.0, 1.0, 1.0]);
    p.copy_out(image.0, 2);
}

/// #5 clears a colour yellow and stores it DONT_CARE, #6 LOADs it and stores it; read back into
/// slot 3.
unsafe fn load_after_dont_care(p: &mut Program) {
    use vk::ImageLayout as L;
    let image = p.image(COLOUR, ONE, vk::ImageUsageFlags::COLOR_ATTACHMENT | TRANSFER);
    p.clear_pass(image.2, vk::AttachmentStoreOp::DONT_CARE, (L::UNDEFINED, L::COLOR_ATTACHMENT_OPTIMAL), YELLOW);
    let ops = (vk::AttachmentLoadOp::LOAD, vk::AttachmentStoreOp::STORE);
    let pass = p.pass((COLOUR, ONE), ops, (L::COLOR_ATTACHMENT_OPTIMAL, L::TRANSFER_SRC_OPTIMAL), false);
    p.begin(pass, image.2, &[]);
    p.device.cmd_end_render_pass(p.cmd);
    p.copy_out(image.0, 3);
}

/// The first program: passes #0 to #6, with four images read back. Returns the read-back
/// buffer: pass #0's image, the resolved one, pass #4's and pass #6's, `BYTES` each.
fn wrong_program() -> Vec<u8> {
    // SAFETY: plain Vulkan use in order: every handle is created before use, used only while
    // alive, and destroyed after the fence wait that proves the GPU done with it.
    unsafe {
        let mut p = Program::new(c"tiler-mistakes", 4);
        blend_over_dont_care(&mut p);
        resolve_outside_the_pass(&mut p);
        unread_depth(&mut p);
        overwrite_unread(&mut p);
        load_after_dont_care(&mut p);
        let bytes = p.finish();
        p.destroy();
        bytes
    }
}

/// The second program: pass #0 clears and stores an image with TRANSIENT_ATTACHMENT usage, then
/// vkCmdCopyImageToBuffer reads it outside the pass. Not valid Vulkan
/// (VUID-VkImageCreateInfo-usage-00963: a transient image has attachment usages only), which is
/// why a tiler cannot run it; lavapipe does.
fn transient_program() -> Vec<u8> {
    // SAFETY: as in `wrong_program`; the one invalid usage is the image's, which lavapipe
    // accepts (it allocates every image in memory).
    unsafe {
        let mut p = Program::new(c"tiler-transient", 1);
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let image = p.image(COLOUR, ONE, usage);
        let layouts = (vk::ImageLayout::UNDEFINED, vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
        p.clear_pass(image.2, vk::AttachmentStoreOp::STORE, layouts, YELLOW);
        p.copy_out(image.0, 0);
        let bytes = p.finish();
        p.destroy();
        bytes
    }
}

/// `program` run once under the layer writing to `out`, with the check or without: its
/// read-back bytes, the layer's report, and the warnings and errors the validation layer below
/// raised meanwhile.
fn run(out: &Path, check: bool, program: fn() -> Vec<u8>) -> (Vec<u8>, FillrateReport, Vec<String>) {
    std::env::set_var("NOSTENCIL_FILLRATE_OUT", out);
    if check {
        std::env::set_var("NOSTENCIL_FILLRATE_TILER", "1");
    } else {
        std::env::remove_var("NOSTENCIL_FILLRATE_TILER");
    }
    let pixels = program();
    let messages = std::mem::take(&mut *common::raw_vulkan::MESSAGES.lock().unwrap_or_else(|e| e.into_inner()));
    let text = std::fs::read_to_string(out).expect("the layer's result");
    (pixels, FillrateReport::from_json(&text).expect("a fill-rate report"), messages)
}

/// Blending (1, 1, 1, 0.5) over `under` in UNORM8, each channel within 2.
fn over(under: [u8; 3]) -> [u8; 3] {
    under.map(|c| ((c as f32 / 255.0 * 0.5 + 0.5) * 255.0).round() as u8)
}

fn near(a: &[u8], b: [u8; 3]) -> bool {
    a.iter().zip(b).all(|(&x, y)| x.abs_diff(y) <= 2)
}

/// The checkerboard's colour at pixel `i` of a `SIZE`-square image (16-pixel cells).
fn pattern(i: usize) -> [u8; 3] {
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: SIZE, height: SIZE } };
    let cell = nostencil_fillrate::poison::cell_size(area) as usize;
    assert_eq!(cell, 16);
    let (x, y) = (i % SIZE as usize, i / SIZE as usize);
    if (x / cell + y / cell) % 2 == 1 {
        [0, 255, 0]
    } else {
        [255, 0, 255]
    }
}

/// The flags as (kind, pass, attachment), sorted.
fn flags_of(report: &FillrateReport) -> Vec<(String, u32, Option<String>)> {
    let check = report.tiler_check.as_ref().expect("the tiler check's report");
    let mut flags: Vec<_> = check.flags.iter().map(|f| (f.kind.clone(), f.pass, f.attachment.clone())).collect();
    flags.sort();
    flags
}

#[test]
fn each_mistake_is_flagged_by_name_and_the_dont_care_load_shows_the_pattern() {
    // It sets the process environment for the layer: in a process of its own.
    common::in_own_process(
        "tiler_check::each_mistake_is_flagged_by_name_and_the_dont_care_load_shows_the_pattern",
        || {
            let first = common::raw_vulkan::under_the_layer("tiler_check");
            let dir = first.parent().expect("scratch folder").to_path_buf();
            let slot = |bytes: &[u8], n: u64| bytes[(n * BYTES) as usize..((n + 1) * BYTES) as usize].to_vec();

            let (off_bytes, report, messages) = run(&dir.join("off.json"), false, wrong_program);
            assert!(messages.is_empty(), "validation messages (check off):\n{}", messages.join("\n"));
            assert!(report.tiler_check.is_none(), "no check asked for");
            let (clean, clean_loaded) = (slot(&off_bytes, 0), slot(&off_bytes, 3));
            assert!(
                clean.chunks(4).all(|p| near(p, over([0, 0, 255]))),
                "without the check the blended image is the clean blue under white: {:?}",
                &clean[..8]
            );
            assert!(clean_loaded.chunks(4).all(|p| near(p, [255, 255, 0])), "lavapipe kept the yellow pass #5 dropped");

            let (on_bytes, report, messages) = run(&dir.join("on.json"), true, wrong_program);
            assert!(messages.is_empty(), "validation messages (check on):\n{}", messages.join("\n"));
            let check = report.tiler_check.clone().expect("the tiler check's report");
            let colour = Some("colour #0 (R8G8B8A8_UNORM)".to_owned());
            let mut expected = vec![
                ("dont_care_load_read".to_owned(), 0, colour.clone()),
                // The blue vkCmdClearColorImage wrote before pass #0 is lost to its DONT_CARE load.
                ("redundant_clear".into(), 0, colour.clone()),
                ("multisampled_stored".into(), 1, colour.clone()),
                ("resolve_outside_pass".into(), 1, colour.clone()),
                ("stored_never_read".into(), 2, Some("depth #0 (D16_UNORM)".into())),
                ("dead_pass".into(), 2, None),
                ("stored_then_overwritten".into(), 3, colour.clone()),
                ("dead_pass".into(), 3, None),
                ("load_after_dont_care".into(), 6, colour.clone()),
                // Every LOAD_OP_LOAD reads the attachment into tile memory (Arm's "attachment
                // needs readback").
                ("attachment_loaded".into(), 6, colour.clone()),
            ];
            expected.sort();
            assert_eq!(flags_of(&report), expected, "{:#?}", check.flags);
            assert!(check.flags.iter().all(|f| f.frame == 0 && f.count == 1 && !f.detail.is_empty()));
            let notes: Vec<(&str, u32, Option<&str>)> =
                check.poisoned.iter().map(|n| (n.when.as_str(), n.pass, n.read_by.as_deref())).collect();
            assert_eq!(
                notes,
                [
                    ("before the pass (DONT_CARE load)", 0, Some("the pass's first draw (blending)")),
                    ("after the pass (DONT_CARE store)", 5, Some("pass #6's LOAD")),
                ]
            );

            // Pass #0's image: the magenta and green checkerboard of 16-pixel cells under the white;
            // pass #6's: the checkerboard pass #5 left, loaded.
            let (poisoned, loaded) = (slot(&on_bytes, 0), slot(&on_bytes, 3));
            for (i, (pixel, loaded)) in poisoned.chunks(4).zip(loaded.chunks(4)).enumerate() {
                let (x, y) = (i % SIZE as usize, i / SIZE as usize);
                assert!(near(pixel, over(pattern(i))), "pixel ({x}, {y}) is {pixel:?}, not the pattern under white");
                assert!(near(loaded, pattern(i)), "pass #6's pixel ({x}, {y}) is {loaded:?}, not the pattern");
            }
            // The table's tiler lines, and both images side by side (docs/fillrate-layer.md shows them).
            let table = nostencil_fillrate_report::output::render(
                &report,
                nostencil_fillrate_report::output::OutputFormat::Table,
            );
            for line in
                ["tiler check: 10 flag(s)", "dead_pass: frame 0 pass #2", "load_after_dont_care: frame 0 pass #6"]
            {
                assert!(table.contains(line), "{line} not in:\n{table}");
            }
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
                r.frames
                    .iter()
                    .flat_map(|f| &f.render_passes)
                    .filter_map(|p| p.counters)
                    .map(|c| c.samples_passed)
                    .collect()
            };
            let off = std::fs::read_to_string(dir.join("off.json")).expect("the first result");
            let off = FillrateReport::from_json(&off).expect("a fill-rate report");
            assert_eq!(counters(&report), counters(&off));

            // The transient image copied after its pass: flagged by its pass and attachment; validation
            // reports the image's invalid usage, and nothing else.
            let (_, report, messages) = run(&dir.join("transient.json"), true, transient_program);
            let invalid = "VUID-VkImageCreateInfo-usage-00963";
            assert!(!messages.is_empty() && messages.iter().all(|m| m.contains(invalid)), "{}", messages.join("\n"));
            assert_eq!(flags_of(&report), [("transient_outside_pass".to_owned(), 0, colour)]);
            let detail = &report.tiler_check.as_ref().expect("the check").flags[0].detail;
            assert!(detail.contains("vkCmdCopyImageToBuffer"), "{detail}");
        },
    );
}
