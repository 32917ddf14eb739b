//! What the cartoon techniques share as options and statistics: the selection outline
//! ([`super::outline`], seed 003) and the ink renderer ([`super::ink`]: `silhouette` and
//! `toon`, seed 002). Their shared drawing is in [`super::cartoon_shading`] and
//! [`super::extruded`].

use std::any::Any;

use super::interface::FrameStats;
use super::options::SilhouetteMethod;

/// What a cartoon frame reports beyond its image and counters.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CartoonStats {
    /// The ink method (`silhouette`, `toon`); none for the outline.
    pub method: Option<SilhouetteMethod>,
    /// The outlined objects (`outline`).
    pub selected: Vec<String>,
    /// Edges drawn per class (edges method), each edge once.
    pub silhouette_edges: usize,
    pub crease_edges: usize,
    pub boundary_edges: usize,
    /// CPU time of this frame's edge work: face normals, classification, quads (ms).
    pub edge_cpu_ms: f64,
    /// Edges in the unique edge lists of all objects.
    pub total_edges: usize,
    /// Objects whose face normals and creases this frame recomputed (edges method): all in the
    /// first frame, then only the skinned ones whose pose changed.
    pub face_normal_updates: usize,
}

impl FrameStats for CartoonStats {
    fn report(&self) -> String {
        match self.method {
            Some(method) if method != SilhouetteMethod::Edges => {
                format!("cartoon ({}): ink on the GPU, no CPU edge work", method.name())
            }
            Some(method) => format!(
                "cartoon ({}): {} edges in the unique edge lists | drawn: {} silhouette, {} crease, {} boundary | \
                 face normals recomputed for {} objects | CPU edge work {:.3} ms",
                method.name(),
                self.total_edges,
                self.silhouette_edges,
                self.crease_edges,
                self.boundary_edges,
                self.face_normal_updates,
                self.edge_cpu_ms
            ),
            None => format!("outline: selected {}", self.selected.join(", ")),
        }
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
