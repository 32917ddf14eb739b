//! Which device extensions a program measured by the layer may see. As RenderDoc does, the
//! layer lists only the extensions whose commands it handles: an extension whose commands record
//! work the layer does not see would leave passes reading 0 draws and 0 fragments, and nothing
//! would say so. So every extension is one of:
//! - **handled**: it has commands that record draws, dispatches, transfers, render passes or
//!   queries, and the layer hooks each of them (VK_EXT_multi_draw's draws, for one);
//! - **passive**: its commands (if any) set state, create objects or query the device, which
//!   changes no count the layer takes (dynamic state, memory, formats, shader features);
//! - **hidden**, with the reason the report gives: what the layer knows it cannot measure, and
//!   every extension it does not know.
//!
//! Hidden extensions are left out of `vkEnumerateDeviceExtensionProperties` and their feature
//! structs answer `VK_FALSE` (`hide_features`), while the layer measures (an output is set).

use std::collections::BTreeMap;
use std::ffi::c_void;
use std::sync::Mutex;

use ash::vk;

use super::report::HiddenExtension;
use super::state::lock;

/// The extensions hidden from the program so far in this process, with why: the report names
/// them (`hidden_extensions`).
static HIDDEN_SO_FAR: Mutex<BTreeMap<String, &'static str>> = Mutex::new(BTreeMap::new());

/// Extensions whose work commands the layer hooks (exports.rs), or which it offers itself.
const HANDLED: &[&str] = &[
    "VK_KHR_swapchain",
    "VK_KHR_create_renderpass2",
    "VK_KHR_dynamic_rendering",
    "VK_KHR_imageless_framebuffer",
    "VK_KHR_draw_indirect_count",
    "VK_EXT_multi_draw",
    "VK_EXT_transform_feedback",
    "VK_EXT_mesh_shader",
    "VK_NV_mesh_shader",
    "VK_KHR_copy_commands2",
    "VK_KHR_synchronization2",
    "VK_KHR_timeline_semaphore",
    "VK_KHR_device_group",
    "VK_EXT_host_query_reset",
    "VK_KHR_descriptor_update_template",
    "VK_KHR_push_descriptor",
    "VK_KHR_multiview",
    "VK_EXT_frame_boundary",
    "VK_EXT_debug_marker",
];

/// Extensions with no command that records work: state, objects, formats, shader features.
const PASSIVE: &[&str] = &[
    "VK_KHR_16bit_storage",
    "VK_KHR_8bit_storage",
    "VK_KHR_bind_memory2",
    "VK_KHR_buffer_device_address",
    "VK_KHR_calibrated_timestamps",
    "VK_KHR_dedicated_allocation",
    "VK_KHR_depth_stencil_resolve",
    "VK_KHR_driver_properties",
    "VK_KHR_dynamic_rendering_local_read",
    "VK_KHR_external_fence",
    "VK_KHR_external_fence_fd",
    "VK_KHR_external_memory",
    "VK_KHR_external_memory_fd",
    "VK_KHR_external_semaphore",
    "VK_KHR_external_semaphore_fd",
    "VK_KHR_format_feature_flags2",
    "VK_KHR_fragment_shader_barycentric",
    "VK_KHR_fragment_shading_rate",
    "VK_KHR_get_memory_requirements2",
    "VK_KHR_global_priority",
    "VK_KHR_image_format_list",
    "VK_KHR_incremental_present",
    "VK_KHR_index_type_uint8",
    "VK_KHR_line_rasterization",
    "VK_KHR_load_store_op_none",
    "VK_KHR_maintenance1",
    "VK_KHR_maintenance2",
    "VK_KHR_maintenance3",
    "VK_KHR_maintenance4",
    "VK_KHR_maintenance5",
    "VK_KHR_maintenance6",
    "VK_KHR_pipeline_executable_properties",
    "VK_KHR_pipeline_library",
    "VK_KHR_portability_subset",
    "VK_KHR_present_id",
    "VK_KHR_present_wait",
    "VK_KHR_relaxed_block_layout",
    "VK_KHR_sampler_mirror_clamp_to_edge",
    "VK_KHR_sampler_ycbcr_conversion",
    "VK_KHR_separate_depth_stencil_layouts",
    "VK_KHR_shader_atomic_int64",
    "VK_KHR_shader_clock",
    "VK_KHR_shader_draw_parameters",
    "VK_KHR_shader_expect_assume",
    "VK_KHR_shader_float16_int8",
    "VK_KHR_shader_float_controls",
    "VK_KHR_shader_float_controls2",
    "VK_KHR_shader_integer_dot_product",
    "VK_KHR_shader_maximal_reconvergence",
    "VK_KHR_shader_non_semantic_info",
    "VK_KHR_shader_quad_control",
    "VK_KHR_shader_subgroup_extended_types",
    "VK_KHR_shader_subgroup_rotate",
    "VK_KHR_shader_subgroup_uniform_control_flow",
    "VK_KHR_shader_terminate_invocation",
    "VK_KHR_spirv_1_4",
    "VK_KHR_storage_buffer_storage_class",
    "VK_KHR_swapchain_mutable_format",
    "VK_KHR_uniform_buffer_standard_layout",
    "VK_KHR_variable_pointers",
    "VK_KHR_vertex_attribute_divisor",
    "VK_KHR_vulkan_memory_model",
    "VK_KHR_workgroup_memory_explicit_layout",
    "VK_KHR_zero_initialize_workgroup_memory",
    "VK_EXT_4444_formats",
    "VK_EXT_astc_decode_mode",
    "VK_EXT_attachment_feedback_loop_dynamic_state",
    "VK_EXT_attachment_feedback_loop_layout",
    "VK_EXT_blend_operation_advanced",
    "VK_EXT_border_color_swizzle",
    "VK_EXT_calibrated_timestamps",
    "VK_EXT_color_write_enable",
    "VK_EXT_conservative_rasterization",
    "VK_EXT_custom_border_color",
    "VK_EXT_depth_bias_control",
    "VK_EXT_depth_clamp_zero_one",
    "VK_EXT_depth_clip_control",
    "VK_EXT_depth_clip_enable",
    "VK_EXT_depth_range_unrestricted",
    "VK_EXT_descriptor_indexing",
    "VK_EXT_display_control",
    "VK_EXT_dynamic_rendering_unused_attachments",
    "VK_EXT_extended_dynamic_state",
    "VK_EXT_extended_dynamic_state2",
    "VK_EXT_extended_dynamic_state3",
    "VK_EXT_external_memory_dma_buf",
    "VK_EXT_external_memory_host",
    "VK_EXT_filter_cubic",
    "VK_EXT_fragment_shader_interlock",
    "VK_EXT_global_priority",
    "VK_EXT_global_priority_query",
    "VK_EXT_graphics_pipeline_library",
    "VK_EXT_hdr_metadata",
    "VK_EXT_image_2d_view_of_3d",
    "VK_EXT_image_drm_format_modifier",
    "VK_EXT_image_robustness",
    "VK_EXT_image_view_min_lod",
    "VK_EXT_index_type_uint8",
    "VK_EXT_inline_uniform_block",
    "VK_EXT_legacy_dithering",
    "VK_EXT_line_rasterization",
    "VK_EXT_load_store_op_none",
    "VK_EXT_memory_budget",
    "VK_EXT_memory_priority",
    "VK_EXT_mutable_descriptor_type",
    "VK_EXT_non_seamless_cube_map",
    "VK_EXT_pageable_device_local_memory",
    "VK_EXT_pci_bus_info",
    "VK_EXT_physical_device_drm",
    "VK_EXT_pipeline_creation_cache_control",
    "VK_EXT_pipeline_creation_feedback",
    "VK_EXT_pipeline_robustness",
    "VK_EXT_post_depth_coverage",
    "VK_EXT_primitive_topology_list_restart",
    "VK_EXT_primitives_generated_query",
    "VK_EXT_private_data",
    "VK_EXT_provoking_vertex",
    "VK_EXT_queue_family_foreign",
    "VK_EXT_rasterization_order_attachment_access",
    "VK_EXT_robustness2",
    "VK_EXT_sample_locations",
    "VK_EXT_sampler_filter_minmax",
    "VK_EXT_scalar_block_layout",
    "VK_EXT_separate_stencil_usage",
    "VK_EXT_shader_atomic_float",
    "VK_EXT_shader_atomic_float2",
    "VK_EXT_shader_demote_to_helper_invocation",
    "VK_EXT_shader_image_atomic_int64",
    "VK_EXT_shader_module_identifier",
    "VK_EXT_shader_object",
    "VK_EXT_shader_stencil_export",
    "VK_EXT_shader_subgroup_ballot",
    "VK_EXT_shader_subgroup_vote",
    "VK_EXT_shader_viewport_index_layer",
    "VK_EXT_subgroup_size_control",
    "VK_EXT_swapchain_maintenance1",
    "VK_EXT_texel_buffer_alignment",
    "VK_EXT_texture_compression_astc_hdr",
    "VK_EXT_tooling_info",
    "VK_EXT_validation_cache",
    "VK_EXT_vertex_attribute_divisor",
    "VK_EXT_vertex_input_dynamic_state",
    "VK_EXT_ycbcr_2plane_444_formats",
    "VK_EXT_ycbcr_image_arrays",
    "VK_ARM_rasterization_order_attachment_access",
    "VK_GOOGLE_decorate_string",
    "VK_GOOGLE_display_timing",
    "VK_GOOGLE_hlsl_functionality1",
    "VK_GOOGLE_user_type",
    "VK_VALVE_mutable_descriptor_type",
];

/// Extensions the layer knows it cannot measure, and why.
const HIDDEN: &[(&str, &str)] = &[
    (
        "VK_EXT_conditional_rendering",
        "draws under conditional rendering may be skipped by the GPU, so the draws counted would not be the draws run",
    ),
    (
        "VK_EXT_multisampled_render_to_single_sampled",
        "passes rasterised at more samples than their attachments hold: the tile traffic would be counted at the wrong sample count",
    ),
    ("VK_EXT_nested_command_buffer", "secondary command buffers executed from secondary command buffers"),
    ("VK_KHR_ray_tracing_pipeline", "vkCmdTraceRaysKHR: ray tracing work"),
    ("VK_KHR_ray_tracing_maintenance1", "vkCmdTraceRaysIndirect2KHR: ray tracing work"),
    ("VK_KHR_acceleration_structure", "acceleration structure builds: GPU work outside render passes"),
    ("VK_EXT_device_generated_commands", "draws and dispatches generated on the GPU"),
    ("VK_NV_device_generated_commands", "draws and dispatches generated on the GPU"),
    ("VK_EXT_descriptor_buffer", "descriptors in buffers, which the tiler check cannot follow"),
    ("VK_KHR_video_queue", "video coding work"),
    ("VK_KHR_video_decode_queue", "video decoding work"),
    ("VK_KHR_video_encode_queue", "video encoding work"),
];

/// Why the layer hides `name` from the program, or None when the program may see it.
pub fn hidden_because(name: &str) -> Option<&'static str> {
    if HANDLED.contains(&name) || PASSIVE.contains(&name) {
        return None;
    }
    if let Some((_, why)) = HIDDEN.iter().find(|(n, _)| *n == name) {
        return Some(why);
    }
    if name.starts_with("VK_KHR_video_") {
        return Some("video coding work");
    }
    Some("not known to the layer: its commands could record work the layer would not see")
}

/// Whether the program is offered `extension`; a hidden one is remembered for the report.
pub fn offered(extension: &vk::ExtensionProperties) -> bool {
    let Ok(name) = extension.extension_name_as_c_str() else { return false };
    let name = name.to_string_lossy();
    match hidden_because(&name) {
        None => true,
        Some(why) => {
            lock(&HIDDEN_SO_FAR).insert(name.into_owned(), why);
            false
        }
    }
}

/// The extensions hidden so far, each with why.
pub fn hidden_so_far() -> Vec<HiddenExtension> {
    lock(&HIDDEN_SO_FAR).iter().map(|(name, why)| HiddenExtension { name: name.clone(), why: (*why).into() }).collect()
}

/// Sets to VK_FALSE the features of hidden extensions in a vkGetPhysicalDeviceFeatures2 chain,
/// so that a program that checks features rather than extensions does not use them either.
///
/// # Safety
/// `p_next` is a valid, writable pNext chain (the application's output structs).
pub unsafe fn hide_features(mut p_next: *mut c_void) {
    while !p_next.is_null() {
        let base = p_next as *mut vk::BaseOutStructure<'_>;
        // SAFETY: every chain node starts like VkBaseOutStructure; each struct below is the
        // node's own type, by its sType.
        unsafe {
            match (*base).s_type {
                vk::StructureType::PHYSICAL_DEVICE_CONDITIONAL_RENDERING_FEATURES_EXT => {
                    let f = &mut *(p_next as *mut vk::PhysicalDeviceConditionalRenderingFeaturesEXT<'_>);
                    f.conditional_rendering = vk::FALSE;
                    f.inherited_conditional_rendering = vk::FALSE;
                }
                vk::StructureType::PHYSICAL_DEVICE_MULTISAMPLED_RENDER_TO_SINGLE_SAMPLED_FEATURES_EXT => {
                    let f = &mut *(p_next as *mut vk::PhysicalDeviceMultisampledRenderToSingleSampledFeaturesEXT<'_>);
                    f.multisampled_render_to_single_sampled = vk::FALSE;
                }
                vk::StructureType::PHYSICAL_DEVICE_NESTED_COMMAND_BUFFER_FEATURES_EXT => {
                    let f = &mut *(p_next as *mut vk::PhysicalDeviceNestedCommandBufferFeaturesEXT<'_>);
                    f.nested_command_buffer = vk::FALSE;
                    f.nested_command_buffer_rendering = vk::FALSE;
                    f.nested_command_buffer_simultaneous_use = vk::FALSE;
                }
                _ => {}
            }
            p_next = (*base).p_next.cast();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_zink_and_the_real_programs_use_is_seen_and_what_records_unseen_work_is_hidden() {
        for seen in ["VK_EXT_multi_draw", "VK_KHR_swapchain", "VK_EXT_transform_feedback", "VK_KHR_dynamic_rendering"] {
            assert_eq!(hidden_because(seen), None, "{seen}");
        }
        for hidden in ["VK_EXT_conditional_rendering", "VK_KHR_ray_tracing_pipeline", "VK_KHR_video_decode_h264"] {
            assert!(hidden_because(hidden).is_some(), "{hidden}");
        }
        let unknown = hidden_because("VK_NV_something_new").expect("an unknown extension is hidden");
        assert!(unknown.contains("not known"), "{unknown}");
    }

    #[test]
    fn no_extension_is_both_seen_and_hidden() {
        for (name, _) in HIDDEN {
            assert!(!HANDLED.contains(name) && !PASSIVE.contains(name), "{name}");
        }
        for name in HANDLED {
            assert!(!PASSIVE.contains(name), "{name} is listed twice");
        }
    }

    #[test]
    fn a_hidden_extensions_feature_reads_false_and_others_are_left_alone() {
        let mut multi = vk::PhysicalDeviceMultiDrawFeaturesEXT::default().multi_draw(true);
        let mut conditional = vk::PhysicalDeviceConditionalRenderingFeaturesEXT::default()
            .conditional_rendering(true)
            .inherited_conditional_rendering(true);
        conditional.p_next = (&mut multi as *mut vk::PhysicalDeviceMultiDrawFeaturesEXT<'_>).cast();
        // SAFETY: a chain of two live structs.
        unsafe {
            hide_features((&mut conditional as *mut vk::PhysicalDeviceConditionalRenderingFeaturesEXT<'_>).cast())
        };
        assert_eq!(conditional.conditional_rendering, vk::FALSE);
        assert_eq!(conditional.inherited_conditional_rendering, vk::FALSE);
        assert_eq!(multi.multi_draw, vk::TRUE);
    }
}
