//! Rendering plumbing shared by every technique: uniforms, meshes on the GPU, the frame
//! recorder that measures passes, the per-pass counters it returns, and the offscreen renderer.

pub mod counters;
pub mod gpu_mesh;
pub mod object_push;
pub mod plan;
pub mod recorder;
pub mod renderer;
pub mod uniforms;

pub use counters::{FrameCounters, PassCounters};
pub use gpu_mesh::{GpuMesh, GpuScene};
pub use object_push::{ObjectPush, OBJECT_PUSH_BYTES};
pub use recorder::FrameRecorder;
pub use renderer::{FrameOutput, Renderer};
pub use uniforms::{FrameDescriptors, FrameUniforms};
