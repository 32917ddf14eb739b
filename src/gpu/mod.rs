//! Vulkan plumbing: what is chosen once (instance, device under the mobile profile), what
//! allocates (memory), what records and submits (commands), what measures (queries), and a
//! window's surface and swapchain.

pub mod barriers;
pub mod commands;
pub mod context;
pub mod descriptors;
pub mod device;
pub mod faults;
pub mod frame_submission;
pub mod instance;
pub mod live_objects;
pub mod memory;
pub mod mobile_profile;
pub mod queries;
pub mod regions;
pub mod swapchain;
pub mod texture;
pub mod thread_time;
pub mod validation;

pub use context::{Gpu, GpuOptions};
pub use device::DeviceChoice;
pub use validation::ValidationChecks;
