//! The loader-layer interface structures, which ash does not define: transcribed from the
//! Vulkan-Loader's `include/vulkan/vk_layer.h` (loader interface version 2; see
//! docs/LoaderLayerInterface.md, "Layer Version Negotiation" and "Layer Call Chains").

use std::ffi::{c_char, c_void};

use ash::vk;

/// `VkLayerFunction::VK_LAYER_LINK_INFO`: the chain info's union holds `pLayerInfo`.
pub const VK_LAYER_LINK_INFO: u32 = 0;

/// `VkLayerFunction::VK_LOADER_DATA_CALLBACK`: the union holds `pfnSetDeviceLoaderData`.
pub const VK_LOADER_DATA_CALLBACK: u32 = 1;

/// `PFN_vkSetDeviceLoaderData`: gives a dispatchable object the layer created itself (a command
/// buffer) the loader's dispatch pointer, so that the layers below can look it up.
pub type PfnSetDeviceLoaderData = unsafe extern "system" fn(vk::Device, *mut c_void) -> vk::Result;

/// `VkNegotiateLayerStructType::LAYER_NEGOTIATE_INTERFACE_STRUCT`.
pub const LAYER_NEGOTIATE_INTERFACE_STRUCT: u32 = 1;

/// The loader interface version this layer speaks.
pub const LAYER_INTERFACE_VERSION: u32 = 2;

/// `PFN_GetPhysicalDeviceProcAddr` (vk_layer.h).
pub type PfnGetPhysicalDeviceProcAddr =
    Option<unsafe extern "system" fn(vk::Instance, *const c_char) -> vk::PFN_vkVoidFunction>;

/// `VkNegotiateLayerInterface`.
#[repr(C)]
pub struct NegotiateLayerInterface {
    pub s_type: u32,
    pub p_next: *mut c_void,
    pub loader_layer_interface_version: u32,
    pub pfn_get_instance_proc_addr: Option<vk::PFN_vkGetInstanceProcAddr>,
    pub pfn_get_device_proc_addr: Option<vk::PFN_vkGetDeviceProcAddr>,
    pub pfn_get_physical_device_proc_addr: PfnGetPhysicalDeviceProcAddr,
}

/// `VkLayerInstanceLink`: one layer's next-in-chain entry points.
#[repr(C)]
pub struct LayerInstanceLink {
    pub p_next: *mut LayerInstanceLink,
    pub pfn_next_get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
    pub pfn_next_get_physical_device_proc_addr: PfnGetPhysicalDeviceProcAddr,
}

/// `VkLayerInstanceCreateInfo` (sType VK_STRUCTURE_TYPE_LOADER_INSTANCE_CREATE_INFO). The
/// union's largest member is two function pointers (`layerDevice`), hence `u` as two words.
#[repr(C)]
pub struct LayerInstanceCreateInfo {
    pub s_type: vk::StructureType,
    pub p_next: *const c_void,
    pub function: u32,
    pub u: [*mut c_void; 2],
}

/// `VkLayerDeviceLink`.
#[repr(C)]
pub struct LayerDeviceLink {
    pub p_next: *mut LayerDeviceLink,
    pub pfn_next_get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
    pub pfn_next_get_device_proc_addr: vk::PFN_vkGetDeviceProcAddr,
}

/// `VkLayerDeviceCreateInfo` (sType VK_STRUCTURE_TYPE_LOADER_DEVICE_CREATE_INFO); the union
/// is `pLayerInfo` or `pfnSetDeviceLoaderData`, one pointer.
#[repr(C)]
pub struct LayerDeviceCreateInfo {
    pub s_type: vk::StructureType,
    pub p_next: *const c_void,
    pub function: u32,
    pub u: *mut c_void,
}

/// The first structure in a pNext chain with `s_type` whose `function` is `function`.
///
/// # Safety
/// `p_next` is a valid Vulkan pNext chain (every node starts with sType, pNext), and every node
/// with `s_type` has the layout of `T`, whose first three fields are sType, pNext, function.
unsafe fn find_link<T>(mut p_next: *const c_void, s_type: vk::StructureType, function: u32) -> Option<*mut T> {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: the caller's contract: every node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next as *const c_void) };
        if ty == s_type {
            // SAFETY: a node of this sType is `T` (contract); `function` is its third field,
            // right after sType and pNext, as in both loader create-info structures.
            let found = unsafe { *((p_next as *const u8).add(2 * std::mem::size_of::<usize>()) as *const u32) };
            if found == function {
                return Some(p_next as *mut T);
            }
        }
        p_next = next;
    }
    None
}

/// The loader's link for this layer in `vkCreateInstance`'s chain: (the next layer's
/// vkGetInstanceProcAddr, and the chain node to advance before calling down).
///
/// # Safety
/// `info` is the create info the loader passed to this layer's vkCreateInstance.
pub unsafe fn instance_link(info: &vk::InstanceCreateInfo) -> Option<*mut LayerInstanceCreateInfo> {
    // SAFETY: the loader's chain is valid; its LOADER_INSTANCE_CREATE_INFO nodes are
    // VkLayerInstanceCreateInfo.
    let node = unsafe {
        find_link::<LayerInstanceCreateInfo>(
            info.p_next,
            vk::StructureType::LOADER_INSTANCE_CREATE_INFO,
            VK_LAYER_LINK_INFO,
        )
    }?;
    // SAFETY: the node was found above; with VK_LAYER_LINK_INFO its union holds pLayerInfo.
    let link = unsafe { (*node).u[0] } as *mut LayerInstanceLink;
    (!link.is_null()).then_some(node)
}

/// As [`instance_link`], for `vkCreateDevice`.
///
/// # Safety
/// `info` is the create info the loader passed to this layer's vkCreateDevice.
pub unsafe fn device_link(info: &vk::DeviceCreateInfo) -> Option<*mut LayerDeviceCreateInfo> {
    // SAFETY: as in `instance_link`, for the device chain's structure.
    let node = unsafe {
        find_link::<LayerDeviceCreateInfo>(
            info.p_next,
            vk::StructureType::LOADER_DEVICE_CREATE_INFO,
            VK_LAYER_LINK_INFO,
        )
    }?;
    // SAFETY: the node was found above; with VK_LAYER_LINK_INFO its union is pLayerInfo.
    let link = unsafe { (*node).u } as *mut LayerDeviceLink;
    (!link.is_null()).then_some(node)
}

/// The loader's vkSetDeviceLoaderData from `vkCreateDevice`'s chain.
///
/// # Safety
/// `info` is the create info the loader passed to this layer's vkCreateDevice.
pub unsafe fn device_loader_data(info: &vk::DeviceCreateInfo) -> Option<PfnSetDeviceLoaderData> {
    // SAFETY: as in `device_link`.
    let node = unsafe {
        find_link::<LayerDeviceCreateInfo>(
            info.p_next,
            vk::StructureType::LOADER_DEVICE_CREATE_INFO,
            VK_LOADER_DATA_CALLBACK,
        )
    }?;
    // SAFETY: with VK_LOADER_DATA_CALLBACK the union is pfnSetDeviceLoaderData (or null).
    let f = unsafe { (*node).u };
    // SAFETY: a non-null function pointer of that type, as the loader put it there.
    (!f.is_null()).then(|| unsafe { std::mem::transmute::<*mut c_void, PfnSetDeviceLoaderData>(f) })
}

/// The key the loader's dispatch puts in every dispatchable handle (instance, physical device,
/// device, queue, command buffer): the first pointer-sized word it points at. A device and its
/// queues and command buffers share one key.
///
/// # Safety
/// `handle` is a live dispatchable Vulkan handle.
pub unsafe fn dispatch_key(handle: u64) -> usize {
    // SAFETY: a dispatchable handle is a pointer to an object whose first word is the loader's
    // dispatch table pointer (LoaderLayerInterface.md, "Distributed Dispatch").
    unsafe { *(handle as usize as *const usize) }
}
