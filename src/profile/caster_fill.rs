//! `profile --caster-fill`: which casters spend the shadow volumes' fill. Each caster's volumes
//! are drawn alone, a frame per caster with the same options, and measured by the same
//! queries: volumes are independent draws, so the casters' counters sum to the frame's.
//! (Per-draw queries cannot nest inside the pass's own: Vulkan allows one active query of a
//! type at a time.)

use std::sync::Arc;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::FrameOutput;
use crate::scene::Scene;
use crate::technique::shadow_volume::ShadowVolumeOptions;
use crate::technique::{render_scene, RenderOptions, ShadowVolumeStats, TechniqueFrame};

/// One caster's share of the volume fill, over every light.
#[derive(Debug, Clone, Serialize)]
pub struct CasterFill {
    pub object: String,
    /// "silhouette" or "two-sided".
    pub path: &'static str,
    /// Fragment shader invocations of its volumes.
    pub fragments: u64,
    /// The same per pixel of the frame.
    pub per_pixel: f64,
    /// Samples of its volumes that passed the depth test.
    pub samples_passed: u64,
    /// Its fragments over the whole frame's volume fragments.
    pub share: f64,
}

/// The `top` casters by volume fragments, measured one at a time against `whole`, the frame
/// with every caster.
pub fn measure(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    options: &RenderOptions,
    whole: &TechniqueFrame,
    top: usize,
) -> Result<Vec<CasterFill>> {
    // Only the shadow-volume family reports casters: its statistics say whose frame this is.
    let Some(stats) = whole.stats::<ShadowVolumeStats>() else {
        return Err(Error::InvalidInput(format!(
            "--caster-fill measures shadow volumes: use it with --technique shadow-volume, not {}",
            options.technique.name()
        )));
    };
    let total = volume_counters(&whole.output).0.max(1);
    let pixels = f64::from(whole.output.counters.width) * f64::from(whole.output.counters.height);
    let casters = stats.casters.clone();
    let mut fills = Vec::with_capacity(casters.len());
    for (index, caster) in casters.iter().enumerate() {
        let alone = RenderOptions {
            shadow_volume: ShadowVolumeOptions { only_caster: Some(index as u32), ..options.shadow_volume },
            ..options.clone()
        };
        let frame = render_scene(gpu, scene, &alone)?;
        let (fragments, samples_passed) = volume_counters(&frame.output);
        fills.push(CasterFill {
            object: caster.object.clone(),
            path: caster.path,
            fragments,
            per_pixel: fragments as f64 / pixels,
            samples_passed,
            share: fragments as f64 / total as f64,
        });
    }
    fills.sort_by_key(|f| std::cmp::Reverse(f.fragments));
    fills.truncate(top);
    Ok(fills)
}

/// Fragments and samples passed of a frame's volume passes.
fn volume_counters(output: &FrameOutput) -> (u64, u64) {
    let volumes = output.counters.passes.iter().filter(|p| p.name.contains("volumes"));
    volumes.fold((0, 0), |(f, s), p| (f + p.fragment_invocations.unwrap_or(0), s + p.samples_passed))
}

/// The table `profile` prints after the frame's.
pub fn table(fills: &[CasterFill]) -> String {
    let mut out = String::from("casters spending most of the volume fill (each drawn alone, every light):\n");
    let width = fills.iter().map(|f| f.object.len()).max().unwrap_or(0).max("caster".len());
    out.push_str(&format!(
        "  {:<width$} {:>10} {:>12} {:>8} {:>7} {:>12}\n",
        "caster", "path", "fragments", "frag/px", "share", "samples"
    ));
    for f in fills {
        out.push_str(&format!(
            "  {:<width$} {:>10} {:>12} {:>8.2} {:>6.1}% {:>12}\n",
            f.object,
            f.path,
            f.fragments,
            f.per_pixel,
            f.share * 100.0,
            f.samples_passed
        ));
    }
    out
}
