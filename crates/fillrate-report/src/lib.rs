//! The fill-rate layer's report, as the layer writes it and `nostencil profile-app` reads it:
//! the schema ([`report`]), the aggregation of a run's journal into it ([`aggregate`],
//! [`work_aggregate`]), its JSON, CSV and table forms ([`output`]), the tiler check's part
//! ([`tiler`]), and the layer's manifest ([`manifest`]), which the installer writes. No Vulkan:
//! what both sides of the report share, and nothing of either.

pub mod aggregate;
pub mod fixtures;
pub mod manifest;
pub mod output;
pub mod report;
pub mod text_table;
pub mod tiler;
pub mod work_aggregate;
