//! Pipelines: fixed-function state as named data (`state`), and the builder that turns a
//! description into a Vulkan pipeline (`builder`).

pub mod builder;
pub mod recipes;
pub mod state;

pub use builder::{Pipeline, PipelineDesc, VertexAttribute, VertexLayout};
pub use state::{
    BlendEquation, BlendState, DepthBias, DepthState, FixedFunction, RasterState, StencilFace, StencilState,
};
