//! `VK_LAYER_NOSTENCIL_fillrate`: a Vulkan layer, built into `libnostencil.so` (the crate's
//! cdylib), that wraps every render pass instance of any application in the queries
//! `nostencil profile` uses, and writes per-frame, per-pass fill-rate counters (DESIGN.md
//! section 12).

pub mod aggregate;
pub mod attachments;
pub mod config;
pub mod frames;
pub mod loader;
pub mod manifest;
pub mod output;
pub mod recording;
pub mod report;
pub mod slots;
