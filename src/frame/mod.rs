//! The frame: render-pass descriptions as data, the render targets, and the read-back image.

pub mod image;
pub mod offscreen;
pub mod render_pass;
pub mod targets;

pub use image::RgbaImage;
pub use render_pass::{RenderPassDesc, StencilMode};
pub use targets::FrameTargets;
