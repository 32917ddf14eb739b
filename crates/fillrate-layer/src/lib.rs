//! `VK_LAYER_NOSTENCIL_fillrate`: a Vulkan layer, `libnostencil_fillrate.so` (this crate's
//! cdylib), that wraps every render pass instance of any application in the queries
//! `nostencil profile` uses, and writes per-frame, per-pass fill-rate counters (docs/design/layer.md).
//! It depends on nothing of the renderer: the report it writes is `nostencil-fillrate-report`'s,
//! and the tile-traffic rule it applies is `nostencil-tiler`'s, both shared with `nostencil`.

// Raw Vulkan by nature (the layer sits between a program and its driver); each unsafe block says
// why it is sound.
#![warn(clippy::undocumented_unsafe_blocks)]

pub mod arrays;
pub mod attachments;
pub mod capture;
pub mod capture_state;
pub mod commands;
pub mod config;
pub mod copies;
pub mod descriptor_templates;
pub mod draw_hooks;
pub mod exports;
pub mod extensions;
pub mod frame_boundary;
pub mod frame_cuts;
pub mod frames;
pub mod gl_swaps;
pub mod image_use;
pub mod in_flight;
pub mod lifecycle;
pub mod loader;
pub mod objects;
pub mod png_file;
pub mod poison;
pub mod proofs;
pub mod queue;
pub mod readback;
pub mod recording;
pub mod slots;
pub mod state;
pub mod tiler_check;
pub mod tiler_pass;
pub mod tiler_state;
pub mod transfer_bytes;
pub mod transfer_hooks;
pub mod work;
pub mod work_hooks;
pub mod work_objects;

// The report's modules, where the layer's own code has always named them.
pub use nostencil_fillrate_report::{aggregate, manifest, output, report, work_aggregate};
