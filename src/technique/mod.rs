//! Techniques: each module records its passes and reads top to bottom.

pub mod alpha_counter;
pub mod cartoon;
pub mod lit;
pub mod planar;
pub mod shadow_atlas;
pub mod shadow_volume;

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::render::{FrameOutput, FrameUniforms, GpuScene, Renderer};
use crate::scene::Scene;

pub use cartoon::{CartoonOptions, CartoonStats, SilhouetteMethod};
pub use planar::{PlanarOptions, PlanarStats};
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

#[derive(Debug, Clone)]
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
    match options.technique {
        Technique::Lit => {
            let mut renderer = Renderer::new(gpu, options.width, options.height, options.stencil, false)?;
            renderer.count_overdraw = options.count_overdraw;
            let meshes = GpuScene::upload(gpu, scene)?;
            let uniforms = FrameUniforms::for_scene(scene, renderer.aspect());
            let clear = scene.background.extend(1.0).to_array();
            let lit = lit::LitPass::new(gpu, &renderer)?;
            let output = renderer.render(&uniforms, clear, |rec| lit.record(rec, scene, &meshes, |_| 1.0))?;
            Ok(TechniqueFrame { output, shadow_volume: None, cartoon: None, planar: None, shadow_atlas: None })
        }
        Technique::ShadowVolume => {
            let mut renderer = shadow_volume::ShadowVolumeRenderer::new(
                gpu,
                scene,
                options.width,
                options.height,
                options.stencil,
                &options.shadow_volume,
            )?;
            renderer.count_overdraw(options.count_overdraw);
            let frame = renderer.frame()?;
            Ok(TechniqueFrame {
                output: frame.output,
                shadow_volume: Some(frame.stats),
                cartoon: None,
                planar: None,
                shadow_atlas: None,
            })
        }
        Technique::Outline | Technique::Silhouette | Technique::Toon => {
            let frame = cartoon::render(
                gpu,
                scene,
                options.width,
                options.height,
                options.stencil,
                options.technique,
                &options.cartoon,
            )?;
            Ok(TechniqueFrame {
                output: frame.output,
                shadow_volume: None,
                cartoon: Some(frame.stats),
                planar: None,
                shadow_atlas: None,
            })
        }
        Technique::Planar => {
            let frame = planar::render(gpu, scene, options.width, options.height, options.stencil, &options.planar)?;
            Ok(TechniqueFrame {
                output: frame.output,
                shadow_volume: None,
                cartoon: None,
                planar: Some(frame.stats),
                shadow_atlas: None,
            })
        }
        Technique::Blob => {
            let (w, h, factor) = (options.width, options.height, options.planar.shadow_factor);
            let frame = planar::blob::render(gpu, scene, w, h, options.stencil, factor)?;
            Ok(TechniqueFrame {
                output: frame.output,
                shadow_volume: None,
                cartoon: None,
                planar: Some(frame.stats),
                shadow_atlas: None,
            })
        }
        Technique::ShadowTexture => {
            let (w, h, factor) = (options.width, options.height, options.planar.shadow_factor);
            let frame = planar::shadow_texture::render(gpu, scene, w, h, options.stencil, factor)?;
            Ok(TechniqueFrame {
                output: frame.output,
                shadow_volume: None,
                cartoon: None,
                planar: Some(frame.stats),
                shadow_atlas: None,
            })
        }
        Technique::ShadowMap | Technique::ShadowTextureAtlas => {
            let kind = if options.technique == Technique::ShadowMap { ShadowKind::Map } else { ShadowKind::Atlas };
            let frame = shadow_atlas::render(
                gpu,
                scene,
                options.width,
                options.height,
                options.stencil,
                kind,
                &options.shadow_atlas,
                options.count_overdraw,
            )?;
            Ok(TechniqueFrame {
                output: frame.output,
                shadow_volume: None,
                shadow_atlas: Some(frame.stats),
                cartoon: None,
                planar: None,
            })
        }
    }
}
