//! A small Vulkan program of our own under the fill-rate layer, with the Khronos validation layer
//! below it (this test binary holds this one test: it sets the loader's environment). It
//! pre-records three command buffers with SIMULTANEOUS_USE, drawing one, two and three
//! full-viewport triangles into an 8x8 depth image (64 samples each), and submits them five
//! times without waiting in between, so each is re-submitted while its previous submission may
//! still be in flight. In the same batches: a dynamic render pass suspended in one command
//! buffer and resumed in the next (the layer must put nothing between them), and once a render
//! pass running a secondary command buffer. The program's own occlusion queries, around the same
//! draws, give the reference counts.

use crate::common;

use ash::vk;

const SIZE: u32 = 8;
const DEPTH: vk::Format = vk::Format::D32_SFLOAT;
/// Rounds of submitting the three pre-recorded buffers without waiting.
const ROUNDS: usize = 5;

#[test]
fn resubmitted_simultaneous_use_buffers_are_measured_every_time_and_suspended_passes_are_left_whole() {
    // It sets the process environment for the layer: in a process of its own.
    common::in_own_process("fillrate_layer_resubmit::resubmitted_simultaneous_use_buffers_are_measured_every_time_and_suspended_passes_are_left_whole", || {
            let out = common::raw_vulkan::under_the_layer("fillrate_layer_resubmit");

        let reference: Vec<u64>;
        // SAFETY: plain Vulkan use in order: every handle is created before use, used only while
        // alive, and destroyed after the fence wait that proves the GPU done with it.
        unsafe {
            let raw = common::raw_vulkan::raw_instance(c"resubmit");
            let (instance, physical, family) = (&raw.instance, raw.physical, raw.family);
            let priorities = [1.0];
            let queues = [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
            let mut v13 = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true).synchronization2(true);
            let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut v13);
            let device = instance
                .create_device(
                    physical,
                    &vk::DeviceCreateInfo::default().queue_create_infos(&queues).push_next(&mut features2),
                    None,
                )
                .expect("device");
            let queue = device.get_device_queue(family, 0);

            let (image, memory, view) = common::raw_vulkan::depth_target(instance, physical, &device, DEPTH, SIZE);
            let range = common::raw_vulkan::DEPTH_RANGE;
            let layout_depth = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
            let attachments = [vk::AttachmentDescription::default()
                .format(DEPTH)
                .samples(vk::SampleCountFlags::TYPE_1)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                .initial_layout(vk::ImageLayout::UNDEFINED)
                .final_layout(layout_depth)];
            let depth_ref = vk::AttachmentReference { attachment: 0, layout: layout_depth };
            let subpasses = [vk::SubpassDescription::default()
                .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
                .depth_stencil_attachment(&depth_ref)];
            let depth_stages = vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
            let depth_access =
                vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ;
            // Each pass clears the image the last one used: depth work waits for the last pass's.
            let dependencies = [vk::SubpassDependency {
                src_subpass: vk::SUBPASS_EXTERNAL,
                dst_subpass: 0,
                src_stage_mask: depth_stages,
                dst_stage_mask: depth_stages,
                src_access_mask: depth_access,
                dst_access_mask: depth_access,
                dependency_flags: vk::DependencyFlags::empty(),
            }];
            let render_pass = device
                .create_render_pass(
                    &vk::RenderPassCreateInfo::default()
                        .attachments(&attachments)
                        .subpasses(&subpasses)
                        .dependencies(&dependencies),
                    None,
                )
                .expect("render pass");
            let views = [view];
            let framebuffer = device
                .create_framebuffer(
                    &vk::FramebufferCreateInfo::default()
                        .render_pass(render_pass)
                        .attachments(&views)
                        .width(SIZE)
                        .height(SIZE)
                        .layers(1),
                    None,
                )
                .expect("framebuffer");
            let layout = device.create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default(), None).expect("layout");
            let pass_pipeline = common::raw_vulkan::depth_pipeline(&device, layout, render_pass, SIZE, DEPTH);
            let dynamic_pipeline = common::raw_vulkan::depth_pipeline(&device, layout, vk::RenderPass::null(), SIZE, DEPTH);
            let app_queries = device
                .create_query_pool(
                    &vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::OCCLUSION).query_count(3),
                    None,
                )
                .expect("query pool");
            let pool = device
                .create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(family), None)
                .expect("command pool");
            let allocate = |level, count| {
                device
                    .allocate_command_buffers(
                        &vk::CommandBufferAllocateInfo::default()
                            .command_pool(pool)
                            .level(level)
                            .command_buffer_count(count),
                    )
                    .expect("command buffers")
            };
            let primaries = allocate(vk::CommandBufferLevel::PRIMARY, 7);
            let secondary = allocate(vk::CommandBufferLevel::SECONDARY, 1)[0];
            let (reference_cmd, pre_recorded, suspend, resume, with_secondary) =
                (primaries[0], &primaries[1..4], primaries[4], primaries[5], primaries[6]);

            let clear = [vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } }];
            let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: SIZE, height: SIZE } };
            let begin_pass = vk::RenderPassBeginInfo::default()
                .render_pass(render_pass)
                .framebuffer(framebuffer)
                .render_area(area)
                .clear_values(&clear);
            let draws_into = |cmd: vk::CommandBuffer, pipeline: vk::Pipeline, draws: u32| {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                for _ in 0..draws {
                    device.cmd_draw(cmd, 3, 1, 0, 0);
                }
            };

            // The reference: the program's own occlusion query across each of the three passes.
            device.begin_command_buffer(reference_cmd, &vk::CommandBufferBeginInfo::default()).expect("begin");
            device.cmd_reset_query_pool(reference_cmd, app_queries, 0, 3);
            for draws in 1..=3u32 {
                device.cmd_begin_query(reference_cmd, app_queries, draws - 1, vk::QueryControlFlags::PRECISE);
                device.cmd_begin_render_pass(reference_cmd, &begin_pass, vk::SubpassContents::INLINE);
                draws_into(reference_cmd, pass_pipeline, draws);
                device.cmd_end_render_pass(reference_cmd);
                device.cmd_end_query(reference_cmd, app_queries, draws - 1);
            }
            device.end_command_buffer(reference_cmd).expect("end");
            let fence = device.create_fence(&vk::FenceCreateInfo::default(), None).expect("fence");
            let one = [reference_cmd];
            device.queue_submit(queue, &[vk::SubmitInfo::default().command_buffers(&one)], fence).expect("submit");
            device.wait_for_fences(&[fence], true, u64::MAX).expect("wait");
            device.reset_fences(&[fence]).expect("reset");
            let mut samples = [0u64; 3];
            device
                .get_query_pool_results(
                    app_queries,
                    0,
                    &mut samples,
                    vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
                )
                .expect("the program's own queries");
            reference = samples.to_vec();

            // Three buffers recorded once, submitted again and again.
            let simultaneous = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::SIMULTANEOUS_USE);
            for (i, &cmd) in pre_recorded.iter().enumerate() {
                device.begin_command_buffer(cmd, &simultaneous).expect("begin");
                device.cmd_begin_render_pass(cmd, &begin_pass, vk::SubpassContents::INLINE);
                draws_into(cmd, pass_pipeline, i as u32 + 1);
                device.cmd_end_render_pass(cmd);
                device.end_command_buffer(cmd).expect("end");
            }
            // A dynamic render pass suspended in one buffer and resumed in the next.
            let to_depth = [vk::ImageMemoryBarrier::default()
                .image(image)
                .subresource_range(range)
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(layout_depth)
                .src_access_mask(depth_access)
                .dst_access_mask(depth_access)];
            let depth_attachment = vk::RenderingAttachmentInfo::default()
                .image_view(view)
                .image_layout(layout_depth)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(clear[0]);
            let rendering = |flags| {
                vk::RenderingInfo::default()
                    .render_area(area)
                    .layer_count(1)
                    .depth_attachment(&depth_attachment)
                    .flags(flags)
            };
            for (cmd, flags) in [(suspend, vk::RenderingFlags::SUSPENDING), (resume, vk::RenderingFlags::RESUMING)] {
                device.begin_command_buffer(cmd, &simultaneous).expect("begin");
                if flags == vk::RenderingFlags::SUSPENDING {
                    device.cmd_pipeline_barrier(
                        cmd,
                        depth_stages,
                        depth_stages,
                        vk::DependencyFlags::empty(),
                        &[],
                        &[],
                        &to_depth,
                    );
                }
                device.cmd_begin_rendering(cmd, &rendering(flags));
                draws_into(cmd, dynamic_pipeline, 1);
                device.cmd_end_rendering(cmd);
                device.end_command_buffer(cmd).expect("end");
            }
            // A render pass whose draw is in a secondary command buffer.
            let inheritance =
                vk::CommandBufferInheritanceInfo::default().render_pass(render_pass).subpass(0).framebuffer(framebuffer);
            device
                .begin_command_buffer(
                    secondary,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::RENDER_PASS_CONTINUE)
                        .inheritance_info(&inheritance),
                )
                .expect("begin secondary");
            draws_into(secondary, pass_pipeline, 1);
            device.end_command_buffer(secondary).expect("end secondary");
            device.begin_command_buffer(with_secondary, &vk::CommandBufferBeginInfo::default()).expect("begin");
            device.cmd_begin_render_pass(with_secondary, &begin_pass, vk::SubpassContents::SECONDARY_COMMAND_BUFFERS);
            device.cmd_execute_commands(with_secondary, &[secondary]);
            device.cmd_end_render_pass(with_secondary);
            device.end_command_buffer(with_secondary).expect("end");

            // Every round in one submit, none waited for before the next: A, suspend, resume, B, C.
            let batch = [pre_recorded[0], suspend, resume, pre_recorded[1], pre_recorded[2]];
            for round in 0..ROUNDS {
                let last = round + 1 == ROUNDS;
                let signal = if last { fence } else { vk::Fence::null() };
                if round == 1 {
                    // vkQueueSubmit2, with the secondary command buffer's pass first.
                    let infos: Vec<vk::CommandBufferSubmitInfo> = [with_secondary]
                        .iter()
                        .chain(&batch)
                        .map(|&c| vk::CommandBufferSubmitInfo::default().command_buffer(c))
                        .collect();
                    device
                        .queue_submit2(queue, &[vk::SubmitInfo2::default().command_buffer_infos(&infos)], signal)
                        .expect("submit2");
                } else {
                    device
                        .queue_submit(queue, &[vk::SubmitInfo::default().command_buffers(&batch)], signal)
                        .expect("submit");
                }
            }
            device.wait_for_fences(&[fence], true, u64::MAX).expect("wait");

            device.destroy_fence(fence, None);
            device.destroy_command_pool(pool, None);
            device.destroy_query_pool(app_queries, None);
            device.destroy_pipeline(pass_pipeline, None);
            device.destroy_pipeline(dynamic_pipeline, None);
            device.destroy_pipeline_layout(layout, None);
            device.destroy_framebuffer(framebuffer, None);
            device.destroy_render_pass(render_pass, None);
            device.destroy_image_view(view, None);
            device.destroy_image(image, None);
            device.free_memory(memory, None);
            device.destroy_device(None);
            raw.destroy();
        }

        common::raw_vulkan::assert_no_messages();
        let pixels = (SIZE * SIZE) as u64;
        assert_eq!(reference, [pixels, 2 * pixels, 3 * pixels], "the program's own queries");
        let report = common::raw_vulkan::layer_report(&out);
        // The program never presents: all its work is one frame.
        let rows = &report.frames[0].render_passes;
        let measured: Vec<(u64, u64)> =
            rows.iter().filter_map(|r| r.counters.as_ref()).map(|c| (c.draws, c.samples_passed)).collect();
        // Round 1 begins with the pass whose one draw is in a secondary command buffer.
        let expected: Vec<(u64, u64)> = (0..ROUNDS)
            .flat_map(|round| {
                let secondary = (round == 1).then_some((1, reference[0]));
                secondary.into_iter().chain((1..=3u64).map(|d| (d, reference[d as usize - 1])))
            })
            .collect();
        assert_eq!(measured, expected, "every submission of the pre-recorded buffers, as the program counts them");
        let mut named: Vec<(&str, u64)> = report.not_measured.iter().map(|n| (n.what.as_str(), n.count)).collect();
        named.sort();
        assert_eq!(
            named,
            vec![
                ("application occlusion query active across the pass", 3),
                ("suspended or resumed dynamic render pass", 2 * ROUNDS as u64),
            ]
        );
    });
}
