//! nostencil: a Vulkan renderer for mobile-class limits, whose main framebuffer has no stencil.
//! Every stencil effect is rebuilt on the alpha channel with fixed-function blend states, and
//! checked against a reference path that uses a real stencil.

pub mod cli;
pub mod error;
pub mod frame;
pub mod gpu;
pub mod mesh;
pub mod pipeline;
pub mod profile;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod technique;
pub mod viewer;

pub use error::{Error, Result};
