//! `Gpu`: everything chosen once per process (instance, device, queue, allocator, command pool),
//! shared through an `Arc` by every resource so that resources destroy themselves on drop.

use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::device::{Device, DeviceChoice};
use super::instance::Instance;
use super::live_objects::{Activity, LiveObjects, ObjectCounts, ObjectKind};
use super::validation::ValidationChecks;
use crate::error::{Error, Result, VkContext};

#[derive(Debug, Clone, Default)]
pub struct GpuOptions {
    /// Khronos validation layer with these checks, and a messenger that records every message.
    pub validation: Option<ValidationChecks>,
    pub device: DeviceChoice,
    /// Record no per-pass queries (counters then read 0, GPU time unknown): for running under a
    /// tool that brackets render passes with queries of its own (the fill-rate layer), so that
    /// it measures on its own instead of reading this crate's.
    pub without_pass_queries: bool,
}

pub struct Gpu {
    allocator: ManuallyDrop<Mutex<Allocator>>,
    command_pool: Mutex<vk::CommandPool>,
    /// What the crate has created on this device and not yet destroyed.
    pub(crate) objects: LiveObjects,
    pub(crate) device: Device,
    pub(crate) instance: Instance,
    /// `GpuOptions::without_pass_queries`.
    pub(crate) without_pass_queries: bool,
    /// Command-buffer labels (VK_EXT_debug_utils), when the instance enabled the extension.
    labels: Option<ash::ext::debug_utils::Device>,
}

impl Gpu {
    pub fn new(options: &GpuOptions) -> Result<Arc<Self>> {
        Self::create(options, &[], &[])
    }

    /// A Gpu that can present: the instance enables `surface_extensions` (from
    /// `ash_window::enumerate_required_extensions`) and the device `VK_KHR_swapchain`. Only the
    /// viewer uses it; offscreen commands never touch the window system.
    pub(crate) fn for_presentation(
        options: &GpuOptions,
        surface_extensions: &[*const std::ffi::c_char],
    ) -> Result<Arc<Self>> {
        Self::create(options, surface_extensions, &[ash::khr::swapchain::NAME])
    }

    fn create(
        options: &GpuOptions,
        instance_extensions: &[*const std::ffi::c_char],
        device_extensions: &[&std::ffi::CStr],
    ) -> Result<Arc<Self>> {
        let instance = Instance::with_extensions(options.validation, instance_extensions)?;
        let device = Device::with_extensions(&instance, &options.device.clone().from_env_or(), device_extensions)?;
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.raw.clone(),
            device: device.raw.clone(),
            physical_device: device.physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| Error::Memory(e.to_string()))?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: `device` was just created and `queue_family` is one of its queue families.
        let command_pool = unsafe { device.raw.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        let labels = instance.debug_labels.then(|| ash::ext::debug_utils::Device::new(&instance.raw, &device.raw));
        Ok(Arc::new(Gpu {
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            command_pool: Mutex::new(command_pool),
            objects: LiveObjects::default(),
            device,
            instance,
            without_pass_queries: options.without_pass_queries,
            labels,
        }))
    }

    pub(crate) fn raw(&self) -> &ash::Device {
        &self.device.raw
    }

    /// Opens a label named `name` on `cmd` (nothing without VK_EXT_debug_utils). Every label
    /// opened must be closed by [`Gpu::end_label`] in the same command buffer.
    pub(crate) fn begin_label(&self, cmd: vk::CommandBuffer, name: &str) {
        let Some(labels) = &self.labels else { return };
        // A name with a NUL (none of ours has one) is cut there.
        let name: Vec<u8> = name.bytes().take_while(|&b| b != 0).chain([0]).collect();
        let Ok(name) = std::ffi::CStr::from_bytes_with_nul(&name) else { return };
        let label = vk::DebugUtilsLabelEXT::default().label_name(name);
        // SAFETY: `cmd` is recording (the caller's contract), the extension is enabled on this
        // instance, and `label` with its name outlives the call.
        unsafe { labels.cmd_begin_debug_utils_label(cmd, &label) };
    }

    /// Closes the label [`Gpu::begin_label`] opened last on `cmd`.
    pub(crate) fn end_label(&self, cmd: vk::CommandBuffer) {
        let Some(labels) = &self.labels else { return };
        // SAFETY: `cmd` is recording and has a label open (the caller's contract).
        unsafe { labels.cmd_end_debug_utils_label(cmd) };
    }

    pub(crate) fn allocator(&self) -> MutexGuard<'_, Allocator> {
        // A poisoned lock means another thread panicked mid-allocation; the allocator's own
        // state is still consistent, so keep going.
        self.allocator.lock().unwrap_or_else(|p| p.into_inner())
    }

    pub(crate) fn command_pool(&self) -> MutexGuard<'_, vk::CommandPool> {
        self.command_pool.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The Vulkan objects alive on this device now, and the allocator's memory blocks.
    pub(crate) fn live_objects(&self) -> ObjectCounts {
        self.objects.snapshot(self.allocator().generate_report().blocks.len())
    }

    /// Counts an object of `kind` created (see `LiveObjects`).
    pub(crate) fn created(&self, kind: ObjectKind) {
        self.objects.created(kind)
    }

    /// Counts an object of `kind` destroyed.
    pub(crate) fn destroyed(&self, kind: ObjectKind) {
        self.objects.destroyed(kind)
    }

    /// Counts a host wait on the GPU that took `took` (fence waits: frames, uploads, presents).
    pub(crate) fn waited(&self, took: std::time::Duration) {
        self.objects.waited(took)
    }

    /// Counts `ns` of CPU time a frame's job took on another thread (`render::jobs`).
    pub(crate) fn counted_job_cpu(&self, ns: u64) {
        self.objects.job_ran(ns)
    }

    /// Counts `ns` of CPU time a frame slot's command-pool reset took on a worker thread.
    pub(crate) fn counted_pool_reset_cpu(&self, ns: u64) {
        self.objects.pool_reset(ns)
    }

    /// Counts `count` state and draw commands a frame recorded (`FrameRecorder`).
    pub(crate) fn counted_commands(&self, count: u64) {
        self.objects.recorded(count)
    }

    /// Objects made and host waits since the device opened (see `Activity::since`).
    pub(crate) fn activity(&self) -> Activity {
        self.objects.activity()
    }

    /// Validation messages recorded so far (empty when validation is off).
    /// The physical device's name (`llvmpipe (LLVM ...)` on lavapipe).
    pub fn device_name(&self) -> &str {
        &self.device.info.name
    }

    pub fn validation_messages(&self) -> Vec<String> {
        self.instance.validation_log().map(|l| l.messages()).unwrap_or_default()
    }

    pub fn validation_enabled(&self) -> bool {
        self.instance.validation_log().is_some()
    }

    /// Which validation checks run (layer, core, synchronisation, best practices, silenced
    /// messages); None when validation is off.
    pub(crate) fn validation_report(&self) -> Option<&crate::gpu::validation::ValidationReport> {
        self.instance.validation_report()
    }

    /// Waits until the device has finished all submitted work, so that what it may still read
    /// or wait on can be destroyed. A failure (device lost) is ignored: nothing is pending then.
    pub fn wait_idle(&self) {
        // SAFETY: the device is alive (owned by `self`) and every queue is used from the
        // caller's one thread, which is the one waiting here.
        let _ = unsafe { self.device.raw.device_wait_idle() };
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: every resource holds an `Arc<Gpu>`, so none is left; after the wait nothing
        // runs. The allocator frees its memory before the device goes, and the allocator is
        // never touched again (ManuallyDrop dropped once, here); the instance outlives the
        // device (it is dropped after this, as a field).
        unsafe {
            let _ = self.device.raw.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.raw.destroy_command_pool(*self.command_pool.get_mut().unwrap_or_else(|p| p.into_inner()), None);
            self.device.raw.destroy_device(None);
        }
    }
}
