//! The layer's exported surface: `vkNegotiateLoaderLayerInterfaceVersion` (interface version 2)
//! and the two `vkGet*ProcAddr`, which hand out the layer's hooks by name and the next layer's
//! functions for everything else.

use std::ffi::c_char;

use ash::vk;
use ash::vk::Handle;

use super::config::Config;
use super::lifecycle::{c_name, create_device, create_instance, destroy_device, destroy_instance};
use super::loader::{NegotiateLayerInterface, LAYER_INTERFACE_VERSION, LAYER_NEGOTIATE_INTERFACE_STRUCT};
use super::state::{self, guard};
use super::{
    capture, commands as c, draw_hooks as d, frame_boundary as fb, image_use as t, objects as o, queue as q,
    transfer_hooks as x, work_hooks as w, work_objects as wo,
};

/// A hook as the loader's generic function pointer.
macro_rules! void_fn {
    ($f:expr, $pfn:ty) => {{
        let f: $pfn = $f;
        // SAFETY: function pointers of any signature have one size; the loader casts back to
        // the type of the name it asked for, which is `$pfn`.
        Some(unsafe { std::mem::transmute::<$pfn, unsafe extern "system" fn()>(f) })
    }};
}

/// The layer's hook for a device-level function name, if it hooks it.
fn device_hook(name: &str) -> vk::PFN_vkVoidFunction {
    match name {
        "vkGetDeviceProcAddr" => void_fn!(get_device_proc_addr, vk::PFN_vkGetDeviceProcAddr),
        "vkDestroyDevice" => void_fn!(destroy_device, vk::PFN_vkDestroyDevice),
        "vkCreateRenderPass" => void_fn!(o::create_render_pass, vk::PFN_vkCreateRenderPass),
        "vkCreateRenderPass2" => void_fn!(o::create_render_pass2, vk::PFN_vkCreateRenderPass2),
        "vkCreateRenderPass2KHR" => void_fn!(o::create_render_pass2_khr, vk::PFN_vkCreateRenderPass2),
        "vkDestroyRenderPass" => void_fn!(o::destroy_render_pass, vk::PFN_vkDestroyRenderPass),
        "vkCreateImage" => void_fn!(o::create_image, vk::PFN_vkCreateImage),
        "vkDestroyImage" => void_fn!(o::destroy_image, vk::PFN_vkDestroyImage),
        "vkCreateImageView" => void_fn!(o::create_image_view, vk::PFN_vkCreateImageView),
        "vkDestroyImageView" => void_fn!(o::destroy_image_view, vk::PFN_vkDestroyImageView),
        "vkCreateCommandPool" => void_fn!(o::create_command_pool, vk::PFN_vkCreateCommandPool),
        "vkDestroyCommandPool" => void_fn!(o::destroy_command_pool, vk::PFN_vkDestroyCommandPool),
        "vkResetCommandPool" => void_fn!(o::reset_command_pool, vk::PFN_vkResetCommandPool),
        "vkAllocateCommandBuffers" => void_fn!(o::allocate_command_buffers, vk::PFN_vkAllocateCommandBuffers),
        "vkFreeCommandBuffers" => void_fn!(o::free_command_buffers, vk::PFN_vkFreeCommandBuffers),
        "vkCreateQueryPool" => void_fn!(o::create_query_pool, vk::PFN_vkCreateQueryPool),
        "vkDestroyQueryPool" => void_fn!(o::destroy_query_pool, vk::PFN_vkDestroyQueryPool),
        "vkResetQueryPool" => void_fn!(o::reset_query_pool, vk::PFN_vkResetQueryPool),
        "vkResetQueryPoolEXT" => void_fn!(o::reset_query_pool_ext, vk::PFN_vkResetQueryPool),
        "vkBeginCommandBuffer" => void_fn!(c::begin_command_buffer, vk::PFN_vkBeginCommandBuffer),
        "vkResetCommandBuffer" => void_fn!(c::reset_command_buffer, vk::PFN_vkResetCommandBuffer),
        "vkCmdResetQueryPool" => void_fn!(d::cmd_reset_query_pool, vk::PFN_vkCmdResetQueryPool),
        "vkCmdBeginQuery" => void_fn!(d::cmd_begin_query, vk::PFN_vkCmdBeginQuery),
        "vkCmdEndQuery" => void_fn!(d::cmd_end_query, vk::PFN_vkCmdEndQuery),
        "vkCmdBeginRenderPass" => void_fn!(c::cmd_begin_render_pass, vk::PFN_vkCmdBeginRenderPass),
        "vkCmdBeginRenderPass2" => void_fn!(c::cmd_begin_render_pass2, vk::PFN_vkCmdBeginRenderPass2),
        "vkCmdBeginRenderPass2KHR" => void_fn!(c::cmd_begin_render_pass2_khr, vk::PFN_vkCmdBeginRenderPass2),
        "vkCmdNextSubpass" => void_fn!(c::cmd_next_subpass, vk::PFN_vkCmdNextSubpass),
        "vkCmdNextSubpass2" => void_fn!(c::cmd_next_subpass2, vk::PFN_vkCmdNextSubpass2),
        "vkCmdNextSubpass2KHR" => void_fn!(c::cmd_next_subpass2_khr, vk::PFN_vkCmdNextSubpass2),
        "vkCmdEndRenderPass" => void_fn!(c::cmd_end_render_pass, vk::PFN_vkCmdEndRenderPass),
        "vkCmdEndRenderPass2" => void_fn!(c::cmd_end_render_pass2, vk::PFN_vkCmdEndRenderPass2),
        "vkCmdEndRenderPass2KHR" => void_fn!(c::cmd_end_render_pass2_khr, vk::PFN_vkCmdEndRenderPass2),
        "vkCmdBeginRendering" => void_fn!(c::cmd_begin_rendering, vk::PFN_vkCmdBeginRendering),
        "vkCmdBeginRenderingKHR" => void_fn!(c::cmd_begin_rendering_khr, vk::PFN_vkCmdBeginRendering),
        "vkCmdEndRendering" => void_fn!(c::cmd_end_rendering, vk::PFN_vkCmdEndRendering),
        "vkCmdEndRenderingKHR" => void_fn!(c::cmd_end_rendering_khr, vk::PFN_vkCmdEndRendering),
        "vkCmdDraw" => void_fn!(d::cmd_draw, vk::PFN_vkCmdDraw),
        "vkCmdDrawIndexed" => void_fn!(d::cmd_draw_indexed, vk::PFN_vkCmdDrawIndexed),
        "vkCmdDrawIndirect" => void_fn!(d::cmd_draw_indirect, vk::PFN_vkCmdDrawIndirect),
        "vkCmdDrawIndexedIndirect" => void_fn!(d::cmd_draw_indexed_indirect, vk::PFN_vkCmdDrawIndexedIndirect),
        "vkCmdDrawIndirectCount" => void_fn!(d::cmd_draw_indirect_count, vk::PFN_vkCmdDrawIndirectCount),
        "vkCmdDrawIndirectCountKHR" => void_fn!(d::cmd_draw_indirect_count_khr, vk::PFN_vkCmdDrawIndirectCount),
        "vkCmdDrawIndexedIndirectCount" => {
            void_fn!(d::cmd_draw_indexed_indirect_count, vk::PFN_vkCmdDrawIndexedIndirectCount)
        }
        "vkCmdDrawIndexedIndirectCountKHR" => {
            void_fn!(d::cmd_draw_indexed_indirect_count_khr, vk::PFN_vkCmdDrawIndexedIndirectCount)
        }
        "vkCmdDrawMultiEXT" => void_fn!(d::cmd_draw_multi_ext, vk::PFN_vkCmdDrawMultiEXT),
        "vkCmdDrawMultiIndexedEXT" => void_fn!(d::cmd_draw_multi_indexed_ext, vk::PFN_vkCmdDrawMultiIndexedEXT),
        "vkCmdDrawIndirectByteCountEXT" => {
            void_fn!(d::cmd_draw_indirect_byte_count_ext, vk::PFN_vkCmdDrawIndirectByteCountEXT)
        }
        "vkCmdDrawMeshTasksEXT" => void_fn!(d::cmd_draw_mesh_tasks_ext, vk::PFN_vkCmdDrawMeshTasksEXT),
        "vkCmdDrawMeshTasksIndirectEXT" => {
            void_fn!(d::cmd_draw_mesh_tasks_indirect_ext, vk::PFN_vkCmdDrawMeshTasksIndirectEXT)
        }
        "vkCmdDrawMeshTasksIndirectCountEXT" => {
            void_fn!(d::cmd_draw_mesh_tasks_indirect_count_ext, vk::PFN_vkCmdDrawMeshTasksIndirectCountEXT)
        }
        "vkCmdDrawMeshTasksNV" => void_fn!(d::cmd_draw_mesh_tasks_nv, vk::PFN_vkCmdDrawMeshTasksNV),
        "vkCmdDrawMeshTasksIndirectNV" => {
            void_fn!(d::cmd_draw_mesh_tasks_indirect_nv, vk::PFN_vkCmdDrawMeshTasksIndirectNV)
        }
        "vkCmdDrawMeshTasksIndirectCountNV" => {
            void_fn!(d::cmd_draw_mesh_tasks_indirect_count_nv, vk::PFN_vkCmdDrawMeshTasksIndirectCountNV)
        }
        "vkCmdBeginQueryIndexedEXT" => void_fn!(d::cmd_begin_query_indexed_ext, vk::PFN_vkCmdBeginQueryIndexedEXT),
        "vkCmdEndQueryIndexedEXT" => void_fn!(d::cmd_end_query_indexed_ext, vk::PFN_vkCmdEndQueryIndexedEXT),
        "vkCmdBeginDebugUtilsLabelEXT" => {
            void_fn!(d::cmd_begin_debug_utils_label, vk::PFN_vkCmdBeginDebugUtilsLabelEXT)
        }
        "vkCmdEndDebugUtilsLabelEXT" => void_fn!(d::cmd_end_debug_utils_label, vk::PFN_vkCmdEndDebugUtilsLabelEXT),
        "vkCmdInsertDebugUtilsLabelEXT" => {
            void_fn!(d::cmd_insert_debug_utils_label, vk::PFN_vkCmdInsertDebugUtilsLabelEXT)
        }
        "vkQueueSubmit" => void_fn!(q::queue_submit, vk::PFN_vkQueueSubmit),
        "vkQueueSubmit2" => void_fn!(q::queue_submit2, vk::PFN_vkQueueSubmit2),
        "vkQueueSubmit2KHR" => void_fn!(q::queue_submit2_khr, vk::PFN_vkQueueSubmit2),
        "vkQueuePresentKHR" => void_fn!(q::queue_present, vk::PFN_vkQueuePresentKHR),
        "vkWaitForFences" => void_fn!(q::wait_for_fences, vk::PFN_vkWaitForFences),
        "vkGetFenceStatus" => void_fn!(q::get_fence_status, vk::PFN_vkGetFenceStatus),
        "vkQueueWaitIdle" => void_fn!(q::queue_wait_idle, vk::PFN_vkQueueWaitIdle),
        "vkDeviceWaitIdle" => void_fn!(q::device_wait_idle, vk::PFN_vkDeviceWaitIdle),
        "vkWaitSemaphores" => void_fn!(q::wait_semaphores, vk::PFN_vkWaitSemaphores),
        "vkWaitSemaphoresKHR" => void_fn!(q::wait_semaphores_khr, vk::PFN_vkWaitSemaphores),
        "vkGetSemaphoreCounterValue" => void_fn!(q::get_semaphore_counter_value, vk::PFN_vkGetSemaphoreCounterValue),
        "vkGetSemaphoreCounterValueKHR" => {
            void_fn!(q::get_semaphore_counter_value_khr, vk::PFN_vkGetSemaphoreCounterValue)
        }
        "vkDestroySemaphore" => void_fn!(q::destroy_semaphore, vk::PFN_vkDestroySemaphore),
        _ => None,
    }
}

/// The layer's hook for `name`: its own, the tiler check's when the check is on, and the
/// capture's when capturing.
fn hook(name: &str, config: &Config) -> vk::PFN_vkVoidFunction {
    work_hook(name)
        .or_else(|| device_hook(name))
        .or_else(|| if config.tiler { tiler_hook(name) } else { None })
        .or_else(|| if config.capture.is_some() { capture_hook(name) } else { None })
}

/// The hooks for work outside render passes (work_hooks.rs): they pass the call on through the
/// tiler check's or the capture's hook of the same name when those are on.
fn work_hook(name: &str) -> vk::PFN_vkVoidFunction {
    match name {
        "vkEndCommandBuffer" => void_fn!(w::end_command_buffer, vk::PFN_vkEndCommandBuffer),
        "vkCreateBuffer" => void_fn!(wo::create_buffer, vk::PFN_vkCreateBuffer),
        "vkDestroyBuffer" => void_fn!(wo::destroy_buffer, vk::PFN_vkDestroyBuffer),
        "vkCreateSwapchainKHR" => void_fn!(wo::create_swapchain, vk::PFN_vkCreateSwapchainKHR),
        "vkGetSwapchainImagesKHR" => void_fn!(wo::get_swapchain_images, vk::PFN_vkGetSwapchainImagesKHR),
        "vkCmdDispatch" => void_fn!(w::cmd_dispatch, vk::PFN_vkCmdDispatch),
        "vkCmdDispatchIndirect" => void_fn!(w::cmd_dispatch_indirect, vk::PFN_vkCmdDispatchIndirect),
        "vkCmdDispatchBase" => void_fn!(w::cmd_dispatch_base, vk::PFN_vkCmdDispatchBase),
        "vkCmdDispatchBaseKHR" => void_fn!(w::cmd_dispatch_base_khr, vk::PFN_vkCmdDispatchBase),
        "vkCmdCopyBuffer" => void_fn!(x::cmd_copy_buffer, vk::PFN_vkCmdCopyBuffer),
        "vkCmdCopyBuffer2" => void_fn!(x::cmd_copy_buffer2, vk::PFN_vkCmdCopyBuffer2),
        "vkCmdCopyBuffer2KHR" => void_fn!(x::cmd_copy_buffer2_khr, vk::PFN_vkCmdCopyBuffer2),
        "vkCmdFillBuffer" => void_fn!(x::cmd_fill_buffer, vk::PFN_vkCmdFillBuffer),
        "vkCmdUpdateBuffer" => void_fn!(x::cmd_update_buffer, vk::PFN_vkCmdUpdateBuffer),
        "vkCmdCopyImage" => void_fn!(x::cmd_copy_image, vk::PFN_vkCmdCopyImage),
        "vkCmdCopyImageToBuffer" => void_fn!(x::cmd_copy_image_to_buffer, vk::PFN_vkCmdCopyImageToBuffer),
        "vkCmdBlitImage" => void_fn!(x::cmd_blit_image, vk::PFN_vkCmdBlitImage),
        "vkCmdResolveImage" => void_fn!(x::cmd_resolve_image, vk::PFN_vkCmdResolveImage),
        "vkCmdClearColorImage" => void_fn!(x::cmd_clear_color_image, vk::PFN_vkCmdClearColorImage),
        "vkCmdClearDepthStencilImage" => {
            void_fn!(x::cmd_clear_depth_stencil_image, vk::PFN_vkCmdClearDepthStencilImage)
        }
        "vkCmdCopyBufferToImage" => void_fn!(x::cmd_copy_buffer_to_image, vk::PFN_vkCmdCopyBufferToImage),
        "vkCmdCopyImage2" => void_fn!(x::cmd_copy_image2, vk::PFN_vkCmdCopyImage2),
        "vkCmdCopyImage2KHR" => void_fn!(x::cmd_copy_image2_khr, vk::PFN_vkCmdCopyImage2),
        "vkCmdCopyImageToBuffer2" => void_fn!(x::cmd_copy_image_to_buffer2, vk::PFN_vkCmdCopyImageToBuffer2),
        "vkCmdCopyImageToBuffer2KHR" => {
            void_fn!(x::cmd_copy_image_to_buffer2_khr, vk::PFN_vkCmdCopyImageToBuffer2)
        }
        "vkCmdBlitImage2" => void_fn!(x::cmd_blit_image2, vk::PFN_vkCmdBlitImage2),
        "vkCmdBlitImage2KHR" => void_fn!(x::cmd_blit_image2_khr, vk::PFN_vkCmdBlitImage2),
        "vkCmdResolveImage2" => void_fn!(x::cmd_resolve_image2, vk::PFN_vkCmdResolveImage2),
        "vkCmdResolveImage2KHR" => void_fn!(x::cmd_resolve_image2_khr, vk::PFN_vkCmdResolveImage2),
        "vkCmdCopyBufferToImage2" => void_fn!(x::cmd_copy_buffer_to_image2, vk::PFN_vkCmdCopyBufferToImage2),
        "vkCmdCopyBufferToImage2KHR" => {
            void_fn!(x::cmd_copy_buffer_to_image2_khr, vk::PFN_vkCmdCopyBufferToImage2)
        }
        "vkCmdPipelineBarrier" => void_fn!(w::cmd_pipeline_barrier, vk::PFN_vkCmdPipelineBarrier),
        "vkCmdPipelineBarrier2" => void_fn!(w::cmd_pipeline_barrier2, vk::PFN_vkCmdPipelineBarrier2),
        "vkCmdPipelineBarrier2KHR" => void_fn!(w::cmd_pipeline_barrier2_khr, vk::PFN_vkCmdPipelineBarrier2),
        "vkCmdWaitEvents" => void_fn!(w::cmd_wait_events, vk::PFN_vkCmdWaitEvents),
        "vkCmdWaitEvents2" => void_fn!(w::cmd_wait_events2, vk::PFN_vkCmdWaitEvents2),
        "vkCmdWaitEvents2KHR" => void_fn!(w::cmd_wait_events2_khr, vk::PFN_vkCmdWaitEvents2),
        "vkCmdExecuteCommands" => void_fn!(w::cmd_execute_commands, vk::PFN_vkCmdExecuteCommands),
        _ => None,
    }
}

/// The capture's hooks (capture.rs): the swapchain's usage gets TRANSFER_SRC.
fn capture_hook(name: &str) -> vk::PFN_vkVoidFunction {
    match name {
        "vkCreateSwapchainKHR" => void_fn!(capture::create_swapchain, vk::PFN_vkCreateSwapchainKHR),
        "vkDestroySwapchainKHR" => void_fn!(capture::destroy_swapchain, vk::PFN_vkDestroySwapchainKHR),
        _ => None,
    }
}

/// The tiler check's hooks (image_use.rs), handed out only when the check is on: each notes
/// what it needs and passes the call on.
fn tiler_hook(name: &str) -> vk::PFN_vkVoidFunction {
    match name {
        "vkCreateFramebuffer" => void_fn!(t::create_framebuffer, vk::PFN_vkCreateFramebuffer),
        "vkDestroyFramebuffer" => void_fn!(t::destroy_framebuffer, vk::PFN_vkDestroyFramebuffer),
        "vkUpdateDescriptorSets" => void_fn!(t::update_descriptor_sets, vk::PFN_vkUpdateDescriptorSets),
        "vkUpdateDescriptorSetWithTemplate" => {
            void_fn!(t::update_descriptor_set_with_template, vk::PFN_vkUpdateDescriptorSetWithTemplate)
        }
        "vkCreateDescriptorUpdateTemplate" => {
            void_fn!(t::create_descriptor_update_template, vk::PFN_vkCreateDescriptorUpdateTemplate)
        }
        "vkCreateDescriptorUpdateTemplateKHR" => {
            void_fn!(t::create_descriptor_update_template_khr, vk::PFN_vkCreateDescriptorUpdateTemplate)
        }
        "vkDestroyDescriptorUpdateTemplate" => {
            void_fn!(t::destroy_descriptor_update_template, vk::PFN_vkDestroyDescriptorUpdateTemplate)
        }
        "vkDestroyDescriptorUpdateTemplateKHR" => {
            void_fn!(t::destroy_descriptor_update_template_khr, vk::PFN_vkDestroyDescriptorUpdateTemplate)
        }
        "vkCmdPushDescriptorSetWithTemplateKHR" => {
            void_fn!(t::cmd_push_descriptor_set_with_template, vk::PFN_vkCmdPushDescriptorSetWithTemplateKHR)
        }
        "vkUpdateDescriptorSetWithTemplateKHR" => {
            void_fn!(t::update_descriptor_set_with_template_khr, vk::PFN_vkUpdateDescriptorSetWithTemplate)
        }
        "vkCreateGraphicsPipelines" => void_fn!(t::create_graphics_pipelines, vk::PFN_vkCreateGraphicsPipelines),
        "vkCmdBindPipeline" => void_fn!(t::cmd_bind_pipeline, vk::PFN_vkCmdBindPipeline),
        "vkCmdBindDescriptorSets" => void_fn!(t::cmd_bind_descriptor_sets, vk::PFN_vkCmdBindDescriptorSets),
        "vkCmdPushDescriptorSetKHR" => void_fn!(t::cmd_push_descriptor_set, vk::PFN_vkCmdPushDescriptorSetKHR),
        "vkCmdDispatch" => void_fn!(t::cmd_dispatch, vk::PFN_vkCmdDispatch),
        "vkCmdDispatchIndirect" => void_fn!(t::cmd_dispatch_indirect, vk::PFN_vkCmdDispatchIndirect),
        "vkCmdCopyImage" => void_fn!(t::cmd_copy_image, vk::PFN_vkCmdCopyImage),
        "vkCmdCopyImageToBuffer" => void_fn!(t::cmd_copy_image_to_buffer, vk::PFN_vkCmdCopyImageToBuffer),
        "vkCmdBlitImage" => void_fn!(t::cmd_blit_image, vk::PFN_vkCmdBlitImage),
        "vkCmdResolveImage" => void_fn!(t::cmd_resolve_image, vk::PFN_vkCmdResolveImage),
        "vkCmdClearColorImage" => void_fn!(t::cmd_clear_color_image, vk::PFN_vkCmdClearColorImage),
        "vkCmdClearDepthStencilImage" => {
            void_fn!(t::cmd_clear_depth_stencil_image, vk::PFN_vkCmdClearDepthStencilImage)
        }
        "vkCmdCopyBufferToImage" => void_fn!(t::cmd_copy_buffer_to_image, vk::PFN_vkCmdCopyBufferToImage),
        "vkCmdCopyImage2" => void_fn!(t::cmd_copy_image2, vk::PFN_vkCmdCopyImage2),
        "vkCmdCopyImage2KHR" => void_fn!(t::cmd_copy_image2_khr, vk::PFN_vkCmdCopyImage2),
        "vkCmdCopyImageToBuffer2" => void_fn!(t::cmd_copy_image_to_buffer2, vk::PFN_vkCmdCopyImageToBuffer2),
        "vkCmdCopyImageToBuffer2KHR" => {
            void_fn!(t::cmd_copy_image_to_buffer2_khr, vk::PFN_vkCmdCopyImageToBuffer2)
        }
        "vkCmdBlitImage2" => void_fn!(t::cmd_blit_image2, vk::PFN_vkCmdBlitImage2),
        "vkCmdBlitImage2KHR" => void_fn!(t::cmd_blit_image2_khr, vk::PFN_vkCmdBlitImage2),
        "vkCmdResolveImage2" => void_fn!(t::cmd_resolve_image2, vk::PFN_vkCmdResolveImage2),
        "vkCmdResolveImage2KHR" => void_fn!(t::cmd_resolve_image2_khr, vk::PFN_vkCmdResolveImage2),
        "vkCmdCopyBufferToImage2" => void_fn!(t::cmd_copy_buffer_to_image2, vk::PFN_vkCmdCopyBufferToImage2),
        "vkCmdCopyBufferToImage2KHR" => {
            void_fn!(t::cmd_copy_buffer_to_image2_khr, vk::PFN_vkCmdCopyBufferToImage2)
        }
        _ => None,
    }
}

/// The layer's hook for an instance-level function name.
fn instance_hook(name: &str) -> vk::PFN_vkVoidFunction {
    match name {
        "vkGetInstanceProcAddr" => void_fn!(get_instance_proc_addr, vk::PFN_vkGetInstanceProcAddr),
        "vkCreateInstance" => void_fn!(create_instance, vk::PFN_vkCreateInstance),
        "vkDestroyInstance" => void_fn!(destroy_instance, vk::PFN_vkDestroyInstance),
        "vkCreateDevice" => void_fn!(create_device, vk::PFN_vkCreateDevice),
        _ => None,
    }
}

/// The hooks that offer VK_EXT_frame_boundary (frame_boundary.rs), handed out for the functions
/// the chain below has.
fn boundary_hook(name: &str) -> vk::PFN_vkVoidFunction {
    match name {
        "vkEnumerateDeviceExtensionProperties" => {
            void_fn!(fb::enumerate_device_extension_properties, vk::PFN_vkEnumerateDeviceExtensionProperties)
        }
        "vkGetPhysicalDeviceFeatures2" => {
            void_fn!(fb::get_physical_device_features2, vk::PFN_vkGetPhysicalDeviceFeatures2)
        }
        "vkGetPhysicalDeviceFeatures2KHR" => {
            void_fn!(fb::get_physical_device_features2_khr, vk::PFN_vkGetPhysicalDeviceFeatures2)
        }
        _ => None,
    }
}

/// The loader asks which interface version the layer speaks and gets its entry points.
///
/// # Safety
/// Called by the Vulkan loader with a valid (or null) `VkNegotiateLayerInterface`.
#[no_mangle]
pub unsafe extern "system" fn vkNegotiateLoaderLayerInterfaceVersion(
    interface: *mut NegotiateLayerInterface,
) -> vk::Result {
    guard(vk::Result::ERROR_INITIALIZATION_FAILED, || {
        // SAFETY: the loader's struct, or null.
        let Some(interface) = (unsafe { interface.as_mut() }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
        if interface.s_type != LAYER_NEGOTIATE_INTERFACE_STRUCT
            || interface.loader_layer_interface_version < LAYER_INTERFACE_VERSION
        {
            return vk::Result::ERROR_INITIALIZATION_FAILED;
        }
        interface.loader_layer_interface_version = LAYER_INTERFACE_VERSION;
        interface.pfn_get_instance_proc_addr = Some(get_instance_proc_addr);
        interface.pfn_get_device_proc_addr = Some(get_device_proc_addr);
        interface.pfn_get_physical_device_proc_addr = None;
        vk::Result::SUCCESS
    })
}

/// The exported vkGetInstanceProcAddr. The layer hands out `get_instance_proc_addr` instead of
/// this symbol's address: inside a shared library, a reference to an exported name binds to the
/// process's first definition, which is the loader's own vkGetInstanceProcAddr when the
/// application links libvulkan directly (and calling back into the loader deadlocks it).
///
/// # Safety
/// Called by the loader (or application) with a valid name.
#[no_mangle]
pub unsafe extern "system" fn vkGetInstanceProcAddr(
    instance: vk::Instance,
    name: *const c_char,
) -> vk::PFN_vkVoidFunction {
    // SAFETY: the caller's arguments.
    unsafe { get_instance_proc_addr(instance, name) }
}

/// The exported vkGetDeviceProcAddr (see [`vkGetInstanceProcAddr`] for why it only forwards).
///
/// # Safety
/// Called by the loader (or application) with a device the layer created and a valid name.
#[no_mangle]
pub unsafe extern "system" fn vkGetDeviceProcAddr(device: vk::Device, name: *const c_char) -> vk::PFN_vkVoidFunction {
    // SAFETY: the caller's arguments.
    unsafe { get_device_proc_addr(device, name) }
}

/// The layer's vkGetInstanceProcAddr: its hooks where the chain below has the function, the
/// next layer's function otherwise.
unsafe extern "system" fn get_instance_proc_addr(
    instance: vk::Instance,
    name: *const c_char,
) -> vk::PFN_vkVoidFunction {
    guard(None, || {
        // SAFETY: a NUL-terminated name from the caller.
        let name_str = unsafe { c_name(name) }?;
        if let Some(hook) = instance_hook(name_str) {
            return Some(hook);
        }
        let data = state::instance_of(instance.as_raw())?;
        // SAFETY: the next layer's GIPA with its instance and the caller's name.
        let next = unsafe { (data.gipa)(instance, name) };
        if let Some(hook) = next.and(boundary_hook(name_str)) {
            return Some(hook);
        }
        if next.is_some() && data.config.out.is_some() {
            if let Some(hook) = hook(name_str, &data.config) {
                return Some(hook);
            }
        }
        next
    })
}

/// The layer's vkGetDeviceProcAddr: its hooks for functions the device has (only while
/// measuring), the next layer's function otherwise.
unsafe extern "system" fn get_device_proc_addr(device: vk::Device, name: *const c_char) -> vk::PFN_vkVoidFunction {
    guard(None, || {
        // SAFETY: a NUL-terminated name from the caller.
        let name_str = unsafe { c_name(name) }?;
        if name_str == "vkGetDeviceProcAddr" {
            return device_hook(name_str);
        }
        let data = state::device_of(device.as_raw())?;
        // SAFETY: the next layer's GDPA with the device it created and the caller's name.
        let next = unsafe { (data.gdpa)(device, name) };
        if next.is_some() && (data.active() || name_str == "vkDestroyDevice") {
            if let Some(hook) = hook(name_str, &data.config) {
                return Some(hook);
            }
        }
        next
    })
}
