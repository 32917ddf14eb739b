//! One interface over every technique's renderer: built once for a scene, it renders that scene
//! frame after frame while its camera, light and object transforms change. `render` and
//! `profile` take one frame from it; the viewer takes every frame.

use std::sync::Arc;

use super::cartoon::CartoonRenderer;
use super::lit::LitRenderer;
use super::planar::blob::BlobRenderer;
use super::planar::shadow_texture::ShadowTextureRenderer;
use super::planar::PlanarRenderer;
use super::shadow_atlas::ShadowAtlasRenderer;
use super::shadow_volume::ShadowVolumeRenderer;
use super::{LightMode, RenderOptions, ShadowKind, Technique, TechniqueFrame};
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::{FrameOutput, Renderer};
use crate::scene::Scene;

pub trait SceneRenderer {
    /// Renders `scene`: the scene this renderer was built for, with camera, light, object
    /// transforms and joint palettes free to change (meshes and objects may not: see
    /// `check_same_scene`).
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame>;

    /// The frame renderer, for its switches (`keep_on_gpu`, `count_overdraw`) and targets.
    fn renderer_mut(&mut self) -> &mut Renderer;

    /// Whether drawing `scene` needs a rebuilt renderer (shadow volumes with `auto`: the camera
    /// moved into or out of a volume, so the counting method changes).
    fn stale_for(&self, _scene: &Scene) -> bool {
        false
    }

    /// Frames until the counters show the steady state, which one-frame renders report (a
    /// fixed light's shadow map and atlases are baked by the first frame and cached after).
    fn frames_to_steady_state(&self) -> u32 {
        1
    }
}

/// Builds the renderer `options.technique` names for `scene` at `options`' size and stencil.
pub fn build<'s>(gpu: &Arc<Gpu>, scene: &'s Scene, options: &RenderOptions) -> Result<Box<dyn SceneRenderer + 's>> {
    let (w, h, stencil) = (options.width, options.height, options.stencil);
    let shadow_factor = options.planar.shadow_factor;
    let renderer: Box<dyn SceneRenderer + 's> = match options.technique {
        Technique::Lit => Box::new(LitRenderer::new(gpu, scene, w, h, stencil)?),
        Technique::ShadowVolume => {
            Box::new(ShadowVolumeRenderer::new(gpu, scene, w, h, stencil, &options.shadow_volume)?)
        }
        Technique::Outline | Technique::Silhouette | Technique::Toon => {
            Box::new(CartoonRenderer::new(gpu, scene, w, h, stencil, options.technique, &options.cartoon)?)
        }
        Technique::Planar => Box::new(PlanarRenderer::new(gpu, scene, w, h, stencil, &options.planar)?),
        Technique::Blob => Box::new(BlobRenderer::new(gpu, scene, w, h, stencil, shadow_factor)?),
        Technique::ShadowTexture => Box::new(ShadowTextureRenderer::new(gpu, scene, w, h, stencil, shadow_factor)?),
        Technique::ShadowMap | Technique::ShadowTextureAtlas => {
            let kind = if options.technique == Technique::ShadowMap { ShadowKind::Map } else { ShadowKind::Atlas };
            Box::new(ShadowAtlasRenderer::new(gpu, scene, w, h, stencil, kind, &options.shadow_atlas)?)
        }
    };
    Ok(renderer)
}

/// Refuses a `scene` that is not a moved pose of `built_for`: a renderer uploads meshes and
/// prepares casters once, so the objects, their meshes and which ones cast shadows must match.
pub fn check_same_scene(built_for: &Scene, scene: &Scene, technique: &str) -> Result<()> {
    let same_objects =
        built_for.objects.len() == scene.objects.len()
            && built_for.objects.iter().zip(&scene.objects).all(|(a, b)| {
                a.mesh == b.mesh && a.casts_shadow == b.casts_shadow && a.skin.is_some() == b.skin.is_some()
            });
    let same_meshes = built_for.meshes.len() == scene.meshes.len()
        && built_for.meshes.iter().zip(&scene.meshes).all(|(a, b)| {
            a.data.positions.len() == b.data.positions.len() && a.data.indices.len() == b.data.indices.len()
        });
    if same_objects && same_meshes {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "scene '{}' is not the one this {technique} renderer was built for (its objects or meshes differ)",
            scene.name
        )))
    }
}

impl TechniqueFrame {
    /// A frame with no technique statistics (the lit scene).
    pub fn plain(output: FrameOutput) -> Self {
        TechniqueFrame { output, shadow_volume: None, cartoon: None, planar: None, shadow_atlas: None }
    }
}

impl SceneRenderer for LitRenderer<'_> {
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
        Ok(TechniqueFrame::plain(LitRenderer::frame_with(self, scene)?))
    }

    fn renderer_mut(&mut self) -> &mut Renderer {
        LitRenderer::renderer_mut(self)
    }
}

impl SceneRenderer for ShadowVolumeRenderer<'_> {
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
        let frame = ShadowVolumeRenderer::frame_with(self, scene)?;
        Ok(TechniqueFrame { shadow_volume: Some(frame.stats), ..TechniqueFrame::plain(frame.output) })
    }

    fn renderer_mut(&mut self) -> &mut Renderer {
        ShadowVolumeRenderer::renderer_mut(self)
    }

    fn stale_for(&self, scene: &Scene) -> bool {
        self.wants_zfail(scene) != self.zfail()
    }
}

impl SceneRenderer for CartoonRenderer<'_> {
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
        let frame = CartoonRenderer::frame_with(self, scene)?;
        Ok(TechniqueFrame { cartoon: Some(frame.stats), ..TechniqueFrame::plain(frame.output) })
    }

    fn renderer_mut(&mut self) -> &mut Renderer {
        CartoonRenderer::renderer_mut(self)
    }
}

/// The three planar-family renderers report the same statistics.
macro_rules! planar_scene_renderer {
    ($renderer:ident) => {
        impl SceneRenderer for $renderer<'_> {
            fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
                let frame = $renderer::frame_with(self, scene)?;
                Ok(TechniqueFrame { planar: Some(frame.stats), ..TechniqueFrame::plain(frame.output) })
            }

            fn renderer_mut(&mut self) -> &mut Renderer {
                $renderer::renderer_mut(self)
            }
        }
    };
}

planar_scene_renderer!(PlanarRenderer);
planar_scene_renderer!(BlobRenderer);
planar_scene_renderer!(ShadowTextureRenderer);

impl SceneRenderer for ShadowAtlasRenderer<'_> {
    fn frame_with(&mut self, scene: &Scene) -> Result<TechniqueFrame> {
        let frame = ShadowAtlasRenderer::frame_with(self, scene)?;
        Ok(TechniqueFrame { shadow_atlas: Some(frame.stats), ..TechniqueFrame::plain(frame.output) })
    }

    fn renderer_mut(&mut self) -> &mut Renderer {
        ShadowAtlasRenderer::renderer_mut(self)
    }

    fn frames_to_steady_state(&self) -> u32 {
        match self.light_mode() {
            LightMode::Moving => 1,
            LightMode::Fixed => 2,
        }
    }
}
