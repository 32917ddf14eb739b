//! The CPU time a thread has used, for counting work moved off the render thread onto jobs
//! (`render::jobs`, a frame slot's command-pool reset) apart from the render thread's own.

/// CPU time the calling thread has used, in ns (`CLOCK_THREAD_CPUTIME_ID`).
#[cfg(unix)]
pub fn thread_cpu_ns() -> Option<u64> {
    let mut now = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `now` is a valid timespec for the call to fill.
    let read = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
    (read == 0)
        .then(|| u64::try_from(now.tv_sec).unwrap_or(0) * 1_000_000_000 + u64::try_from(now.tv_nsec).unwrap_or(0))
}

#[cfg(not(unix))]
pub fn thread_cpu_ns() -> Option<u64> {
    None
}
