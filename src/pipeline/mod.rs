//! Pipelines as plain data: fixed-function state as named data (`state`), and what a pipeline
//! is made of (`desc`). `render::Pipeline` turns a description into the Vulkan object.

pub mod desc;
pub mod recipes;
pub mod state;

pub use desc::{PipelineDesc, VertexAttribute, VertexLayout};
pub use state::{
    BlendEquation, BlendState, DepthBias, DepthState, FixedFunction, RasterState, StencilFace, StencilState,
};
