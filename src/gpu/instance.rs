//! The Vulkan instance: loader, optional Khronos validation layer (with the checks chosen in
//! `validation`: core, synchronisation, best practices) and a debug-utils messenger that records
//! every validation message so that tests can fail on any of them.

use std::ffi::{c_char, c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::{ext::debug_utils, ext::validation_features, vk};

use super::validation::{self, ValidationChecks, ValidationReport};
use crate::error::{Error, Result, VkContext};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Messages the validation layer reported (warnings and errors), in order.
#[derive(Clone, Default)]
pub struct ValidationLog(Arc<Mutex<Vec<String>>>);

impl ValidationLog {
    pub fn messages(&self) -> Vec<String> {
        self.0.lock().map(|m| m.clone()).unwrap_or_default()
    }

    fn push(&self, message: String) {
        if let Ok(mut messages) = self.0.lock() {
            messages.push(message);
        }
    }
}

pub struct Instance {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    messenger: Option<(debug_utils::Instance, vk::DebugUtilsMessengerEXT, Box<ValidationLog>)>,
    validation: Option<ValidationReport>,
    /// VK_EXT_debug_utils is enabled, so command buffers can carry labels (each measured pass
    /// is labelled with its name for RenderDoc, the validation layer and the fill-rate layer).
    pub debug_labels: bool,
}

impl Instance {
    pub fn new(validation: Option<ValidationChecks>) -> Result<Self> {
        Self::with_extensions(validation, &[])
    }

    /// As `new`, with more instance extensions enabled: the window-system surface extensions
    /// (`ash_window::enumerate_required_extensions`), which only the viewer asks for.
    pub fn with_extensions(validation: Option<ValidationChecks>, extra_extensions: &[*const c_char]) -> Result<Self> {
        // SAFETY: this loads the system's Vulkan loader (libvulkan), whose initialisers are
        // trusted like any system library's; a missing loader is reported, not assumed.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| {
            Error::Device(format!(
                "no Vulkan loader found ({e}); install libvulkan1 and a driver such as mesa-vulkan-drivers (tools/setup-debian.sh)"
            ))
        })?;

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"nostencil")
            .engine_name(c"nostencil")
            .api_version(vk::API_VERSION_1_0);

        let mut layers = Vec::new();
        let mut extensions = extra_extensions.to_vec();
        let mut report = None;
        if let Some(checks) = validation {
            report = Some(validation_layer_report(&entry, checks)?);
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(validation_features::NAME.as_ptr());
        }
        // Labels cost nothing where no tool listens; the loader offers the extension almost
        // everywhere, and validation needs it for its messenger.
        let debug_labels = validation.is_some() || offers_debug_utils(&entry);
        if debug_labels {
            extensions.push(debug_utils::NAME.as_ptr());
        }

        let features = validation.map(ValidationChecks::enabled_features).unwrap_or_default();
        let mut validation_features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&features);
        let mut create_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if validation.is_some() {
            create_info = create_info.push_next(&mut validation_features);
        }
        // SAFETY: every layer and extension name is a NUL-terminated static string (our
        // constants, or those of `ash_window::enumerate_required_extensions` for the viewer);
        // they, `app_info` and the chained `validation_features` (with its `features`) outlive
        // the call, and the layer and its VK_EXT_validation_features were checked to be there.
        let raw = unsafe { entry.create_instance(&create_info, None) }.map_err(|result| {
            if result == vk::Result::ERROR_INCOMPATIBLE_DRIVER {
                Error::Device("no Vulkan driver (ICD) could be loaded: no Vulkan device".into())
            } else {
                Error::Vulkan { call: "vkCreateInstance", result }
            }
        })?;

        let mut instance = Instance { entry, raw, messenger: None, validation: report, debug_labels };
        if validation.is_some() {
            instance.install_messenger()?;
        }
        Ok(instance)
    }

    fn install_messenger(&mut self) -> Result<()> {
        let loader = debug_utils::Instance::new(&self.entry, &self.raw);
        let log = Box::new(ValidationLog::default());
        let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(on_validation_message))
            .user_data(&*log as *const ValidationLog as *mut c_void);
        // SAFETY: the instance enabled VK_EXT_debug_utils (with validation). The user data points
        // at the boxed log, whose heap address is stable and which is kept beside the messenger
        // and dropped only after the messenger is destroyed (see `drop`).
        let messenger =
            unsafe { loader.create_debug_utils_messenger(&info, None) }.vk("vkCreateDebugUtilsMessengerEXT")?;
        self.messenger = Some((loader, messenger, log));
        Ok(())
    }

    /// The validation messages so far; empty when validation is off.
    pub fn validation_log(&self) -> Option<&ValidationLog> {
        self.messenger.as_ref().map(|(_, _, log)| &**log)
    }

    /// Which validation checks this instance runs with; None when validation is off.
    pub fn validation_report(&self) -> Option<&ValidationReport> {
        self.validation.as_ref()
    }
}

/// Whether the loader (or an implicit layer) offers VK_EXT_debug_utils.
fn offers_debug_utils(entry: &ash::Entry) -> bool {
    // SAFETY: `entry` holds a loaded loader; no layer name is passed.
    let extensions = unsafe { entry.enumerate_instance_extension_properties(None) }.unwrap_or_default();
    extensions.iter().any(|e| e.extension_name_as_c_str().ok() == Some(debug_utils::NAME))
}

/// Checks that the validation layer is installed and offers VK_EXT_validation_features (through
/// which synchronisation validation is requested), and names it with its version.
fn validation_layer_report(entry: &ash::Entry, checks: ValidationChecks) -> Result<ValidationReport> {
    // SAFETY: `entry` holds a loaded loader.
    let available = unsafe { entry.enumerate_instance_layer_properties() }.vk("vkEnumerateInstanceLayerProperties")?;
    let Some(layer) = available.iter().find(|l| l.layer_name_as_c_str().ok() == Some(VALIDATION_LAYER)) else {
        return Err(Error::Device(
            "validation was requested but VK_LAYER_KHRONOS_validation is not installed (package vulkan-validationlayers)".into(),
        ));
    };
    // SAFETY: as above; the layer name is a NUL-terminated static string of an installed layer.
    let layer_extensions = unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
        .vk("vkEnumerateInstanceExtensionProperties")?;
    if !layer_extensions.iter().any(|e| e.extension_name_as_c_str().ok() == Some(validation_features::NAME)) {
        return Err(Error::Device(
            "the installed VK_LAYER_KHRONOS_validation does not offer VK_EXT_validation_features: synchronisation validation cannot be requested".into(),
        ));
    }
    let version = layer.spec_version;
    let name = format!(
        "{} {}.{}.{} (build {})",
        VALIDATION_LAYER.to_string_lossy(),
        vk::api_version_major(version),
        vk::api_version_minor(version),
        vk::api_version_patch(version),
        layer.implementation_version
    );
    Ok(ValidationReport::new(name, checks))
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: every device of this instance is gone (a `Gpu` destroys its device before its
        // instance field drops). The messenger goes before the instance, and its log (`_log`)
        // only after the messenger, at the end of the `if let`.
        unsafe {
            if let Some((loader, messenger, _log)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            self.raw.destroy_instance(None);
        }
    }
}

unsafe extern "system" fn on_validation_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    let (id, text) = if data.is_null() {
        (String::new(), "(no message)".to_owned())
    } else {
        // SAFETY: Vulkan passes callback data valid for the duration of the callback; the two
        // accessors read its NUL-terminated message ID name and message (or none).
        unsafe {
            (
                (*data).message_id_name_as_c_str().map(|m| m.to_string_lossy().into_owned()).unwrap_or_default(),
                (*data)
                    .message_as_c_str()
                    .map(|m| m.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "(no message)".to_owned()),
            )
        }
    };
    // Only the message IDs listed in `validation::SILENCED`, each with its reason.
    if validation::is_silenced(&id) {
        return vk::FALSE;
    }
    let message = format!("[{severity:?}] {text}");
    eprintln!("vulkan validation: {message}");
    if !user_data.is_null() {
        // SAFETY: user_data is the boxed ValidationLog owned by the Instance that outlives
        // the messenger.
        let log = unsafe { &*(user_data as *const ValidationLog) };
        log.push(message);
    }
    vk::FALSE
}
