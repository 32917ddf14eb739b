//! Techniques: each is one folder implementing [`interface::TechniqueInfo`] (its name and
//! variants), [`TechniqueUnit`] (its pass kinds and plan, and what it builds) and
//! `render::passes::Passes` (its renderer's part), held as a [`Technique`] and listed once in
//! [`registry::TECHNIQUES`]. The renderer skeleton they share
//! is [`frame_renderer`].

pub mod cartoon;
pub mod cartoon_shading;
pub mod extruded;
pub mod flags;
pub mod frame_renderer;
pub mod ink;
pub mod interface;
pub mod light_loop;
pub mod lit;
pub mod material_variants;
pub mod options;
pub mod outline;
pub mod planar;
pub mod registry;
pub mod shadow_atlas;
pub mod shadow_tone;
pub mod shadow_volume;
pub mod unit;
pub mod xray;

use std::sync::Arc;

use crate::error::Result;
use crate::gpu::Gpu;
use crate::scene::Scene;

pub use cartoon::CartoonStats;
pub use interface::{FrameStats, RenderOptions, SceneRenderer, Technique, TechniqueFrame};
pub use options::{
    AtlasBake, CartoonOptions, InkStyle, InkStyles, LightMode, Normalize, OutlineMethod, Seams, ShadowAtlasOptions,
    ShadowKind, ShadowMode, ShadowVolumeOptions, SilhouetteMethod, TextureShadowOn, VolumeExtrusion, VolumeMethod,
};
pub use planar::{GivenPlane, PlanarOptions, PlanarStats};
pub use registry::{by_name, TECHNIQUES};
pub use shadow_atlas::ShadowAtlasStats;
pub use shadow_tone::{ShadowTone, SharedShadowArgs};
pub use shadow_volume::ShadowVolumeStats;

/// Renders `scene` with the options' technique and returns the steady-state frame (a cached
/// shadow map or bake already skipped) with its counters.
pub fn render_scene(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions) -> Result<TechniqueFrame> {
    frame_renderer::render_one(gpu, scene, options)
}
