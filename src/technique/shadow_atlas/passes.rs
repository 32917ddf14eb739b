//! The pipelines of the seed 004 techniques, as data, and the frame's pass plan: the shadow
//! map prepass, then (atlas and projective) the bakes, dilations and mips, all cached while
//! neither the light nor a model moves, then the scene pass.

use crate::pipeline::recipes::NO_WRITE;
use crate::pipeline::{DepthState, FixedFunction, PipelineDesc, RasterState, VertexAttribute, VertexLayout};
use crate::render::plan::{Draws, MaterialVariant, PassPlan, PlannedPass, Push, SetRole, Target, When};
use crate::render::OBJECT_PUSH_BYTES;
use crate::technique::material_variants::with_surface_variants;
use crate::technique::options::ShadowKind;

/// position (vec3) + normal (vec3) + atlas UV (vec2), then the material's inputs: UV0, UV1
/// (vec2 each) and COLOR_0 (vec4).
pub const ATLAS_VERTEX: VertexLayout = VertexLayout {
    attributes: &[
        VertexAttribute::Vec3,
        VertexAttribute::Vec3,
        VertexAttribute::Vec2,
        VertexAttribute::Vec2,
        VertexAttribute::Vec2,
        VertexAttribute::Vec4,
    ],
};

/// The light's depth, stored for sampling.
pub const SHADOW_MAP: Target = Target::Offscreen("shadow map (depth only)");
/// Each model's raw bake, in atlas space.
pub const ATLAS_SPACE: Target = Target::Offscreen("shadow texture (atlas space)");
/// Each model's raw projective bake, in the light's view.
pub const LIGHT_SPACE: Target = Target::Offscreen("shadow texture (light space)");
/// Mip 0 of each model's shadow texture, dilated from the raw bake.
pub const TEXTURE_MIP0: Target = Target::Offscreen("shadow texture mip 0");

/// The light's view-projection and bias, with the shadow map for the compare.
pub const LIGHT: SetRole = SetRole::Own("shadow light");
/// A model's shadow texture, sampled trilinearly by the scene pass.
pub const SHADOW_TEXTURE: SetRole = SetRole::Own("shadow texture");
/// A model's raw bake, read texel by texel by the dilation.
pub const RAW_BAKE: SetRole = SetRole::Own("raw bake");

pub const SHADOW_MAP_PASS: &str = "shadow map";
pub const BAKE_PASS: &str = "atlas bake";
pub const PROJECTIVE_BAKE_PASS: &str = "projective bake";
pub const DILATE_PASS: &str = "atlas dilate";
pub const MIPS_PASS: &str = "atlas mips";
pub const SCENE_PASS: &str = "scene";

pub fn shadow_map_desc() -> PipelineDesc {
    PipelineDesc {
        name: "shadow map",
        vertex_shader: "shadow_map.vert",
        fragment_shader: "shadow_map.frag",
        vertex_layout: ATLAS_VERTEX,
        fixed: FixedFunction { raster: RasterState::CULL_NONE, blend: NO_WRITE, ..FixedFunction::OPAQUE },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

/// The shadow map's pipeline for MASK casters: texels below the cutoff cast nothing.
pub fn shadow_map_masked_desc() -> PipelineDesc {
    PipelineDesc {
        name: "shadow map (alpha mask)",
        vertex_shader: "shadow_map_masked.vert",
        fragment_shader: "shadow_map_masked.frag",
        ..shadow_map_desc()
    }
}

pub fn bake_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas bake",
        vertex_shader: "shadow_atlas_bake.vert",
        fragment_shader: "shadow_atlas_bake.frag",
        vertex_layout: ATLAS_VERTEX,
        // Atlas space has no facing and no depth: every triangle writes its texels.
        fixed: FixedFunction { raster: RasterState::CULL_NONE, depth: DepthState::OFF, ..FixedFunction::OPAQUE },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

/// The projective bake: the model from the light, writing only its shadowed texels (no depth:
/// every surface on a texel's light ray writes, which is the method's flaw).
pub fn projective_bake_desc() -> PipelineDesc {
    PipelineDesc {
        name: "projective bake",
        vertex_shader: "projective_bake.vert",
        fragment_shader: "projective_bake.frag",
        ..bake_desc()
    }
}

pub fn dilate_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas dilate",
        vertex_shader: "fullscreen.vert",
        fragment_shader: "shadow_atlas_dilate.frag",
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction::FULLSCREEN,
        push_constant_bytes: 16,
        subpass: 0,
    }
}

pub fn scene_desc(kind: ShadowKind) -> PipelineDesc {
    PipelineDesc {
        name: "scene",
        vertex_shader: "shadow_atlas_scene.vert",
        fragment_shader: match kind {
            ShadowKind::Atlas => "shadow_atlas_scene.frag",
            ShadowKind::Map => "shadow_map_scene.frag",
            ShadowKind::Projective => "projective_scene.frag",
        },
        vertex_layout: ATLAS_VERTEX,
        fixed: FixedFunction::OPAQUE,
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

/// The frame of `kind`, pass by pass (no stencil anywhere: there is no reference path).
pub fn plan(kind: ShadowKind) -> PassPlan {
    let moved = When::LightOrCastersMoved;
    let mut plan = PassPlan::new();
    plan.push(
        PlannedPass::new(
            SHADOW_MAP_PASS,
            shadow_map_desc(),
            Draws::Geometry("casters"),
            Push::PerDraw("object transform"),
        )
        .or_variant(MaterialVariant::Masked, shadow_map_desc().name, shadow_map_masked_desc())
        .with_sets(&[LIGHT, SetRole::Material])
        .into_target(SHADOW_MAP)
        .when(moved),
    );
    let scene_sets = match kind {
        ShadowKind::Map => [SetRole::Frame, SetRole::Material, LIGHT],
        ShadowKind::Atlas | ShadowKind::Projective => {
            let (name, desc, draws, target) = if kind == ShadowKind::Atlas {
                (BAKE_PASS, bake_desc(), "each model at its atlas UVs", ATLAS_SPACE)
            } else {
                (PROJECTIVE_BAKE_PASS, projective_bake_desc(), "each model from the light", LIGHT_SPACE)
            };
            plan.push(
                PlannedPass::new(name, desc, Draws::Geometry(draws), Push::PerDraw("object transform"))
                    .with_sets(&[LIGHT])
                    .into_target(target)
                    .when(moved),
            );
            // Projective: radius 0, a copy (uncovered texels are lit, not a gutter).
            plan.push(
                PlannedPass::new(
                    DILATE_PASS,
                    dilate_desc(),
                    Draws::Geometry("full screen per model"),
                    Push::PerDraw("dilation radius"),
                )
                .with_sets(&[RAW_BAKE])
                .into_target(TEXTURE_MIP0)
                .when(moved),
            );
            plan.push(PlannedPass::commands(MIPS_PASS, Draws::Geometry("blits per model"), TEXTURE_MIP0).when(moved));
            [SetRole::Frame, SetRole::Material, SHADOW_TEXTURE]
        }
    };
    let scene = scene_desc(kind);
    let pass =
        PlannedPass::new(SCENE_PASS, scene.clone(), Draws::Objects, Push::PerDraw("object transform and colour"));
    let pass = with_surface_variants(pass, &scene);
    plan.push(match kind {
        // The projection from the light is the light's (set 3).
        ShadowKind::Projective => pass.with_sets(&[scene_sets[0], scene_sets[1], scene_sets[2], LIGHT]),
        _ => pass.with_sets(&scene_sets),
    });
    plan
}
