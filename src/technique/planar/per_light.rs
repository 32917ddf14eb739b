//! Planar shadows from several lights (`--shadow-mode additive`): Doom 3's and Ogre's per-light
//! loop with flattened casters in place of shadow volumes (docs/planar-shadows.md, "Several
//! lights"). Per light, its casters flattened along it write an alpha flag (a write, so overlaps
//! count once), then its shading adds it through `DST_ALPHA` on receivers and resets the flag
//! with the same blend. The reference is Ogre's stencil loop.

use ash::vk;

use super::flattened::{flattened_desc, PlanarDraw, PlanarKinds};
use super::receiver::LIGHT_REACHES_PLANE;
use super::scene_meshes::{named_scene_pass, scene_desc, scene_sets};
use crate::frame::StencilMode;
use crate::pipeline::recipes::{
    stencil_equal, ADD_LIGHT, ADD_LIGHT_WHERE_LIT_RESET, MASK_SHADOWED, NO_WRITE, STENCIL_EQUAL_ZERO_THEN_INCREMENT,
};
use crate::pipeline::{BlendState, DepthState, PipelineDesc, StencilState};
use crate::render::plan::{MaterialVariant, Only, PassPlan, PlannedPass, When};
use crate::render::LIGHT_PUSH_BYTES;
use crate::shaders;
use crate::technique::light_loop::{self, PlannedLight};
use crate::technique::options::PlanarOptions;

/// Doom 3's and Ogre's loop with flattened casters: ambient, then per light its flag and its
/// shading, then the blended objects.
pub(super) fn plan(options: &PlanarOptions, stencil: StencilMode, lights: &[PlannedLight]) -> PassPlan<PlanarKinds> {
    let mut plan = PassPlan::new();
    let ambient =
        PipelineDesc { fragment_shader: shaders::LIT_AMBIENT_FRAG, ..scene_desc("scene (ambient)", false, None) };
    let ambient_skinned = PipelineDesc {
        fragment_shader: shaders::LIT_AMBIENT_FRAG,
        ..scene_desc("scene (ambient, skinned)", true, None)
    };
    let push = "object transform and colour, alpha 1";
    let pass =
        named_scene_pass("scene (ambient)", ambient.clone(), ambient, ambient_skinned, push, PlanarDraw::Ambient);
    plan.push(pass.only(Only::Opaque));
    for (index, light) in lights.iter().enumerate() {
        let i = index as u8;
        if light.shadows {
            plan.push(flag_pass(stencil, options.shadow_lod.is_some(), light, i));
        }
        plan.push(light_shading_pass(stencil, light, i));
    }
    let scene = scene_desc("scene", false, None);
    let skinned = scene_desc("scene (skinned)", true, None);
    let transparent = named_scene_pass("transparent", scene.clone(), scene, skinned, push, PlanarDraw::Transparent);
    plan.push(transparent.only(Only::Blended));
    plan
}

/// Light `i`'s flag: its casters flattened along it, alpha := 0 where they land (emulated), or
/// stencil `EQUAL 0, INCR_WRAP` (the reference). Colour is left alone: the light's shading reads
/// the flag.
fn flag_pass(stencil: StencilMode, lod: bool, light: &PlannedLight, i: u8) -> PlannedPass<PlanarKinds> {
    let (names, blend, test, push) = match stencil {
        StencilMode::Emulated => (
            [
                "planar shadow (alpha flag)",
                "planar shadow (skinned, alpha flag)",
                "planar shadow (alpha flag, alpha mask)",
                "planar shadow (skinned, alpha flag, alpha mask)",
            ],
            MASK_SHADOWED,
            None,
            "caster transform, alpha 0, plane (n, d), light",
        ),
        StencilMode::Reference => (
            [
                "planar shadow (stencil flag)",
                "planar shadow (skinned, stencil flag)",
                "planar shadow (stencil flag, alpha mask)",
                "planar shadow (skinned, stencil flag, alpha mask)",
            ],
            NO_WRITE,
            Some(STENCIL_EQUAL_ZERO_THEN_INCREMENT),
            "caster transform, plane (n, d), light",
        ),
    };
    let [plain, skinned, masked, skinned_masked] = names;
    let cut_out = |name: &'static str, vertex_shader: shaders::Shader, is_skinned: bool| PipelineDesc {
        name,
        vertex_shader,
        fragment_shader: shaders::OBJECT_COLOUR_MASKED_FRAG,
        ..flattened_desc(name, is_skinned, blend, test)
    };
    let draw = PlanarDraw::ProjectedCasters { lod, light: Some(i) };
    PlannedPass::own(
        light_loop::pass_name(light, "planar shadow"),
        flattened_desc(plain, false, blend, test),
        draw,
        push,
    )
    .or_pipeline(flattened_desc(skinned, true, blend, test))
    .or_variant(MaterialVariant::Masked, plain, cut_out(masked, shaders::PLANAR_SHADOW_MASKED_VERT, false))
    .or_variant(
        MaterialVariant::Masked,
        skinned,
        cut_out(skinned_masked, shaders::PLANAR_SHADOW_MASKED_SKINNED_VERT, true),
    )
    .with_sets(&scene_sets())
    .when(When::If(LIGHT_REACHES_PLANE.for_light(i)))
    .for_light(i)
}

/// A light's shading pipeline: the scene's vertex stage (invariant: depth EQUAL meets the
/// ambient pass), the light's contribution out through `blend`.
fn shading_desc(name: &'static str, skinned: bool, blend: BlendState, stencil: Option<StencilState>) -> PipelineDesc {
    let mut desc = PipelineDesc {
        fragment_shader: shaders::LIT_LIGHT_FRAG,
        push_constant_bytes: LIGHT_PUSH_BYTES,
        ..scene_desc(name, skinned, stencil)
    };
    desc.fixed.depth = DepthState { compare: Some(vk::CompareOp::EQUAL), write: false };
    desc.fixed.blend = blend;
    desc
}

/// Light `i`'s shading: receivers through its flag when it casts shadows (emulated: `DST_ALPHA`,
/// alpha reset to 1 by the same blend; reference: stencil `EQUAL 0`), casters and skinned
/// objects unmasked (a stray flattened fragment on them must not count).
fn light_shading_pass(stencil: StencilMode, light: &PlannedLight, i: u8) -> PlannedPass<PlanarKinds> {
    let casters = shading_desc("shading (casters)", false, ADD_LIGHT, None);
    let skinned = shading_desc("shading (skinned)", true, ADD_LIGHT, None);
    let receivers = match (light.shadows, stencil) {
        (false, _) => shading_desc("shading (no shadows)", false, ADD_LIGHT, None),
        (true, StencilMode::Emulated) => shading_desc("shading", false, ADD_LIGHT_WHERE_LIT_RESET, None),
        (true, StencilMode::Reference) => shading_desc("shading (stencil)", false, ADD_LIGHT, Some(stencil_equal(0))),
    };
    let others = if light.shadows { casters } else { receivers.clone() };
    let draw = PlanarDraw::Shading { light: i, shadowed: light.shadows };
    let push = "object transform and colour, alpha 1, light";
    named_scene_pass(light_loop::pass_name(light, "shading"), receivers, others, skinned, push, draw)
        .only(Only::Opaque)
        .for_light(i)
}
