//! Shadow volumes counted in the colour alpha channel (seed 000, docs/design/shadow-volumes.md), and the
//! real-stencil reference they are proven against: the recipes and pass plan
//! ([`recipes`]), the casters and their volumes on the CPU ([`casters`]), each frame's volumes
//! laid out ([`frame_volumes`]) and written into their buffers ([`volume_uploads`]), and the
//! renderer that draws them ([`renderer`]); with what only this technique uses: the alpha
//! counter's arithmetic ([`alpha_counter`]), the occluder map that culls hidden casters
//! ([`occluder_map`], [`culling`]) and the shadow mesh the GPU extrudes ([`shadow_mesh`],
//! [`gpu_extrusion`]).

pub mod alpha_counter;
pub mod bounds;
pub mod casters;
pub mod convex_region;
pub mod culling;
pub mod doubled;
pub mod frame_volumes;
pub mod gpu_extrusion;
pub mod near_caps;
pub mod occluder_map;
pub mod recipes;
pub mod renderer;
pub mod shadow_mesh;
pub mod stats;
pub mod volume_uploads;

use super::frame_renderer::BuildContext;
use super::interface::{RenderOptions, TechniqueInfo, Variant};
use super::light_loop::{PlannedLight, ShadowedLights};
use super::unit::{Prepared, TechniqueUnit};
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::render::plan::PassPlan;
use crate::scene::Scene;
use recipes::VolumeKinds;
use renderer::{ShadowVolumePasses, VolumeSetup};

pub use super::options::{Normalize, ShadowMode, ShadowVolumeOptions, VolumeExtrusion, VolumeMethod};
#[cfg(test)]
pub use casters::build_volume;
pub use casters::prepare_casters;
#[cfg(test)]
pub use recipes::SATURATION_PROBE;
pub use renderer::ShadowVolumeStats;

/// The normalisations worth listing in `mode`: in the additive loop `max` runs exactly `seed`'s
/// passes (it differed only in the darkness step, which the loop has no use for).
fn normalisations(mode: ShadowMode) -> impl Iterator<Item = Normalize> {
    Normalize::ALL.iter().copied().filter(move |&n| !(mode == ShadowMode::Additive && n == Normalize::Max))
}

/// Shadow volumes counted in alpha (seed 000).
pub struct ShadowVolumes;

impl TechniqueInfo for ShadowVolumes {
    fn name(&self) -> &'static str {
        "shadow-volume"
    }

    fn about(&self) -> &'static str {
        "shadow volumes counted in the alpha channel (seed 000)"
    }

    fn plan_notes(&self) -> Result<Option<String>> {
        let additive = "In the additive loop (`--shadow-mode additive`, the default) `max` runs the same passes as \
                        `seed`: the mask is exactly 0 or 1, with no darkness step. Its counter counts down from 1, \
                        so no N0; iterations for k = 1, 2, 4, 8: ";
        let down: Vec<String> = alpha_counter::TABLE_INCREMENTS
            .iter()
            .map(|&k| alpha_counter::down_iterations(k).map(|n| n.to_string()))
            .collect::<Result<_>>()?;
        let modulate = alpha_counter::iteration_section()?;
        Ok(Some(format!("{additive}{}.\n\n{modulate}", down.join(", "))))
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        // The probe is a diagnostic: never part of a timed frame (docs/design/saturation.md).
        let untimed_probe = ShadowVolumeOptions { saturation_probe: false, ..options.shadow_volume };
        let options = &RenderOptions { shadow_volume: untimed_probe, ..options.clone() };
        let mut variants = vec![Variant {
            label: "reference (stencil)".into(),
            options: RenderOptions { stencil: StencilMode::Reference, ..options.clone() },
        }];
        variants.extend(normalisations(options.shadow_mode).map(|normalize| Variant {
            label: format!("emulated {}", normalize.name()),
            options: RenderOptions {
                stencil: StencilMode::Emulated,
                shadow_volume: ShadowVolumeOptions { normalize, ..options.shadow_volume },
                ..options.clone()
            },
        }));
        // The additive loop's cost beside the seed's single darkening of the finished frame.
        if options.shadow_mode == ShadowMode::Additive {
            variants.push(Variant {
                label: "emulated seed, modulate".into(),
                options: RenderOptions {
                    stencil: StencilMode::Emulated,
                    shadow_volume: ShadowVolumeOptions { normalize: Normalize::Seed, ..options.shadow_volume },
                    shadow_mode: ShadowMode::Modulate,
                    ..options.clone()
                },
            });
        }
        variants
    }

    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        let mut variants = Vec::new();
        for method in [VolumeMethod::ZPass, VolumeMethod::ZFail] {
            let counting = ShadowVolumeOptions { method, ..options.shadow_volume };
            variants.push(Variant {
                label: format!("reference, {}", method.name()),
                options: RenderOptions { stencil: StencilMode::Reference, shadow_volume: counting, ..options.clone() },
            });
            for normalize in normalisations(options.shadow_mode) {
                variants.push(Variant {
                    label: format!("emulated {}, {}", normalize.name(), method.name()),
                    options: RenderOptions {
                        stencil: StencilMode::Emulated,
                        shadow_volume: ShadowVolumeOptions { normalize, ..counting },
                        ..options.clone()
                    },
                });
            }
        }
        // Volumes extruded by the shadow mesh: its own pipelines, beside the indexed ones (for
        // the casters it does not take), on both counters.
        for (stencil, normalize, method) in [
            (StencilMode::Reference, Normalize::Seed, VolumeMethod::ZFail),
            (StencilMode::Emulated, Normalize::Seed, VolumeMethod::ZPass),
        ] {
            variants.push(Variant {
                label: format!("{}, {}, --volume-extrusion shader", stencil.name(), method.name()),
                options: RenderOptions {
                    stencil,
                    shadow_volume: ShadowVolumeOptions {
                        method,
                        normalize,
                        extrusion: VolumeExtrusion::Shader,
                        ..options.shadow_volume
                    },
                    ..options.clone()
                },
            });
        }
        // The opt-in probe, beside the subpass apply's own count (a cross-check): it reads the
        // seed's up-counter, so the modulate mode's frame.
        variants.push(Variant {
            label: "emulated subpass, zpass, modulate, --saturation-probe".into(),
            options: RenderOptions {
                stencil: StencilMode::Emulated,
                shadow_volume: ShadowVolumeOptions {
                    method: VolumeMethod::ZPass,
                    normalize: Normalize::Subpass,
                    saturation_probe: true,
                    ..options.shadow_volume
                },
                shadow_mode: ShadowMode::Modulate,
                ..options.clone()
            },
        });
        variants
    }

    fn compare_variant(&self, name: &str, options: &RenderOptions) -> Result<RenderOptions> {
        if let Some(options) = super::interface::stencil_variant(name, options) {
            return Ok(options);
        }
        let normalize = <Normalize as clap::ValueEnum>::from_str(name, false).map_err(|_| {
            Error::InvalidInput(format!("--compare {name}: variants are emulated, reference, seed, max and subpass"))
        })?;
        Ok(RenderOptions {
            stencil: StencilMode::Emulated,
            shadow_volume: ShadowVolumeOptions { normalize, ..options.shadow_volume },
            ..options.clone()
        })
    }

    fn shadowed_lights(&self, options: &RenderOptions, _lights: &[PlannedLight]) -> ShadowedLights {
        options.shadow_mode.shadowed_lights()
    }

    fn describe(&self, options: &RenderOptions) -> String {
        let normalise = match options.stencil {
            StencilMode::Emulated => format!(", {}", options.shadow_volume.normalize.name()),
            StencilMode::Reference => String::new(),
        };
        format!("{} ({}{normalise}, k={})", self.name(), options.stencil.name(), options.shadow_volume.increment)
    }
}

impl TechniqueUnit for ShadowVolumes {
    type Kinds = VolumeKinds;
    type Setup = VolumeSetup;
    type Passes = ShadowVolumePasses;

    fn plan(&self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan<VolumeKinds>> {
        recipes::plan(
            &options.shadow_volume,
            options.shadow_mode,
            options.shadow_tone,
            options.stencil,
            options.samples,
            lights,
        )
    }

    fn setup(&self, gpu: &Gpu, scene: &Scene, options: &RenderOptions) -> Result<Prepared<VolumeSetup>> {
        renderer::setup(gpu, scene, options)
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, setup: VolumeSetup) -> Result<ShadowVolumePasses> {
        renderer::make(ctx, scene, setup)
    }
}
