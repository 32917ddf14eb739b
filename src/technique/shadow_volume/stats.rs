//! What a shadow-volume frame reports beyond its counters: the counting method, the counter's
//! capacity and saturation, each caster's path and each light's volumes and fill
//! (`profile`'s technique statistics, in its table and JSON).

use std::any::Any;
use std::sync::Arc;

use super::casters::Caster;
use crate::scene::Scene;
use crate::technique::interface::FrameStats;
pub(super) const MEASURED_BY_APPLY: &str = "counted by the subpass apply with fragment atomics";
pub(super) const MEASURED_BY_PROBE: &str = "counted by the saturation probe pass";
pub(super) const NOT_MEASURED: &str = "not measured (use --saturation-probe)";
pub(super) const NOT_MEASURED_NO_ATOMICS: &str =
    "not measured: the device lacks fragmentStoresAndAtomics (use --saturation-probe)";
pub(super) const MEASURED_BY_MASK: &str = "counted by the subpass mask with fragment atomics";
pub(super) const NOT_MEASURED_ADDITIVE: &str =
    "not measured: in additive mode the subpass mask counts it (--normalize subpass, fragment atomics)";
pub(super) const NOT_COUNTED_REFERENCE: &str = "n/a (reference: the stencil wraps, it does not clamp)";

/// What the frame did, beyond its image and counters.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ShadowVolumeStats {
    pub zfail: bool,
    pub seed_iterations: usize,
    /// The largest count the alpha counter holds: 255 / k.
    pub capacity: u32,
    /// Samples whose counter sits at its clamp (a count of 255/k or more) once every volume is
    /// drawn, as many per pixel as it has samples at the clamp (a pixel at one sample): counted
    /// by the subpass apply's atomic add, else by the opt-in probe's samples passed; `None`
    /// where neither ran (and always on the reference, whose stencil wraps instead).
    pub saturated_samples: Option<u64>,
    /// Where `saturated_samples` comes from, or why it is not measured.
    pub saturation_measured_by: &'static str,
    /// The probe's own count of samples when `--saturation-probe` ran (for `subpass`, a cross-check of
    /// the apply's count on the same frame).
    pub probe_saturated_samples: Option<u64>,
    /// k, for the report.
    #[serde(skip)]
    pub increment: u8,
    /// Each caster's volume path and what the counter holds of it: fixed at build, and shared
    /// by every frame's stats (a frame's clone costs no allocation per caster).
    pub casters: Arc<[CasterReport]>,
    /// `additive` or `modulate`.
    pub mode: &'static str,
    /// Per light: whether it casts, and the volumes drawn for it this frame.
    pub lights: Vec<LightReport>,
    /// CPU time this frame spent deciding which casters are culled, over every light (0 without
    /// `--cull-casters`; next to nothing where a light's culling is kept from an earlier frame):
    /// what culling adds to a frame whose light moves.
    pub culling_cpu_ms: f64,
}

/// One light of the frame, as the shadow volumes saw it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LightReport {
    pub name: String,
    pub shadows: bool,
    /// Casters whose volume was drawn for this light (the others are out of its reach, or
    /// shade nothing on screen, or culled).
    pub volumes: usize,
    /// Of those, the volumes drawn from the previous frames' buffers: neither the light nor the
    /// caster moved, so they were not built again (an unposed caster's only).
    pub reused: usize,
    /// Of those, the volumes extruded in the vertex shader from tables built at load
    /// (`--volume-extrusion gpu`): nothing built on the CPU.
    pub extruded: usize,
    /// Casters left out because they lie wholly in the shadow of other casters
    /// (`--cull-casters`).
    pub culled: usize,
    /// Whether that culling was decided on an earlier frame: neither the light nor any caster
    /// moved since (and none is skinned), so it was not decided again.
    pub culling_reused: bool,
    /// Near caps (triangles) of open casters drawn by one counting pipeline instead of both, in
    /// z-pass: the other one sees them only behind their own faces (`near_caps`;
    /// `--whole-near-caps` sets this to 0).
    pub near_caps_one_pipeline: u64,
    /// Fragment shader invocations of this light's volume passes per pixel of the frame: the
    /// volumes' fill (None where the device has no pipeline statistics).
    pub volume_fill: Option<f64>,
    /// Samples of this light's volume passes that passed the depth test, per pixel of the frame.
    /// In z-pass these are the volume fragments in front of the visible surfaces: what even
    /// volumes clamped exactly to the visible receivers would still draw, the floor under the
    /// fill. (In z-fail, those behind them.)
    pub volume_samples_passed: f64,
}

/// How one caster casts.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct CasterReport {
    /// The object's name.
    pub object: String,
    /// "silhouette" or "two-sided".
    pub path: &'static str,
    /// Why that path: "closed and consistently wound", "open (4 boundary edges)", ...
    pub reason: String,
    /// Closed parts of this caster the counter holds over one pixel: 255 / k, halved for a
    /// two-sided caster (it counts 2 per crossing).
    pub capacity: u32,
}

impl CasterReport {
    pub(super) fn new(scene: &Scene, caster: &Caster, counter_capacity: u32) -> Self {
        let path = &caster.mesh.path;
        CasterReport {
            object: scene.objects[caster.object].name.clone(),
            path: path.name(),
            reason: path.reason().to_owned(),
            capacity: counter_capacity / path.count_per_crossing(),
        }
    }
}

impl FrameStats for ShadowVolumeStats {
    fn report(&self) -> String {
        let saturation = match (self.saturated_samples, self.probe_saturated_samples) {
            (Some(n), Some(probe)) if self.saturation_measured_by != MEASURED_BY_PROBE => {
                format!("{n} ({}; the probe counts {probe})", self.saturation_measured_by)
            }
            (Some(n), _) => format!("{n} ({})", self.saturation_measured_by),
            (None, _) => self.saturation_measured_by.to_owned(),
        };
        let mut report = format!(
            "shadow volumes: {}, {} | counter capacity {} volumes (k = {}) | saturated samples: {saturation}",
            self.mode,
            if self.zfail { "z-fail" } else { "z-pass" },
            self.capacity,
            self.increment,
        );
        for light in &self.lights {
            let shadows = if light.shadows {
                let fill = light.volume_fill.map_or("not measured".into(), |f| format!("{f:.2}"));
                format!(
                    "{} volumes ({} extruded on the GPU, {} reused from earlier frames), {} casters culled{}{} | volume fill {fill} fragments/px, {:.2} samples passed/px{}",
                    light.volumes,
                    light.extruded,
                    light.reused,
                    light.culled,
                    if light.culling_reused { " (decided on an earlier frame)" } else { "" },
                    match light.near_caps_one_pipeline {
                        0 => String::new(),
                        n => format!(", {n} near caps drawn by one pipeline"),
                    },
                    light.volume_samples_passed,
                    if self.zfail { "" } else { " (the floor: in front of the receivers)" },
                )
            } else {
                "casts no shadow".into()
            };
            report.push_str(&format!("\n  light '{}': {shadows}", light.name));
        }
        for caster in self.casters.iter() {
            report.push_str(&format!(
                "\n  caster '{}': {} ({}), capacity {}",
                caster.object, caster.path, caster.reason, caster.capacity
            ));
        }
        report
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    fn brief(&self) -> Option<String> {
        Some(if self.zfail { "z-fail" } else { "z-pass" }.into())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
