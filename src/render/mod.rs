//! Rendering plumbing shared by every technique: uniforms, meshes on the GPU, the frame
//! recorder that measures passes, and the offscreen renderer.

pub mod gpu_mesh;
pub mod recorder;
pub mod renderer;
pub mod uniforms;

pub use gpu_mesh::{GpuMesh, GpuScene};
pub use recorder::FrameRecorder;
pub use renderer::{FrameOutput, Renderer};
pub use uniforms::{FrameDescriptors, FrameUniforms};
