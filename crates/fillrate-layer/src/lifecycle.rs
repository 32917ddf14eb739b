//! vkCreateInstance / vkDestroyInstance / vkCreateDevice / vkDestroyDevice: walking the loader's
//! chain (LoaderLayerInterface.md, "Layer Call Chains"), enabling the query features, and the
//! final read back and write at device destruction.

use std::ffi::{c_char, CStr};
use std::sync::{Arc, Mutex, Once};

use ash::vk;
use ash::vk::Handle;

use super::capture::capture_device;
use super::capture_state::CaptureDevice;
use super::config::Config;
use super::frame_boundary;
use super::frames::FrameAssembler;
use super::loader::{
    device_link, device_loader_data, instance_link, LayerDeviceLink, LayerInstanceLink, PfnSetDeviceLoaderData,
};
use super::readback::{read_completed, write_if_due};
use super::report::CounterSupport;
use super::state::{self, guard, DeviceData, DeviceInfo, DeviceState, InstanceData, NextFns};

/// Says `message` on stderr once per process.
fn say_once(once: &Once, message: &str) {
    once.call_once(|| eprintln!("nostencil fill-rate layer: {message}"));
}

fn process_name() -> String {
    std::env::current_exe()
        .ok()
        .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .unwrap_or_else(|| "unknown".into())
}

/// # Safety
/// Called by the loader as vkCreateInstance, with its chain info in `info`'s pNext.
pub(super) unsafe extern "system" fn create_instance(
    info: *const vk::InstanceCreateInfo,
    allocator: *const vk::AllocationCallbacks<'_>,
    instance: *mut vk::Instance,
) -> vk::Result {
    // SAFETY: the loader passes a valid create info.
    let Some(info_ref) = (unsafe { info.as_ref() }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    // SAFETY: `info_ref` came from the loader with its chain.
    let Some(node) = (unsafe { instance_link(info_ref) }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    // SAFETY: `node` is the loader's VkLayerInstanceCreateInfo; its pLayerInfo is non-null
    // (checked by `instance_link`). Advancing it before calling down is the loader's protocol.
    let next_gipa = unsafe {
        let link = (*node).u[0] as *mut LayerInstanceLink;
        (*node).u[0] = (*link).p_next.cast();
        (*link).pfn_next_get_instance_proc_addr
    };
    // SAFETY: vkCreateInstance is fetched with a null instance, as the loader allows.
    let create = unsafe { next_gipa(vk::Instance::null(), c"vkCreateInstance".as_ptr()) };
    let Some(create) = create else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    // SAFETY: the pointer is the next layer's vkCreateInstance.
    let create: vk::PFN_vkCreateInstance = unsafe { std::mem::transmute(create) };
    // SAFETY: the application's arguments, passed on unchanged.
    let result = unsafe { create(info, allocator, instance) };
    if result != vk::Result::SUCCESS {
        return result;
    }
    guard((), || {
        // SAFETY: vkCreateInstance succeeded, so `*instance` is the new instance.
        let handle = unsafe { *instance };
        // SAFETY: the application info, when given, is valid with a NUL-terminated name or null.
        let application = unsafe { info_ref.p_application_info.as_ref() }
            .filter(|a| !a.p_application_name.is_null())
            // SAFETY: as above.
            .map(|a| unsafe { CStr::from_ptr(a.p_application_name) }.to_string_lossy().into_owned())
            .filter(|name| !name.is_empty())
            .unwrap_or_else(process_name);
        let (config, warnings) = Config::from_env();
        for warning in warnings {
            eprintln!("nostencil fill-rate layer: {warning}");
        }
        if config.out.is_none() {
            static ONCE: Once = Once::new();
            let capture = if config.capture.is_some() { " (nor capturing)" } else { "" };
            say_once(&ONCE, &format!("NOSTENCIL_FILLRATE_OUT is not set: measuring nothing{capture}"));
        }
        if config.out.is_some() && config.frame_on == super::config::FrameOn::Swap {
            super::gl_swaps::register();
        }
        // SAFETY: the next layer's GIPA with the instance it created.
        let fns =
            unsafe { ash::Instance::load_with(|name| std::mem::transmute(next_gipa(handle, name.as_ptr())), handle) };
        let features2 = [c"vkGetPhysicalDeviceFeatures2", c"vkGetPhysicalDeviceFeatures2KHR"].map(|name| {
            // SAFETY: as above; the function has this type, or is null (None: both one pointer).
            unsafe {
                std::mem::transmute::<vk::PFN_vkVoidFunction, Option<vk::PFN_vkGetPhysicalDeviceFeatures2>>(next_gipa(
                    handle,
                    name.as_ptr(),
                ))
            }
        });
        state::add_instance(InstanceData { handle, gipa: next_gipa, fns, features2, application, config });
    });
    result
}

/// # Safety
/// Called as vkDestroyInstance.
pub(super) unsafe extern "system" fn destroy_instance(
    instance: vk::Instance,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    let data = guard(None, || state::remove_instance(instance));
    if let Some(data) = data {
        // SAFETY: the application's arguments, passed to the next layer's vkDestroyInstance.
        unsafe { (data.fns.fp_v1_0().destroy_instance)(instance, allocator) };
    }
}

/// Turns on pipelineStatisticsQuery and occlusionQueryPrecise in `features` where `supported`
/// has them; returns whether anything changed.
fn enable_query_features(features: &mut vk::PhysicalDeviceFeatures, supported: &vk::PhysicalDeviceFeatures) -> bool {
    let before = (features.pipeline_statistics_query, features.occlusion_query_precise);
    features.pipeline_statistics_query |= supported.pipeline_statistics_query;
    features.occlusion_query_precise |= supported.occlusion_query_precise;
    before != (features.pipeline_statistics_query, features.occlusion_query_precise)
}

/// The VkPhysicalDeviceFeatures2 in a pNext chain, if any.
///
/// # Safety
/// `p_next` is a valid pNext chain.
unsafe fn features2_in_chain(mut p_next: *const std::ffi::c_void) -> Option<*mut vk::PhysicalDeviceFeatures2<'static>> {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next.cast()) };
        if ty == vk::StructureType::PHYSICAL_DEVICE_FEATURES_2 {
            return Some(p_next as *mut _);
        }
        p_next = next;
    }
    None
}

/// # Safety
/// Called by the loader as vkCreateDevice, with its chain info in `info`'s pNext.
pub(super) unsafe extern "system" fn create_device(
    physical: vk::PhysicalDevice,
    info: *const vk::DeviceCreateInfo,
    allocator: *const vk::AllocationCallbacks<'_>,
    device: *mut vk::Device,
) -> vk::Result {
    // SAFETY: the loader passes a valid create info.
    let Some(info_ref) = (unsafe { info.as_ref() }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    let Some(instance) = guard(None, || state::instance_of(physical.as_raw())) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    // SAFETY: `info_ref` came from the loader with its chain.
    let Some(node) = (unsafe { device_link(info_ref) }) else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    // SAFETY: the loader's VkLayerDeviceCreateInfo with a non-null pLayerInfo; advanced before
    // calling down, as the loader's protocol says.
    let (next_gipa, next_gdpa) = unsafe {
        let link = (*node).u as *mut LayerDeviceLink;
        (*node).u = (*link).p_next.cast();
        ((*link).pfn_next_get_instance_proc_addr, (*link).pfn_next_get_device_proc_addr)
    };
    // SAFETY: vkCreateDevice fetched from the next layer for this instance.
    let create = unsafe { next_gipa(instance.handle, c"vkCreateDevice".as_ptr()) };
    let Some(create) = create else { return vk::Result::ERROR_INITIALIZATION_FAILED };
    // SAFETY: the pointer is the next layer's vkCreateDevice.
    let create: vk::PFN_vkCreateDevice = unsafe { std::mem::transmute(create) };

    let active = instance.config.out.is_some();
    // SAFETY: `physical` is the application's physical device of this instance.
    let supported = unsafe { instance.fns.get_physical_device_features(physical) };
    let mut copy = *info_ref;
    let mut features = vk::PhysicalDeviceFeatures::default();
    let mut restore: Option<(*mut vk::PhysicalDeviceFeatures2<'static>, vk::PhysicalDeviceFeatures)> = None;
    if active {
        // SAFETY: pEnabledFeatures is null or valid.
        if let Some(app_features) = unsafe { info_ref.p_enabled_features.as_ref() } {
            features = *app_features;
            enable_query_features(&mut features, &supported);
            copy.p_enabled_features = &features;
        // SAFETY: the application's chain is valid.
        } else if let Some(features2) = unsafe { features2_in_chain(info_ref.p_next) } {
            // The features live in the application's VkPhysicalDeviceFeatures2 inside its chain,
            // which cannot be copied generically (unknown node sizes before it): set the two
            // bits in place for the call, then put the application's values back.
            // SAFETY: the node is the application's VkPhysicalDeviceFeatures2, valid for the
            // call; it is restored right after.
            unsafe {
                let original = (*features2).features;
                if enable_query_features(&mut (*features2).features, &supported) {
                    restore = Some((features2, original));
                }
            }
        } else {
            enable_query_features(&mut features, &supported);
            copy.p_enabled_features = &features;
        }
    }
    // VK_EXT_frame_boundary, offered by the layer where the driver lacks it: kept from below.
    // SAFETY: the application's extension names.
    let without =
        unsafe { frame_boundary::without_name(info_ref.pp_enabled_extension_names, info_ref.enabled_extension_count) };
    let emulated = without.is_some() && !guard(true, || frame_boundary::below_has(&instance, physical));
    let mut unlinked = frame_boundary::Unlinked::default();
    if let (true, Some(names)) = (emulated, &without) {
        copy.pp_enabled_extension_names = names.as_ptr();
        copy.enabled_extension_count = names.len() as u32;
        let ty = vk::StructureType::PHYSICAL_DEVICE_FRAME_BOUNDARY_FEATURES_EXT;
        // SAFETY: the chain starts at our copy's field; its nodes are restored after the call.
        unsafe { frame_boundary::unlink(std::ptr::addr_of_mut!(copy.p_next).cast(), ty, &mut unlinked) };
    }
    // SAFETY: the application's create info, with at most the two query features added (and
    // the frame-boundary extension the layer provides taken out).
    let result = unsafe { create(physical, &copy, allocator, device) };
    // SAFETY: the same chain, still alive.
    unsafe { unlinked.restore() };
    if let Some((features2, original)) = restore {
        // SAFETY: the same node, still alive: the application's values back.
        unsafe { (*features2).features = original };
    }
    if result != vk::Result::SUCCESS {
        return result;
    }
    guard((), || {
        // SAFETY: vkCreateDevice succeeded.
        let handle = unsafe { *device };
        // SAFETY: the loader's create info, with its chain.
        let set_loader_data = unsafe { device_loader_data(info_ref) };
        let created = (physical, info_ref, (without.is_some(), emulated));
        register_device(&instance, created, handle, next_gdpa, &supported, set_loader_data);
    });
    result
}

fn register_device(
    instance: &InstanceData,
    (physical, create_info, (frame_boundaries, frame_boundary_emulated)): (
        vk::PhysicalDevice,
        &vk::DeviceCreateInfo<'_>,
        (bool, bool),
    ),
    handle: vk::Device,
    gdpa: vk::PFN_vkGetDeviceProcAddr,
    supported: &vk::PhysicalDeviceFeatures,
    set_loader_data: Option<PfnSetDeviceLoaderData>,
) {
    // SAFETY: `physical` belongs to `instance`.
    let properties = unsafe { instance.fns.get_physical_device_properties(physical) };
    // SAFETY: as above.
    let memory = unsafe { instance.fns.get_physical_device_memory_properties(physical) };
    // SAFETY: as above.
    let families = unsafe { instance.fns.get_physical_device_queue_family_properties(physical) };
    let timestamp_bits: Vec<u32> = families.iter().map(|f| f.timestamp_valid_bits).collect();
    let support = CounterSupport {
        pipeline_statistics: supported.pipeline_statistics_query == vk::TRUE,
        occlusion_precise: supported.occlusion_query_precise == vk::TRUE,
        timestamps: timestamp_bits.iter().any(|&b| b > 0),
    };
    if instance.config.out.is_some() {
        let missing: Vec<&str> = [
            (support.pipeline_statistics, "pipelineStatisticsQuery (no vertex/primitive/fragment counts)"),
            (support.occlusion_precise, "occlusionQueryPrecise (samples passed may be inexact)"),
            (support.timestamps, "timestamps (no GPU time)"),
        ]
        .into_iter()
        .filter(|(has, _)| !has)
        .map(|(_, what)| what)
        .collect();
        if !missing.is_empty() {
            static ONCE: Once = Once::new();
            say_once(&ONCE, &format!("the device lacks {}", missing.join(", ")));
        }
    }
    // SAFETY: the next layer's GDPA with the device it created.
    let fns = unsafe { ash::Device::load_with(|name| std::mem::transmute(gdpa(handle, name.as_ptr())), handle) };
    // SAFETY: as above.
    let next = unsafe { NextFns::load(gdpa, handle) };
    let name = properties.device_name_as_c_str().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let capture = match instance.config.capture {
        // SAFETY: the application's create info, with which the device was just made.
        Some(_) => unsafe { capture_device(instance, physical, &families, create_info) },
        None => CaptureDevice::default(),
    };
    // A program that enabled VK_EXT_frame_boundary marks its frames: only its marks cut them.
    let device_state = DeviceState {
        frames: Some(FrameAssembler::new(instance.config.frames)),
        boundaries: frame_boundaries,
        ..DeviceState::default()
    };
    state::add_device(Arc::new(DeviceData {
        handle,
        gdpa,
        fns,
        next,
        info: DeviceInfo {
            name,
            support,
            timestamp_bits,
            timestamp_period: properties.limits.timestamp_period as f64,
            memory,
            set_loader_data,
            capture,
            frame_boundary_emulated,
        },
        application: instance.application.clone(),
        config: instance.config.clone(),
        state: Mutex::new(device_state),
    }));
}

/// # Safety
/// Called as vkDestroyDevice.
pub(super) unsafe extern "system" fn destroy_device(device: vk::Device, allocator: *const vk::AllocationCallbacks<'_>) {
    let data = guard(None, || state::remove_device(device));
    let Some(data) = data else { return };
    guard((), || {
        let mut st = data.state();
        // The application has waited for all its work before destroying the device.
        read_completed(&data, &mut st, |_| true);
        st.frames().close_last();
        super::readback::finish_frames(&data, &mut st);
        if data.config.tiler {
            st.tiler.check.finish();
        }
        write_if_due(&data, &mut st, true);
        let pools: Vec<vk::QueryPool> = st.buffers.values().flat_map(|b| b.recording.pools()).collect();
        for pool in pools {
            // SAFETY: the layer's own pools; no work is pending at device destruction.
            unsafe { data.fns.destroy_query_pool(pool, None) };
        }
        super::proofs::destroy(&data, &mut st);
        super::capture::destroy(&data, &mut st);
        for (_, pool) in st.copy_pools.drain() {
            // SAFETY: the layer's own command pools; their buffers were freed at read back.
            unsafe { data.fns.destroy_command_pool(pool, None) };
        }
    });
    if let Some(destroy) = data.next.destroy_device {
        // SAFETY: the application's arguments, passed on.
        unsafe { destroy(device, allocator) };
    }
}

/// The name at `name` (a NUL-terminated C string from the loader or application).
///
/// # Safety
/// `name` is null or a valid C string.
pub unsafe fn c_name<'a>(name: *const c_char) -> Option<&'a str> {
    if name.is_null() {
        return None;
    }
    // SAFETY: the caller's contract.
    unsafe { CStr::from_ptr(name) }.to_str().ok()
}
