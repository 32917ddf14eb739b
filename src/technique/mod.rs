//! Techniques: each module records its passes and reads top to bottom.

pub mod alpha_counter;
pub mod lit;
pub mod shadow_volume;

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::render::{FrameOutput, FrameUniforms, GpuScene, Renderer};
use crate::scene::Scene;

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
}

impl Technique {
    pub const ALL: &'static [Technique] = &[Technique::Lit, Technique::ShadowVolume];

    pub fn name(self) -> &'static str {
        match self {
            Technique::Lit => "lit",
            Technique::ShadowVolume => "shadow-volume",
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
    /// Heat-map frame: alpha ends up holding the fragments shaded per pixel.
    pub count_overdraw: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 256,
            height: 256,
            stencil: StencilMode::Emulated,
            technique: Technique::Lit,
            shadow_volume: ShadowVolumeOptions::default(),
            count_overdraw: false,
        }
    }
}

/// Every pipeline a technique builds, labelled with its path (emulated / reference), in pass
/// order: the source of `nostencil passes`.
pub fn pipeline_descs(options: &RenderOptions) -> Vec<(&'static str, crate::pipeline::PipelineDesc)> {
    match options.technique {
        Technique::Lit => vec![("both", lit::scene_pipeline_desc())],
        Technique::ShadowVolume => shadow_volume::pipeline_descs(&options.shadow_volume),
    }
}

/// A rendered frame and what the technique reports about it.
pub struct TechniqueFrame {
    pub output: FrameOutput,
    pub shadow_volume: Option<ShadowVolumeStats>,
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
            Ok(TechniqueFrame { output, shadow_volume: None })
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
            Ok(TechniqueFrame { output: frame.output, shadow_volume: Some(frame.stats) })
        }
    }
}
