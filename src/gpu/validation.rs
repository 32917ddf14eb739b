//! Which checks of the Khronos validation layer are on, and which of its messages are silenced
//! (with the reason). The choice is made here, in code, and reaches the layer through
//! `VkValidationFeaturesEXT` chained into the instance create info: never through environment
//! variables, so every GPU test and `--validation` run checks the same things.

use ash::vk;
use serde::Serialize;

/// Which of the layer's checks run; core checks always do. Tests and a bare `--validation` run
/// them all (`ALL`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct ValidationChecks {
    /// Synchronisation validation: hazards between commands (a read after a write with no
    /// barrier, a layout transition racing a draw). The canary test (tests/inside/sync_canary.rs)
    /// proves it bites. Its state in this layer version (1.3.239) grows by tens of KiB per
    /// submitted frame for the life of the device, so a long session may leave it out.
    pub synchronization: bool,
    /// Best-practices checks: the layer's generic advice (vendor-specific advice needs layer
    /// settings that only environment variables or a settings file reach in this layer version).
    pub best_practices: bool,
}

impl ValidationChecks {
    pub const ALL: ValidationChecks = ValidationChecks { synchronization: true, best_practices: true };

    /// `all`, or a comma-separated list of `core`, `sync`, `best-practices` (core is always on,
    /// so `core` alone means only it).
    pub fn parse(text: &str) -> Result<Self, String> {
        if text == "all" {
            return Ok(Self::ALL);
        }
        let mut checks = ValidationChecks { synchronization: false, best_practices: false };
        for name in text.split(',').map(str::trim) {
            match name {
                "core" => {}
                "sync" => checks.synchronization = true,
                "best-practices" => checks.best_practices = true,
                other => {
                    return Err(format!(
                        "unknown validation check '{other}': use `all` or a list of core, sync, best-practices"
                    ))
                }
            }
        }
        Ok(checks)
    }

    /// The `VkValidationFeatureEnableEXT` list for these checks (core checks are on by default).
    pub fn enabled_features(self) -> Vec<vk::ValidationFeatureEnableEXT> {
        let mut features = Vec::new();
        if self.synchronization {
            features.push(vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION);
        }
        if self.best_practices {
            features.push(vk::ValidationFeatureEnableEXT::BEST_PRACTICES);
        }
        features
    }
}

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
    pub fn new(layer: String, checks: ValidationChecks) -> Self {
        ValidationReport {
            layer,
            core: true,
            synchronization: checks.synchronization,
            best_practices: checks.best_practices,
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
    fn features_follow_the_checks() {
        let sync = vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION;
        let best = vk::ValidationFeatureEnableEXT::BEST_PRACTICES;
        assert_eq!(ValidationChecks::ALL.enabled_features(), vec![sync, best]);
        assert_eq!(ValidationChecks::parse("all"), Ok(ValidationChecks::ALL));
        assert_eq!(ValidationChecks::parse("core,best-practices,sync"), Ok(ValidationChecks::ALL));
        assert_eq!(ValidationChecks::parse("core, best-practices").map(|c| c.enabled_features()), Ok(vec![best]));
        assert_eq!(ValidationChecks::parse("core").map(|c| c.enabled_features()), Ok(vec![]));
        let error = ValidationChecks::parse("core,gpu").unwrap_err();
        assert!(error.contains("'gpu'"), "{error}");
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
