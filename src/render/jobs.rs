//! A frame's CPU work run as jobs on other cores than the render thread, as Doom 3 BFG builds
//! its shadow volumes: rayon's pool runs them, each worker with a scratch of its own kept from
//! frame to frame, and the CPU time they take is counted on the device's activity, beside the
//! render thread's own, so that moving work off the render thread never hides it.

use std::sync::{Mutex, MutexGuard};

use rayon::prelude::*;

use crate::gpu::thread_time::thread_cpu_ns;
use crate::gpu::Gpu;

/// One `T` per worker of the pool (and one for a caller outside it), kept across frames: a job
/// borrows its thread's, so workers never share one and a steady frame allocates nothing.
pub struct PerWorker<T> {
    slots: Vec<Mutex<T>>,
}

impl<T: Default> Default for PerWorker<T> {
    fn default() -> Self {
        PerWorker { slots: (0..=rayon::current_num_threads()).map(|_| Mutex::default()).collect() }
    }
}

impl<T> PerWorker<T> {
    /// The calling thread's `T`.
    pub fn mine(&self) -> MutexGuard<'_, T> {
        let at = rayon::current_thread_index().map_or(0, |worker| worker + 1) % self.slots.len().max(1);
        // A poisoned slot only means a job panicked mid-write; the next one starts it over.
        self.slots[at].lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

/// Runs `job` on every item, in parallel on the pool, and returns the results in the items'
/// order; the CPU time the jobs take on other threads than the caller's is added to `gpu`'s
/// activity (what the caller runs itself is in its own CPU time already).
pub fn run<I: Send, R: Send>(gpu: &Gpu, items: Vec<I>, job: impl Fn(I) -> R + Sync) -> Vec<R> {
    let caller = std::thread::current().id();
    items
        .into_par_iter()
        .map(|item| {
            let elsewhere = std::thread::current().id() != caller;
            let start = thread_cpu_ns().filter(|_| elsewhere);
            let result = job(item);
            if let (Some(start), Some(end)) = (start, thread_cpu_ns()) {
                gpu.counted_job_cpu(end.saturating_sub(start));
            }
            result
        })
        .collect()
}
