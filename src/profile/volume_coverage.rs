//! The area shadow volumes rasterise, beside the fill counter. lavapipe's fragment shader
//! invocations are 16 per 4x4 block a triangle touches, so thin walls (most of a real caster's
//! volume) count many times the samples they cover. The exact area comes from drawing the same
//! frame's volumes again without their depth test (`ShadowVolumeOptions::coverage_probe`): the
//! passes' occlusion queries then count every sample the volumes cover.

use std::sync::Arc;

use serde::Serialize;

use crate::error::Result;
use crate::gpu::Gpu;
use crate::scene::Scene;
use crate::technique::shadow_volume::ShadowVolumeOptions;
use crate::technique::{render_scene, RenderOptions, ShadowVolumeStats, TechniqueFrame};

/// One light's volumes: the samples they cover, the fill counter and the samples that pass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LightCoverage {
    pub light: String,
    /// Samples the volume passes cover, per pixel of the frame (exact: the depth test off).
    pub samples_covered_per_px: f64,
    /// The fill counter (fragment shader invocations per pixel), as in the light's report.
    pub fill_per_px: Option<f64>,
    /// Samples that passed the depth test per pixel, as in the light's report: the floor.
    pub samples_passed_per_px: f64,
}

impl LightCoverage {
    /// Fill counted per sample covered: lavapipe's block granularity on thin walls.
    pub fn fill_per_covered_sample(&self) -> Option<f64> {
        let fill = self.fill_per_px?;
        (self.samples_covered_per_px > 0.0).then(|| fill / self.samples_covered_per_px)
    }
}

/// Each shadowing light's coverage, measured with one more frame; `None` for a frame that is
/// not a shadow-volume frame.
pub fn measure(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    options: &RenderOptions,
    whole: &TechniqueFrame,
) -> Result<Option<Vec<LightCoverage>>> {
    let Some(stats) = whole.stats::<ShadowVolumeStats>() else { return Ok(None) };
    let probe_options = RenderOptions {
        shadow_volume: ShadowVolumeOptions { coverage_probe: true, ..options.shadow_volume },
        ..options.clone()
    };
    let probe = render_scene(gpu, scene, &probe_options)?;
    let Some(probed) = probe.stats::<ShadowVolumeStats>() else { return Ok(None) };
    let coverage = stats
        .lights
        .iter()
        .zip(&probed.lights)
        .filter(|(light, _)| light.shadows)
        .map(|(light, probed)| LightCoverage {
            light: light.name.clone(),
            samples_covered_per_px: probed.volume_samples_passed,
            fill_per_px: light.volume_fill,
            samples_passed_per_px: light.volume_samples_passed,
        })
        .collect();
    Ok(Some(coverage))
}

/// The lines `profile` prints after the technique's report.
pub fn table(coverage: &[LightCoverage]) -> String {
    let mut out =
        String::from("shadow volumes' area (their samples covered, counted with the depth test off; exact):\n");
    for light in coverage {
        let fill =
            light.fill_per_px.map_or("fill not measured".to_owned(), |fill| format!("fill {fill:.2} fragments/px"));
        let ratio =
            light.fill_per_covered_sample().map_or(String::new(), |r| format!(" ({r:.1} counted per sample covered)"));
        out.push_str(&format!(
            "  light '{}': {:.2} samples covered/px, {fill}{ratio}, {:.2} passed/px\n",
            light.light, light.samples_covered_per_px, light.samples_passed_per_px
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ratio_is_fill_over_covered_and_absent_without_either() {
        let light = LightCoverage {
            light: "sun".into(),
            samples_covered_per_px: 2.0,
            fill_per_px: Some(10.0),
            samples_passed_per_px: 0.5,
        };
        assert_eq!(light.fill_per_covered_sample(), Some(5.0));
        assert_eq!(LightCoverage { fill_per_px: None, ..light.clone() }.fill_per_covered_sample(), None);
        assert_eq!(LightCoverage { samples_covered_per_px: 0.0, ..light }.fill_per_covered_sample(), None);
    }
}
