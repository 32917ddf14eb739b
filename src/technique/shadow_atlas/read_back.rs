//! Reading a baked shadow texture back to the CPU (`nostencil bake`, the tests).

use std::sync::Arc;

use image::RgbaImage;

use super::bake::AtlasTargets;
use super::page_targets::AtlasPage;
use crate::error::{Error, Result};
use crate::frame::image_from_rgba8;
use crate::gpu::texture::{read_back_mip, read_back_square};
use crate::gpu::Gpu;
use crate::scene::Scene;

/// Where a renderer's shadow textures are.
pub enum ShadowTextures<'a> {
    /// The atlas: every model's texture a tile of one page.
    Page(&'a AtlasPage),
    /// The projective texture: one texture per model.
    PerModel(&'a AtlasTargets),
}

/// Reads back mip `mip` of object `object`'s shadow texture (R, G, B: the lights in map layers
/// 0, 1, 2, 255 lit, 0 shadowed; A: 255 where a triangle covers the texel or dilation reached
/// it). `frames`: frames rendered so far (none: nothing is baked yet).
pub fn read_shadow_texture(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    textures: Option<ShadowTextures<'_>>,
    frames: u32,
    object: usize,
    mip: u32,
) -> Result<RgbaImage> {
    let textures =
        textures.ok_or_else(|| Error::InvalidInput("only shadow-texture-atlas bakes shadow textures".into()))?;
    let no_object = || Error::InvalidInput(format!("no object {object} in scene '{}'", scene.name));
    let (image, corner, size, mip_levels) = match textures {
        ShadowTextures::Page(page) => {
            let t = page.tiles.get(object).ok_or_else(no_object)?;
            (page.texture.raw, Some((t.tile.x, t.tile.y)), t.tile.size, t.mip_levels)
        }
        ShadowTextures::PerModel(atlas) => {
            let o = atlas.objects.get(object).ok_or_else(no_object)?;
            (o.texture.raw, None, o.size, o.mip_levels)
        }
    };
    if mip >= mip_levels {
        return Err(Error::InvalidInput(format!("mip {mip}: the shadow texture has {mip_levels}")));
    }
    if frames == 0 {
        return Err(Error::InvalidInput("no frame rendered yet: nothing is baked".into()));
    }
    let side = (size >> mip).max(1);
    let texels = match corner {
        Some((x, y)) => read_back_square(gpu, image, mip, (x >> mip, y >> mip), side)?,
        None => read_back_mip(gpu, image, mip, side)?,
    };
    image_from_rgba8(side, side, texels)
}
