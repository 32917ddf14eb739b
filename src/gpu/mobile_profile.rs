//! The mobile profile: the device features and limits nostencil allows itself, after the
//! Android Baseline 2022 Vulkan profile. The device is created with nothing beyond it, and the
//! limits here are the ones every technique must stay inside, whatever the running device offers.

use ash::vk;

/// Limits the renderer promises to respect. A device must offer at least these.
pub const MAX_PUSH_CONSTANT_BYTES: u32 = 128;
pub const MAX_BOUND_DESCRIPTOR_SETS: u32 = 4;
pub const MAX_COLOR_ATTACHMENTS: u32 = 4;
pub const MAX_IMAGE_SIDE: u32 = 4096;
pub const MAX_UNIFORM_BUFFER_RANGE: u32 = 16384;
pub const MAX_VERTEX_INPUT_ATTRIBUTES: u32 = 16;

/// Features the profile forbids: mobile-class GPUs cannot be assumed to have them, so no
/// technique may rely on them, and the device is created with all of them off.
pub const FORBIDDEN_FEATURES: [&str; 6] =
    ["geometryShader", "wideLines", "logicOp", "dualSrcBlend", "fillModeNonSolid", "depthClamp"];

/// One limit check: what the profile needs and what the device reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct LimitCheck {
    pub name: &'static str,
    pub profile: String,
    pub device: String,
    pub ok: bool,
}

fn at_least(name: &'static str, profile: u32, device: u32) -> LimitCheck {
    LimitCheck { name, profile: profile.to_string(), device: device.to_string(), ok: device >= profile }
}

/// Every limit the running device is checked against.
pub fn check_limits(limits: &vk::PhysicalDeviceLimits, timestamp_valid_bits: u32) -> Vec<LimitCheck> {
    vec![
        at_least("maxPushConstantsSize", MAX_PUSH_CONSTANT_BYTES, limits.max_push_constants_size),
        at_least("maxBoundDescriptorSets", MAX_BOUND_DESCRIPTOR_SETS, limits.max_bound_descriptor_sets),
        at_least("maxColorAttachments", MAX_COLOR_ATTACHMENTS, limits.max_color_attachments),
        at_least("maxImageDimension2D", MAX_IMAGE_SIDE, limits.max_image_dimension2_d),
        at_least("maxFramebufferWidth", MAX_IMAGE_SIDE, limits.max_framebuffer_width),
        at_least("maxFramebufferHeight", MAX_IMAGE_SIDE, limits.max_framebuffer_height),
        at_least("maxUniformBufferRange", MAX_UNIFORM_BUFFER_RANGE, limits.max_uniform_buffer_range),
        at_least("maxVertexInputAttributes", MAX_VERTEX_INPUT_ATTRIBUTES, limits.max_vertex_input_attributes),
        LimitCheck {
            name: "timestampComputeAndGraphics",
            profile: "true".into(),
            device: (limits.timestamp_compute_and_graphics == vk::TRUE).to_string(),
            ok: limits.timestamp_compute_and_graphics == vk::TRUE,
        },
        LimitCheck {
            name: "timestampValidBits (graphics queue)",
            profile: ">= 36".into(),
            device: timestamp_valid_bits.to_string(),
            ok: timestamp_valid_bits >= 36,
        },
    ]
}

/// Features nostencil turns on, and why. Everything else stays off.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct EnabledFeatures {
    /// Exact samples-passed counts for the fill-rate report (in Android Baseline 2022).
    pub occlusion_query_precise: bool,
    /// Fragment and vertex invocation counters. Not in the Android baseline: used only by the
    /// profiler, never by rendering, and reported as unavailable where the device lacks it.
    pub pipeline_statistics_query: bool,
    /// Storage-buffer atomics in fragment shaders (in Android Baseline 2022): the subpass
    /// shadow apply counts saturated samples with them (docs/design/saturation.md). Without it that
    /// count is reported as not measured.
    pub fragment_stores_and_atomics: bool,
}

impl EnabledFeatures {
    pub fn choose(supported: &vk::PhysicalDeviceFeatures) -> Self {
        EnabledFeatures {
            occlusion_query_precise: supported.occlusion_query_precise == vk::TRUE,
            pipeline_statistics_query: supported.pipeline_statistics_query == vk::TRUE,
            fragment_stores_and_atomics: supported.fragment_stores_and_atomics == vk::TRUE,
        }
    }

    pub fn to_vk(self) -> vk::PhysicalDeviceFeatures {
        vk::PhysicalDeviceFeatures {
            occlusion_query_precise: self.occlusion_query_precise as vk::Bool32,
            pipeline_statistics_query: self.pipeline_statistics_query as vk::Bool32,
            fragment_stores_and_atomics: self.fragment_stores_and_atomics as vk::Bool32,
            ..Default::default()
        }
    }
}

/// The forbidden features as they are set in a features struct (all must be false).
pub fn forbidden_features_enabled(features: &vk::PhysicalDeviceFeatures) -> Vec<&'static str> {
    let flags = [
        features.geometry_shader,
        features.wide_lines,
        features.logic_op,
        features.dual_src_blend,
        features.fill_mode_non_solid,
        features.depth_clamp,
    ];
    FORBIDDEN_FEATURES.iter().zip(flags).filter(|(_, on)| *on == vk::TRUE).map(|(name, _)| *name).collect()
}

/// A push-constant block size a pipeline asks for, checked against the profile.
pub fn check_push_constants(pipeline: &str, bytes: u32) -> crate::error::Result<()> {
    if bytes > MAX_PUSH_CONSTANT_BYTES {
        return Err(crate::error::Error::InvalidInput(format!(
            "pipeline '{pipeline}' needs {bytes} bytes of push constants; the mobile profile allows {MAX_PUSH_CONSTANT_BYTES}"
        )));
    }
    Ok(())
}

/// A render target side, checked against the profile (0 and above 4096 are refused).
pub fn check_image_size(what: &str, width: u32, height: u32) -> crate::error::Result<()> {
    if width == 0 || height == 0 {
        return Err(crate::error::Error::InvalidInput(format!(
            "{what} size {width}x{height}: width and height must be at least 1"
        )));
    }
    if width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE {
        return Err(crate::error::Error::InvalidInput(format!(
            "{what} size {width}x{height}: the mobile profile allows at most {MAX_IMAGE_SIDE} pixels per side"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enabled_features_never_include_forbidden_ones() {
        let everything = vk::PhysicalDeviceFeatures {
            geometry_shader: vk::TRUE,
            wide_lines: vk::TRUE,
            logic_op: vk::TRUE,
            dual_src_blend: vk::TRUE,
            fill_mode_non_solid: vk::TRUE,
            depth_clamp: vk::TRUE,
            occlusion_query_precise: vk::TRUE,
            pipeline_statistics_query: vk::TRUE,
            ..Default::default()
        };
        assert_eq!(forbidden_features_enabled(&everything).len(), 6);
        let chosen = EnabledFeatures::choose(&everything).to_vk();
        assert!(forbidden_features_enabled(&chosen).is_empty());
    }

    #[test]
    fn image_sizes_are_checked() {
        assert!(check_image_size("frame", 256, 256).is_ok());
        assert!(check_image_size("frame", 4096, 1).is_ok());
        assert!(check_image_size("frame", 0, 256).is_err());
        assert!(check_image_size("frame", 4097, 256).is_err());
    }

    #[test]
    fn push_constant_budget_is_128_bytes() {
        assert!(check_push_constants("p", 128).is_ok());
        assert!(check_push_constants("p", 132).is_err());
    }
}
