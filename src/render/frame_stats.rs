//! What a technique reports about a frame beyond its counters: `profile`'s lines under the
//! table, its JSON, the viewer's title.

use std::any::Any;
use std::fmt;

/// What a technique reports about a frame beyond its counters.
pub trait FrameStats: fmt::Debug {
    /// Lines printed under `profile`'s table (none for a technique with nothing to add).
    fn report(&self) -> String;

    /// The `technique_stats` object of `profile --format json`.
    fn json(&self) -> serde_json::Value;

    /// A few words for the viewer's title ("z-fail").
    fn brief(&self) -> Option<String> {
        None
    }

    fn as_any(&self) -> &dyn Any;
}

/// A technique with nothing to report.
#[derive(Debug)]
pub struct NoStats;

impl FrameStats for NoStats {
    fn report(&self) -> String {
        String::new()
    }

    fn json(&self) -> serde_json::Value {
        serde_json::Value::Null
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
