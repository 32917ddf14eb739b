//! A small Vulkan program of our own under the fill-rate layer, with the Khronos validation layer
//! below it (this test binary holds this one test: it sets the loader's environment). Its only
//! synchronisation is one timeline semaphore: it never waits on a fence, never idles and never
//! presents. Every frame is one submit (vkQueueSubmit2, or vkQueueSubmit with
//! VkTimelineSemaphoreSubmitInfo on odd frames) of two batches on the graphics queue:
//! - batch 1 runs a long-lived command buffer (1, 2 or 3 full-viewport triangles into an 8x8
//!   depth image, by dynamic rendering) and signals `v + 1`;
//! - batch 2 waits for `v + 2`, which the host signals later (wait-before-signal), runs a
//!   one-time command buffer of its own pool (4 triangles, inside an occlusion query of the
//!   program's own) and signals `v + 3`.
//!
//! The host waits for `v + 1` (vkWaitSemaphores) and right away resets the long-lived buffer
//! (vkResetCommandBuffer, or by re-recording it on odd frames) while batch 2 cannot have run yet.
//! Then it signals `v + 2`, waits for `v + 3`, reads its own query and resets it on the host
//! (vkResetQueryPool: the layer must have read the query at the wait), and frees the one-time
//! buffer and destroys its pool (on odd frames destroys the pool alone). When the device offers a second queue (of the
//! graphics family, or another graphics family), odd frames go to it. Last, one call runs a
//! SIMULTANEOUS_USE buffer twice in one batch and once in the next.

use crate::common;

use ash::vk;

const SIZE: u32 = 8;
const DEPTH: vk::Format = vk::Format::D32_SFLOAT;
const FRAMES: u64 = 6;
/// Triangles in each frame's one-time command buffer.
const ONCE_DRAWS: u32 = 4;
/// Triangles of the buffer submitted three times in the last call.
const TWICE_DRAWS: u32 = 2;
/// Why the first of two runs of one buffer in one batch is not measured.
const OVERWRITTEN: &str = "command buffer submitted again before its results were copied";

/// Draws of the long-lived command buffer in frame `frame`.
fn reused_draws(frame: u64) -> u32 {
    frame as u32 % 3 + 1
}

#[test]
fn timeline_only_program_on_its_queues_is_measured_with_buffers_reset_and_freed_as_soon_as_waited() {
    // It sets the process environment for the layer: in a process of its own.
    common::in_own_process("fillrate_layer_timeline::timeline_only_program_on_its_queues_is_measured_with_buffers_reset_and_freed_as_soon_as_waited", || {
            let out = common::raw_vulkan::under_the_layer("fillrate_layer_timeline");

        let mut app_samples = Vec::new();
        // SAFETY: plain Vulkan use in order: every handle is created before use, used only while
        // alive, and destroyed after the timeline wait that proves the GPU done with it.
        unsafe {
            let raw = common::raw_vulkan::raw_instance(c"timeline");
            let (instance, physical, family) = (&raw.instance, raw.physical, raw.family);
            // Two queues if the device has them: a second of the graphics family, or else the first
            // of another graphics family.
            let families = instance.get_physical_device_queue_family_properties(physical);
            let second_family = (0..families.len() as u32)
                .find(|&f| f != family && families[f as usize].queue_flags.contains(vk::QueueFlags::GRAPHICS));
            let priorities = [1.0, 1.0];
            let mut queue_infos = vec![vk::DeviceQueueCreateInfo::default()
                .queue_family_index(family)
                .queue_priorities(&priorities[..families[family as usize].queue_count.min(2) as usize])];
            let mut queues = vec![(family, 0)];
            if families[family as usize].queue_count > 1 {
                queues.push((family, 1));
            } else if let Some(other) = second_family {
                queue_infos.push(
                    vk::DeviceQueueCreateInfo::default().queue_family_index(other).queue_priorities(&priorities[..1]),
                );
                queues.push((other, 0));
            }
            eprintln!("queues used: {}", queues.len());
            let mut v12 = vk::PhysicalDeviceVulkan12Features::default().timeline_semaphore(true).host_query_reset(true);
            let mut v13 = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true).synchronization2(true);
            let mut features2 = vk::PhysicalDeviceFeatures2::default()
                .features(vk::PhysicalDeviceFeatures::default().occlusion_query_precise(true))
                .push_next(&mut v12)
                .push_next(&mut v13);
            let device = instance
                .create_device(
                    physical,
                    &vk::DeviceCreateInfo::default().queue_create_infos(&queue_infos).push_next(&mut features2),
                    None,
                )
                .expect("device");
            let queues: Vec<(u32, vk::Queue)> = queues.iter().map(|&(f, i)| (f, device.get_device_queue(f, i))).collect();

            let (image, memory, view) = common::raw_vulkan::depth_target(instance, physical, &device, DEPTH, SIZE);
            let range = common::raw_vulkan::DEPTH_RANGE;
            let layout = device.create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default(), None).expect("layout");
            let pipeline = common::raw_vulkan::depth_pipeline(&device, layout, vk::RenderPass::null(), SIZE, DEPTH);

            let mut timeline_type =
                vk::SemaphoreTypeCreateInfo::default().semaphore_type(vk::SemaphoreType::TIMELINE).initial_value(0);
            let timeline = device
                .create_semaphore(&vk::SemaphoreCreateInfo::default().push_next(&mut timeline_type), None)
                .expect("timeline semaphore");
            let wait_for = |value: u64| {
                let semaphores = [timeline];
                let values = [value];
                device
                    .wait_semaphores(&vk::SemaphoreWaitInfo::default().semaphores(&semaphores).values(&values), u64::MAX)
                    .expect("timeline wait");
            };

            // The long-lived buffer of each queue family, in a pool that resets single buffers.
            let long_lived: Vec<(vk::CommandPool, vk::CommandBuffer)> = queues
                .iter()
                .map(|&(family, _)| {
                    let pool = device
                        .create_command_pool(
                            &vk::CommandPoolCreateInfo::default()
                                .queue_family_index(family)
                                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
                            None,
                        )
                        .expect("command pool");
                    let cmd = device
                        .allocate_command_buffers(
                            &vk::CommandBufferAllocateInfo::default()
                                .command_pool(pool)
                                .level(vk::CommandBufferLevel::PRIMARY)
                                .command_buffer_count(1),
                        )
                        .expect("command buffer")[0];
                    (pool, cmd)
                })
                .collect();

            let depth_stages = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
            let depth_access =
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ;
            let layout_depth = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;
            let clear = vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } };
            let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: SIZE, height: SIZE } };
            // The program's own occlusion query, inside the one-time buffer's pass.
            let app_queries = device
                .create_query_pool(
                    &vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::OCCLUSION).query_count(1),
                    None,
                )
                .expect("query pool");
            device.reset_query_pool(app_queries, 0, 1);
            // One dynamic render pass of `draws` full-viewport triangles (inside the program's own
            // occlusion query if `query`), after a barrier that orders it after every earlier pass on
            // the image (each clears it).
            let record = |cmd: vk::CommandBuffer, flags: vk::CommandBufferUsageFlags, draws: u32, query: bool| {
                device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default().flags(flags)).expect("begin");
                let barriers = [vk::ImageMemoryBarrier2::default()
                    .image(image)
                    .subresource_range(range)
                    .old_layout(vk::ImageLayout::UNDEFINED)
                    .new_layout(layout_depth)
                    .src_stage_mask(depth_stages)
                    .src_access_mask(depth_access)
                    .dst_stage_mask(depth_stages)
                    .dst_access_mask(depth_access)];
                device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&barriers));
                let attachment = vk::RenderingAttachmentInfo::default()
                    .image_view(view)
                    .image_layout(layout_depth)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(clear);
                device.cmd_begin_rendering(
                    cmd,
                    &vk::RenderingInfo::default().render_area(area).layer_count(1).depth_attachment(&attachment),
                );
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                if query {
                    device.cmd_begin_query(cmd, app_queries, 0, vk::QueryControlFlags::PRECISE);
                }
                for _ in 0..draws {
                    device.cmd_draw(cmd, 3, 1, 0, 0);
                }
                if query {
                    device.cmd_end_query(cmd, app_queries, 0);
                }
                device.cmd_end_rendering(cmd);
                device.end_command_buffer(cmd).expect("end");
            };
            for (i, &(_, cmd)) in long_lived.iter().enumerate() {
                record(cmd, vk::CommandBufferUsageFlags::empty(), reused_draws(i as u64), false);
            }

            let mut value = 0u64;
            for frame in 0..FRAMES {
                let which = frame as usize % queues.len();
                let (family, queue) = queues[which];
                let reused = long_lived[which].1;
                let once_pool = device
                    .create_command_pool(
                        &vk::CommandPoolCreateInfo::default()
                            .queue_family_index(family)
                            .flags(vk::CommandPoolCreateFlags::TRANSIENT),
                        None,
                    )
                    .expect("command pool");
                let once = device
                    .allocate_command_buffers(
                        &vk::CommandBufferAllocateInfo::default()
                            .command_pool(once_pool)
                            .level(vk::CommandBufferLevel::PRIMARY)
                            .command_buffer_count(1),
                    )
                    .expect("command buffer")[0];
                record(once, vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT, ONCE_DRAWS, true);

                // Batch 1 after everything before (v), batch 2 after the host's signal (v + 2).
                let waits = [value, value + 2];
                let signals = [value + 1, value + 3];
                if frame % 2 == 0 {
                    let semaphore = |v: u64| {
                        [vk::SemaphoreSubmitInfo::default()
                            .semaphore(timeline)
                            .value(v)
                            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)]
                    };
                    let (wait1, wait2, signal1, signal2) =
                        (semaphore(waits[0]), semaphore(waits[1]), semaphore(signals[0]), semaphore(signals[1]));
                    let buffers1 = [vk::CommandBufferSubmitInfo::default().command_buffer(reused)];
                    let buffers2 = [vk::CommandBufferSubmitInfo::default().command_buffer(once)];
                    let batches = [
                        vk::SubmitInfo2::default()
                            .wait_semaphore_infos(&wait1)
                            .command_buffer_infos(&buffers1)
                            .signal_semaphore_infos(&signal1),
                        vk::SubmitInfo2::default()
                            .wait_semaphore_infos(&wait2)
                            .command_buffer_infos(&buffers2)
                            .signal_semaphore_infos(&signal2),
                    ];
                    device.queue_submit2(queue, &batches, vk::Fence::null()).expect("submit2");
                } else {
                    let semaphores = [timeline];
                    let stages = [vk::PipelineStageFlags::ALL_COMMANDS];
                    let (buffers1, buffers2) = ([reused], [once]);
                    let (wait1, wait2, signal1, signal2) = ([waits[0]], [waits[1]], [signals[0]], [signals[1]]);
                    let mut values1 = vk::TimelineSemaphoreSubmitInfo::default()
                        .wait_semaphore_values(&wait1)
                        .signal_semaphore_values(&signal1);
                    let mut values2 = vk::TimelineSemaphoreSubmitInfo::default()
                        .wait_semaphore_values(&wait2)
                        .signal_semaphore_values(&signal2);
                    let batches = [
                        vk::SubmitInfo::default()
                            .wait_semaphores(&semaphores)
                            .wait_dst_stage_mask(&stages)
                            .command_buffers(&buffers1)
                            .signal_semaphores(&semaphores)
                            .push_next(&mut values1),
                        vk::SubmitInfo::default()
                            .wait_semaphores(&semaphores)
                            .wait_dst_stage_mask(&stages)
                            .command_buffers(&buffers2)
                            .signal_semaphores(&semaphores)
                            .push_next(&mut values2),
                    ];
                    device.queue_submit(queue, &batches, vk::Fence::null()).expect("submit");
                }

                // Batch 1 is done; batch 2 cannot have begun. Reset the long-lived buffer now (by
                // vkResetCommandBuffer, or by re-recording it), before the layer had any other proof.
                wait_for(value + 1);
                let next_draws = reused_draws(frame + queues.len() as u64);
                if frame % 2 == 0 {
                    device.reset_command_buffer(reused, vk::CommandBufferResetFlags::empty()).expect("reset");
                }
                record(reused, vk::CommandBufferUsageFlags::empty(), next_draws, false);
                device
                    .signal_semaphore(&vk::SemaphoreSignalInfo::default().semaphore(timeline).value(value + 2))
                    .expect("signal");
                wait_for(value + 3);
                // The program reads its own query and resets it on the host for the next frame.
                let mut samples = [0u64];
                device
                    .get_query_pool_results(app_queries, 0, &mut samples, vk::QueryResultFlags::TYPE_64)
                    .expect("the program's own query");
                app_samples.push(samples[0]);
                device.reset_query_pool(app_queries, 0, 1);
                if frame % 2 == 0 {
                    device.free_command_buffers(once_pool, &[once]);
                }
                device.destroy_command_pool(once_pool, None);
                value += 3;
            }

            // One SIMULTANEOUS_USE buffer three times in one call: twice in batch 1, once in batch 2.
            // The first run's queries are overwritten by the second before any copy can run (the
            // layer puts nothing between the application's buffers): named. The other two are
            // measured, each from its own batch's copy.
            let twice = long_lived[0].1;
            record(twice, vk::CommandBufferUsageFlags::SIMULTANEOUS_USE, TWICE_DRAWS, false);
            let twice_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(twice); 2];
            let signal = [vk::SemaphoreSubmitInfo::default()
                .semaphore(timeline)
                .value(value + 1)
                .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
            let batches = [
                vk::SubmitInfo2::default().command_buffer_infos(&twice_infos),
                vk::SubmitInfo2::default().command_buffer_infos(&twice_infos[..1]).signal_semaphore_infos(&signal),
            ];
            device.queue_submit2(queues[0].1, &batches, vk::Fence::null()).expect("submit2");
            wait_for(value + 1);

            for (pool, _) in long_lived {
                device.destroy_command_pool(pool, None);
            }
            device.destroy_semaphore(timeline, None);
            device.destroy_query_pool(app_queries, None);
            device.destroy_pipeline(pipeline, None);
            device.destroy_pipeline_layout(layout, None);
            device.destroy_image_view(view, None);
            device.destroy_image(image, None);
            device.free_memory(memory, None);
            device.destroy_device(None);
            raw.destroy();
        }

        let pixels = (SIZE * SIZE) as u64;
        assert_eq!(app_samples, [ONCE_DRAWS as u64 * pixels; FRAMES as usize], "the program's own query");
        common::raw_vulkan::assert_no_messages();
        let report = common::raw_vulkan::layer_report(&out);
        let named: Vec<(&str, u64)> = report.not_measured.iter().map(|n| (n.what.as_str(), n.count)).collect();
        assert_eq!(named, [(OVERWRITTEN, 1)], "only the first of two runs in one batch is left unmeasured");
        // The program never presents: all its work is one frame, in submission order.
        assert_eq!(report.frames.len(), 1, "one frame");
        let rows = &report.frames[0].render_passes;
        let measured: Vec<(u64, Option<u64>)> = rows
            .iter()
            .map(|r| (r.counters.as_ref().map_or(0, |c| c.draws), r.counters.as_ref().map(|c| c.samples_passed)))
            .collect();
        let twice = TWICE_DRAWS as u64;
        let expected: Vec<(u64, Option<u64>)> = (0..FRAMES)
            .flat_map(|frame| {
                let reused = reused_draws(frame) as u64;
                [(reused, Some(reused * pixels)), (ONCE_DRAWS as u64, Some(ONCE_DRAWS as u64 * pixels))]
            })
            .chain([(0, None), (twice, Some(twice * pixels)), (twice, Some(twice * pixels))])
            .collect();
        assert_eq!(measured, expected, "every pass of every frame, each sample of its full-viewport triangles");
        assert_eq!(rows[2 * FRAMES as usize].not_measured.as_deref(), Some(OVERWRITTEN));
    });
}
