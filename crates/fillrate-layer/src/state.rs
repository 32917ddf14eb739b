//! The layer's global state: the instances and devices it created, found from any dispatchable
//! handle (device, queue, command buffer) by the loader's dispatch key; and each device's next-
//! layer entry points and mutable bookkeeping.

use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

use ash::vk;
use ash::vk::Handle;

use super::attachments::RenderPassInfo;
use super::config::Config;
use super::frames::FrameAssembler;
use super::in_flight::Proof;
use super::in_flight::SubmissionCopy;
use super::in_flight::TimelineSignal;
use super::loader::{dispatch_key, PfnSetDeviceLoaderData};
use super::recording::{RecordedPass, Recording};
use super::report::CounterSupport;

/// Runs `f`, turning a panic into `fallback` and one line on stderr: a panic must never unwind
/// into the application's C frames.
pub fn guard<T>(fallback: T, f: impl FnOnce() -> T) -> T {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(value) => value,
        Err(_) => {
            eprintln!("nostencil fill-rate layer: internal error (panic caught); the call was passed on");
            fallback
        }
    }
}

pub fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

macro_rules! next_fns {
    ($($field:ident: $pfn:ident = $name:literal,)*) => {
        /// The next layer's entry points for every device function the layer hooks (None where
        /// the device does not have it), by the exact name the application asked for.
        pub struct NextFns {
            $(pub $field: Option<vk::$pfn>,)*
        }

        impl NextFns {
            /// # Safety
            /// `gdpa` is the next layer's vkGetDeviceProcAddr and `device` a device it created.
            pub unsafe fn load(gdpa: vk::PFN_vkGetDeviceProcAddr, device: vk::Device) -> Self {
                NextFns {
                    $(
                        // SAFETY: the loader returns the function named, whose type is `$pfn`,
                        // or null (None: both are one pointer).
                        $field: unsafe {
                            std::mem::transmute::<vk::PFN_vkVoidFunction, Option<vk::$pfn>>(
                                gdpa(device, concat!($name, "\0").as_ptr().cast()),
                            )
                        },
                    )*
                }
            }
        }
    };
}

next_fns! {
    destroy_device: PFN_vkDestroyDevice = "vkDestroyDevice",
    create_render_pass: PFN_vkCreateRenderPass = "vkCreateRenderPass",
    create_render_pass2: PFN_vkCreateRenderPass2 = "vkCreateRenderPass2",
    create_render_pass2_khr: PFN_vkCreateRenderPass2 = "vkCreateRenderPass2KHR",
    destroy_render_pass: PFN_vkDestroyRenderPass = "vkDestroyRenderPass",
    create_image: PFN_vkCreateImage = "vkCreateImage",
    destroy_image: PFN_vkDestroyImage = "vkDestroyImage",
    create_image_view: PFN_vkCreateImageView = "vkCreateImageView",
    destroy_image_view: PFN_vkDestroyImageView = "vkDestroyImageView",
    create_command_pool: PFN_vkCreateCommandPool = "vkCreateCommandPool",
    destroy_command_pool: PFN_vkDestroyCommandPool = "vkDestroyCommandPool",
    reset_command_pool: PFN_vkResetCommandPool = "vkResetCommandPool",
    allocate_command_buffers: PFN_vkAllocateCommandBuffers = "vkAllocateCommandBuffers",
    free_command_buffers: PFN_vkFreeCommandBuffers = "vkFreeCommandBuffers",
    begin_command_buffer: PFN_vkBeginCommandBuffer = "vkBeginCommandBuffer",
    reset_command_buffer: PFN_vkResetCommandBuffer = "vkResetCommandBuffer",
    create_query_pool: PFN_vkCreateQueryPool = "vkCreateQueryPool",
    destroy_query_pool: PFN_vkDestroyQueryPool = "vkDestroyQueryPool",
    reset_query_pool: PFN_vkResetQueryPool = "vkResetQueryPool",
    reset_query_pool_ext: PFN_vkResetQueryPool = "vkResetQueryPoolEXT",
    cmd_reset_query_pool: PFN_vkCmdResetQueryPool = "vkCmdResetQueryPool",
    cmd_begin_query: PFN_vkCmdBeginQuery = "vkCmdBeginQuery",
    cmd_end_query: PFN_vkCmdEndQuery = "vkCmdEndQuery",
    cmd_begin_render_pass: PFN_vkCmdBeginRenderPass = "vkCmdBeginRenderPass",
    cmd_begin_render_pass2: PFN_vkCmdBeginRenderPass2 = "vkCmdBeginRenderPass2",
    cmd_begin_render_pass2_khr: PFN_vkCmdBeginRenderPass2 = "vkCmdBeginRenderPass2KHR",
    cmd_next_subpass: PFN_vkCmdNextSubpass = "vkCmdNextSubpass",
    cmd_next_subpass2: PFN_vkCmdNextSubpass2 = "vkCmdNextSubpass2",
    cmd_next_subpass2_khr: PFN_vkCmdNextSubpass2 = "vkCmdNextSubpass2KHR",
    cmd_end_render_pass: PFN_vkCmdEndRenderPass = "vkCmdEndRenderPass",
    cmd_end_render_pass2: PFN_vkCmdEndRenderPass2 = "vkCmdEndRenderPass2",
    cmd_end_render_pass2_khr: PFN_vkCmdEndRenderPass2 = "vkCmdEndRenderPass2KHR",
    cmd_begin_rendering: PFN_vkCmdBeginRendering = "vkCmdBeginRendering",
    cmd_begin_rendering_khr: PFN_vkCmdBeginRendering = "vkCmdBeginRenderingKHR",
    cmd_end_rendering: PFN_vkCmdEndRendering = "vkCmdEndRendering",
    cmd_end_rendering_khr: PFN_vkCmdEndRendering = "vkCmdEndRenderingKHR",
    cmd_draw: PFN_vkCmdDraw = "vkCmdDraw",
    cmd_draw_indexed: PFN_vkCmdDrawIndexed = "vkCmdDrawIndexed",
    cmd_draw_indirect: PFN_vkCmdDrawIndirect = "vkCmdDrawIndirect",
    cmd_draw_indexed_indirect: PFN_vkCmdDrawIndexedIndirect = "vkCmdDrawIndexedIndirect",
    cmd_draw_indirect_count: PFN_vkCmdDrawIndirectCount = "vkCmdDrawIndirectCount",
    cmd_draw_indirect_count_khr: PFN_vkCmdDrawIndirectCount = "vkCmdDrawIndirectCountKHR",
    cmd_draw_indexed_indirect_count: PFN_vkCmdDrawIndexedIndirectCount = "vkCmdDrawIndexedIndirectCount",
    cmd_draw_indexed_indirect_count_khr: PFN_vkCmdDrawIndexedIndirectCount = "vkCmdDrawIndexedIndirectCountKHR",
    cmd_draw_multi_ext: PFN_vkCmdDrawMultiEXT = "vkCmdDrawMultiEXT",
    cmd_draw_multi_indexed_ext: PFN_vkCmdDrawMultiIndexedEXT = "vkCmdDrawMultiIndexedEXT",
    cmd_draw_indirect_byte_count_ext: PFN_vkCmdDrawIndirectByteCountEXT = "vkCmdDrawIndirectByteCountEXT",
    cmd_draw_mesh_tasks_ext: PFN_vkCmdDrawMeshTasksEXT = "vkCmdDrawMeshTasksEXT",
    cmd_draw_mesh_tasks_indirect_ext: PFN_vkCmdDrawMeshTasksIndirectEXT = "vkCmdDrawMeshTasksIndirectEXT",
    cmd_draw_mesh_tasks_indirect_count_ext: PFN_vkCmdDrawMeshTasksIndirectCountEXT = "vkCmdDrawMeshTasksIndirectCountEXT",
    cmd_draw_mesh_tasks_nv: PFN_vkCmdDrawMeshTasksNV = "vkCmdDrawMeshTasksNV",
    cmd_draw_mesh_tasks_indirect_nv: PFN_vkCmdDrawMeshTasksIndirectNV = "vkCmdDrawMeshTasksIndirectNV",
    cmd_draw_mesh_tasks_indirect_count_nv: PFN_vkCmdDrawMeshTasksIndirectCountNV = "vkCmdDrawMeshTasksIndirectCountNV",
    cmd_begin_query_indexed_ext: PFN_vkCmdBeginQueryIndexedEXT = "vkCmdBeginQueryIndexedEXT",
    cmd_end_query_indexed_ext: PFN_vkCmdEndQueryIndexedEXT = "vkCmdEndQueryIndexedEXT",
    cmd_begin_debug_utils_label: PFN_vkCmdBeginDebugUtilsLabelEXT = "vkCmdBeginDebugUtilsLabelEXT",
    cmd_end_debug_utils_label: PFN_vkCmdEndDebugUtilsLabelEXT = "vkCmdEndDebugUtilsLabelEXT",
    cmd_insert_debug_utils_label: PFN_vkCmdInsertDebugUtilsLabelEXT = "vkCmdInsertDebugUtilsLabelEXT",
    queue_submit: PFN_vkQueueSubmit = "vkQueueSubmit",
    queue_submit2: PFN_vkQueueSubmit2 = "vkQueueSubmit2",
    queue_submit2_khr: PFN_vkQueueSubmit2 = "vkQueueSubmit2KHR",
    queue_present: PFN_vkQueuePresentKHR = "vkQueuePresentKHR",
    wait_for_fences: PFN_vkWaitForFences = "vkWaitForFences",
    get_fence_status: PFN_vkGetFenceStatus = "vkGetFenceStatus",
    queue_wait_idle: PFN_vkQueueWaitIdle = "vkQueueWaitIdle",
    device_wait_idle: PFN_vkDeviceWaitIdle = "vkDeviceWaitIdle",
    wait_semaphores: PFN_vkWaitSemaphores = "vkWaitSemaphores",
    wait_semaphores_khr: PFN_vkWaitSemaphores = "vkWaitSemaphoresKHR",
    get_semaphore_counter_value: PFN_vkGetSemaphoreCounterValue = "vkGetSemaphoreCounterValue",
    get_semaphore_counter_value_khr: PFN_vkGetSemaphoreCounterValue = "vkGetSemaphoreCounterValueKHR",
    destroy_semaphore: PFN_vkDestroySemaphore = "vkDestroySemaphore",
    create_framebuffer: PFN_vkCreateFramebuffer = "vkCreateFramebuffer",
    destroy_framebuffer: PFN_vkDestroyFramebuffer = "vkDestroyFramebuffer",
    update_descriptor_sets: PFN_vkUpdateDescriptorSets = "vkUpdateDescriptorSets",
    update_descriptor_set_with_template: PFN_vkUpdateDescriptorSetWithTemplate = "vkUpdateDescriptorSetWithTemplate",
    update_descriptor_set_with_template_khr: PFN_vkUpdateDescriptorSetWithTemplate = "vkUpdateDescriptorSetWithTemplateKHR",
    create_descriptor_update_template: PFN_vkCreateDescriptorUpdateTemplate = "vkCreateDescriptorUpdateTemplate",
    create_descriptor_update_template_khr: PFN_vkCreateDescriptorUpdateTemplate = "vkCreateDescriptorUpdateTemplateKHR",
    destroy_descriptor_update_template: PFN_vkDestroyDescriptorUpdateTemplate = "vkDestroyDescriptorUpdateTemplate",
    destroy_descriptor_update_template_khr: PFN_vkDestroyDescriptorUpdateTemplate = "vkDestroyDescriptorUpdateTemplateKHR",
    cmd_push_descriptor_set_with_template: PFN_vkCmdPushDescriptorSetWithTemplateKHR = "vkCmdPushDescriptorSetWithTemplateKHR",
    create_graphics_pipelines: PFN_vkCreateGraphicsPipelines = "vkCreateGraphicsPipelines",
    cmd_bind_pipeline: PFN_vkCmdBindPipeline = "vkCmdBindPipeline",
    cmd_bind_descriptor_sets: PFN_vkCmdBindDescriptorSets = "vkCmdBindDescriptorSets",
    cmd_push_descriptor_set: PFN_vkCmdPushDescriptorSetKHR = "vkCmdPushDescriptorSetKHR",
    cmd_dispatch: PFN_vkCmdDispatch = "vkCmdDispatch",
    cmd_dispatch_indirect: PFN_vkCmdDispatchIndirect = "vkCmdDispatchIndirect",
    cmd_copy_image: PFN_vkCmdCopyImage = "vkCmdCopyImage",
    cmd_copy_image_to_buffer: PFN_vkCmdCopyImageToBuffer = "vkCmdCopyImageToBuffer",
    cmd_blit_image: PFN_vkCmdBlitImage = "vkCmdBlitImage",
    cmd_resolve_image: PFN_vkCmdResolveImage = "vkCmdResolveImage",
    cmd_clear_color_image: PFN_vkCmdClearColorImage = "vkCmdClearColorImage",
    cmd_clear_depth_stencil_image: PFN_vkCmdClearDepthStencilImage = "vkCmdClearDepthStencilImage",
    cmd_copy_buffer_to_image: PFN_vkCmdCopyBufferToImage = "vkCmdCopyBufferToImage",
    cmd_copy_image2: PFN_vkCmdCopyImage2 = "vkCmdCopyImage2",
    cmd_copy_image2_khr: PFN_vkCmdCopyImage2 = "vkCmdCopyImage2KHR",
    cmd_copy_image_to_buffer2: PFN_vkCmdCopyImageToBuffer2 = "vkCmdCopyImageToBuffer2",
    cmd_copy_image_to_buffer2_khr: PFN_vkCmdCopyImageToBuffer2 = "vkCmdCopyImageToBuffer2KHR",
    cmd_blit_image2: PFN_vkCmdBlitImage2 = "vkCmdBlitImage2",
    cmd_blit_image2_khr: PFN_vkCmdBlitImage2 = "vkCmdBlitImage2KHR",
    cmd_resolve_image2: PFN_vkCmdResolveImage2 = "vkCmdResolveImage2",
    cmd_resolve_image2_khr: PFN_vkCmdResolveImage2 = "vkCmdResolveImage2KHR",
    cmd_copy_buffer_to_image2: PFN_vkCmdCopyBufferToImage2 = "vkCmdCopyBufferToImage2",
    cmd_copy_buffer_to_image2_khr: PFN_vkCmdCopyBufferToImage2 = "vkCmdCopyBufferToImage2KHR",
    create_swapchain_khr: PFN_vkCreateSwapchainKHR = "vkCreateSwapchainKHR",
    destroy_swapchain_khr: PFN_vkDestroySwapchainKHR = "vkDestroySwapchainKHR",
    get_swapchain_images_khr: PFN_vkGetSwapchainImagesKHR = "vkGetSwapchainImagesKHR",
    end_command_buffer: PFN_vkEndCommandBuffer = "vkEndCommandBuffer",
    create_buffer: PFN_vkCreateBuffer = "vkCreateBuffer",
    destroy_buffer: PFN_vkDestroyBuffer = "vkDestroyBuffer",
    cmd_dispatch_base: PFN_vkCmdDispatchBase = "vkCmdDispatchBase",
    cmd_dispatch_base_khr: PFN_vkCmdDispatchBase = "vkCmdDispatchBaseKHR",
    cmd_copy_buffer: PFN_vkCmdCopyBuffer = "vkCmdCopyBuffer",
    cmd_copy_buffer2: PFN_vkCmdCopyBuffer2 = "vkCmdCopyBuffer2",
    cmd_copy_buffer2_khr: PFN_vkCmdCopyBuffer2 = "vkCmdCopyBuffer2KHR",
    cmd_fill_buffer: PFN_vkCmdFillBuffer = "vkCmdFillBuffer",
    cmd_update_buffer: PFN_vkCmdUpdateBuffer = "vkCmdUpdateBuffer",
    cmd_pipeline_barrier: PFN_vkCmdPipelineBarrier = "vkCmdPipelineBarrier",
    cmd_pipeline_barrier2: PFN_vkCmdPipelineBarrier2 = "vkCmdPipelineBarrier2",
    cmd_pipeline_barrier2_khr: PFN_vkCmdPipelineBarrier2 = "vkCmdPipelineBarrier2KHR",
    cmd_wait_events: PFN_vkCmdWaitEvents = "vkCmdWaitEvents",
    cmd_wait_events2: PFN_vkCmdWaitEvents2 = "vkCmdWaitEvents2",
    cmd_wait_events2_khr: PFN_vkCmdWaitEvents2 = "vkCmdWaitEvents2KHR",
    cmd_execute_commands: PFN_vkCmdExecuteCommands = "vkCmdExecuteCommands",
}

pub struct InstanceData {
    pub handle: vk::Instance,
    pub gipa: vk::PFN_vkGetInstanceProcAddr,
    pub fns: ash::Instance,
    /// The next layer's vkGetPhysicalDeviceFeatures2 and its KHR alias, loaded with `fns` at
    /// vkCreateInstance (None where the instance has none: a Vulkan 1.0 instance, no extension).
    pub features2: [Option<vk::PFN_vkGetPhysicalDeviceFeatures2>; 2],
    pub application: String,
    pub config: Config,
}

/// What the layer learnt of the device at creation.
pub struct DeviceInfo {
    pub name: String,
    pub support: CounterSupport,
    /// timestampValidBits per queue family.
    pub timestamp_bits: Vec<u32>,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period: f64,
    /// For the host-visible buffers the layer copies results into (copies.rs).
    pub memory: vk::PhysicalDeviceMemoryProperties,
    /// The loader's callback for command buffers the layer allocates itself.
    pub set_loader_data: Option<PfnSetDeviceLoaderData>,
    /// What the capture (capture.rs) needs to know of the device's queues and surfaces.
    pub capture: super::capture_state::CaptureDevice,
    /// The program enabled VK_EXT_frame_boundary, which the layer offers and keeps from the
    /// driver (frame_boundary.rs): its structs are taken out of the chains passed on.
    pub frame_boundary_emulated: bool,
}

/// A command buffer the layer saw allocated.
pub struct CommandBufferData {
    pub pool: vk::CommandPool,
    pub recording: Recording,
    /// The tiler check's events and bindings (tiler_state.rs).
    pub tiler: super::tiler_state::CommandTiler,
}

/// One command buffer's measured passes in one submission, waiting to be read back.
pub struct Pending {
    pub queue: vk::Queue,
    pub sequence: u64,
    pub frame: u64,
    pub buffer: vk::CommandBuffer,
    pub passes: Vec<RecordedPass>,
    /// Dispatch groups and transfers outside render passes (work.rs).
    pub work: Vec<super::work::RecordedWork>,
    pub timestamp_bits: u32,
    /// Set when the results can no longer be trusted (why).
    pub spoiled: Option<String>,
    /// This submission's own copy of the layer's results (None: read from the query pools).
    pub copy: Option<SubmissionCopy>,
    /// The secondary command buffers `buffer` executed (their queries are in `passes`, `work`).
    pub secondaries: Vec<vk::CommandBuffer>,
    /// The layer's buffer that reset the secondaries' queries first in the batch (its pool).
    pub resets: Option<(vk::CommandPool, vk::CommandBuffer)>,
}

#[derive(Default)]
pub struct DeviceState {
    pub render_passes: HashMap<vk::RenderPass, RenderPassInfo>,
    pub image_samples: HashMap<vk::Image, u32>,
    /// Images' formats and sizes, for the bytes of transfers (transfer_bytes.rs).
    pub images: HashMap<vk::Image, super::transfer_bytes::ImageInfo>,
    /// Buffers' sizes (vkCmdFillBuffer with VK_WHOLE_SIZE).
    pub buffer_sizes: HashMap<vk::Buffer, u64>,
    /// Indirect-argument buffers the layer made readable (TRANSFER_SRC), whose dispatch
    /// arguments it copies at the end of a submission.
    pub indirect_buffers: std::collections::HashSet<vk::Buffer>,
    /// Swapchains' format and extent, for their images.
    pub swapchains: HashMap<vk::SwapchainKHR, (vk::Format, vk::Extent2D)>,
    pub views: HashMap<vk::ImageView, (vk::Format, u32)>,
    pub command_pools: HashMap<vk::CommandPool, u32>,
    pub buffers: HashMap<vk::CommandBuffer, CommandBufferData>,
    /// The application's query pools: type and statistic bits.
    pub app_pools: HashMap<vk::QueryPool, (vk::QueryType, vk::QueryPipelineStatisticFlags)>,
    pub pending: Vec<Pending>,
    /// The layer's command pools for its copy command buffers, by queue family.
    pub copy_pools: HashMap<u32, vk::CommandPool>,
    /// The layer's fences in flight that prove submissions done (proofs.rs), and spare ones.
    pub proofs: Vec<Proof>,
    pub spare_fences: Vec<vk::Fence>,
    /// The last submission that signals each fence: (queue, sequence).
    pub fences: HashMap<vk::Fence, (vk::Queue, u64)>,
    /// Timeline semaphore signals that would prove pending submissions complete.
    pub timeline_signals: Vec<TimelineSignal>,
    pub sequence: u64,
    pub frames: Option<FrameAssembler>,
    /// The program marks its frames with VK_EXT_frame_boundary: only its boundaries cut frames.
    pub boundaries: bool,
    pub not_measured: BTreeMap<String, u64>,
    /// Frames finished when the file was last written.
    pub written_at: u64,
    /// When the file was last written.
    pub last_write: Option<std::time::Instant>,
    /// The NOSTENCIL_FILLRATE_FRAMES file is written; nothing more is measured.
    pub finished: bool,
    /// Frames appended to the journal (report.rs, `JournalLine`), and the open journal.
    pub journaled: u64,
    pub journal: Option<std::fs::File>,
    /// The tiler check's objects and verdicts (tiler_state.rs, tiler_check.rs).
    pub tiler: super::tiler_state::TilerState,
    /// The capture's swapchains and presents (capture.rs).
    pub capture: super::capture_state::CaptureState,
}

impl DeviceState {
    pub fn frames(&mut self) -> &mut FrameAssembler {
        self.frames.get_or_insert_with(|| FrameAssembler::new(None))
    }

    pub fn count_not_measured(&mut self, what: &str) {
        *self.not_measured.entry(what.to_owned()).or_default() += 1;
    }
}

pub struct DeviceData {
    pub handle: vk::Device,
    pub gdpa: vk::PFN_vkGetDeviceProcAddr,
    /// The next layer's core functions (those the layer calls itself).
    pub fns: ash::Device,
    pub next: NextFns,
    pub info: DeviceInfo,
    pub application: String,
    pub config: Config,
    pub state: Mutex<DeviceState>,
}

impl DeviceData {
    pub fn state(&self) -> MutexGuard<'_, DeviceState> {
        lock(&self.state)
    }

    /// The layer measures: an output file was named.
    pub fn active(&self) -> bool {
        self.config.out.is_some()
    }
}

fn instances() -> &'static Mutex<Vec<Arc<InstanceData>>> {
    static INSTANCES: OnceLock<Mutex<Vec<Arc<InstanceData>>>> = OnceLock::new();
    INSTANCES.get_or_init(|| Mutex::new(Vec::new()))
}

fn devices() -> &'static Mutex<Vec<Arc<DeviceData>>> {
    static DEVICES: OnceLock<Mutex<Vec<Arc<DeviceData>>>> = OnceLock::new();
    DEVICES.get_or_init(|| Mutex::new(Vec::new()))
}

pub fn add_instance(data: InstanceData) {
    lock(instances()).push(Arc::new(data));
}

pub fn remove_instance(handle: vk::Instance) -> Option<Arc<InstanceData>> {
    let mut list = lock(instances());
    let index = list.iter().position(|i| i.handle == handle)?;
    Some(list.remove(index))
}

/// The instance `handle` is, or (for a physical device) belongs to: by handle, then by
/// dispatch key, then the only one.
pub fn instance_of(handle: u64) -> Option<Arc<InstanceData>> {
    let list = lock(instances());
    if let Some(found) = list.iter().find(|i| i.handle.as_raw() == handle) {
        return Some(found.clone());
    }
    if handle != 0 {
        // SAFETY: `handle` is a live dispatchable handle the loader passed, and every listed
        // instance is alive (removed at vkDestroyInstance).
        let key = unsafe { dispatch_key(handle) };
        // SAFETY: as above.
        if let Some(found) = list.iter().find(|i| unsafe { dispatch_key(i.handle.as_raw()) } == key) {
            return Some(found.clone());
        }
    }
    // A physical device whose key is not its instance's: the only instance, if there is one.
    (handle != 0 && list.len() == 1).then(|| list[0].clone())
}

/// Every device the layer created, alive now.
pub fn all_devices() -> Vec<Arc<DeviceData>> {
    lock(devices()).clone()
}

pub fn add_device(data: Arc<DeviceData>) {
    lock(devices()).push(data);
}

pub fn remove_device(handle: vk::Device) -> Option<Arc<DeviceData>> {
    let mut list = lock(devices());
    let index = list.iter().position(|d| d.handle == handle)?;
    Some(list.remove(index))
}

/// The device a device, queue or command buffer handle belongs to.
pub fn device_of(handle: u64) -> Option<Arc<DeviceData>> {
    let list = lock(devices());
    if let Some(found) = list.iter().find(|d| d.handle.as_raw() == handle) {
        return Some(found.clone());
    }
    if handle == 0 {
        return None;
    }
    // SAFETY: `handle` is a live dispatchable handle the application passed, and each listed
    // device is alive (removed at vkDestroyDevice); a device, its queues and its command
    // buffers share the loader's dispatch key.
    let key = unsafe { dispatch_key(handle) };
    // SAFETY: as above.
    list.iter().find(|d| unsafe { dispatch_key(d.handle.as_raw()) } == key).cloned()
}
