//! The material variants of a scene pass's pipeline (`render::plan::MaterialVariant`), made
//! from the pass's opaque pipeline so that every technique draws each material alike:
//! - alpha mask: the `_masked` fragment shader (discards below the cutoff), same state;
//! - double-sided: the `_masked` shader (it also serves double-sided MASK), no culling; the
//!   shader turns the normal to the viewer on back faces;
//! - blend: the `_blend` shader (the material's alpha out), depth tested but not written,
//!   `OVER_KEEPING_ALPHA`, no stencil write (the emulated path keeps alpha, so the reference
//!   keeps its stencil); culled as the material says.
//!
//! Pipeline names are static: each opaque pipeline that has variants is listed here with its
//! variants' names.

use crate::pipeline::recipes::OVER_KEEPING_ALPHA;
use crate::pipeline::{DepthState, PipelineDesc, RasterState};
use crate::render::plan::{MaterialVariant, PassKinds, PlannedPass};
use crate::shaders;

/// [masked, double-sided, blend, blend double-sided] names of the variants of `base`.
fn variant_names(base: &str) -> Option<[&'static str; 4]> {
    Some(match base {
        "scene" => ["scene (alpha mask)", "scene (double-sided)", "scene (blend)", "scene (blend, double-sided)"],
        // The additive loop's passes draw opaque and cut-out materials only (`Only::Opaque`):
        // their blend variants are never bound.
        "scene (ambient)" => [
            "scene (ambient, alpha mask)",
            "scene (ambient, double-sided)",
            "scene (ambient, blend)",
            "scene (ambient, blend, double-sided)",
        ],
        "shading" => {
            ["shading (alpha mask)", "shading (double-sided)", "shading (blend)", "shading (blend, double-sided)"]
        }
        "shading (subpass)" => [
            "shading (subpass, alpha mask)",
            "shading (subpass, double-sided)",
            "shading (subpass, blend)",
            "shading (subpass, blend, double-sided)",
        ],
        "shading (subpass, counts saturation)" => [
            "shading (subpass, counts saturation, alpha mask)",
            "shading (subpass, counts saturation, double-sided)",
            "shading (subpass, counts saturation, blend)",
            "shading (subpass, counts saturation, blend, double-sided)",
        ],
        "shading (stencil)" => [
            "shading (stencil, alpha mask)",
            "shading (stencil, double-sided)",
            "shading (blend, no stencil)",
            "shading (blend, double-sided, no stencil)",
        ],
        "scene (ambient, skinned)" => [
            "scene (ambient, skinned, alpha mask)",
            "scene (ambient, skinned, double-sided)",
            "scene (ambient, skinned, blend)",
            "scene (ambient, skinned, blend, double-sided)",
        ],
        "shading (casters)" => [
            "shading (casters, alpha mask)",
            "shading (casters, double-sided)",
            "shading (casters, blend)",
            "shading (casters, blend, double-sided)",
        ],
        "shading (skinned)" => [
            "shading (skinned, alpha mask)",
            "shading (skinned, double-sided)",
            "shading (skinned, blend)",
            "shading (skinned, blend, double-sided)",
        ],
        "shading (no shadows)" => [
            "shading (no shadows, alpha mask)",
            "shading (no shadows, double-sided)",
            "shading (no shadows, blend)",
            "shading (no shadows, blend, double-sided)",
        ],
        "scene (stencil 1)" => [
            "scene (stencil 1, alpha mask)",
            "scene (stencil 1, double-sided)",
            "scene (blend, no stencil)",
            "scene (blend, double-sided, no stencil)",
        ],
        "scene (skinned)" => [
            "scene (skinned, alpha mask)",
            "scene (skinned, double-sided)",
            "scene (skinned, blend)",
            "scene (skinned, blend, double-sided)",
        ],
        "scene (skinned, stencil 1)" => [
            "scene (skinned, stencil 1, alpha mask)",
            "scene (skinned, stencil 1, double-sided)",
            "scene (skinned, blend, no stencil)",
            "scene (skinned, blend, double-sided, no stencil)",
        ],
        "selected (stencil)" => [
            "selected (stencil, alpha mask)",
            "selected (stencil, double-sided)",
            "selected (blend, no stencil)",
            "selected (blend, double-sided, no stencil)",
        ],
        _ => return None,
    })
}

/// The fragment shaders of the variants of an opaque fragment shader: (masked, blend).
fn variant_shaders(fragment: shaders::Shader) -> Option<(shaders::Shader, shaders::Shader)> {
    Some(match fragment {
        shaders::LIT_FRAG => (shaders::LIT_MASKED_FRAG, shaders::LIT_BLEND_FRAG),
        shaders::LIT_AMBIENT_FRAG => (shaders::LIT_AMBIENT_MASKED_FRAG, shaders::LIT_BLEND_FRAG),
        shaders::LIT_LIGHT_FRAG => (shaders::LIT_LIGHT_MASKED_FRAG, shaders::LIT_BLEND_FRAG),
        shaders::LIT_LIGHT_SUBPASS_FRAG => (shaders::LIT_LIGHT_SUBPASS_MASKED_FRAG, shaders::LIT_BLEND_FRAG),
        shaders::LIT_LIGHT_SUBPASS_COUNTED_FRAG => {
            (shaders::LIT_LIGHT_SUBPASS_COUNTED_MASKED_FRAG, shaders::LIT_BLEND_FRAG)
        }
        shaders::CARTOON_SHADE_FRAG => (shaders::CARTOON_SHADE_MASKED_FRAG, shaders::CARTOON_SHADE_BLEND_FRAG),
        shaders::SHADOW_ATLAS_SCENE_FRAG => {
            (shaders::SHADOW_ATLAS_SCENE_MASKED_FRAG, shaders::SHADOW_ATLAS_SCENE_BLEND_FRAG)
        }
        shaders::SHADOW_MAP_SCENE_FRAG => (shaders::SHADOW_MAP_SCENE_MASKED_FRAG, shaders::SHADOW_MAP_SCENE_BLEND_FRAG),
        shaders::PROJECTIVE_SCENE_FRAG => (shaders::PROJECTIVE_SCENE_MASKED_FRAG, shaders::PROJECTIVE_SCENE_BLEND_FRAG),
        _ => return None,
    })
}

/// The pipeline `base` (opaque, single-sided) draws `variant` with; `None` when `base` has no
/// variants listed here.
pub fn variant_of(base: &PipelineDesc, variant: MaterialVariant) -> Option<PipelineDesc> {
    let [masked, double_sided, blend, blend_double_sided] = variant_names(base.name)?;
    let (masked_shader, blend_shader) = variant_shaders(base.fragment_shader)?;
    let mut desc = base.clone();
    let both_faces = RasterState { cull: ash::vk::CullModeFlags::NONE, ..base.fixed.raster };
    let blended = |desc: &mut PipelineDesc| {
        desc.fragment_shader = blend_shader;
        desc.fixed.depth = DepthState { compare: base.fixed.depth.compare, write: false };
        desc.fixed.blend = OVER_KEEPING_ALPHA;
        desc.fixed.stencil = None;
    };
    match variant {
        MaterialVariant::Masked => {
            desc.name = masked;
            desc.fragment_shader = masked_shader;
        }
        MaterialVariant::DoubleSided => {
            desc.name = double_sided;
            desc.fragment_shader = masked_shader;
            desc.fixed.raster = both_faces;
        }
        MaterialVariant::Blend => {
            desc.name = blend;
            blended(&mut desc);
        }
        MaterialVariant::BlendDoubleSided => {
            desc.name = blend_double_sided;
            blended(&mut desc);
            desc.fixed.raster = both_faces;
        }
    }
    Some(desc)
}

/// Every variant of `base` added to `pass` (nothing when `base` has none).
pub fn with_surface_variants<K: PassKinds>(mut pass: PlannedPass<K>, base: &PipelineDesc) -> PlannedPass<K> {
    use MaterialVariant::*;
    for variant in [Masked, DoubleSided, Blend, BlendDoubleSided] {
        if let Some(desc) = variant_of(base, variant) {
            pass = pass.or_variant(variant, base.name, desc);
        }
    }
    pass
}
