//! The ground shadows of seed 001, each a technique of its own: planar projected shadows with
//! double darkening stopped in alpha ([`projected`]), blobs ([`blob`]) and a render-texture
//! shadow ([`shadow_texture`]). What they share: the receiver plane and the projection onto it
//! ([`receiver`]), the scene's meshes with GPU skins and the lit scene pass ([`scene_meshes`]),
//! and GPU skinning ([`skin`]).

pub mod blob;
pub mod projected;
pub mod receiver;
pub mod scene_meshes;
pub mod shadow_texture;
pub mod skin;

use std::any::Any;

use crate::frame::StencilMode;
use crate::pipeline::DepthBias;
use crate::technique::interface::{FrameStats, Technique, Variant};
use crate::technique::options::RenderOptions;
use scene_meshes::SceneMeshes;

pub use blob::BlobShadows;
pub use projected::{Planar, PlanarPush, PLANAR_PUSH_BYTES};
pub use receiver::{caster_bounds, light_reaches_plane, project_onto_plane, receiver_plane, ReceiverPlane};
pub use shadow_texture::ShadowTexture;

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PlanarOptions {
    /// Shadowed receiver colour = colour x shadow_factor/255 (`1 - s` as an 8-bit value, so that
    /// both paths multiply by exactly the same number).
    pub shadow_factor: u8,
    /// Draw the projected shadows (off: the scene pass alone, GPU-skinned, with the receiver
    /// mask in alpha: what the tests compare against).
    pub shadows: bool,
}

impl Default for PlanarOptions {
    fn default() -> Self {
        PlanarOptions { shadow_factor: 102, shadows: true }
    }
}

/// Pulls what lies flat on the ground (a flattened caster, a blob, a receiver drawn again)
/// towards the camera so it wins LESS_OR_EQUAL against the ground under it (same plane,
/// different triangles: depths differ in the last bits).
pub(crate) const SHADOW_BIAS: DepthBias = DepthBias { constant: -4.0, slope: -1.5 };

/// What a seed 001 frame did, beyond its image and counters.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct PlanarStats {
    pub plane_height: f32,
    pub casters: usize,
    pub skinned_casters: usize,
    pub shadow_factor: u8,
}

impl PlanarStats {
    pub(crate) fn of(plane: &ReceiverPlane, meshes: &SceneMeshes, shadow_factor: u8) -> Self {
        PlanarStats {
            plane_height: plane.height,
            casters: plane.receivers.iter().filter(|r| !**r).count(),
            skinned_casters: meshes.skinned.iter().filter(|s| s.is_some()).count(),
            shadow_factor,
        }
    }
}

impl FrameStats for PlanarStats {
    fn report(&self) -> String {
        String::new()
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
    let with = |label: &str, technique: &'static dyn Technique, stencil| Variant {
        label: label.into(),
        options: RenderOptions { technique, stencil, ..options.clone() },
    };
    vec![
        with("planar reference (stencil)", &Planar, StencilMode::Reference),
        with("planar emulated (alpha)", &Planar, StencilMode::Emulated),
        with("blob", &BlobShadows, StencilMode::Emulated),
        with("shadow texture", &ShadowTexture, StencilMode::Emulated),
    ]
}
