//! The frame: render-pass descriptions as data, the render targets, and the read-back image
//! (an `image::RgbaImage`) written as PNG, and the sRGB encoding the frame's colour uses.

pub use nostencil_tiler::bandwidth;
pub mod offscreen;
pub mod png;
pub mod readback;
pub mod render_pass;
pub mod srgb;
pub mod targets;

pub use png::{write_atomically, write_png};
pub use readback::image_from_rgba8;
pub use render_pass::StencilMode;
pub use targets::FrameTargets;
