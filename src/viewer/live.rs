//! The technique the viewer shows, built once per (technique, stencil mode, options, size) and
//! kept between frames; each frame renders the live scene (moved camera, light, objects) into
//! the RGBA8 target, where it stays on the GPU for the copy to the window.

use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::profile::FrameCounters;
use crate::render::{FrameUniforms, GpuScene, Renderer};
use crate::scene::Scene;
use crate::technique::lit::LitPass;
use crate::technique::shadow_volume::ShadowVolumeRenderer;
use crate::technique::{ShadowVolumeOptions, Technique};

/// Techniques the viewer renders live (the others render offscreen with `nostencil render`).
pub const LIVE_TECHNIQUES: &[Technique] = &[Technique::Lit, Technique::ShadowVolume];

/// Everything that selects how a frame is rendered; a change rebuilds the live technique.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    pub technique: Technique,
    pub stencil: StencilMode,
    pub shadow_volume: ShadowVolumeOptions,
}

impl Settings {
    /// "shadow-volume (emulated, seed)" for the window title.
    pub fn describe(&self) -> String {
        match self.technique {
            Technique::Lit => format!("{} ({})", self.technique.name(), self.stencil.name()),
            Technique::ShadowVolume => {
                let normalise = match self.stencil {
                    StencilMode::Emulated => format!(", {}", self.shadow_volume.normalize.name()),
                    StencilMode::Reference => String::new(),
                };
                format!(
                    "{} ({}{normalise}, k={})",
                    self.technique.name(),
                    self.stencil.name(),
                    self.shadow_volume.increment
                )
            }
            other => other.name().to_owned(),
        }
    }
}

/// Boxed: a live technique is built once and kept, and variants differ a lot in size.
enum Kind<'s> {
    Lit(Box<LitFrame>),
    ShadowVolume(Box<ShadowVolumeRenderer<'s>>),
}

struct LitFrame {
    renderer: Renderer,
    meshes: GpuScene,
    lit: LitPass,
}

pub struct LiveTechnique<'s> {
    pub settings: Settings,
    pub extent: vk::Extent2D,
    kind: Kind<'s>,
}

/// What one frame reports.
pub struct LiveFrame {
    pub counters: FrameCounters,
    /// Shadow volumes: z-fail was used.
    pub zfail: Option<bool>,
}

impl<'s> LiveTechnique<'s> {
    /// `base` is the scene as loaded: meshes are uploaded and casters prepared from it once.
    pub fn new(gpu: &Arc<Gpu>, base: &'s Scene, settings: Settings, extent: vk::Extent2D) -> Result<Self> {
        let (width, height) = (extent.width, extent.height);
        let kind = match settings.technique {
            Technique::Lit => {
                let mut renderer = Renderer::new(gpu, width, height, settings.stencil, false)?;
                renderer.keep_on_gpu(true);
                let meshes = GpuScene::upload(gpu, base)?;
                let lit = LitPass::new(gpu, &renderer)?;
                Kind::Lit(Box::new(LitFrame { renderer, meshes, lit }))
            }
            Technique::ShadowVolume => {
                let mut sv =
                    ShadowVolumeRenderer::new(gpu, base, width, height, settings.stencil, &settings.shadow_volume)?;
                sv.renderer_mut().keep_on_gpu(true);
                Kind::ShadowVolume(Box::new(sv))
            }
            other => {
                return Err(crate::Error::InvalidInput(format!(
                    "view shows {} live; render '{}' with `nostencil render --technique {1}`",
                    LIVE_TECHNIQUES.iter().map(|t| t.name()).collect::<Vec<_>>().join(" and "),
                    other.name()
                )))
            }
        };
        Ok(LiveTechnique { settings, extent, kind })
    }

    /// Whether `scene` needs a rebuild (shadow volumes with `auto`: the camera moved into or out
    /// of a volume, so the counting method changes).
    pub fn stale_for(&self, scene: &Scene) -> bool {
        match &self.kind {
            Kind::Lit(_) => false,
            Kind::ShadowVolume(sv) => sv.wants_zfail(scene) != sv.zfail(),
        }
    }

    /// Renders `scene` into the colour target and waits for it (the counters are read back).
    pub fn frame(&mut self, scene: &Scene) -> Result<LiveFrame> {
        match &mut self.kind {
            Kind::Lit(frame) => {
                let LitFrame { renderer, meshes, lit } = &mut **frame;
                // As `technique::render_scene` does for `lit`, so that both give the same image.
                let uniforms = FrameUniforms::for_scene(scene, renderer.aspect());
                let clear = scene.background.extend(1.0).to_array();
                let output = renderer.render(&uniforms, clear, |rec| lit.record(rec, scene, meshes, |_| 1.0))?;
                Ok(LiveFrame { counters: output.counters, zfail: None })
            }
            Kind::ShadowVolume(sv) => {
                let frame = sv.frame_with(scene)?;
                Ok(LiveFrame { counters: frame.output.counters, zfail: Some(frame.stats.zfail) })
            }
        }
    }

    /// The colour target holding the last frame (layout TRANSFER_SRC_OPTIMAL).
    pub fn colour_image(&mut self) -> vk::Image {
        match &mut self.kind {
            Kind::Lit(frame) => frame.renderer.targets.colour.raw,
            Kind::ShadowVolume(sv) => sv.renderer_mut().targets.colour.raw,
        }
    }
}
