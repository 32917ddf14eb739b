//! `nostencil bake`'s entry: the atlas renderer built and run for one frame, its shadow
//! textures then read back.

use std::sync::Arc;

use image::RgbaImage;

use super::passes::AtlasKinds;
use super::read_back::read_shadow_texture;
use super::renderer::{build, ShadowPasses};
use super::stats::AtlasInfo;
use super::techniques::SHADOW_TEXTURE_ATLAS;
use crate::error::Result;
use crate::gpu::Gpu;
use crate::scene::Scene;
use crate::technique::frame_renderer::FrameRenderer;
use crate::technique::interface::{RenderOptions, Technique, TechniqueRenderer};
use crate::technique::options::ShadowKind;

/// How far `bake` is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BakeStep {
    /// `done` of `total` meshes laid out in their atlases.
    Layout { done: usize, total: usize },
    /// Everything built: the shadow map and shadow textures are being rendered.
    Rendering,
}

/// A scene's shadow textures, baked.
pub struct Baked<'s> {
    scene: &'s Scene,
    renderer: FrameRenderer<'s, AtlasKinds, ShadowPasses>,
}

/// Builds the shadow-texture-atlas renderer for `scene` (frames of `options`' size) and renders
/// one frame, which bakes every model's shadow texture.
pub fn bake<'s>(
    gpu: &Arc<Gpu>,
    scene: &'s Scene,
    options: &RenderOptions,
    progress: &mut dyn FnMut(BakeStep),
) -> Result<Baked<'s>> {
    let options = RenderOptions { technique: Technique(&SHADOW_TEXTURE_ATLAS), ..options.clone() };
    let mut layout = |done, total| progress(BakeStep::Layout { done, total });
    let mut renderer = build(ShadowKind::Atlas.name(), ShadowKind::Atlas, gpu, scene, &options, &mut layout)?;
    progress(BakeStep::Rendering);
    renderer.frame_with(scene)?;
    Ok(Baked { scene, renderer })
}

impl<'s> Baked<'s> {
    /// Renders another frame of `scene` (the same scene, some models moved, say), which
    /// re-bakes the shadow textures that can have changed; its statistics say how many.
    #[cfg(test)]
    pub fn frame_with(&mut self, scene: &'s Scene) -> Result<crate::technique::interface::TechniqueFrame> {
        self.scene = scene;
        self.renderer.frame_with(scene)
    }

    /// Mip `mip` of object `object`'s shadow texture (R, G, B: the lights in map layers 0, 1,
    /// 2, 255 lit, 0 shadowed; A: 255 where a triangle covers the texel or dilation reached it).
    pub fn read_shadow_texture(&self, object: usize, mip: u32) -> Result<RgbaImage> {
        let passes = self.renderer.passes();
        read_shadow_texture(passes.gpu(), self.scene, passes.shadow_textures(), passes.frames(), object, mip)
    }

    /// Each mesh's atlas layout, by mesh index.
    pub fn atlases(&self) -> &[AtlasInfo] {
        self.renderer.passes().atlases()
    }
}
