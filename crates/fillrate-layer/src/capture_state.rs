//! What the capture (capture.rs) keeps per device: learnt at vkCreateDevice and
//! vkCreateSwapchainKHR, counted at each present. Data only, so that the device state
//! (state.rs) can hold it without importing the capture's hooks.

use std::collections::HashMap;

use ash::vk;

/// What the capture needs of the device, learnt at vkCreateDevice (only when capturing).
#[derive(Default)]
pub struct CaptureDevice {
    pub physical: vk::PhysicalDevice,
    /// Each queue family's capabilities.
    pub families: Vec<vk::QueueFlags>,
    /// The queues the application asked for: (family, count), unprotected only.
    pub queues: Vec<(u32, u32)>,
    /// The next layer's vkGetPhysicalDeviceSurfaceCapabilitiesKHR (None without the extension).
    pub surface_capabilities: Option<vk::PFN_vkGetPhysicalDeviceSurfaceCapabilitiesKHR>,
}

/// A swapchain as the capture sees it.
#[derive(Debug, Clone)]
pub struct SwapchainInfo {
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    /// Its images can be copied (TRANSFER_SRC usage), or why not.
    pub readable: Result<(), String>,
}

/// The device's part of the capture.
#[derive(Default)]
pub struct CaptureState {
    pub swapchains: HashMap<vk::SwapchainKHR, SwapchainInfo>,
    /// Presents so far: the frame the next present ends.
    pub presents: u64,
    /// Semaphores presents waited on: a present does not say when it is done with them, so
    /// they are destroyed with the device.
    pub semaphores: Vec<vk::Semaphore>,
}
