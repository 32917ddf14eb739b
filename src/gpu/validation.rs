//! Which checks of the Khronos validation layer are on, and which of its messages are silenced
//! (with the reason). The choice is made here, in code, and reaches the layer through
//! `VkValidationFeaturesEXT` chained into the instance create info: never through environment
//! variables, so every GPU test and `--validation` run checks the same things.

use ash::vk;
use serde::Serialize;

/// Synchronisation validation: hazards between commands (a read after a write with no barrier,
/// a layout transition racing a draw). The canary test (tests/sync_canary.rs) proves it bites.
pub const SYNCHRONIZATION: bool = true;

/// Best-practices checks: the layer's generic advice (vendor-specific advice needs layer
/// settings that only environment variables or a settings file reach in this layer version).
pub const BEST_PRACTICES: bool = true;

/// Best-practices messages that are not wrong for this renderer, by message ID, with the reason.
/// Every other best-practices message fails a test like any validation error. Those the
/// renderer could honour were fixed instead: exact barrier stages and accesses (it flagged
/// ALL_COMMANDS and MEMORY_READ/WRITE in the texture barriers) and one clear value per
/// attachment (a resolve target's clear value was passed at one sample).
pub const SILENCED: &[Silenced] = &[
    Silenced {
        id: "UNASSIGNED-BestPractices-vkCreateCommandPool-command-buffer-reset",
        why: "the viewer re-records each frame in flight's command buffer while the other one is \
              pending, so its buffers are reset one at a time, which needs RESET_COMMAND_BUFFER",
    },
    Silenced {
        id: "UNASSIGNED-BestPractices-DrawState-ClearCmdBeforeDraw",
        why: "the real-stencil reference path clears the stencil with vkCmdClearAttachments \
              before each effect, the first one included; it is the oracle the emulation is \
              compared with, not a path tuned for speed",
    },
    Silenced {
        id: "UNASSIGNED-BestPractices-vkCreateRenderPass-image-requires-memory",
        why: "the per-sample read-back (MSAA proofs) stores the multisampled colour on purpose \
              to read every sample; the frame itself keeps it transient and DONT_CARE",
    },
    Silenced {
        id: "UNASSIGNED-BestPractices-Error-Result",
        why: "every failing VkResult is already returned as an error naming the call; the layer's \
              copy (e.g. SURFACE_LOST when the X server goes away) would only repeat it",
    },
];

/// A message ID the messenger ignores, and why.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Silenced {
    pub id: &'static str,
    pub why: &'static str,
}

/// True when a message with this ID is one of `SILENCED`.
pub fn is_silenced(message_id: &str) -> bool {
    SILENCED.iter().any(|s| s.id == message_id)
}

/// The `VkValidationFeatureEnableEXT` list for the checks above (core checks are on by default).
pub fn enabled_features() -> Vec<vk::ValidationFeatureEnableEXT> {
    let mut features = Vec::new();
    if SYNCHRONIZATION {
        features.push(vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION);
    }
    if BEST_PRACTICES {
        features.push(vk::ValidationFeatureEnableEXT::BEST_PRACTICES);
    }
    features
}

/// What validation an instance runs with, for `nostencil info --validation`.
#[derive(Debug, Clone, Serialize)]
pub struct ValidationReport {
    /// The layer and its version, as the loader reports it.
    pub layer: String,
    pub core: bool,
    pub synchronization: bool,
    pub best_practices: bool,
    /// GPU-assisted validation and debug printf instrument shaders: slow, and off.
    pub gpu_assisted: bool,
    pub debug_printf: bool,
    /// Message severities and types the messenger records (and tests fail on).
    pub recorded: &'static str,
    pub silenced: &'static [Silenced],
}

impl ValidationReport {
    pub fn new(layer: String) -> Self {
        ValidationReport {
            layer,
            core: true,
            synchronization: SYNCHRONIZATION,
            best_practices: BEST_PRACTICES,
            gpu_assisted: false,
            debug_printf: false,
            recorded: "warnings and errors, validation and performance messages",
            silenced: SILENCED,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn features_follow_the_switches() {
        let features = enabled_features();
        assert_eq!(features.contains(&vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION), SYNCHRONIZATION);
        assert_eq!(features.contains(&vk::ValidationFeatureEnableEXT::BEST_PRACTICES), BEST_PRACTICES);
        assert!(!features.contains(&vk::ValidationFeatureEnableEXT::GPU_ASSISTED));
    }

    #[test]
    fn every_silenced_message_says_why() {
        for silenced in SILENCED {
            assert!(!silenced.id.is_empty() && silenced.why.len() > 20, "{silenced:?}");
            assert!(is_silenced(silenced.id));
        }
        assert!(!is_silenced("SYNC-HAZARD-READ-AFTER-WRITE"));
    }
}
