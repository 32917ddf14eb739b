//! A Vulkan program of the tests' own that draws through the paths the fill-rate layer measures
//! beyond plain draws: VK_EXT_multi_draw (plain and indexed), secondary command buffers (a
//! render pass's contents, a dynamic render pass's contents, and transfers outside any pass) and
//! a multiview pass of two views. Every draw is a rectangle of `rect.vert` whose edges lie on
//! pixel boundaries, so the program knows its draws, vertices and samples by hand
//! ([`known_passes`]). With `own_queries` it records the same draws inline, with occlusion and
//! statistics queries of its own around each pass: the figures the layer's must equal. Each
//! submission is waited for; the program reads its images and its copied buffer back.

use ash::vk;

use super::raw_vulkan::{self, RawInstance};

mod objects;
use objects::{allocate, buffer, colour_range, pipeline, render_pass, target};

/// The target's side, in pixels.
pub const SIZE: u32 = 32;
/// Views of the multiview pass.
pub const VIEWS: u32 = 2;
/// Bytes the secondary's transfers fill and copy.
pub const WORK_BYTES: u64 = 256;

/// Samples rectangle `k` of `rect.vert` covers in one view.
pub fn rect_samples(k: u64) -> u64 {
    16 * (k + 1)
}

/// A render pass as the program knows it: draws, vertex shader invocations, samples passed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Figures {
    pub draws: u64,
    pub vertices: u64,
    pub samples: u64,
    /// Fragment shader invocations: from the program's own queries only (None: not asked).
    pub fragments: Option<u64>,
}

/// The passes of one submission, in order, as drawn: (rectangles, views).
const PASSES: [(&[u64], u64); 4] = [
    // A: vkCmdDrawMultiEXT of rectangles 0 to 2, then vkCmdDraw of 3.
    (&[0, 1, 2, 3], 1),
    // B: two secondaries: vkCmdDraw of 4; vkCmdDrawMultiIndexedEXT of 5 and 6.
    (&[4, 5, 6], 1),
    // C: multiview, two views: vkCmdDraw of 7.
    (&[7], VIEWS as u64),
    // D: dynamic rendering, its contents in a secondary: vkCmdDraw of 1.
    (&[1], 1),
];

/// The figures of each pass, known by hand (fragments unknown: lavapipe shades whole blocks).
pub fn known_passes() -> Vec<Figures> {
    PASSES
        .iter()
        .map(|(rects, views)| Figures {
            draws: rects.len() as u64,
            vertices: 6 * rects.len() as u64 * views,
            samples: rects.iter().map(|&k| rect_samples(k)).sum::<u64>() * views,
            fragments: None,
        })
        .collect()
}

/// What a run of the program saw.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Outcome {
    /// Per pass, from the program's own queries (first submission); empty without them.
    pub own: Vec<Figures>,
    /// The two images' bytes after the last submission: the flat target, then both layers.
    pub images: Vec<u8>,
}

/// Runs `submissions` submissions of the program.
///
/// # Safety
/// Plain Vulkan use, in order; every object is destroyed before it returns.
pub unsafe fn run(name: &std::ffi::CStr, submissions: u32, own_queries: bool) -> Outcome {
    let raw = raw_vulkan::raw_instance(name);
    let program = Program::new(&raw, own_queries);
    let mut own = Vec::new();
    for s in 0..submissions {
        let figures = program.submit();
        if s == 0 {
            own = figures;
        }
    }
    let images = program.read_back();
    program.destroy();
    raw.destroy();
    Outcome { own, images }
}

struct Target {
    image: vk::Image,
    memory: vk::DeviceMemory,
    view: vk::ImageView,
}

struct Program<'a> {
    raw: &'a RawInstance,
    device: ash::Device,
    multi: ash::ext::multi_draw::Device,
    queue: vk::Queue,
    own_queries: bool,
    flat: Target,
    layered: Target,
    passes: [vk::RenderPass; 3],
    framebuffers: [vk::Framebuffer; 3],
    layout: vk::PipelineLayout,
    pipelines: [vk::Pipeline; 3],
    indices: (vk::Buffer, vk::DeviceMemory),
    work: (vk::Buffer, vk::DeviceMemory),
    readback: (vk::Buffer, vk::DeviceMemory),
    queries: [vk::QueryPool; 2],
    pool: vk::CommandPool,
    primary: vk::CommandBuffer,
    fence: vk::Fence,
}

const FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
const STATISTICS: vk::QueryPipelineStatisticFlags = vk::QueryPipelineStatisticFlags::from_raw(
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS.as_raw(),
);
/// Query slots a pass may take (the multiview pass takes one per view).
const SLOTS: u32 = 8;

impl<'a> Program<'a> {
    unsafe fn new(raw: &'a RawInstance, own_queries: bool) -> Self {
        let (instance, physical) = (&raw.instance, raw.physical);
        let priorities = [1.0];
        let queues =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(raw.family).queue_priorities(&priorities)];
        let mut multiview = vk::PhysicalDeviceMultiviewFeatures::default().multiview(true);
        let mut dynamic = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true);
        let mut multi = vk::PhysicalDeviceMultiDrawFeaturesEXT::default().multi_draw(true);
        let features =
            vk::PhysicalDeviceFeatures::default().pipeline_statistics_query(true).occlusion_query_precise(true);
        let extensions = [ash::ext::multi_draw::NAME.as_ptr()];
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&extensions)
            .enabled_features(&features)
            .push_next(&mut multiview)
            .push_next(&mut dynamic)
            .push_next(&mut multi);
        let device = instance.create_device(physical, &info, None).expect("device");
        let multi = ash::ext::multi_draw::Device::new(instance, &device);
        let queue = device.get_device_queue(raw.family, 0);
        let objects = (instance, physical, &device);
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let flat = target(objects, 1, usage);
        let layered = target(objects, VIEWS, usage);

        let clear_pass = render_pass(&device, vk::AttachmentLoadOp::CLEAR, vk::ImageLayout::UNDEFINED, 0);
        let load_pass = render_pass(&device, vk::AttachmentLoadOp::LOAD, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, 0);
        let multiview_pass = render_pass(&device, vk::AttachmentLoadOp::CLEAR, vk::ImageLayout::UNDEFINED, 0b11);
        let framebuffer = |pass, view| raw_vulkan::framebuffer(&device, pass, view, SIZE);
        let framebuffers = [
            framebuffer(clear_pass, flat.view),
            framebuffer(load_pass, flat.view),
            framebuffer(multiview_pass, layered.view),
        ];

        let push = [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::FRAGMENT, offset: 0, size: 16 }];
        let layout = device
            .create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push), None)
            .expect("layout");
        let pipelines = [
            pipeline(&device, layout, clear_pass),
            pipeline(&device, layout, multiview_pass),
            pipeline(&device, layout, vk::RenderPass::null()),
        ];

        let index_bytes = 48 * 2;
        let indices = buffer(objects, index_bytes, vk::BufferUsageFlags::INDEX_BUFFER, true);
        let mapped = device.map_memory(indices.1, 0, index_bytes, vk::MemoryMapFlags::empty()).expect("map");
        let words: Vec<u16> = (0..48).collect();
        std::ptr::copy_nonoverlapping(words.as_ptr(), mapped.cast::<u16>(), words.len());
        device.unmap_memory(indices.1);
        let work =
            buffer(objects, WORK_BYTES, vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC, false);
        let image_bytes = (SIZE * SIZE * 4 * (1 + VIEWS)) as u64;
        let readback = buffer(objects, image_bytes + WORK_BYTES, vk::BufferUsageFlags::TRANSFER_DST, true);
        let query = |ty, stats| {
            let info =
                vk::QueryPoolCreateInfo::default().query_type(ty).query_count(SLOTS * 4).pipeline_statistics(stats);
            device.create_query_pool(&info, None).expect("query pool")
        };
        let queries = [
            query(vk::QueryType::OCCLUSION, vk::QueryPipelineStatisticFlags::empty()),
            query(vk::QueryType::PIPELINE_STATISTICS, STATISTICS),
        ];
        let pool = device
            .create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(raw.family), None)
            .expect("command pool");
        let primary = allocate(&device, pool, vk::CommandBufferLevel::PRIMARY);
        let fence = device.create_fence(&vk::FenceCreateInfo::default(), None).expect("fence");
        let program = Program {
            raw,
            device,
            multi,
            queue,
            own_queries,
            flat,
            layered,
            passes: [clear_pass, load_pass, multiview_pass],
            framebuffers,
            layout,
            pipelines,
            indices,
            work,
            readback,
            queries,
            pool,
            primary,
            fence,
        };
        program.record();
        program
    }

    /// The draws of rectangle list `rects`, as each pass makes them.
    unsafe fn colour(&self, cmd: vk::CommandBuffer, rgba: [f32; 4]) {
        let bytes: Vec<u8> = rgba.iter().flat_map(|c| c.to_ne_bytes()).collect();
        self.device.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::FRAGMENT, 0, &bytes);
    }

    unsafe fn draw_rect(&self, cmd: vk::CommandBuffer, k: u32) {
        self.device.cmd_draw(cmd, 6, 1, 6 * k, 0);
    }

    /// Pass A's draws: a multi-draw of rectangles 0 to 2, then rectangle 3.
    unsafe fn pass_a(&self, cmd: vk::CommandBuffer) {
        self.device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipelines[0]);
        self.colour(cmd, [1.0, 0.0, 0.0, 1.0]);
        let infos: Vec<vk::MultiDrawInfoEXT> =
            (0..3).map(|k| vk::MultiDrawInfoEXT { first_vertex: 6 * k, vertex_count: 6 }).collect();
        (self.multi.fp().cmd_draw_multi_ext)(
            cmd,
            infos.len() as u32,
            infos.as_ptr(),
            1,
            0,
            std::mem::size_of::<vk::MultiDrawInfoEXT>() as u32,
        );
        self.draw_rect(cmd, 3);
    }

    /// Pass B's first secondary's draw: rectangle 4.
    unsafe fn pass_b_first(&self, cmd: vk::CommandBuffer) {
        self.device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipelines[0]);
        self.colour(cmd, [0.0, 1.0, 0.0, 1.0]);
        self.draw_rect(cmd, 4);
    }

    /// Pass B's second secondary's draws: an indexed multi-draw of rectangles 5 and 6.
    unsafe fn pass_b_second(&self, cmd: vk::CommandBuffer) {
        self.device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipelines[0]);
        self.colour(cmd, [0.0, 0.0, 1.0, 1.0]);
        self.device.cmd_bind_index_buffer(cmd, self.indices.0, 0, vk::IndexType::UINT16);
        let infos = [
            vk::MultiDrawIndexedInfoEXT { first_index: 30, index_count: 6, vertex_offset: 0 },
            vk::MultiDrawIndexedInfoEXT { first_index: 36, index_count: 6, vertex_offset: 0 },
        ];
        (self.multi.fp().cmd_draw_multi_indexed_ext)(
            cmd,
            infos.len() as u32,
            infos.as_ptr(),
            1,
            0,
            std::mem::size_of::<vk::MultiDrawIndexedInfoEXT>() as u32,
            std::ptr::null(),
        );
    }

    /// Pass D's draw: rectangle 1, through dynamic rendering's pipeline.
    unsafe fn pass_d(&self, cmd: vk::CommandBuffer) {
        self.device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipelines[2]);
        self.colour(cmd, [1.0, 1.0, 0.0, 1.0]);
        self.draw_rect(cmd, 1);
    }

    /// The program's own queries around a pass's draws (`index`: its slots).
    unsafe fn own_begin(&self, cmd: vk::CommandBuffer, index: u32) {
        if self.own_queries {
            self.device.cmd_begin_query(cmd, self.queries[0], index * SLOTS, vk::QueryControlFlags::PRECISE);
            self.device.cmd_begin_query(cmd, self.queries[1], index * SLOTS, vk::QueryControlFlags::empty());
        }
    }

    unsafe fn own_end(&self, cmd: vk::CommandBuffer, index: u32) {
        if self.own_queries {
            self.device.cmd_end_query(cmd, self.queries[1], index * SLOTS);
            self.device.cmd_end_query(cmd, self.queries[0], index * SLOTS);
        }
    }

    /// A secondary command buffer continuing a pass: `inheritance` names it; `draws` records.
    unsafe fn secondary(
        &self,
        inheritance: &vk::CommandBufferInheritanceInfo<'_>,
        flags: vk::CommandBufferUsageFlags,
        draws: impl FnOnce(vk::CommandBuffer),
    ) -> vk::CommandBuffer {
        let cmd = allocate(&self.device, self.pool, vk::CommandBufferLevel::SECONDARY);
        let begin = vk::CommandBufferBeginInfo::default().flags(flags).inheritance_info(inheritance);
        self.device.begin_command_buffer(cmd, &begin).expect("begin secondary");
        draws(cmd);
        self.device.end_command_buffer(cmd).expect("end secondary");
        cmd
    }

    /// Records the one primary command buffer every submission runs.
    unsafe fn record(&self) {
        let device = &self.device;
        let cmd = self.primary;
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: SIZE, height: SIZE } };
        let clear = [vk::ClearValue { color: vk::ClearColorValue { float32: [0.0, 0.0, 0.0, 1.0] } }];
        let begin_info = |pass, fb| {
            vk::RenderPassBeginInfo::default().render_pass(pass).framebuffer(fb).render_area(area).clear_values(&clear)
        };
        let continue_flags = vk::CommandBufferUsageFlags::RENDER_PASS_CONTINUE;
        let inherit_b = vk::CommandBufferInheritanceInfo::default()
            .render_pass(self.passes[1])
            .subpass(0)
            .framebuffer(self.framebuffers[1]);
        let formats = [FORMAT];
        let mut inherit_rendering = vk::CommandBufferInheritanceRenderingInfo::default()
            .color_attachment_formats(&formats)
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let inherit_d = vk::CommandBufferInheritanceInfo::default().push_next(&mut inherit_rendering);
        let secondaries = (!self.own_queries).then(|| {
            [
                self.secondary(&inherit_b, continue_flags, |c| self.pass_b_first(c)),
                self.secondary(&inherit_b, continue_flags, |c| self.pass_b_second(c)),
                self.secondary(&inherit_d, continue_flags, |c| self.pass_d(c)),
                self.secondary(
                    &vk::CommandBufferInheritanceInfo::default(),
                    vk::CommandBufferUsageFlags::empty(),
                    |c| {
                        device.cmd_fill_buffer(c, self.work.0, 0, WORK_BYTES, 0x0102_0304);
                    },
                ),
            ]
        });

        device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default()).expect("begin");
        if self.own_queries {
            device.cmd_reset_query_pool(cmd, self.queries[0], 0, SLOTS * 4);
            device.cmd_reset_query_pool(cmd, self.queries[1], 0, SLOTS * 4);
        }
        // A: inline, cleared.
        device.cmd_begin_render_pass(
            cmd,
            &begin_info(self.passes[0], self.framebuffers[0]),
            vk::SubpassContents::INLINE,
        );
        self.own_begin(cmd, 0);
        self.pass_a(cmd);
        self.own_end(cmd, 0);
        device.cmd_end_render_pass(cmd);
        // B: its contents in two secondaries (inline with the program's own queries).
        match &secondaries {
            Some(s) => {
                let contents = vk::SubpassContents::SECONDARY_COMMAND_BUFFERS;
                device.cmd_begin_render_pass(cmd, &begin_info(self.passes[1], self.framebuffers[1]), contents);
                device.cmd_execute_commands(cmd, &s[..2]);
            }
            None => {
                let contents = vk::SubpassContents::INLINE;
                device.cmd_begin_render_pass(cmd, &begin_info(self.passes[1], self.framebuffers[1]), contents);
                self.own_begin(cmd, 1);
                self.pass_b_first(cmd);
                self.pass_b_second(cmd);
                self.own_end(cmd, 1);
            }
        }
        device.cmd_end_render_pass(cmd);
        // C: multiview, both layers of the layered target.
        device.cmd_begin_render_pass(
            cmd,
            &begin_info(self.passes[2], self.framebuffers[2]),
            vk::SubpassContents::INLINE,
        );
        self.own_begin(cmd, 2);
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipelines[1]);
        self.colour(cmd, [1.0, 0.0, 1.0, 1.0]);
        self.draw_rect(cmd, 7);
        self.own_end(cmd, 2);
        device.cmd_end_render_pass(cmd);
        // D: dynamic rendering onto the flat target after B, its contents in a secondary.
        let barrier = [vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
            .dst_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::COLOR_ATTACHMENT_READ)];
        let colour_stage = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT;
        device.cmd_pipeline_barrier(cmd, colour_stage, colour_stage, vk::DependencyFlags::empty(), &barrier, &[], &[]);
        let attachments = [vk::RenderingAttachmentInfo::default()
            .image_view(self.flat.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let rendering = vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&attachments);
        match &secondaries {
            Some(s) => {
                let rendering = rendering.flags(vk::RenderingFlags::CONTENTS_SECONDARY_COMMAND_BUFFERS);
                device.cmd_begin_rendering(cmd, &rendering);
                device.cmd_execute_commands(cmd, &s[2..3]);
            }
            None => {
                device.cmd_begin_rendering(cmd, &rendering);
                self.own_begin(cmd, 3);
                self.pass_d(cmd);
                self.own_end(cmd, 3);
            }
        }
        device.cmd_end_rendering(cmd);
        // Work outside any pass, in a secondary: a fill (inline with the program's own queries).
        match &secondaries {
            Some(s) => device.cmd_execute_commands(cmd, &s[3..4]),
            None => device.cmd_fill_buffer(cmd, self.work.0, 0, WORK_BYTES, 0x0102_0304),
        }
        self.copy_out(cmd);
        device.end_command_buffer(cmd).expect("end");
    }

    /// Copies both targets and the filled buffer into the read-back buffer.
    unsafe fn copy_out(&self, cmd: vk::CommandBuffer) {
        let device = &self.device;
        let to_transfer = |image, layers, old| {
            vk::ImageMemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                .dst_access_mask(vk::AccessFlags::TRANSFER_READ)
                .old_layout(old)
                .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                .image(image)
                .subresource_range(colour_range(layers))
        };
        let images = [
            to_transfer(self.flat.image, 1, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
            to_transfer(self.layered.image, VIEWS, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
        ];
        let filled = [vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
            .dst_access_mask(vk::AccessFlags::TRANSFER_READ)];
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::TRANSFER,
            vk::DependencyFlags::empty(),
            &filled,
            &[],
            &images,
        );
        let layer_bytes = (SIZE * SIZE * 4) as u64;
        let region = |offset, layers| vk::BufferImageCopy {
            buffer_offset: offset,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: layers,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D { width: SIZE, height: SIZE, depth: 1 },
        };
        let transfer_src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        device.cmd_copy_image_to_buffer(cmd, self.flat.image, transfer_src, self.readback.0, &[region(0, 1)]);
        device.cmd_copy_image_to_buffer(
            cmd,
            self.layered.image,
            transfer_src,
            self.readback.0,
            &[region(layer_bytes, VIEWS)],
        );
        let copy = vk::BufferCopy { src_offset: 0, dst_offset: layer_bytes * (1 + VIEWS as u64), size: WORK_BYTES };
        device.cmd_copy_buffer(cmd, self.work.0, self.readback.0, &[copy]);
        let host = [vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
            .dst_access_mask(vk::AccessFlags::HOST_READ)];
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &host,
            &[],
            &[],
        );
        // Back for the next submission: pass A starts from UNDEFINED; the flat target's LOADs
        // (B, D) come after A.
    }

    /// One submission, waited for; the program's own figures when it has queries.
    unsafe fn submit(&self) -> Vec<Figures> {
        let buffers = [self.primary];
        let device = &self.device;
        device
            .queue_submit(self.queue, &[vk::SubmitInfo::default().command_buffers(&buffers)], self.fence)
            .expect("submit");
        device.wait_for_fences(&[self.fence], true, u64::MAX).expect("wait");
        device.reset_fences(&[self.fence]).expect("reset fence");
        if !self.own_queries {
            return Vec::new();
        }
        // Each index with its availability: a multiview query spreads its results over one index
        // per view as the implementation chooses, and their sum is the total. Mesa 22.3's
        // lavapipe writes the total to the first and leaves the others unavailable, so an
        // unavailable one adds nothing (as the layer reads them).
        let flags = vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WITH_AVAILABILITY;
        let read = |pool, query, words: usize| -> Vec<u64> {
            let mut values = [0u64; 3];
            let result = (device.fp_v1_0().get_query_pool_results)(
                device.handle(),
                pool,
                query,
                1,
                (words + 1) * 8,
                values.as_mut_ptr().cast(),
                ((words + 1) * 8) as u64,
                flags,
            );
            assert!(matches!(result, vk::Result::SUCCESS | vk::Result::NOT_READY), "{result:?}");
            if values[words] == 0 {
                vec![0; words]
            } else {
                values[..words].to_vec()
            }
        };
        known_passes()
            .iter()
            .zip(PASSES)
            .enumerate()
            .map(|(i, (known, (_, views)))| {
                let first = i as u32 * SLOTS;
                let run = first..first + views as u32;
                let occlusion: u64 = run.clone().map(|q| read(self.queries[0], q, 1)[0]).sum();
                let statistics: Vec<Vec<u64>> = run.map(|q| read(self.queries[1], q, 2)).collect();
                Figures {
                    draws: known.draws,
                    vertices: statistics.iter().map(|s| s[0]).sum(),
                    samples: occlusion,
                    fragments: Some(statistics.iter().map(|s| s[1]).sum()),
                }
            })
            .collect()
    }

    /// The read-back buffer: both targets' pixels; checks the filled words.
    unsafe fn read_back(&self) -> Vec<u8> {
        let image_bytes = (SIZE * SIZE * 4 * (1 + VIEWS)) as usize;
        let size = image_bytes as u64 + WORK_BYTES;
        let mapped = self.device.map_memory(self.readback.1, 0, size, vk::MemoryMapFlags::empty()).expect("map");
        let bytes = std::slice::from_raw_parts(mapped.cast::<u8>(), size as usize).to_vec();
        self.device.unmap_memory(self.readback.1);
        let words = &bytes[image_bytes..];
        assert!(
            words.chunks(4).all(|w| u32::from_ne_bytes([w[0], w[1], w[2], w[3]]) == 0x0102_0304),
            "the secondary's fill reached the buffer"
        );
        bytes[..image_bytes].to_vec()
    }

    unsafe fn destroy(self) {
        let device = &self.device;
        device.destroy_fence(self.fence, None);
        device.destroy_command_pool(self.pool, None);
        for pool in self.queries {
            device.destroy_query_pool(pool, None);
        }
        for (buffer, memory) in [self.indices, self.work, self.readback] {
            device.destroy_buffer(buffer, None);
            device.free_memory(memory, None);
        }
        for pipeline in self.pipelines {
            device.destroy_pipeline(pipeline, None);
        }
        device.destroy_pipeline_layout(self.layout, None);
        for fb in self.framebuffers {
            device.destroy_framebuffer(fb, None);
        }
        for pass in self.passes {
            device.destroy_render_pass(pass, None);
        }
        for t in [&self.flat, &self.layered] {
            device.destroy_image_view(t.view, None);
            device.destroy_image(t.image, None);
            device.free_memory(t.memory, None);
        }
        let _ = self.raw;
        device.destroy_device(None);
    }
}
