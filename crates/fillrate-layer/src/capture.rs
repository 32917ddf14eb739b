//! `NOSTENCIL_FILLRATE_CAPTURE=FILE.png` with `NOSTENCIL_FILLRATE_CAPTURE_FRAME=N` (`profile-app
//! --capture FILE.png --capture-frame N`): the image a program presents at the end of frame N,
//! written as a PNG, so that a program's output can be compared with the layer's checks on and
//! off. At vkCreateSwapchainKHR the layer adds TRANSFER_SRC to the swapchain's usage (where the
//! surface allows it). At the present that ends frame N it submits, on the present's queue, a
//! copy of the presented image into a host-visible buffer of its own, waiting on the present's
//! semaphores and signalling one of its own, which the present then waits on instead; the image
//! goes PRESENT_SRC -> TRANSFER_SRC_OPTIMAL -> PRESENT_SRC around the copy. Once the copy's fence
//! signals, BGRA is swizzled to RGB and the PNG written (a temporary file, then a rename).

use std::path::Path;

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::capture_state::{CaptureDevice, SwapchainInfo};
use super::config::CaptureConfig;
use super::copies::host_memory_type;
use super::objects::device_and;
use super::png_file::RgbaPixels;
use super::state::{guard, DeviceData, DeviceState, InstanceData};

/// How long the layer waits for its copy before giving the capture up.
const COPY_TIMEOUT_NS: u64 = 10_000_000_000;

/// What the capture needs of a device being created (only when capturing).
///
/// # Safety
/// `info` is the application's valid device create info; `physical` belongs to `instance`.
pub unsafe fn capture_device(
    instance: &InstanceData,
    physical: vk::PhysicalDevice,
    families: &[vk::QueueFamilyProperties],
    info: &vk::DeviceCreateInfo<'_>,
) -> CaptureDevice {
    // SAFETY: the caller's create info holds queueCreateInfoCount queue infos.
    let queues = unsafe { app_array(info.p_queue_create_infos, info.queue_create_info_count) };
    let queues = queues.iter().filter(|q| q.flags.is_empty()).map(|q| (q.queue_family_index, q.queue_count));
    // SAFETY: the next layer's GIPA with its own instance; the pointer, when given, has the
    // named function's type.
    let surface_capabilities = unsafe {
        (instance.gipa)(instance.handle, c"vkGetPhysicalDeviceSurfaceCapabilitiesKHR".as_ptr()).map(|f| {
            std::mem::transmute::<unsafe extern "system" fn(), vk::PFN_vkGetPhysicalDeviceSurfaceCapabilitiesKHR>(f)
        })
    };
    CaptureDevice {
        physical,
        families: families.iter().map(|f| f.queue_flags).collect(),
        queues: queues.collect(),
        surface_capabilities,
    }
}

/// Says `message` about the capture on stderr.
fn say(capture: &CaptureConfig, message: &str) {
    eprintln!("nostencil fill-rate layer: capture of frame {} to {}: {message}", capture.frame, capture.path.display());
}

/// Whether `surface`'s swapchain images may be made TRANSFER_SRC.
fn transfer_source_allowed(device: &DeviceData, surface: vk::SurfaceKHR) -> Result<(), String> {
    let setup = &device.info.capture;
    let query = setup.surface_capabilities.ok_or("the instance has no vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
    let mut capabilities = vk::SurfaceCapabilitiesKHR::default();
    // SAFETY: the application's surface, which it is creating a swapchain for, and the physical
    // device the device was made from.
    let result = unsafe { query(setup.physical, surface, &mut capabilities) };
    if result != vk::Result::SUCCESS {
        return Err(format!("vkGetPhysicalDeviceSurfaceCapabilitiesKHR failed ({result:?})"));
    }
    if !capabilities.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_SRC) {
        return Err("the surface does not allow TRANSFER_SRC usage: its images cannot be copied".into());
    }
    Ok(())
}

/// vkCreateSwapchainKHR (hooked only when capturing): TRANSFER_SRC added to the usage where the
/// surface allows it, so that the presented image can be copied.
pub(super) unsafe extern "system" fn create_swapchain(
    device: vk::Device,
    info: *const vk::SwapchainCreateInfoKHR<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    swapchain: *mut vk::SwapchainKHR,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.create_swapchain_khr) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's valid create info.
    let Some(app_info) = (unsafe { info.as_ref() }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    let readable = guard(Err("internal error".into()), || transfer_source_allowed(&data, app_info.surface));
    let mut ours = *app_info;
    if readable.is_ok() {
        ours.image_usage |= vk::ImageUsageFlags::TRANSFER_SRC;
    }
    // SAFETY: the application's create info with one usage bit more, which the surface allows.
    let result = unsafe { next(device, &ours, allocator, swapchain) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            let swapchain_info = SwapchainInfo { format: ours.image_format, extent: ours.image_extent, readable };
            // SAFETY: the call succeeded, so `*swapchain` is the new swapchain.
            data.state().capture.swapchains.insert(unsafe { *swapchain }, swapchain_info);
        });
    }
    result
}

/// vkDestroySwapchainKHR (hooked only when capturing): the handle may be reused.
pub(super) unsafe extern "system" fn destroy_swapchain(
    device: vk::Device,
    swapchain: vk::SwapchainKHR,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.destroy_swapchain_khr) else { return };
    guard((), || {
        data.state().capture.swapchains.remove(&swapchain);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, swapchain, allocator) }
}

/// Whether `format`'s four bytes a pixel are blue first (to swizzle), red first, or neither
/// (refused: named).
fn blue_first(format: vk::Format) -> Result<bool, String> {
    match nostencil_tiler::formats::byte_order(format) {
        Some("BGRA") => Ok(true),
        Some(_) => Ok(false),
        None => Err(format!("the swapchain's format {format:?} is not 8-bit RGBA or BGRA; only those are captured")),
    }
}

/// The presented image's bytes (tightly packed, 4 a pixel) as an RGBA image.
fn to_image(format: vk::Format, extent: vk::Extent2D, mut bytes: Vec<u8>) -> Result<RgbaPixels, String> {
    if blue_first(format)? {
        bytes.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
    }
    RgbaPixels::new(extent.width, extent.height, bytes)
}

/// The layer's objects for one capture. Null until made: destroying a null handle does nothing,
/// so `release` frees whatever was made.
#[derive(Default)]
struct CopyObjects {
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    fence: vk::Fence,
    semaphore: vk::Semaphore,
}

impl CopyObjects {
    /// Destroys them all but the semaphore (a present may be waiting on it).
    fn release(&self, device: &DeviceData) {
        // SAFETY: the layer's own objects on the live device, null or no longer in use (the
        // copy's fence signalled, or it was never submitted).
        unsafe {
            device.fns.destroy_command_pool(self.pool, None);
            device.fns.destroy_buffer(self.buffer, None);
            device.fns.free_memory(self.memory, None);
            device.fns.destroy_fence(self.fence, None);
        }
    }
}

/// A capture submitted: its copy runs before the present, which waits on `semaphore`.
pub struct Capturing {
    objects: CopyObjects,
    format: vk::Format,
    extent: vk::Extent2D,
}

impl Capturing {
    /// The present's info waiting on the layer's semaphore instead of the application's (which
    /// the copy waited on). Lives as long as `self`.
    pub fn patched<'a>(&'a self, info: &vk::PresentInfoKHR<'a>) -> vk::PresentInfoKHR<'a> {
        let mut patched = *info;
        patched.wait_semaphore_count = 1;
        patched.p_wait_semaphores = &self.objects.semaphore;
        patched
    }
}

/// The image a present shows of the first swapchain the layer saw created: (image, its info).
///
/// # Safety
/// `info` is the application's valid present info.
unsafe fn presented(
    device: &DeviceData,
    state: &DeviceState,
    info: &vk::PresentInfoKHR<'_>,
) -> Result<(vk::Image, SwapchainInfo), String> {
    // SAFETY: the present info holds swapchainCount swapchains and image indices.
    let (swapchains, indices) = unsafe {
        (app_array(info.p_swapchains, info.swapchain_count), app_array(info.p_image_indices, info.swapchain_count))
    };
    let (swapchain, index, found) = swapchains
        .iter()
        .zip(indices)
        .find_map(|(s, &i)| state.capture.swapchains.get(s).map(|found| (*s, i, found.clone())))
        .ok_or("the present shows no swapchain the layer saw created")?;
    found.readable.clone()?;
    blue_first(found.format)?;
    let images = swapchain_images(device, swapchain)?;
    let image = images.get(index as usize).copied().ok_or("the presented image index is not the swapchain's")?;
    Ok((image, found))
}

fn swapchain_images(device: &DeviceData, swapchain: vk::SwapchainKHR) -> Result<Vec<vk::Image>, String> {
    let get = device.next.get_swapchain_images_khr.ok_or("the device has no vkGetSwapchainImagesKHR")?;
    let mut count = 0u32;
    // SAFETY: the application's live swapchain; the first call asks for the count only.
    let result = unsafe { get(device.handle, swapchain, &mut count, std::ptr::null_mut()) };
    let mut images = vec![vk::Image::null(); count as usize];
    // SAFETY: `images` holds `count` handles.
    let result = result
        .result()
        .and_then(|()| unsafe { get(device.handle, swapchain, &mut count, images.as_mut_ptr()) }.result());
    result.map_err(|e| format!("vkGetSwapchainImagesKHR failed ({e:?})"))?;
    images.truncate(count as usize);
    Ok(images)
}

/// The queue family of `queue`, found among the queues the application asked for; it must be
/// able to copy.
fn family_of(device: &DeviceData, queue: vk::Queue) -> Result<u32, String> {
    let setup = &device.info.capture;
    let family = setup
        .queues
        .iter()
        .flat_map(|&(family, count)| (0..count).map(move |i| (family, i)))
        // SAFETY: a queue the application asked for at device creation.
        .find(|&(family, i)| unsafe { device.fns.get_device_queue(family, i) } == queue)
        .map(|(family, _)| family)
        .ok_or("the present's queue is not one the layer saw asked for")?;
    let copies = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE | vk::QueueFlags::TRANSFER;
    match setup.families.get(family as usize) {
        Some(flags) if flags.intersects(copies) => Ok(family),
        _ => Err(format!("the present's queue family {family} cannot copy")),
    }
}

/// Makes the pool, command buffer, host-visible buffer of `bytes`, fence and semaphore into
/// `objects` (whatever fails leaves the rest null, for `release`).
fn make_objects(device: &DeviceData, objects: &mut CopyObjects, family: u32, bytes: u64) -> Result<(), String> {
    let failed = |what: &str, e: vk::Result| format!("the layer could not {what} ({e:?})");
    let fns = &device.fns;
    let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(family);
    let buffer_info = vk::BufferCreateInfo::default().size(bytes).usage(vk::BufferUsageFlags::TRANSFER_DST);
    // SAFETY: plain object creation on the live device; each object goes into `objects` as soon
    // as it exists.
    unsafe {
        objects.pool = fns.create_command_pool(&pool_info, None).map_err(|e| failed("make a command pool", e))?;
        let allocate = vk::CommandBufferAllocateInfo::default().command_pool(objects.pool).command_buffer_count(1);
        objects.cmd = fns.allocate_command_buffers(&allocate).map_err(|e| failed("allocate a command buffer", e))?[0];
        objects.buffer = fns.create_buffer(&buffer_info, None).map_err(|e| failed("make a buffer", e))?;
        let requirements = fns.get_buffer_memory_requirements(objects.buffer);
        let memory_type =
            host_memory_type(device, requirements.memory_type_bits).ok_or("no host-visible memory for the capture")?;
        let allocate =
            vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(memory_type);
        objects.memory = fns.allocate_memory(&allocate, None).map_err(|e| failed("allocate memory", e))?;
        fns.bind_buffer_memory(objects.buffer, objects.memory, 0).map_err(|e| failed("bind memory", e))?;
        objects.fence =
            fns.create_fence(&vk::FenceCreateInfo::default(), None).map_err(|e| failed("make a fence", e))?;
        objects.semaphore = fns
            .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
            .map_err(|e| failed("make a semaphore", e))?;
    }
    let set_loader_data = device.info.set_loader_data.ok_or("the loader gave no vkSetDeviceLoaderData")?;
    // SAFETY: the layer's new command buffer: the loader's dispatch pointer goes into it.
    let result = unsafe { set_loader_data(device.handle, objects.cmd.as_raw() as usize as *mut std::ffi::c_void) };
    result.result().map_err(|e| failed("register its command buffer with the loader", e))
}

/// A layout transition of the colour `image`.
fn transition(image: vk::Image, layouts: (vk::ImageLayout, vk::ImageLayout)) -> vk::ImageMemoryBarrier<'static> {
    let range = vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    };
    vk::ImageMemoryBarrier::default()
        .old_layout(layouts.0)
        .new_layout(layouts.1)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range)
}

/// Records: the presented image to TRANSFER_SRC_OPTIMAL after everything before (the present's
/// semaphores, or the queue's earlier work), copied into the buffer, back to PRESENT_SRC, and
/// the buffer's bytes made visible to the host.
///
/// # Safety
/// `objects` were made by `make_objects`; `image` is the presented swapchain image, in
/// PRESENT_SRC_KHR, of `extent`.
unsafe fn record(
    device: &DeviceData,
    objects: &CopyObjects,
    image: vk::Image,
    extent: vk::Extent2D,
) -> ash::prelude::VkResult<()> {
    use vk::{AccessFlags as A, ImageLayout as L, PipelineStageFlags as S};
    let (fns, cmd) = (&device.fns, objects.cmd);
    let to_copy = transition(image, (L::PRESENT_SRC_KHR, L::TRANSFER_SRC_OPTIMAL))
        .src_access_mask(A::MEMORY_WRITE)
        .dst_access_mask(A::TRANSFER_READ);
    let back = transition(image, (L::TRANSFER_SRC_OPTIMAL, L::PRESENT_SRC_KHR));
    let to_host = vk::BufferMemoryBarrier::default()
        .src_access_mask(A::TRANSFER_WRITE)
        .dst_access_mask(A::HOST_READ)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .buffer(objects.buffer)
        .size(vk::WHOLE_SIZE);
    let region = vk::BufferImageCopy {
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        },
        image_extent: vk::Extent3D { width: extent.width, height: extent.height, depth: 1 },
        ..Default::default()
    };
    let none = vk::DependencyFlags::empty();
    let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
    // SAFETY: the caller's contract.
    unsafe {
        fns.begin_command_buffer(cmd, &begin)?;
        fns.cmd_pipeline_barrier(cmd, S::ALL_COMMANDS, S::TRANSFER, none, &[], &[], &[to_copy]);
        fns.cmd_copy_image_to_buffer(cmd, image, L::TRANSFER_SRC_OPTIMAL, objects.buffer, &[region]);
        fns.cmd_pipeline_barrier(cmd, S::TRANSFER, S::BOTTOM_OF_PIPE, none, &[], &[], &[back]);
        fns.cmd_pipeline_barrier(cmd, S::TRANSFER, S::HOST, none, &[], &[to_host], &[]);
        fns.end_command_buffer(cmd)
    }
}

/// Submits the recorded copy on `queue`: it waits on the present's semaphores and signals the
/// layer's, with the layer's fence.
///
/// # Safety
/// `info` is the application's valid present info; `queue` is held by the caller (the present).
unsafe fn submit(
    device: &DeviceData,
    queue: vk::Queue,
    objects: &CopyObjects,
    info: &vk::PresentInfoKHR<'_>,
) -> Result<(), String> {
    let submit = device.next.queue_submit.ok_or("the device has no vkQueueSubmit")?;
    // SAFETY: the present info holds waitSemaphoreCount binary semaphores.
    let waits = unsafe { app_array(info.p_wait_semaphores, info.wait_semaphore_count) };
    let stages = vec![vk::PipelineStageFlags::ALL_COMMANDS; waits.len()];
    let (cmds, signals) = ([objects.cmd], [objects.semaphore]);
    let batch = vk::SubmitInfo::default()
        .wait_semaphores(waits)
        .wait_dst_stage_mask(&stages)
        .command_buffers(&cmds)
        .signal_semaphores(&signals);
    // SAFETY: the layer's recorded buffer; the semaphores the application meant the present to
    // wait on, which the present will no longer wait on.
    let result = unsafe { submit(queue, 1, &batch, objects.fence) };
    result.result().map_err(|e| format!("the layer's copy could not be submitted ({e:?})"))
}

/// At a present: when it ends the frame to capture, submits the copy of the presented image.
/// Returns the capture to finish after the present (whose wait the caller must then patch), or
/// None with nothing submitted.
///
/// # Safety
/// `info` is the application's valid present info; `queue` is held by the caller.
pub unsafe fn begin(device: &DeviceData, queue: vk::Queue, info: &vk::PresentInfoKHR<'_>) -> Option<Capturing> {
    let capture = device.config.capture.as_ref()?;
    let mut state = device.state();
    let frame = state.capture.presents;
    state.capture.presents += 1;
    if frame != capture.frame {
        return None;
    }
    // SAFETY: the caller's contract.
    let started = unsafe { start(device, &state, queue, info) };
    started.map_err(|why| say(capture, &why)).ok()
}

/// Finds the presented image, makes the objects, records and submits the copy.
///
/// # Safety
/// As `begin`.
unsafe fn start(
    device: &DeviceData,
    state: &DeviceState,
    queue: vk::Queue,
    info: &vk::PresentInfoKHR<'_>,
) -> Result<Capturing, String> {
    // SAFETY: the caller's contract.
    let (image, swapchain) = unsafe { presented(device, state, info) }?;
    let family = family_of(device, queue)?;
    let extent = swapchain.extent;
    let mut objects = CopyObjects::default();
    let bytes = extent.width as u64 * extent.height as u64 * 4;
    let made = make_objects(device, &mut objects, family, bytes)
        .and_then(|()| {
            // SAFETY: the objects were just made; the image is the one presented, in PRESENT_SRC.
            unsafe { record(device, &objects, image, extent) }.map_err(|e| format!("recording the copy failed ({e:?})"))
        })
        // SAFETY: the caller's contract.
        .and_then(|()| unsafe { submit(device, queue, &objects, info) });
    if let Err(why) = made {
        objects.release(device);
        // SAFETY: never submitted.
        unsafe { device.fns.destroy_semaphore(objects.semaphore, None) };
        return Err(why);
    }
    Ok(Capturing { objects, format: swapchain.format, extent })
}

/// After the present: waits for the copy, writes the PNG, releases the objects (keeping the
/// semaphore until the device is destroyed).
pub fn finish(device: &DeviceData, capturing: Capturing) {
    let Some(capture) = device.config.capture.as_ref() else { return };
    let objects = &capturing.objects;
    // SAFETY: the layer's fence, submitted with its copy.
    let waited = unsafe { device.fns.wait_for_fences(&[objects.fence], true, COPY_TIMEOUT_NS) };
    device.state().capture.semaphores.push(objects.semaphore);
    if let Err(e) = waited {
        // The copy may still run: its objects are left alone, not freed.
        say(capture, &format!("the layer's copy did not finish ({e:?})"));
        return;
    }
    match read(device, &capturing).and_then(|image| write(&image, &capture.path)) {
        Ok(()) => eprintln!(
            "nostencil fill-rate layer: frame {}'s presented image written to {}",
            capture.frame,
            capture.path.display()
        ),
        Err(why) => say(capture, &why),
    }
    objects.release(device);
}

/// The copied bytes as an RGBA image.
fn read(device: &DeviceData, capturing: &Capturing) -> Result<RgbaPixels, String> {
    let extent = capturing.extent;
    let bytes = extent.width as usize * extent.height as usize * 4;
    let memory = capturing.objects.memory;
    // SAFETY: the layer's host-visible, coherent memory, which the finished copy wrote.
    let mapped = unsafe { device.fns.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }
        .map_err(|e| format!("the layer could not map its buffer ({e:?})"))?;
    // SAFETY: the mapping holds at least the buffer's `bytes`.
    let pixels = unsafe { std::slice::from_raw_parts(mapped as *const u8, bytes) }.to_vec();
    // SAFETY: mapped above.
    unsafe { device.fns.unmap_memory(memory) };
    to_image(capturing.format, extent, pixels)
}

/// Writes `image` as an opaque RGB PNG (a presented image's alpha is not shown).
fn write(image: &RgbaPixels, path: &Path) -> Result<(), String> {
    image.write_rgb_png(path)
}

/// Destroys the semaphores presents waited on (at vkDestroyDevice, after the application's
/// swapchains and its wait for the device).
pub fn destroy(device: &DeviceData, state: &mut DeviceState) {
    for semaphore in state.capture.semaphores.drain(..) {
        // SAFETY: the layer's own semaphores; nothing waits on them any more.
        unsafe { device.fns.destroy_semaphore(semaphore, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bgra_is_swizzled_rgba_kept_and_other_formats_named() {
        let extent = vk::Extent2D { width: 2, height: 1 };
        let bytes = vec![1, 2, 3, 4, 5, 6, 7, 8];
        let image = to_image(vk::Format::B8G8R8A8_SRGB, extent, bytes.clone()).expect("BGRA");
        assert_eq!(image.as_raw(), &[3, 2, 1, 4, 7, 6, 5, 8]);
        let image = to_image(vk::Format::R8G8B8A8_UNORM, extent, bytes.clone()).expect("RGBA");
        assert_eq!(image.as_raw(), &bytes);
        let refused = to_image(vk::Format::A2B10G10R10_UNORM_PACK32, extent, bytes).expect_err("10-bit");
        assert!(refused.contains("A2B10G10R10_UNORM_PACK32") && refused.contains("RGBA or BGRA"), "{refused}");
    }
}
