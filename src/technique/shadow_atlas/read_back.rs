//! Reading a baked shadow texture back to the CPU (`nostencil bake`, the tests).

use std::sync::Arc;

use image::RgbaImage;

use super::bake::AtlasTargets;
use crate::error::{Error, Result};
use crate::frame::image_from_rgba8;
use crate::gpu::texture::read_back_mip;
use crate::gpu::Gpu;
use crate::scene::Scene;

/// Reads back mip `mip` of object `object`'s shadow texture (R, G, B: the lights in map layers
/// 0, 1, 2, 255 lit, 0 shadowed; A: 255 where a triangle covers the texel or dilation reached it). `frames`: frames rendered so far
/// (none: nothing is baked yet).
pub fn read_shadow_texture(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    atlas: Option<&AtlasTargets>,
    frames: u32,
    object: usize,
    mip: u32,
) -> Result<RgbaImage> {
    let atlas = atlas.ok_or_else(|| Error::InvalidInput("only shadow-texture-atlas bakes shadow textures".into()))?;
    let shadow = atlas
        .objects
        .get(object)
        .ok_or_else(|| Error::InvalidInput(format!("no object {object} in scene '{}'", scene.name)))?;
    if mip >= shadow.mip_levels {
        return Err(Error::InvalidInput(format!("mip {mip}: the shadow texture has {}", shadow.mip_levels)));
    }
    if frames == 0 {
        return Err(Error::InvalidInput("no frame rendered yet: nothing is baked".into()));
    }
    let side = (shadow.size >> mip).max(1);
    let texels = read_back_mip(gpu, shadow.texture.raw, mip, side)?;
    image_from_rgba8(side, side, texels)
}
