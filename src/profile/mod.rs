//! Fill-rate profiling: per-pass counters and the reports made from them.

pub mod bench;
pub mod budget;
pub mod chart;
pub mod compare;
pub mod counters;
pub mod heatmap;
pub mod passes;
pub mod report;

pub use counters::{FrameCounters, PassCounters};
