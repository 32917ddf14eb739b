//! Physical device choice and logical device creation under the mobile profile.

use std::ffi::CStr;

use ash::vk;

use super::instance::Instance;
use super::mobile_profile::{self, EnabledFeatures, LimitCheck};
use crate::error::{Error, Result, VkContext};

/// Which physical device to use. `NOSTENCIL_DEVICE` (a name fragment such as `lavapipe`, or an
/// index) overrides `Auto`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum DeviceChoice {
    /// A hardware GPU if there is one, else the CPU (lavapipe) device.
    #[default]
    Auto,
    Index(usize),
    /// Case-insensitive substring of the device name; `lavapipe` also matches llvmpipe.
    Name(String),
}

impl DeviceChoice {
    pub fn parse(text: &str) -> Self {
        match text.trim() {
            "" | "auto" => DeviceChoice::Auto,
            t => t.parse().map(DeviceChoice::Index).unwrap_or_else(|_| DeviceChoice::Name(t.to_owned())),
        }
    }

    /// The explicit choice, else `NOSTENCIL_DEVICE`, else automatic.
    pub fn from_env_or(self) -> Self {
        match (&self, std::env::var("NOSTENCIL_DEVICE")) {
            (DeviceChoice::Auto, Ok(value)) => DeviceChoice::parse(&value),
            _ => self,
        }
    }
}

/// What was learnt about the chosen device.
#[derive(Debug, Clone)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub device_type: vk::PhysicalDeviceType,
    pub api_version: u32,
    pub limits: vk::PhysicalDeviceLimits,
    pub timestamp_valid_bits: u32,
    pub limit_checks: Vec<LimitCheck>,
    pub features: EnabledFeatures,
    pub has_lazily_allocated_memory: bool,
}

pub struct Device {
    pub physical: vk::PhysicalDevice,
    pub raw: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub info: DeviceInfo,
    pub memory_properties: vk::PhysicalDeviceMemoryProperties,
}

struct Candidate {
    index: usize,
    physical: vk::PhysicalDevice,
    name: String,
    properties: vk::PhysicalDeviceProperties,
}

fn is_software(name: &str, ty: vk::PhysicalDeviceType) -> bool {
    ty == vk::PhysicalDeviceType::CPU || name.to_lowercase().contains("llvmpipe")
}

fn matches_name(name: &str, wanted: &str) -> bool {
    let name = name.to_lowercase();
    let wanted = wanted.to_lowercase();
    // lavapipe reports itself as "llvmpipe (LLVM ...)".
    name.contains(&wanted) || (wanted == "lavapipe" && name.contains("llvmpipe"))
}

impl Device {
    /// As `new`, with device extensions enabled (`VK_KHR_swapchain`, for the viewer only); a
    /// device that lacks one is refused with its name.
    pub fn with_extensions(instance: &Instance, choice: &DeviceChoice, extensions: &[&CStr]) -> Result<Self> {
        let candidate = choose_physical_device(instance, choice)?;
        let physical = candidate.physical;
        let raw_instance = &instance.raw;

        // SAFETY: `physical` was enumerated from this instance, which is alive for the call.
        let families = unsafe { raw_instance.get_physical_device_queue_family_properties(physical) };
        let (queue_family, family) = families
            .iter()
            .enumerate()
            .find(|(_, f)| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
            .ok_or_else(|| Error::Device(format!("device '{}' has no graphics queue", candidate.name)))?;
        let queue_family = queue_family as u32;

        let limits = candidate.properties.limits;
        let limit_checks = mobile_profile::check_limits(&limits, family.timestamp_valid_bits);
        if let Some(bad) = limit_checks.iter().find(|c| !c.ok) {
            return Err(Error::Device(format!(
                "device '{}' is below the mobile profile: {} is {}, the profile needs {}",
                candidate.name, bad.name, bad.device, bad.profile
            )));
        }

        // SAFETY: as above.
        let available = unsafe { raw_instance.enumerate_device_extension_properties(physical) }
            .vk("vkEnumerateDeviceExtensionProperties")?;
        if let Some(missing) = extensions
            .iter()
            .find(|wanted| !available.iter().any(|e| e.extension_name_as_c_str().ok() == Some(**wanted)))
        {
            return Err(Error::Device(format!(
                "device '{}' lacks the extension {}",
                candidate.name,
                missing.to_string_lossy()
            )));
        }
        let extension_names: Vec<*const std::ffi::c_char> = extensions.iter().map(|e| e.as_ptr()).collect();

        // SAFETY: as above.
        let supported = unsafe { raw_instance.get_physical_device_features(physical) };
        let features = EnabledFeatures::choose(&supported);
        let vk_features = features.to_vk();
        debug_assert!(mobile_profile::forbidden_features_enabled(&vk_features).is_empty());

        let priorities = [1.0f32];
        let queue_info =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
        let create_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_extension_names(&extension_names)
            .enabled_features(&vk_features);
        // SAFETY: `create_info` and everything it points at (queue info, priorities, extension
        // names, features) live until the call returns; the extensions were checked available.
        let raw = unsafe { raw_instance.create_device(physical, &create_info, None) }.vk("vkCreateDevice")?;
        // SAFETY: the device was created with one queue of `queue_family`.
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };
        // SAFETY: as for the queries above.
        let memory_properties = unsafe { raw_instance.get_physical_device_memory_properties(physical) };
        let has_lazily_allocated_memory = memory_properties.memory_types
            [..memory_properties.memory_type_count as usize]
            .iter()
            .any(|t| t.property_flags.contains(vk::MemoryPropertyFlags::LAZILY_ALLOCATED));

        Ok(Device {
            physical,
            raw,
            queue,
            queue_family,
            memory_properties,
            info: DeviceInfo {
                index: candidate.index,
                name: candidate.name,
                device_type: candidate.properties.device_type,
                api_version: candidate.properties.api_version,
                limits,
                timestamp_valid_bits: family.timestamp_valid_bits,
                limit_checks,
                features,
                has_lazily_allocated_memory,
            },
        })
    }
}

fn choose_physical_device(instance: &Instance, choice: &DeviceChoice) -> Result<Candidate> {
    // SAFETY: the instance is alive for the call.
    let physicals = unsafe { instance.raw.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    let candidates: Vec<Candidate> = physicals
        .into_iter()
        .enumerate()
        .map(|(index, physical)| {
            // SAFETY: `physical` was just enumerated from this instance.
            let properties = unsafe { instance.raw.get_physical_device_properties(physical) };
            let name = properties
                .device_name_as_c_str()
                .map(CStr::to_string_lossy)
                .map(|n| n.into_owned())
                .unwrap_or_else(|_| format!("device {index}"));
            Candidate { index, physical, name, properties }
        })
        .collect();
    if candidates.is_empty() {
        return Err(Error::Device("no Vulkan device found (is mesa-vulkan-drivers installed?)".into()));
    }
    let names = || candidates.iter().map(|c| format!("{}: {}", c.index, c.name)).collect::<Vec<_>>().join(", ");

    let found = match choice {
        DeviceChoice::Index(i) => candidates.iter().position(|c| c.index == *i),
        DeviceChoice::Name(wanted) => candidates.iter().position(|c| matches_name(&c.name, wanted)),
        DeviceChoice::Auto => candidates
            .iter()
            .enumerate()
            .min_by_key(|(_, c)| {
                let rank = match c.properties.device_type {
                    vk::PhysicalDeviceType::DISCRETE_GPU => 0,
                    vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
                    vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
                    _ => 3,
                };
                if is_software(&c.name, c.properties.device_type) {
                    4
                } else {
                    rank
                }
            })
            .map(|(i, _)| i),
    };
    // The list is named before it is consumed; the position came from it, so `nth` finds it,
    // and a miss (no match) is the user's choice of device, reported with what is available.
    let available = names();
    found
        .and_then(|position| candidates.into_iter().nth(position))
        .ok_or_else(|| Error::Device(format!("no Vulkan device matches {choice:?}; available: {available}")))
}

/// A Vulkan device as another program (a GL program on zink) is told to pick it: its name, its
/// PCI ids, and whether it is the CPU's (lavapipe).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceIdentity {
    pub name: String,
    pub vendor_id: u32,
    pub device_id: u32,
    pub software: bool,
}

/// The device `choice` names, as [`Device::new`] would choose it, without creating it.
pub fn identify(choice: &DeviceChoice) -> Result<DeviceIdentity> {
    let instance = Instance::new(None)?;
    let candidate = choose_physical_device(&instance, choice)?;
    Ok(DeviceIdentity {
        software: is_software(&candidate.name, candidate.properties.device_type),
        vendor_id: candidate.properties.vendor_id,
        device_id: candidate.properties.device_id,
        name: candidate.name,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_choice_parses_index_name_and_auto() {
        assert_eq!(DeviceChoice::parse("auto"), DeviceChoice::Auto);
        assert_eq!(DeviceChoice::parse("1"), DeviceChoice::Index(1));
        assert_eq!(DeviceChoice::parse("lavapipe"), DeviceChoice::Name("lavapipe".into()));
        assert!(matches_name("llvmpipe (LLVM 15.0.6, 256 bits)", "lavapipe"));
        assert!(matches_name("llvmpipe (LLVM 15.0.6, 256 bits)", "LLVMpipe"));
        assert!(!matches_name("AMD Radeon", "lavapipe"));
    }
}
