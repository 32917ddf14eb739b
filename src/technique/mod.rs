//! Techniques: each module records its passes and reads top to bottom.

pub mod alpha_counter;
pub mod cartoon;
pub mod lit;
pub mod planar;
pub mod scene_renderer;
pub mod shadow_atlas;
pub mod shadow_volume;

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::render::FrameOutput;
use crate::scene::Scene;

pub use cartoon::{CartoonOptions, CartoonStats, SilhouetteMethod};
pub use planar::{PlanarOptions, PlanarStats};
pub use scene_renderer::{check_same_scene, SceneRenderer};
pub use shadow_atlas::{LightMode, ShadowAtlasOptions, ShadowAtlasStats, ShadowKind};
pub use shadow_volume::{Normalize, ShadowVolumeOptions, ShadowVolumeStats, VolumeMethod};

/// What `--technique` selects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Technique {
    /// The scene lit with Lambert + ambient, no shadows: the base every technique adds to.
    #[default]
    Lit,
    /// Shadow volumes counted in the alpha channel (seed 000).
    ShadowVolume,
    /// Selection outline without a stencil (seed 003).
    Outline,
    /// Lambert shading with ink lines (seed 002).
    Silhouette,
    /// Toon shading (N.L through a ramp) with ink lines (seed 002).
    Toon,
    /// Casters (skinned on the GPU) projected onto the ground, double darkening stopped in alpha
    /// in one pass (seed 001).
    Planar,
    /// A soft round texture on a quad under each caster (seed 001's cheapest shadow).
    Blob,
    /// Casters drawn from the light into a small texture that the ground looks up (seed 001).
    ShadowTexture,
    /// A depth-compared shadow map from the light (seed 004's comparison).
    ShadowMap,
    /// Shadow textures baked into each model's atlas from the shadow map (seed 004).
    ShadowTextureAtlas,
}

impl Technique {
    pub const ALL: &'static [Technique] = &[
        Technique::Lit,
        Technique::ShadowVolume,
        Technique::Outline,
        Technique::Silhouette,
        Technique::Toon,
        Technique::Planar,
        Technique::Blob,
        Technique::ShadowTexture,
        Technique::ShadowMap,
        Technique::ShadowTextureAtlas,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Technique::Lit => "lit",
            Technique::ShadowVolume => "shadow-volume",
            Technique::Outline => "outline",
            Technique::Silhouette => "silhouette",
            Technique::Toon => "toon",
            Technique::Planar => "planar",
            Technique::Blob => "blob",
            Technique::ShadowTexture => "shadow-texture",
            Technique::ShadowMap => "shadow-map",
            Technique::ShadowTextureAtlas => "shadow-texture-atlas",
        }
    }

    pub fn parse(text: &str) -> Result<Self> {
        Technique::ALL.iter().copied().find(|t| t.name() == text).ok_or_else(|| {
            Error::InvalidInput(format!(
                "unknown technique '{text}'; available: {}",
                Technique::ALL.iter().map(|t| t.name()).collect::<Vec<_>>().join(", ")
            ))
        })
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub stencil: StencilMode,
    pub technique: Technique,
    pub shadow_volume: ShadowVolumeOptions,
    pub shadow_atlas: ShadowAtlasOptions,
    /// Heat-map frame: alpha ends up holding the fragments shaded per pixel.
    pub count_overdraw: bool,
    pub cartoon: CartoonOptions,
    pub planar: PlanarOptions,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 256,
            height: 256,
            stencil: StencilMode::Emulated,
            technique: Technique::Lit,
            shadow_volume: ShadowVolumeOptions::default(),
            shadow_atlas: ShadowAtlasOptions::default(),
            count_overdraw: false,
            cartoon: CartoonOptions::default(),
            planar: PlanarOptions::default(),
        }
    }
}

/// Every pipeline a technique builds, labelled with its path (emulated / reference), in pass
/// order: the source of `nostencil passes`.
pub fn pipeline_descs(options: &RenderOptions) -> Vec<(&'static str, crate::pipeline::PipelineDesc)> {
    match options.technique {
        Technique::Lit => vec![("both", lit::scene_pipeline_desc())],
        Technique::ShadowVolume => shadow_volume::pipeline_descs(&options.shadow_volume),
        Technique::Planar | Technique::Blob | Technique::ShadowTexture => {
            let descs = match options.technique {
                Technique::Planar => planar::pipeline_descs(),
                Technique::Blob => planar::blob::pipeline_descs(),
                _ => planar::shadow_texture::pipeline_descs(),
            };
            descs.into_iter().map(|d| (if d.fixed.stencil.is_some() { "reference" } else { "emulated" }, d)).collect()
        }
        Technique::Outline | Technique::Silhouette | Technique::Toon => cartoon::pipeline_descs(options.technique)
            .into_iter()
            .map(|d| (if d.fixed.stencil.is_some() { "reference" } else { "emulated" }, d))
            .collect(),
        Technique::ShadowMap => shadow_atlas::pipeline_descs(ShadowKind::Map),
        Technique::ShadowTextureAtlas => shadow_atlas::pipeline_descs(ShadowKind::Atlas),
    }
}

/// A rendered frame and what the technique reports about it.
pub struct TechniqueFrame {
    pub output: FrameOutput,
    pub shadow_volume: Option<ShadowVolumeStats>,
    pub cartoon: Option<CartoonStats>,
    pub planar: Option<PlanarStats>,
    pub shadow_atlas: Option<ShadowAtlasStats>,
}

/// Renders `scene` with the chosen technique and returns the image and its counters.
pub fn render_scene(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions) -> Result<TechniqueFrame> {
    let mut renderer = scene_renderer::build(gpu, scene, options)?;
    renderer.renderer_mut().count_overdraw = options.count_overdraw;
    for _ in 1..renderer.frames_to_steady_state() {
        renderer.frame_with(scene)?;
    }
    renderer.frame_with(scene)
}
