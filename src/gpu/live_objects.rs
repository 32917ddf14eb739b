//! Counts of the Vulkan objects alive on one device, kept by the code that creates and
//! destroys them (cheap atomics, always on): a long run that ends with more objects than it
//! had after its first round leaks. `nostencil view --report-objects` prints them; the soak test
//! compares them.

use std::fmt;
use std::sync::atomic::{AtomicI64, AtomicU64, Ordering};
use std::time::Duration;

/// A kind of Vulkan object the crate creates and destroys itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObjectKind {
    Buffer,
    Image,
    ImageView,
    /// A sub-allocation of gpu-allocator, or a dedicated lazily allocated vkDeviceMemory.
    MemoryAllocation,
    Sampler,
    RenderPass,
    Framebuffer,
    Pipeline,
    PipelineLayout,
    ShaderModule,
    DescriptorPool,
    DescriptorSetLayout,
    QueryPool,
    CommandPool,
    CommandBuffer,
    Fence,
    Semaphore,
    Swapchain,
}

impl ObjectKind {
    pub const ALL: [ObjectKind; 18] = [
        ObjectKind::Buffer,
        ObjectKind::Image,
        ObjectKind::ImageView,
        ObjectKind::MemoryAllocation,
        ObjectKind::Sampler,
        ObjectKind::RenderPass,
        ObjectKind::Framebuffer,
        ObjectKind::Pipeline,
        ObjectKind::PipelineLayout,
        ObjectKind::ShaderModule,
        ObjectKind::DescriptorPool,
        ObjectKind::DescriptorSetLayout,
        ObjectKind::QueryPool,
        ObjectKind::CommandPool,
        ObjectKind::CommandBuffer,
        ObjectKind::Fence,
        ObjectKind::Semaphore,
        ObjectKind::Swapchain,
    ];

    /// The name printed in a report ("image-views").
    pub fn name(self) -> &'static str {
        match self {
            ObjectKind::Buffer => "buffers",
            ObjectKind::Image => "images",
            ObjectKind::ImageView => "image-views",
            ObjectKind::MemoryAllocation => "allocations",
            ObjectKind::Sampler => "samplers",
            ObjectKind::RenderPass => "render-passes",
            ObjectKind::Framebuffer => "framebuffers",
            ObjectKind::Pipeline => "pipelines",
            ObjectKind::PipelineLayout => "pipeline-layouts",
            ObjectKind::ShaderModule => "shader-modules",
            ObjectKind::DescriptorPool => "descriptor-pools",
            ObjectKind::DescriptorSetLayout => "descriptor-set-layouts",
            ObjectKind::QueryPool => "query-pools",
            ObjectKind::CommandPool => "command-pools",
            ObjectKind::CommandBuffer => "command-buffers",
            ObjectKind::Fence => "fences",
            ObjectKind::Semaphore => "semaphores",
            ObjectKind::Swapchain => "swapchains",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// Live objects of each kind on one device, what was made since it opened, and the host's
/// waits on it.
#[derive(Default)]
pub struct LiveObjects {
    counts: [AtomicI64; ObjectKind::ALL.len()],
    /// Objects made since the device opened, per kind (never counted down).
    made: [AtomicU64; ObjectKind::ALL.len()],
    /// Host waits on the GPU (fences), and the nanoseconds they took.
    waits: AtomicU64,
    wait_ns: AtomicU64,
    /// CPU time of the jobs run for frames on other threads than the caller's.
    job_ns: AtomicU64,
    /// Of that, the frame slots' command-pool resets.
    pool_reset_ns: AtomicU64,
    /// State and draw commands recorded into frames (`FrameRecorder`).
    commands: AtomicU64,
}

impl LiveObjects {
    /// Counts `ns` of CPU time a job took on another thread.
    pub fn job_ran(&self, ns: u64) {
        self.job_ns.fetch_add(ns, Ordering::Relaxed);
    }

    /// Counts `ns` of CPU time a frame slot's command-pool reset took on another thread (a job).
    pub fn pool_reset(&self, ns: u64) {
        self.job_ran(ns);
        self.pool_reset_ns.fetch_add(ns, Ordering::Relaxed);
    }

    /// Counts `count` state and draw commands a frame recorded.
    pub fn recorded(&self, count: u64) {
        self.commands.fetch_add(count, Ordering::Relaxed);
    }

    pub fn created(&self, kind: ObjectKind) {
        self.counts[kind.index()].fetch_add(1, Ordering::Relaxed);
        self.made[kind.index()].fetch_add(1, Ordering::Relaxed);
    }

    /// Counts one host wait on the GPU that took `took`.
    pub fn waited(&self, took: Duration) {
        self.waits.fetch_add(1, Ordering::Relaxed);
        self.wait_ns.fetch_add(u64::try_from(took.as_nanos()).unwrap_or(u64::MAX), Ordering::Relaxed);
    }

    /// What was made and waited for so far: two of these a frame apart are what the frame did.
    pub fn activity(&self) -> Activity {
        Activity {
            made: ObjectKind::ALL.map(|kind| self.made[kind.index()].load(Ordering::Relaxed)),
            waits: self.waits.load(Ordering::Relaxed),
            wait_ns: self.wait_ns.load(Ordering::Relaxed),
            job_ns: self.job_ns.load(Ordering::Relaxed),
            pool_reset_ns: self.pool_reset_ns.load(Ordering::Relaxed),
            commands: self.commands.load(Ordering::Relaxed),
        }
    }

    pub fn destroyed(&self, kind: ObjectKind) {
        self.counts[kind.index()].fetch_sub(1, Ordering::Relaxed);
    }

    /// The counts now; `memory_blocks` is what the allocator reports holding.
    pub fn snapshot(&self, memory_blocks: usize) -> ObjectCounts {
        ObjectCounts {
            live: ObjectKind::ALL.map(|kind| self.counts[kind.index()].load(Ordering::Relaxed)),
            memory_blocks,
        }
    }
}

/// Objects made per kind and host waits, since the device opened or (from [`Activity::since`])
/// over a stretch of time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Activity {
    made: [u64; ObjectKind::ALL.len()],
    pub waits: u64,
    pub wait_ns: u64,
    /// CPU time of jobs on other threads (`render::jobs`, and the pool resets below).
    pub job_ns: u64,
    /// Of `job_ns`, the frame slots' command-pool resets (`gpu::frame_submission`).
    pub pool_reset_ns: u64,
    /// State and draw commands recorded into frames: binds, pushes, scissors and viewports,
    /// draws and clears (`FrameRecorder`). A driver records and checks each one by one, and
    /// lavapipe allocates and frees each, so on the render thread they are most of a frame's
    /// CPU once its volumes are built elsewhere.
    pub commands: u64,
}

impl Activity {
    /// What happened between `earlier` and this.
    pub fn since(&self, earlier: &Activity) -> Activity {
        let mut made = [0; ObjectKind::ALL.len()];
        for (i, m) in made.iter_mut().enumerate() {
            *m = self.made[i].saturating_sub(earlier.made[i]);
        }
        Activity {
            made,
            waits: self.waits.saturating_sub(earlier.waits),
            wait_ns: self.wait_ns.saturating_sub(earlier.wait_ns),
            job_ns: self.job_ns.saturating_sub(earlier.job_ns),
            pool_reset_ns: self.pool_reset_ns.saturating_sub(earlier.pool_reset_ns),
            commands: self.commands.saturating_sub(earlier.commands),
        }
    }

    /// Objects of `kind` made.
    pub fn made(&self, kind: ObjectKind) -> u64 {
        self.made[kind.index()]
    }
}

/// The live counts at one moment, with the number of vkDeviceMemory blocks gpu-allocator holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjectCounts {
    live: [i64; ObjectKind::ALL.len()],
    /// vkDeviceMemory blocks gpu-allocator holds (it keeps some empty ones for reuse).
    pub memory_blocks: usize,
}

impl ObjectCounts {
    pub fn get(&self, kind: ObjectKind) -> i64 {
        self.live[kind.index()]
    }
}

impl fmt::Display for ObjectCounts {
    /// "buffers=3 images=2 ..." (every kind, zeros too, so that reports line up).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let fields: Vec<String> = ObjectKind::ALL.iter().map(|k| format!("{}={}", k.name(), self.get(*k))).collect();
        write!(f, "{} memory-blocks={}", fields.join(" "), self.memory_blocks)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_go_up_and_down_per_kind_and_print_every_kind() {
        for (i, kind) in ObjectKind::ALL.iter().enumerate() {
            assert_eq!(kind.index(), i, "{kind:?} is out of order in ALL");
        }
        let live = LiveObjects::default();
        live.created(ObjectKind::Image);
        live.created(ObjectKind::Image);
        live.created(ObjectKind::Fence);
        live.destroyed(ObjectKind::Image);
        let counts = live.snapshot(2);
        assert_eq!(counts.get(ObjectKind::Image), 1);
        assert_eq!(counts.get(ObjectKind::Fence), 1);
        assert_eq!(counts.get(ObjectKind::Buffer), 0);
        let text = counts.to_string();
        assert!(text.starts_with("buffers=0 images=1 image-views=0"), "{text}");
        assert!(text.ends_with("swapchains=0 memory-blocks=2"), "{text}");
        assert_eq!(text.split(' ').count(), ObjectKind::ALL.len() + 1);
    }

    #[test]
    fn activity_counts_what_was_made_and_waited_for_between_two_moments() {
        let live = LiveObjects::default();
        live.created(ObjectKind::Buffer);
        let before = live.activity();
        live.created(ObjectKind::Buffer);
        live.destroyed(ObjectKind::Buffer);
        live.created(ObjectKind::MemoryAllocation);
        live.waited(Duration::from_micros(3));
        let during = live.activity().since(&before);
        assert_eq!(during.made(ObjectKind::Buffer), 1, "made, whatever was destroyed");
        assert_eq!(during.made(ObjectKind::MemoryAllocation), 1);
        assert_eq!(during.made(ObjectKind::Image), 0);
        assert_eq!((during.waits, during.wait_ns), (1, 3_000));
    }
}
