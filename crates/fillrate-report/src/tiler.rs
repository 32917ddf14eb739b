//! The tiler check's part of the report (`NOSTENCIL_FILLRATE_TILER=1`, `profile-app
//! --tiler-check`): the mistakes it flagged and the attachments it poisoned. The check itself is
//! the layer's.

use serde::{Deserialize, Serialize};

/// One mistake, named by the pass (position in the frame, label) and attachment.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TilerFlag {
    /// "dont_care_load_read", "multisampled_stored", "resolve_outside_pass",
    /// "transient_outside_pass", "stored_then_overwritten", "stored_never_read", "dead_pass",
    /// "load_after_dont_care" or "full_frame_copy_to_swapchain".
    pub kind: String,
    /// The first frame it was seen in.
    pub frame: u64,
    /// The pass's position in that frame, from 0.
    pub pass: u32,
    pub label: Option<String>,
    pub attachment: Option<String>,
    /// One line for a person.
    pub detail: String,
    /// How many times it was seen.
    pub count: u64,
    /// For a finding about work outside render passes ("full_frame_copy_to_swapchain"): the
    /// work row's position in the frame (then `pass` is 0 and means nothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub work: Option<u32>,
}

/// An attachment the check filled with the pattern, and whether a later use read it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PoisonNote {
    /// "before the pass (DONT_CARE load)" or "after the pass (DONT_CARE store)".
    pub when: String,
    pub frame: u64,
    pub pass: u32,
    pub label: Option<String>,
    pub attachment: String,
    /// What read the pattern, if anything did ("the pass's first draw (blending)", "pass #2's
    /// LOAD", "vkCmdCopyImage"); null: nothing read it, the output cannot show it.
    pub read_by: Option<String>,
    pub count: u64,
}

/// The check's part of the layer's report.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TilerReport {
    pub flags: Vec<TilerFlag>,
    pub poisoned: Vec<PoisonNote>,
    /// Why reads cannot all be seen (descriptor update templates): then no flag says an output
    /// was never read or overwritten unread, nor that a pass was dead.
    #[serde(default)]
    pub reads_unknown: Option<String>,
}
