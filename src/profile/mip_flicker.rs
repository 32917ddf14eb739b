//! Seed 004's anti-aliasing claim (figures 6 and 7), measured: shadow textures are sampled
//! through their mips, so a minified shadow should flicker less than the shadow map's hard
//! compare as the light turns. Both techniques render the same scene at neighbouring light
//! angles (the moving light, `MOVING_LIGHT_STEP` a frame); a pixel flickers at a step when its
//! colour jumps by more than `FLICKER_THRESHOLD`, far more than the Lambert term moves in one
//! step, about what a shadow edge crossing the pixel does.

use std::fmt::Write as _;
use std::sync::Arc;

use image::RgbaImage;

use super::table1::{self, TECHNIQUES};
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::scene::Scene;
use crate::technique::options::{LightMode, ShadowAtlasOptions, ShadowKind};
use crate::technique::shadow_atlas::light::MOVING_LIGHT_STEP;
use crate::technique::{RenderOptions, Technique};

/// Largest jump of any colour channel (sRGB-encoded, 0..=255) between two neighbouring light
/// angles that does not count as a flicker. A 0.02 radian turn moves N.L by at most 0.02, a few
/// levels; a pixel crossing from lit to shadowed drops by the whole Lambert term.
pub const FLICKER_THRESHOLD: u8 = 32;

/// Whether `bench --mip-flicker` takes `technique`: either of the two Table 1 compares, seed
/// 004's shadow texture atlas and the shadow map.
pub fn compares(technique: Technique) -> bool {
    table1::covers(technique)
}

/// One technique's flicker over the turning light.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FlickerRow {
    pub technique: ShadowKind,
    /// Pixels that flickered at one step or more.
    pub flickering_pixels: u32,
    /// Flickers summed over the steps (a pixel at each step it flickered).
    pub flicker_events: u32,
    /// Mean over pixels and steps of the largest channel change, in levels of 255.
    pub mean_change: f64,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct FlickerReport {
    pub schema: &'static str,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// Light steps compared (frames rendered: one more).
    pub steps: u32,
    pub step_radians: f32,
    pub threshold: u8,
    pub rows: Vec<FlickerRow>,
}

/// Renders `scene` with the shadow texture atlas and the shadow map at `steps + 1` neighbouring
/// light angles (frames of `options`' size) and counts the pixels that flicker.
pub fn measure(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions, steps: u32) -> Result<FlickerReport> {
    if steps == 0 {
        return Err(Error::InvalidInput("--mip-flicker needs at least 1 light step".into()));
    }
    let rows = TECHNIQUES
        .into_iter()
        .map(|kind| {
            let technique = kind.technique();
            let opts = RenderOptions {
                technique,
                shadow_atlas: ShadowAtlasOptions { light: LightMode::Moving, ..options.shadow_atlas },
                count_overdraw: false,
                ..options.clone()
            };
            let mut renderer = technique.build(gpu, scene, &opts)?;
            let frames = (0..=steps)
                .map(|_| Ok(renderer.frame_with(scene)?.output.image))
                .collect::<Result<Vec<RgbaImage>>>()?;
            Ok(flicker_of(kind, &frames))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(FlickerReport {
        schema: "nostencil-mip-flicker/1",
        scene: scene.name.clone(),
        width: options.width,
        height: options.height,
        steps,
        step_radians: MOVING_LIGHT_STEP,
        threshold: FLICKER_THRESHOLD,
        rows,
    })
}

/// The flicker of one technique's frames, in light order.
pub fn flicker_of(technique: ShadowKind, frames: &[RgbaImage]) -> FlickerRow {
    let pixels = frames.first().map_or(0, |f| f.width() * f.height()) as usize;
    let mut flickered = vec![false; pixels];
    let (mut events, mut total_change, mut compared) = (0u32, 0u64, 0u64);
    for pair in frames.windows(2) {
        for (i, (a, b)) in pair[0].pixels().zip(pair[1].pixels()).enumerate() {
            let change = (0..3).map(|c| a.0[c].abs_diff(b.0[c])).max().unwrap_or(0);
            total_change += change as u64;
            compared += 1;
            if change > FLICKER_THRESHOLD {
                events += 1;
                if let Some(f) = flickered.get_mut(i) {
                    *f = true;
                }
            }
        }
    }
    FlickerRow {
        technique,
        flickering_pixels: flickered.iter().filter(|&&f| f).count() as u32,
        flicker_events: events,
        mean_change: total_change as f64 / compared.max(1) as f64,
    }
}

impl FlickerReport {
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "mip anti-aliasing (seed 004, figures 6 and 7) | scene {} | {}x{} | {} light steps of {} rad | flicker: a channel jumps by more than {}",
            self.scene, self.width, self.height, self.steps, self.step_radians, self.threshold
        );
        let _ = writeln!(
            out,
            "{:<21} {:>18} {:>15} {:>12}",
            "technique", "flickering pixels", "flicker events", "mean change"
        );
        for r in &self.rows {
            let _ = writeln!(
                out,
                "{:<21} {:>18} {:>15} {:>12.2}",
                r.technique.name(),
                r.flickering_pixels,
                r.flicker_events,
                r.mean_change
            );
        }
        out
    }
}
