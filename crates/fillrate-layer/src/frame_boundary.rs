//! VK_EXT_frame_boundary offered where the driver lacks it, so that a program that never
//! presents can still mark its frames for the layer (frame_cuts.rs reads the marks). The
//! extension has no commands, only `VkFrameBoundaryEXT` in the chains of submissions and
//! presents and a feature struct; so the layer lists it (here and in its manifest, which the
//! loader checks enabled extensions against), and keeps all of it from the layers and driver
//! below: the name out of vkCreateDevice's extensions, the structs out of every chain it
//! passes on. A chain is const to the layer: a node is unlinked in place for the call and put
//! back right after, as lifecycle.rs does with the features.

use std::ffi::{c_char, c_void, CStr};

use ash::vk;
use ash::vk::Handle;

use super::arrays::app_array;
use super::state::{self, guard, InstanceData};

pub const NAME: &CStr = c"VK_EXT_frame_boundary";
const SPEC_VERSION: u32 = 1;

/// Whether the layers and driver below offer the extension on `physical`.
pub fn below_has(instance: &InstanceData, physical: vk::PhysicalDevice) -> bool {
    // SAFETY: `physical` is a physical device of `instance`; the call goes down the chain.
    let listed = unsafe { instance.fns.enumerate_device_extension_properties(physical) }.unwrap_or_default();
    listed.iter().any(|e| e.extension_name_as_c_str() == Ok(NAME))
}

fn property() -> vk::ExtensionProperties {
    let mut property = vk::ExtensionProperties { spec_version: SPEC_VERSION, ..Default::default() };
    for (to, &from) in property.extension_name.iter_mut().zip(NAME.to_bytes()) {
        *to = from as c_char;
    }
    property
}

/// The Vulkan two-call answer: `list`'s length, or as much of it as fits.
///
/// # Safety
/// `count` is valid; `out` null or holding `*count` elements.
unsafe fn answer(list: &[vk::ExtensionProperties], count: *mut u32, out: *mut vk::ExtensionProperties) -> vk::Result {
    // SAFETY: the caller's contract.
    unsafe {
        if out.is_null() {
            *count = list.len() as u32;
            return vk::Result::SUCCESS;
        }
        let n = (*count as usize).min(list.len());
        std::ptr::copy_nonoverlapping(list.as_ptr(), out, n);
        *count = n as u32;
        if n < list.len() {
            vk::Result::INCOMPLETE
        } else {
            vk::Result::SUCCESS
        }
    }
}

/// vkEnumerateDeviceExtensionProperties: the layer's own list when asked by its name, and the
/// extension added to the device's when it is not there.
pub(super) unsafe extern "system" fn enumerate_device_extension_properties(
    physical: vk::PhysicalDevice,
    layer: *const c_char,
    count: *mut u32,
    out: *mut vk::ExtensionProperties,
) -> vk::Result {
    // SAFETY: the caller's name, null or a C string.
    let asked = (!layer.is_null()).then(|| unsafe { CStr::from_ptr(layer) }.to_str().ok()).flatten();
    if asked == Some(super::manifest::LAYER_NAME) {
        // SAFETY: the caller's arrays.
        return unsafe { answer(&[property()], count, out) };
    }
    let Some(instance) = guard(None, || state::instance_of(physical.as_raw())) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // Loaded when the instance was created: asked now, the loader's terminator would look the
    // name up in the chain's finished table and hand back the top of the chain (this hook).
    let next = instance.fns.fp_v1_0().enumerate_device_extension_properties;
    if asked.is_some() {
        // SAFETY: the application's arguments, passed on.
        return unsafe { next(physical, layer, count, out) };
    }
    let mut n = 0u32;
    // SAFETY: a count query down the chain.
    let result = unsafe { next(physical, layer, &mut n, std::ptr::null_mut()) };
    if result != vk::Result::SUCCESS {
        return result;
    }
    let mut list = vec![vk::ExtensionProperties::default(); n as usize];
    // SAFETY: `list` holds `n` elements.
    let result = unsafe { next(physical, layer, &mut n, list.as_mut_ptr()) };
    if result != vk::Result::SUCCESS && result != vk::Result::INCOMPLETE {
        return result;
    }
    list.truncate(n as usize);
    if !list.iter().any(|e| e.extension_name_as_c_str() == Ok(NAME)) {
        list.push(property());
    }
    if instance.config.out.is_some() {
        // Measuring: only what the layer can measure is offered (extensions.rs).
        list.retain(|e| guard(true, || super::extensions::offered(e)));
    }
    // SAFETY: the caller's arrays.
    unsafe { answer(&list, count, out) }
}

/// A node unlinked from a chain: where its predecessor's pNext lives, and what it held.
#[derive(Default)]
pub struct Unlinked(Vec<(*mut *const c_void, *const c_void)>);

impl Unlinked {
    /// Puts every unlinked node back, last first.
    ///
    /// # Safety
    /// The chains are the ones unlinked from, still alive.
    pub unsafe fn restore(self) {
        for (field, value) in self.0.into_iter().rev() {
            // SAFETY: the caller's contract.
            unsafe { *field = value };
        }
    }
}

/// Unlinks every node of type `ty` from the chain whose head pointer lives at `head`.
///
/// # Safety
/// `head` points at a valid pNext field, of a chain the caller may write to until it restores it.
pub unsafe fn unlink(head: *mut *const c_void, ty: vk::StructureType, unlinked: &mut Unlinked) {
    let mut field = head;
    // SAFETY: the caller's contract; every chain node starts like VkBaseInStructure.
    unsafe {
        while !(*field).is_null() {
            let node = *field as *mut vk::BaseOutStructure<'static>;
            if (*node).s_type == ty {
                unlinked.0.push((field, *field));
                *field = (*node).p_next as *const c_void;
            } else {
                field = std::ptr::addr_of_mut!((*node).p_next).cast();
            }
        }
    }
}

/// Unlinks the VkFrameBoundaryEXT of each of `count` infos at `infos` (submit or present
/// infos; `p_next_of` finds an info's pNext field) when the layer emulates the extension.
///
/// # Safety
/// `infos` holds `count` valid infos the caller may write to until it restores them.
pub unsafe fn strip<T>(
    emulated: bool,
    infos: *const T,
    count: u32,
    p_next_of: fn(*mut T) -> *mut *const c_void,
) -> Unlinked {
    let mut unlinked = Unlinked(Vec::new());
    if !emulated || infos.is_null() {
        return unlinked;
    }
    for i in 0..count as usize {
        // SAFETY: the caller's contract.
        unsafe { unlink(p_next_of((infos as *mut T).add(i)), vk::StructureType::FRAME_BOUNDARY_EXT, &mut unlinked) };
    }
    unlinked
}

/// The extension names without VK_EXT_frame_boundary, if it was among them.
///
/// # Safety
/// `names` holds `count` C strings.
pub unsafe fn without_name(names: *const *const c_char, count: u32) -> Option<Vec<*const c_char>> {
    // SAFETY: the caller's contract.
    let all = unsafe { app_array(names, count) };
    // SAFETY: as above: each is a C string.
    let keep: Vec<*const c_char> = all.iter().copied().filter(|&n| unsafe { CStr::from_ptr(n) } != NAME).collect();
    (keep.len() < all.len()).then_some(keep)
}

/// vkGetPhysicalDeviceFeatures2 (and its KHR alias): the feature struct is kept from the layers
/// below and answered `frameBoundary = VK_TRUE` when they lack the extension.
unsafe fn features2_with(
    pick: fn(&InstanceData) -> Option<vk::PFN_vkGetPhysicalDeviceFeatures2>,
    physical: vk::PhysicalDevice,
    features: *mut vk::PhysicalDeviceFeatures2<'_>,
) {
    let Some(instance) = guard(None, || state::instance_of(physical.as_raw())) else { return };
    // Loaded when the instance was created (see enumerate_device_extension_properties), by the
    // name the program called: the KHR alias on a Vulkan 1.0 instance.
    let Some(next) = pick(&instance) else { return };
    let measuring = instance.config.out.is_some() && !features.is_null();
    let hide = move || {
        if measuring {
            // SAFETY: the application's writable chain, after the call filled it.
            guard((), || unsafe { super::extensions::hide_features((*features).p_next) })
        }
    };
    let emulate = guard(false, || !below_has(&instance, physical));
    if !emulate || features.is_null() {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(physical, features) };
        return hide();
    }
    let mut unlinked = Unlinked(Vec::new());
    let ty = vk::StructureType::PHYSICAL_DEVICE_FRAME_BOUNDARY_FEATURES_EXT;
    // SAFETY: the application's writable chain, put back below.
    unsafe {
        unlink(std::ptr::addr_of_mut!((*features).p_next).cast(), ty, &mut unlinked);
        next(physical, features);
    }
    let nodes: Vec<*const c_void> = unlinked.0.iter().map(|&(_, node)| node).collect();
    // SAFETY: the same chain; each node is the application's feature struct.
    unsafe {
        unlinked.restore();
        for node in nodes {
            (*(node as *mut vk::PhysicalDeviceFrameBoundaryFeaturesEXT<'_>)).frame_boundary = vk::TRUE;
        }
    }
    hide();
}

pub(super) unsafe extern "system" fn get_physical_device_features2(
    physical: vk::PhysicalDevice,
    features: *mut vk::PhysicalDeviceFeatures2<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { features2_with(|i| i.features2[0], physical, features) }
}

pub(super) unsafe extern "system" fn get_physical_device_features2_khr(
    physical: vk::PhysicalDevice,
    features: *mut vk::PhysicalDeviceFeatures2<'_>,
) {
    // SAFETY: the application's arguments.
    unsafe { features2_with(|i| i.features2[1], physical, features) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unlink_takes_every_node_of_the_type_out_and_restore_puts_them_back() {
        let mut boundary = vk::PhysicalDeviceFrameBoundaryFeaturesEXT::default();
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut v13).push_next(&mut boundary);
        let types = |f: &vk::PhysicalDeviceFeatures2<'_>| {
            let mut out = Vec::new();
            let mut node = f.p_next as *const vk::BaseInStructure<'_>;
            while !node.is_null() {
                // SAFETY: the test's own chain.
                unsafe {
                    out.push((*node).s_type);
                    node = (*node).p_next;
                }
            }
            out
        };
        let before = types(&features);
        let mut unlinked = Unlinked(Vec::new());
        let ty = vk::StructureType::PHYSICAL_DEVICE_FRAME_BOUNDARY_FEATURES_EXT;
        // SAFETY: the test's own chain, restored below.
        unsafe { unlink(std::ptr::addr_of_mut!(features.p_next).cast(), ty, &mut unlinked) };
        assert_eq!(types(&features), [vk::StructureType::PHYSICAL_DEVICE_VULKAN_1_3_FEATURES]);
        // SAFETY: the same chain.
        unsafe { unlinked.restore() };
        assert_eq!(types(&features), before);
        assert_eq!(property().extension_name_as_c_str(), Ok(NAME));
    }
}
