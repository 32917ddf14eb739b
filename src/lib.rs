//! nostencil: a Vulkan renderer for mobile-class limits, whose main framebuffer has no stencil.
//! Every stencil effect is rebuilt on the alpha channel with fixed-function blend states, and
//! checked against a reference path that uses a real stencil.

pub mod error;
pub mod mesh;
pub mod scene;

pub use error::{Error, Result};
