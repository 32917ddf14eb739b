//! Test-only fault injection: GPU failures the driver cannot be made to produce on demand
//! (a lost device, device memory running out, a small heap). Compiled in only with the cargo
//! feature `fault-injection`, which the crate's dev-dependency on itself turns on for its own
//! tests; a normal build reads no variable here and every function answers "no fault".
//!
//! - `NOSTENCIL_FAULT_SUBMIT=WHERE:RESULT`: the submit of WHERE (`frame`: a frame's passes;
//!   `present`: the viewer's copy to the window) fails with RESULT (`device-lost` or
//!   `out-of-device-memory`).
//! - `NOSTENCIL_FAULT_HEAP_MIB=N`: the device's heaps report at most N MiB.
//! - `NOSTENCIL_FAULT_CRASH_AFTER=N`: the viewer aborts (SIGABRT) right after its Nth present: a
//!   program that crashes on purpose, for profile-app's crash report.

use ash::vk;

/// Which submission a fault is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Submission {
    Frame,
    Present,
}

/// The result an injected fault makes the `submission` submit fail with, if any.
pub fn submit_fault(submission: Submission) -> Option<vk::Result> {
    if !cfg!(feature = "fault-injection") {
        return None;
    }
    let value = std::env::var("NOSTENCIL_FAULT_SUBMIT").ok()?;
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
    if !cfg!(feature = "fault-injection") {
        return None;
    }
    std::env::var("NOSTENCIL_FAULT_CRASH_AFTER").ok()?.parse().ok()
}

/// The injected heap size limit in bytes, if any.
pub fn heap_limit() -> Option<u64> {
    if !cfg!(feature = "fault-injection") {
        return None;
    }
    let mib: u64 = std::env::var("NOSTENCIL_FAULT_HEAP_MIB").ok()?.parse().ok()?;
    Some(mib << 20)
}
