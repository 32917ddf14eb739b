//! What the fill-rate layer cannot measure it names and leaves alone, without a crash and
//! without a validation message from the validation layer placed below it. A small Vulkan
//! program in this process (its own test binary: it sets the loader's environment) records four
//! render pass instances: one running an empty secondary command buffer, one multiview (both
//! measured, with no draw), one plain (measured, under a debug label), one inside the
//! application's own occlusion query (named), then one through vkCmdBeginRenderPass2 and one
//! through vkCmdBeginRendering (both measured). Enabling VK_EXT_conditional_rendering, which the
//! layer does not offer, is refused (by the loader); the report names it as hidden. Its device
//! features come in a VkPhysicalDeviceFeatures2 chain (multiview, dynamic rendering), which the
//! layer extends in place.

use crate::common;

use ash::vk;

#[test]
fn what_cannot_be_measured_is_named_and_every_begin_api_is_measured() {
    // It sets the process environment for the layer: in a process of its own.
    common::in_own_process(
        "fillrate_layer_unhandled::what_cannot_be_measured_is_named_and_every_begin_api_is_measured",
        || {
            let out = common::raw_vulkan::under_the_layer("fillrate_layer_unhandled");

            // SAFETY: the whole body is plain Vulkan use in order: every handle is created before use,
            // used only while alive, and destroyed after the fence wait that proves the GPU done with it.
            unsafe {
                let raw = common::raw_vulkan::raw_instance(c"unhandled-cases");
                let (instance, physical, family) = (&raw.instance, raw.physical, raw.family);
                let priorities = [1.0];
                let queues =
                    [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
                let mut multiview = vk::PhysicalDeviceMultiviewFeatures::default().multiview(true);
                let mut dynamic = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true);
                let mut features2 =
                    vk::PhysicalDeviceFeatures2::default().push_next(&mut multiview).push_next(&mut dynamic);
                // An extension the layer does not offer (lavapipe has it): the loader, which checks
                // enabled extensions against what the layers list, refuses it.
                let hidden = [ash::ext::conditional_rendering::NAME.as_ptr()];
                let refused = instance.create_device(
                    physical,
                    &vk::DeviceCreateInfo::default().queue_create_infos(&queues).enabled_extension_names(&hidden),
                    None,
                );
                assert_eq!(refused.err(), Some(vk::Result::ERROR_EXTENSION_NOT_PRESENT), "a hidden extension");
                // The loader says why; that message is the one expected here.
                let mut messages = common::raw_vulkan::MESSAGES.lock().unwrap_or_else(|e| e.into_inner());
                let loader = |m: &String| {
                    m.contains("VK_EXT_conditional_rendering not supported")
                        || m.contains("Failed to validate extensions")
                };
                assert!(!messages.is_empty() && messages.iter().all(loader), "{messages:?}");
                messages.clear();
                drop(messages);
                let device = instance
                    .create_device(
                        physical,
                        &vk::DeviceCreateInfo::default().queue_create_infos(&queues).push_next(&mut features2),
                        None,
                    )
                    .expect("device");
                // The layer put its two features in for the call only: the application's struct is as it was.
                assert_eq!(features2.features.pipeline_statistics_query, vk::FALSE);
                let queue = device.get_device_queue(family, 0);

                let format = vk::Format::R8G8B8A8_UNORM;
                let extent = vk::Extent2D { width: 16, height: 16 };
                let image = device
                    .create_image(
                        &vk::ImageCreateInfo::default()
                            .image_type(vk::ImageType::TYPE_2D)
                            .format(format)
                            .extent(extent.into())
                            .mip_levels(1)
                            .array_layers(1)
                            .samples(vk::SampleCountFlags::TYPE_1)
                            .usage(vk::ImageUsageFlags::COLOR_ATTACHMENT),
                        None,
                    )
                    .expect("image");
                let requirements = device.get_image_memory_requirements(image);
                let memory_props = instance.get_physical_device_memory_properties(physical);
                let memory = device
                    .allocate_memory(
                        &vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(
                            common::raw_vulkan::device_local_memory_type(&memory_props, requirements.memory_type_bits),
                        ),
                        None,
                    )
                    .expect("memory");
                device.bind_image_memory(image, memory, 0).expect("bind");
                let view = device
                    .create_image_view(
                        &vk::ImageViewCreateInfo::default()
                            .image(image)
                            .view_type(vk::ImageViewType::TYPE_2D)
                            .format(format)
                            .subresource_range(vk::ImageSubresourceRange {
                                aspect_mask: vk::ImageAspectFlags::COLOR,
                                base_mip_level: 0,
                                level_count: 1,
                                base_array_layer: 0,
                                layer_count: 1,
                            }),
                        None,
                    )
                    .expect("view");

                let attachments = [vk::AttachmentDescription::default()
                    .format(format)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                    .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                    .initial_layout(vk::ImageLayout::UNDEFINED)
                    .final_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
                let colour_ref =
                    [vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
                let subpasses = [vk::SubpassDescription::default()
                    .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
                    .color_attachments(&colour_ref)];
                // One pass after another writes the same image: colour writes wait for the last pass's.
                let dependencies = [vk::SubpassDependency {
                    src_subpass: vk::SUBPASS_EXTERNAL,
                    dst_subpass: 0,
                    src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                    dst_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                    src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                    dst_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                    dependency_flags: vk::DependencyFlags::empty(),
                }];
                let info = vk::RenderPassCreateInfo::default()
                    .attachments(&attachments)
                    .subpasses(&subpasses)
                    .dependencies(&dependencies);
                let plain_pass = device.create_render_pass(&info, None).expect("render pass");
                let view_masks = [1u32];
                let mut multiview_info = vk::RenderPassMultiviewCreateInfo::default().view_masks(&view_masks);
                let multiview_pass =
                    device.create_render_pass(&info.push_next(&mut multiview_info), None).expect("multiview pass");
                let attachments2 = [vk::AttachmentDescription2::default()
                    .format(format)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .load_op(vk::AttachmentLoadOp::LOAD)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                    .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                    .initial_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .final_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
                let colour_ref2 = [vk::AttachmentReference2::default()
                    .attachment(0)
                    .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .aspect_mask(vk::ImageAspectFlags::COLOR)];
                let subpasses2 = [vk::SubpassDescription2::default()
                    .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
                    .color_attachments(&colour_ref2)];
                let dependencies2 = [vk::SubpassDependency2::default()
                    .src_subpass(vk::SUBPASS_EXTERNAL)
                    .dst_subpass(0)
                    .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
                    .dst_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
                    .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                    .dst_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::COLOR_ATTACHMENT_READ)];
                let loading_pass = device
                    .create_render_pass2(
                        &vk::RenderPassCreateInfo2::default()
                            .attachments(&attachments2)
                            .subpasses(&subpasses2)
                            .dependencies(&dependencies2),
                        None,
                    )
                    .expect("render pass 2");
                let views = [view];
                let framebuffer = |pass| {
                    device
                        .create_framebuffer(
                            &vk::FramebufferCreateInfo::default()
                                .render_pass(pass)
                                .attachments(&views)
                                .width(extent.width)
                                .height(extent.height)
                                .layers(1),
                            None,
                        )
                        .expect("framebuffer")
                };
                let (plain_fb, multiview_fb) = (framebuffer(plain_pass), framebuffer(multiview_pass));
                let loading_fb = framebuffer(loading_pass);
                let labels = ash::ext::debug_utils::Device::new(instance, &device);
                let app_queries = device
                    .create_query_pool(
                        &vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::OCCLUSION).query_count(1),
                        None,
                    )
                    .expect("query pool");
                let pool = device
                    .create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(family), None)
                    .expect("command pool");
                let allocate = |level| {
                    device
                        .allocate_command_buffers(
                            &vk::CommandBufferAllocateInfo::default()
                                .command_pool(pool)
                                .level(level)
                                .command_buffer_count(1),
                        )
                        .expect("command buffer")[0]
                };
                let (primary, secondary) =
                    (allocate(vk::CommandBufferLevel::PRIMARY), allocate(vk::CommandBufferLevel::SECONDARY));

                let inheritance = vk::CommandBufferInheritanceInfo::default()
                    .render_pass(plain_pass)
                    .subpass(0)
                    .framebuffer(plain_fb);
                device
                    .begin_command_buffer(
                        secondary,
                        &vk::CommandBufferBeginInfo::default()
                            .flags(vk::CommandBufferUsageFlags::RENDER_PASS_CONTINUE)
                            .inheritance_info(&inheritance),
                    )
                    .expect("begin secondary");
                device.end_command_buffer(secondary).expect("end secondary");

                let clear = [vk::ClearValue { color: vk::ClearColorValue { float32: [0.0, 0.0, 0.0, 1.0] } }];
                let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
                let begin = |pass, fb| {
                    vk::RenderPassBeginInfo::default()
                        .render_pass(pass)
                        .framebuffer(fb)
                        .render_area(area)
                        .clear_values(&clear)
                };
                device.begin_command_buffer(primary, &vk::CommandBufferBeginInfo::default()).expect("begin");
                device.cmd_reset_query_pool(primary, app_queries, 0, 1);
                device.cmd_begin_render_pass(
                    primary,
                    &begin(plain_pass, plain_fb),
                    vk::SubpassContents::SECONDARY_COMMAND_BUFFERS,
                );
                device.cmd_execute_commands(primary, &[secondary]);
                device.cmd_end_render_pass(primary);
                device.cmd_begin_render_pass(
                    primary,
                    &begin(multiview_pass, multiview_fb),
                    vk::SubpassContents::INLINE,
                );
                device.cmd_end_render_pass(primary);
                labels.cmd_begin_debug_utils_label(primary, &vk::DebugUtilsLabelEXT::default().label_name(c"plain"));
                device.cmd_begin_render_pass(primary, &begin(plain_pass, plain_fb), vk::SubpassContents::INLINE);
                device.cmd_end_render_pass(primary);
                labels.cmd_end_debug_utils_label(primary);
                device.cmd_begin_query(primary, app_queries, 0, vk::QueryControlFlags::empty());
                device.cmd_begin_render_pass(primary, &begin(plain_pass, plain_fb), vk::SubpassContents::INLINE);
                device.cmd_end_render_pass(primary);
                device.cmd_end_query(primary, app_queries, 0);
                device.cmd_begin_render_pass2(
                    primary,
                    &begin(loading_pass, loading_fb),
                    &vk::SubpassBeginInfo::default().contents(vk::SubpassContents::INLINE),
                );
                device.cmd_end_render_pass2(primary, &vk::SubpassEndInfo::default());
                let barrier = [vk::MemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                    .dst_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)];
                let stage = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT;
                device.cmd_pipeline_barrier(primary, stage, stage, vk::DependencyFlags::empty(), &barrier, &[], &[]);
                let colour = [vk::RenderingAttachmentInfo::default()
                    .image_view(view)
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::DONT_CARE)
                    .clear_value(clear[0])];
                device.cmd_begin_rendering(
                    primary,
                    &vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&colour),
                );
                device.cmd_end_rendering(primary);
                device.end_command_buffer(primary).expect("end");

                let fence = device.create_fence(&vk::FenceCreateInfo::default(), None).expect("fence");
                let buffers = [primary];
                device
                    .queue_submit(queue, &[vk::SubmitInfo::default().command_buffers(&buffers)], fence)
                    .expect("submit");
                device.wait_for_fences(&[fence], true, u64::MAX).expect("wait");
                // The application's own query still reads: the layer left it alone.
                let mut samples = [0u64; 1];
                device
                    .get_query_pool_results(
                        app_queries,
                        0,
                        &mut samples,
                        vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
                    )
                    .expect("the application's query result");
                assert_eq!(samples[0], 0, "no draws, no samples");

                device.destroy_fence(fence, None);
                device.destroy_command_pool(pool, None);
                device.destroy_query_pool(app_queries, None);
                device.destroy_framebuffer(plain_fb, None);
                device.destroy_framebuffer(multiview_fb, None);
                device.destroy_render_pass(plain_pass, None);
                device.destroy_render_pass(multiview_pass, None);
                device.destroy_framebuffer(loading_fb, None);
                device.destroy_render_pass(loading_pass, None);
                device.destroy_image_view(view, None);
                device.destroy_image(image, None);
                device.free_memory(memory, None);
                device.destroy_device(None);
                raw.destroy();
            }

            common::raw_vulkan::assert_no_messages();
            let report = common::raw_vulkan::layer_report(&out);
            assert_eq!(report.application, "unhandled-cases");
            let rows = &report.frames[0].render_passes;
            let reasons: Vec<Option<&str>> = rows.iter().map(|r| r.not_measured.as_deref()).collect();
            assert_eq!(
                reasons,
                vec![None, None, None, Some("application occlusion query active across the pass"), None, None]
            );
            let apis: Vec<&str> = rows.iter().map(|r| r.api.as_str()).collect();
            assert_eq!(apis[4..], ["vkCmdBeginRenderPass2", "vkCmdBeginRendering"]);
            assert_eq!(rows[2].label.as_deref(), Some("plain"));
            assert!(rows.iter().enumerate().all(|(i, r)| (i == 2) == r.label.is_some()));
            // Render pass 2 loads and stores; dynamic rendering clears and discards.
            let traffic = |r: usize| {
                let a = &rows[r].attachments[0];
                (
                    a.role.as_str(),
                    a.format.as_str(),
                    a.load_op.as_str(),
                    a.store_op.as_str(),
                    a.bytes_loaded,
                    a.bytes_stored,
                )
            };
            assert_eq!(traffic(4), ("colour", "R8G8B8A8_UNORM", "LOAD", "STORE", 1024, 1024));
            assert_eq!(traffic(5), ("colour", "R8G8B8A8_UNORM", "CLEAR", "DONT_CARE", 0, 0));
            assert!(rows[4].counters.is_some() && rows[5].counters.is_some());
            let measured = rows[2].counters.expect("the plain pass is measured");
            assert_eq!((measured.draws, measured.samples_passed), (0, 0));
            assert_eq!(measured.bytes_stored, 16 * 16 * 4);
            assert!(rows.iter().all(|r| (r.render_area.width, r.render_area.height) == (16, 16)));
            let mut named: Vec<(&str, u64)> = report.not_measured.iter().map(|n| (n.what.as_str(), n.count)).collect();
            named.sort();
            assert_eq!(named, vec![("application occlusion query active across the pass", 1)]);
            let offered_not: Vec<&str> = report.hidden_extensions.iter().map(|h| h.name.as_str()).collect();
            assert!(offered_not.contains(&"VK_EXT_conditional_rendering"), "{offered_not:?}");
            // A pass run by a secondary command buffer and a multiview pass are measured: no draws.
            for row in &rows[..2] {
                let c = row.counters.expect("measured");
                assert_eq!((c.draws, c.samples_passed, c.fragment_invocations), (0, 0, Some(0)));
            }
        },
    );
}
