//! What the three seed 001 techniques share: the technique types themselves (so that each
//! can name the others in `bench`), their statistics, and the depth bias of what lies flat on
//! the ground.

use std::any::Any;

use super::lod::CasterLods;
use super::receiver::ReceiverPlane;
use super::scene_meshes::SceneMeshes;
use crate::frame::StencilMode;
use crate::pipeline::DepthBias;
use crate::technique::interface::{FrameStats, RenderOptions, Technique, Variant};
use crate::technique::options::{PlanarOptions, TextureShadowOn};
use crate::technique::shadow_tone::ShadowTone;

/// Planar projected shadows, double darkening stopped in alpha (implemented in `projected`).
pub struct Planar;

/// A soft round texture on a quad under each caster (implemented in `blob`).
pub struct BlobShadows;

/// Casters drawn from the light into a small texture the ground looks up (in `shadow_texture`).
pub struct ShadowTexture;

/// `--shadow-lod`'s ratio where a variant needs one and the user gave none (`passes`, `bench`):
/// a quarter of the triangles.
pub const DEFAULT_SHADOW_LOD: f32 = 0.25;

/// Pulls what lies flat on the ground (a flattened caster, a blob, a receiver drawn again)
/// towards the camera so it wins LESS_OR_EQUAL against the ground under it (same plane,
/// different triangles: depths differ in the last bits).
pub const SHADOW_BIAS: DepthBias = DepthBias { constant: -4.0, slope: -1.5 };

/// What a seed 001 frame did, beyond its image and counters.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct PlanarStats {
    pub plane_height: f32,
    /// The receiving plane's unit normal (0, 1, 0 unless `--plane-normal` tilts it).
    pub plane_normal: [f32; 3],
    pub casters: usize,
    /// Objects skinned on the GPU (0 with `--skinning cpu`).
    pub skinned_casters: usize,
    pub shadow_factor: u8,
    /// With `--shadow-lod`: the casters' triangles in full and as simplified.
    pub caster_triangles: Option<usize>,
    pub lod_triangles: Option<usize>,
}

impl PlanarStats {
    pub(crate) fn of(plane: &ReceiverPlane, meshes: &SceneMeshes, tone: ShadowTone) -> Self {
        PlanarStats {
            plane_height: plane.height,
            plane_normal: plane.plane.normal.to_array(),
            casters: plane.receivers.iter().filter(|r| !**r).count(),
            skinned_casters: meshes.meshes.skinned_on_gpu(),
            shadow_factor: tone.darkest(),
            caster_triangles: None,
            lod_triangles: None,
        }
    }

    /// With the triangle counts of the simplified casters, if the shadow is cast from them.
    pub(crate) fn with_lods(self, lods: Option<&CasterLods>) -> Self {
        PlanarStats {
            caster_triangles: lods.map(|l| l.full_triangles),
            lod_triangles: lods.map(|l| l.lod_triangles),
            ..self
        }
    }
}

impl FrameStats for PlanarStats {
    fn report(&self) -> String {
        match (self.caster_triangles, self.lod_triangles) {
            (Some(full), Some(lod)) => format!("shadow LOD: {lod} of {full} caster triangles"),
            _ => String::new(),
        }
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// What `bench` times for any of the three: all of seed 001's shadows side by side, the
/// real-stencil reference first.
pub fn bench_variants(options: &RenderOptions) -> Vec<Variant> {
    let full = PlanarOptions { shadow_lod: None, texture_on: TextureShadowOn::Receivers, ..options.planar };
    let with = |label: &str, technique: Technique, stencil| Variant {
        label: label.into(),
        options: RenderOptions { technique, stencil, planar: full, ..options.clone() },
    };
    let lod =
        PlanarOptions { shadow_lod: Some(options.planar.shadow_lod.unwrap_or(DEFAULT_SHADOW_LOD)), ..options.planar };
    let with_lod = |label: &str, stencil| Variant {
        label: format!("{label} {:.2}", lod.shadow_lod.unwrap_or(DEFAULT_SHADOW_LOD)),
        options: RenderOptions { technique: Technique(&Planar), stencil, planar: lod, ..options.clone() },
    };
    vec![
        with("planar reference (stencil)", Technique(&Planar), StencilMode::Reference),
        with("planar emulated (alpha)", Technique(&Planar), StencilMode::Emulated),
        with_lod("planar emulated, shadow LOD", StencilMode::Emulated),
        with("blob", Technique(&BlobShadows), StencilMode::Emulated),
        with("shadow texture", Technique(&ShadowTexture), StencilMode::Emulated),
        Variant {
            label: "shadow texture on a quad (the seed's)".into(),
            options: RenderOptions {
                technique: Technique(&ShadowTexture),
                stencil: StencilMode::Emulated,
                planar: PlanarOptions { texture_on: TextureShadowOn::Quad, ..full },
                ..options.clone()
            },
        },
    ]
}
