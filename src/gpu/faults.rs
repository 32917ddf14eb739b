//! Fault injection for tests: GPU failures the driver cannot be made to produce on demand
//! (a lost device, device memory running out, a small heap). The tests run the real `nostencil`
//! program, so the hooks are in every build, each behind an environment variable read once;
//! with none of them set (a user's run) every function answers "no fault".
//!
//! - `NOSTENCIL_FAULT_SUBMIT=WHERE:RESULT`: the submit of WHERE (`frame`: a frame's passes;
//!   `present`: the viewer's copy to the window) fails with RESULT (`device-lost` or
//!   `out-of-device-memory`).
//! - `NOSTENCIL_FAULT_HEAP_MIB=N`: the device's heaps report at most N MiB.
//! - `NOSTENCIL_FAULT_CRASH_AFTER=N`: the viewer aborts (SIGABRT) right after its Nth present: a
//!   program that crashes on purpose, for profile-app's crash report.

use std::sync::OnceLock;

use ash::vk;

/// Which submission a fault is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Submission {
    Frame,
    Present,
}

/// The result an injected fault makes the `submission` submit fail with, if any.
pub fn submit_fault(submission: Submission) -> Option<vk::Result> {
    static FAULT: OnceLock<Option<String>> = OnceLock::new();
    let value = FAULT.get_or_init(|| std::env::var("NOSTENCIL_FAULT_SUBMIT").ok()).as_deref()?;
    let (at, result) = value.split_once(':')?;
    let wanted = match at {
        "frame" => Submission::Frame,
        "present" => Submission::Present,
        _ => return None,
    };
    let result = match result {
        "device-lost" => vk::Result::ERROR_DEVICE_LOST,
        "out-of-device-memory" => vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
        _ => return None,
    };
    (wanted == submission).then_some(result)
}

/// The present after which the viewer crashes on purpose, if any.
pub fn crash_after_presents() -> Option<u32> {
    static AFTER: OnceLock<Option<u32>> = OnceLock::new();
    *AFTER.get_or_init(|| std::env::var("NOSTENCIL_FAULT_CRASH_AFTER").ok()?.parse().ok())
}

/// The injected heap size limit in bytes, if any.
pub fn heap_limit() -> Option<u64> {
    static LIMIT: OnceLock<Option<u64>> = OnceLock::new();
    *LIMIT.get_or_init(|| std::env::var("NOSTENCIL_FAULT_HEAP_MIB").ok()?.parse::<u64>().ok().map(|mib| mib << 20))
}
