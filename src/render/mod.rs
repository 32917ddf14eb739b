//! Rendering plumbing shared by every technique: uniforms, meshes on the GPU, pipelines built
//! from their descriptions, the frame recorder that measures passes, the per-pass counters it
//! returns and the bookkeeping they come from, the overdraw pipelines of a heat-map frame, the offscreen renderer, the per-sample read-back of a kept multisampled frame, presenting a frame through a swapchain,
//! and the jobs that run a frame's CPU work on other cores.

pub mod counters;
pub mod frame_copy;
pub mod frame_record;
pub mod frame_stats;
pub mod gpu_mesh;
pub mod instances;
pub mod jobs;
pub mod materials;
pub mod object_push;
pub mod overdraw;
pub mod passes;
pub mod per_slot;
pub mod pipeline_object;
pub mod plan;
pub mod plan_execution;
pub mod present;
pub mod recorder;
pub mod renderer;
// Only the tests read a kept multisampled frame back sample by sample.
#[cfg(test)]
pub mod sample_readback;
pub mod uniforms;

pub use counters::{FrameCounters, PassCounters};
pub use gpu_mesh::{scene_vertices, skinned_vertices, GpuMesh, GpuScene, SceneVertex, Skinning};
pub use materials::GpuMaterials;
pub use object_push::{object_push, LightPush, ObjectPush, LIGHT_PUSH_BYTES, OBJECT_PUSH_BYTES};
pub use pipeline_object::{Pipeline, PipelineTarget};
pub use recorder::{FrameRecorder, IndexedDraw};
pub use renderer::{FrameOutput, PresentedFrame, Renderer};
#[cfg(test)]
pub use sample_readback::FrameSamples;
pub use uniforms::FrameUniforms;
