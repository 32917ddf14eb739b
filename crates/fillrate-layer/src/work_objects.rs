//! What the work rows need to know of the program's objects: buffers' sizes (a fill to the
//! end), indirect-argument buffers made readable (their dispatches' workgroups, copies.rs), and
//! swapchains' images (a full-frame copy into one is named).

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::objects::device_and;
use super::state::guard;
use super::transfer_bytes as bytes;

/// Whether a pNext chain holds a struct of type `ty`.
///
/// # Safety
/// `p_next` is a valid pNext chain.
unsafe fn chain_has(mut p_next: *const std::ffi::c_void, ty: vk::StructureType) -> bool {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure<'_>;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (node, next) = unsafe { ((*base).s_type, (*base).p_next.cast()) };
        if node == ty {
            return true;
        }
        p_next = next;
    }
    false
}

pub(super) unsafe extern "system" fn create_buffer(
    device: vk::Device,
    info: *const vk::BufferCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    buffer: *mut vk::Buffer,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.create_buffer) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's valid create info.
    let Some(app_info) = (unsafe { info.as_ref() }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    // An indirect-argument buffer may also be copied from, so the layer can read back what an
    // indirect dispatch ran (copies.rs); nothing else of the buffer changes.
    // (Not when VK_KHR_maintenance5's usage struct in the chain replaces `usage`.)
    // SAFETY: the application's valid chain.
    let usage2 = unsafe { chain_has(app_info.p_next, vk::StructureType::BUFFER_USAGE_FLAGS_2_CREATE_INFO_KHR) };
    let indirect = data.active() && !usage2 && app_info.usage.contains(vk::BufferUsageFlags::INDIRECT_BUFFER);
    let mut ours = *app_info;
    if indirect {
        ours.usage |= vk::BufferUsageFlags::TRANSFER_SRC;
    }
    // SAFETY: the application's create info, at most one usage bit added.
    let result = unsafe { next(device, &ours, allocator, buffer) };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: the new handle (the call succeeded).
            let handle = unsafe { *buffer };
            let mut st = data.state();
            st.buffer_sizes.insert(handle, app_info.size);
            if indirect {
                st.indirect_buffers.insert(handle);
            }
        });
    }
    result
}

pub(super) unsafe extern "system" fn destroy_buffer(
    device: vk::Device,
    buffer: vk::Buffer,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.destroy_buffer) else { return };
    guard((), || {
        let mut st = data.state();
        st.buffer_sizes.remove(&buffer);
        st.indirect_buffers.remove(&buffer);
    });
    // SAFETY: the application's arguments, passed on.
    unsafe { next(device, buffer, allocator) }
}

/// vkCreateSwapchainKHR: its format and extent are kept for its images (through the capture's
/// hook when capturing, which adds a usage bit).
pub(super) unsafe extern "system" fn create_swapchain(
    device: vk::Device,
    info: *const vk::SwapchainCreateInfoKHR<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    swapchain: *mut vk::SwapchainKHR,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.create_swapchain_khr) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let result = if data.config.capture.is_some() {
        // SAFETY: the application's arguments, passed on through the capture.
        unsafe { super::capture::create_swapchain(device, info, allocator, swapchain) }
    } else {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(device, info, allocator, swapchain) }
    };
    if result == vk::Result::SUCCESS {
        guard((), || {
            // SAFETY: a valid create info and the new handle (the call succeeded).
            let (info, handle) = unsafe { (&*info, *swapchain) };
            data.state().swapchains.insert(handle, (info.image_format, info.image_extent));
        });
    }
    result
}

/// vkGetSwapchainImagesKHR: the images are noted as a swapchain's (a full-frame copy or blit
/// into one is named).
pub(super) unsafe extern "system" fn get_swapchain_images(
    device: vk::Device,
    swapchain: vk::SwapchainKHR,
    count: *mut u32,
    images: *mut vk::Image,
) -> vk::Result {
    let Some((data, next)) = device_and(device.as_raw(), |d| d.next.get_swapchain_images_khr) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: the application's arguments, passed on.
    let result = unsafe { next(device, swapchain, count, images) };
    if result == vk::Result::SUCCESS && !images.is_null() {
        guard((), || {
            // SAFETY: the call filled `*count` images.
            let handles = unsafe { app_array(images, *count) };
            let mut st = data.state();
            let Some(&(format, extent)) = st.swapchains.get(&swapchain) else { return };
            for &image in handles {
                let info = bytes::ImageInfo {
                    format,
                    extent: vk::Extent3D { width: extent.width, height: extent.height, depth: 1 },
                    mip_levels: 1,
                    array_layers: 1,
                    samples: 1,
                    swapchain: true,
                };
                st.images.insert(image, info);
            }
        });
    }
    result
}
