//! `VK_LAYER_NOSTENCIL_fillrate`: a Vulkan layer, built into `libnostencil.so` (the crate's
//! cdylib), that wraps every render pass instance of any application in the queries
//! `nostencil profile` uses, and writes per-frame, per-pass fill-rate counters (docs/design/layer.md).

pub mod aggregate;
pub mod arrays;
pub mod attachments;
pub mod capture;
pub mod capture_state;
pub mod commands;
pub mod config;
pub mod copies;
pub mod draw_hooks;
pub mod exports;
pub mod frame_boundary;
pub mod frame_cuts;
pub mod frames;
pub mod image_use;
pub mod in_flight;
pub mod lifecycle;
pub mod loader;
pub mod manifest;
pub mod objects;
pub mod output;
pub mod poison;
pub mod proofs;
pub mod queue;
pub mod readback;
pub mod recording;
pub mod report;
pub mod slots;
pub mod state;
pub mod tiler_check;
pub mod tiler_pass;
pub mod tiler_state;
pub mod transfer_bytes;
pub mod transfer_hooks;
pub mod work;
pub mod work_aggregate;
pub mod work_hooks;
pub mod work_objects;
