//! Fill-rate profiling: per-pass counters and the reports made from them.

pub mod bench;
pub mod counters;
pub mod passes;
pub mod report;

pub use counters::{FrameCounters, PassCounters};
