//! Fill-rate profiling: reports, charts and budgets made from the frame's per-pass counters
//! (`render::counters`), and the seed 004 Table 1 bench.

pub mod bench;
pub mod bootstrap;
pub mod budget;
pub mod caster_fill;
pub mod chart;
pub mod compare;
pub mod frame_loop;
pub mod heatmap;
pub mod html;
pub mod junit;
pub mod mip_flicker;
pub mod passes;
pub mod report;
pub mod table1;
pub use nostencil_fillrate_report::text_table;
pub mod trace;
pub mod volume_coverage;
