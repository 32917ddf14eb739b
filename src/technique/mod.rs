//! Techniques: each module records its passes and reads top to bottom.

pub mod alpha_counter;
pub mod lit;
pub mod planar;
pub mod shadow_volume;

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::render::{FrameOutput, FrameUniforms, GpuScene, Renderer};
use crate::scene::Scene;

pub use planar::{PlanarOptions, PlanarStats};
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
    /// Casters (skinned on the GPU) projected onto the ground, double darkening stopped in alpha
    /// in one pass (seed 001).
    Planar,
    /// A soft round texture on a quad under each caster (seed 001's cheapest shadow).
    Blob,
    /// Casters drawn from the light into a small texture that the ground looks up (seed 001).
    ShadowTexture,
}

impl Technique {
    pub const ALL: &'static [Technique] =
        &[Technique::Lit, Technique::ShadowVolume, Technique::Planar, Technique::Blob, Technique::ShadowTexture];

    pub fn name(self) -> &'static str {
        match self {
            Technique::Lit => "lit",
            Technique::ShadowVolume => "shadow-volume",
            Technique::Planar => "planar",
            Technique::Blob => "blob",
            Technique::ShadowTexture => "shadow-texture",
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
            planar: PlanarOptions::default(),
        }
    }
}

/// A rendered frame and what the technique reports about it.
pub struct TechniqueFrame {
    pub output: FrameOutput,
    pub shadow_volume: Option<ShadowVolumeStats>,
    pub planar: Option<PlanarStats>,
}

/// Renders `scene` with the chosen technique and returns the image and its counters.
pub fn render_scene(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions) -> Result<TechniqueFrame> {
    match options.technique {
        Technique::Lit => {
            let mut renderer = Renderer::new(gpu, options.width, options.height, options.stencil, false)?;
            let meshes = GpuScene::upload(gpu, scene)?;
            let uniforms = FrameUniforms::for_scene(scene, renderer.aspect());
            let clear = scene.background.extend(1.0).to_array();
            let lit = lit::LitPass::new(gpu, &renderer)?;
            let output = renderer.render(&uniforms, clear, |rec| lit.record(rec, scene, &meshes, |_| 1.0))?;
            Ok(TechniqueFrame { output, shadow_volume: None, planar: None })
        }
        Technique::ShadowVolume => {
            let frame = shadow_volume::render(
                gpu,
                scene,
                options.width,
                options.height,
                options.stencil,
                &options.shadow_volume,
            )?;
            Ok(TechniqueFrame { output: frame.output, shadow_volume: Some(frame.stats), planar: None })
        }
        Technique::Planar => {
            let frame = planar::render(gpu, scene, options.width, options.height, options.stencil, &options.planar)?;
            Ok(TechniqueFrame { output: frame.output, shadow_volume: None, planar: Some(frame.stats) })
        }
        Technique::Blob => {
            let (w, h, factor) = (options.width, options.height, options.planar.shadow_factor);
            let frame = planar::blob::render(gpu, scene, w, h, options.stencil, factor)?;
            Ok(TechniqueFrame { output: frame.output, shadow_volume: None, planar: Some(frame.stats) })
        }
        Technique::ShadowTexture => {
            let (w, h, factor) = (options.width, options.height, options.planar.shadow_factor);
            let frame = planar::shadow_texture::render(gpu, scene, w, h, options.stencil, factor)?;
            Ok(TechniqueFrame { output: frame.output, shadow_volume: None, planar: Some(frame.stats) })
        }
    }
}
