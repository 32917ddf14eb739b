//! What the cartoon techniques share as options and statistics: the selection outline
//! ([`super::outline`], seed 003) and the ink renderer ([`super::ink`]: `silhouette` and
//! `toon`, seed 002). Their shared drawing is in [`super::cartoon_shading`] and
//! [`super::extruded`].

use std::any::Any;

use super::interface::FrameStats;
use crate::error::{Error, Result};

/// How `silhouette` and `toon` find their ink.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SilhouetteMethod {
    /// CPU edge classification, screen-space quads.
    #[default]
    Edges,
    /// N.V per vertex looked up in a 1D texture (dark rim).
    Shader,
    /// Normal-extruded inverted hull.
    Hull,
}

impl SilhouetteMethod {
    pub const ALL: [SilhouetteMethod; 3] = [SilhouetteMethod::Edges, SilhouetteMethod::Shader, SilhouetteMethod::Hull];

    pub fn parse(text: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == text)
            .ok_or_else(|| Error::InvalidInput(format!("--silhouette {text}: use edges, shader or hull")))
    }

    pub fn name(self) -> &'static str {
        match self {
            SilhouetteMethod::Edges => "edges",
            SilhouetteMethod::Shader => "shader",
            SilhouetteMethod::Hull => "hull",
        }
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CartoonOptions {
    /// Objects to outline (`outline`); empty: the scene's first closed object.
    pub select: Vec<String>,
    pub silhouette: SilhouetteMethod,
    /// Edges whose faces fold by more than this many degrees are creases.
    pub crease_deg: f32,
    /// Ink line width in pixels (edges), and the width of the hull rim.
    pub line_width: f32,
    /// Outline width in pixels (`outline`).
    pub outline_width: f32,
    /// Outline colour, 8-bit RGB (so every path writes the same bytes).
    pub outline_colour: [u8; 3],
}

impl Default for CartoonOptions {
    fn default() -> Self {
        CartoonOptions {
            select: Vec::new(),
            silhouette: SilhouetteMethod::Edges,
            crease_deg: 40.0,
            line_width: 2.0,
            outline_width: 4.0,
            outline_colour: [255, 160, 0],
        }
    }
}

impl CartoonOptions {
    /// Checks the numbers a user typed.
    pub fn check(&self) -> Result<()> {
        if !(self.line_width.is_finite() && (0.5..=64.0).contains(&self.line_width)) {
            return Err(Error::InvalidInput(format!("--line-width {}: use 0.5 to 64 pixels", self.line_width)));
        }
        if !(self.outline_width.is_finite() && (0.5..=64.0).contains(&self.outline_width)) {
            return Err(Error::InvalidInput(format!("--outline-width {}: use 0.5 to 64 pixels", self.outline_width)));
        }
        if !(self.crease_deg.is_finite() && (0.0..=180.0).contains(&self.crease_deg)) {
            return Err(Error::InvalidInput(format!("--crease-angle {}: use 0 to 180 degrees", self.crease_deg)));
        }
        Ok(())
    }

    /// Parses `--select NAME,NAME,...` (empty: the default selection).
    pub fn parse_select(text: &str) -> Vec<String> {
        text.split(',').map(str::trim).filter(|s| !s.is_empty()).map(str::to_owned).collect()
    }
}

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
}

impl FrameStats for CartoonStats {
    fn report(&self) -> String {
        match self.method {
            Some(method) if method != SilhouetteMethod::Edges => {
                format!("cartoon ({}): ink on the GPU, no CPU edge work", method.name())
            }
            Some(method) => format!(
                "cartoon ({}): {} edges in the unique edge lists | drawn: {} silhouette, {} crease, {} boundary | \
                 CPU edge work {:.3} ms",
                method.name(),
                self.total_edges,
                self.silhouette_edges,
                self.crease_edges,
                self.boundary_edges,
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
