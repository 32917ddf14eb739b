//! The pipelines of the seed 004 techniques, as data, and the frame's pass plan: a shadow-map
//! prepass per shadowing light (its layer of the map array), then the atlas page's bake, page
//! pass and mips (the projective texture: per-model bakes, copies and mips), all cached while
//! neither a light nor a model moves, then the scene pass.

use crate::pipeline::recipes::NO_WRITE;
use crate::pipeline::{DepthState, FixedFunction, PipelineDesc, RasterState, VertexLayout};
use crate::render::plan::{
    Condition, DrawKind, Label, MaterialVariant, PassKinds, PassPlan, PlannedPass, SetRole, When,
};
use crate::render::{LIGHT_PUSH_BYTES, OBJECT_PUSH_BYTES};
use crate::shaders;
use crate::technique::light_loop::{self, PlannedLight};
use crate::technique::material_variants::with_surface_variants;
use crate::technique::options::ShadowKind;

/// position (vec3) + normal (vec3) + atlas UV (vec2), then the material's inputs: UV0, UV1
/// (vec2 each) and COLOR_0 (vec4).
pub const ATLAS_VERTEX: VertexLayout = VertexLayout::ATLAS;

/// The kinds of the seed 004 plans.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AtlasKinds;

impl PassKinds for AtlasKinds {
    type Draw = AtlasDraw;
    type Set = AtlasSet;
    type Target = AtlasTarget;
}

/// What the seed 004 renderer draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AtlasDraw {
    /// The casters from the pass's light, depth only, into its layer.
    ShadowMap,
    /// Layer 0 cleared, nothing drawn: no light has a map, and the array is bound all the same.
    ClearMap,
    /// Each model at its atlas UVs, lit or shadowed per texel (the atlas: only the rasterised
    /// models re-baked this frame, each in its tile of the raw page).
    Bake,
    /// Each model from the light (the projective texture's bake).
    ProjectiveBake,
    /// One full-screen pass per model, from its raw bake into its shadow texture.
    Dilate,
    /// One quad per re-baked tile into the atlas page: a geometry image's texels baked from
    /// their surface points, a rasterised model's tile dilated from the raw page.
    Page,
    /// The atlas page's mip chain (the projective texture: each model's), by blits.
    Mips,
    /// Every object, lit, its Lambert term scaled by its shadow.
    Scene,
}

impl DrawKind for AtlasDraw {
    fn describe(self) -> &'static str {
        match self {
            AtlasDraw::ShadowMap => "casters",
            AtlasDraw::ClearMap => "nothing (the layer is cleared)",
            AtlasDraw::Bake => "each model at its atlas UVs",
            AtlasDraw::ProjectiveBake => "each model from the light",
            AtlasDraw::Dilate => "full screen per model",
            AtlasDraw::Page => "a quad per re-baked tile",
            AtlasDraw::Mips => "one blit chain (the projective texture: one per model)",
            AtlasDraw::Scene => "objects",
        }
    }
}

/// The seed 004 descriptor sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AtlasSet {
    /// Every light's view-projection, bias and map layer, with the map array for the compare.
    Light,
    /// A model's shadow texture, sampled trilinearly by the scene pass.
    ShadowTexture,
    /// A model's raw bake (the atlas: the raw page), read texel by texel by the dilation.
    RawBake,
    /// The atlas page's tiles and the geometry images' texel surfaces.
    PageTiles,
}

impl Label for AtlasSet {
    fn label(self) -> &'static str {
        match self {
            AtlasSet::Light => "shadow light",
            AtlasSet::ShadowTexture => "shadow texture",
            AtlasSet::RawBake => "raw bake",
            AtlasSet::PageTiles => "page tiles",
        }
    }
}

/// The seed 004 render passes, before the frame's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AtlasTarget {
    /// A layer of the lights' depth array, stored for sampling.
    ShadowMap,
    /// Each model's raw bake, in atlas space.
    AtlasSpace,
    /// Each model's raw projective bake, in the light's view.
    LightSpace,
    /// Mip 0 of each model's shadow texture, dilated from the raw bake.
    TextureMip0,
    /// Mip 0 of the atlas page, loaded (the tiles not re-baked keep their texels).
    PageMip0,
}

impl Label for AtlasTarget {
    fn label(self) -> &'static str {
        match self {
            AtlasTarget::ShadowMap => "shadow map (depth only)",
            AtlasTarget::AtlasSpace => "shadow texture (atlas space)",
            AtlasTarget::LightSpace => "shadow texture (light space)",
            AtlasTarget::TextureMip0 => "shadow texture mip 0",
            AtlasTarget::PageMip0 => "atlas page mip 0 (loaded)",
        }
    }
}

/// The cached passes' condition: the frames in which the light or a caster moved (else the
/// shadow maps and bake of the frame before still hold).
pub const LIGHT_OR_CASTERS_MOVED: Condition = Condition::named("when the light or a caster moved");
/// The frames that re-bake a rasterised model's shadow texture (the atlas page's raster bake;
/// geometry images are baked by their texels).
pub const RASTERISED_TILES_STALE: Condition = Condition::named("when a rasterised model's shadow texture is re-baked");

const LIGHT: SetRole<AtlasSet> = SetRole::Own(AtlasSet::Light);
const SHADOW_TEXTURE: SetRole<AtlasSet> = SetRole::Own(AtlasSet::ShadowTexture);
const RAW_BAKE: SetRole<AtlasSet> = SetRole::Own(AtlasSet::RawBake);
const PAGE_TILES: SetRole<AtlasSet> = SetRole::Own(AtlasSet::PageTiles);

pub fn shadow_map_desc() -> PipelineDesc {
    PipelineDesc {
        name: "shadow map",
        vertex_shader: shaders::SHADOW_MAP_VERT,
        fragment_shader: shaders::SHADOW_MAP_FRAG,
        vertex_layout: ATLAS_VERTEX,
        fixed: FixedFunction { raster: RasterState::CULL_NONE, blend: NO_WRITE, ..FixedFunction::OPAQUE },
        // The object's push and which light (`shaders/light_push.glsl`).
        push_constant_bytes: LIGHT_PUSH_BYTES,
    }
}

/// The shadow map's pipeline for MASK casters: texels below the cutoff cast nothing.
pub fn shadow_map_masked_desc() -> PipelineDesc {
    PipelineDesc {
        name: "shadow map (alpha mask)",
        vertex_shader: shaders::SHADOW_MAP_MASKED_VERT,
        fragment_shader: shaders::SHADOW_MAP_MASKED_FRAG,
        ..shadow_map_desc()
    }
}

pub fn bake_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas bake",
        vertex_shader: shaders::SHADOW_ATLAS_BAKE_VERT,
        fragment_shader: shaders::SHADOW_ATLAS_BAKE_FRAG,
        vertex_layout: ATLAS_VERTEX,
        // Atlas space has no facing and no depth: every triangle writes its texels.
        fixed: FixedFunction { raster: RasterState::CULL_NONE, depth: DepthState::OFF, ..FixedFunction::OPAQUE },
        push_constant_bytes: OBJECT_PUSH_BYTES,
    }
}

/// The projective bake: the model from the light, writing only its shadowed texels (no depth:
/// every surface on a texel's light ray writes, which is the method's flaw).
pub fn projective_bake_desc() -> PipelineDesc {
    PipelineDesc {
        name: "projective bake",
        vertex_shader: shaders::PROJECTIVE_BAKE_VERT,
        fragment_shader: shaders::PROJECTIVE_BAKE_FRAG,
        ..bake_desc()
    }
}

pub fn dilate_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas dilate",
        vertex_shader: shaders::FULLSCREEN_VERT,
        fragment_shader: shaders::SHADOW_ATLAS_DILATE_FRAG,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction::FULLSCREEN,
        push_constant_bytes: 16,
    }
}

/// The atlas page pass over geometry images' tiles: a quad per tile from gl_VertexIndex and
/// gl_InstanceIndex (no vertex buffer), each texel baked from its surface point; the page's
/// size in the push.
pub fn page_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas page",
        vertex_shader: shaders::SHADOW_ATLAS_PAGE_VERT,
        fragment_shader: shaders::SHADOW_ATLAS_PAGE_FRAG,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction::FULLSCREEN,
        push_constant_bytes: 16,
    }
}

/// The atlas page pass over rasterised tiles: the same quads, each texel dilated from the
/// raw page.
pub fn page_dilate_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas page (dilate)",
        vertex_shader: shaders::SHADOW_ATLAS_PAGE_DILATE_VERT,
        fragment_shader: shaders::SHADOW_ATLAS_PAGE_DILATE_FRAG,
        ..page_desc()
    }
}

pub fn scene_desc(kind: ShadowKind) -> PipelineDesc {
    PipelineDesc {
        name: "scene",
        vertex_shader: shaders::SHADOW_ATLAS_SCENE_VERT,
        fragment_shader: match kind {
            ShadowKind::Atlas => shaders::SHADOW_ATLAS_SCENE_FRAG,
            ShadowKind::Map => shaders::SHADOW_MAP_SCENE_FRAG,
            ShadowKind::Projective => shaders::PROJECTIVE_SCENE_FRAG,
        },
        vertex_layout: ATLAS_VERTEX,
        fixed: FixedFunction::OPAQUE,
        push_constant_bytes: OBJECT_PUSH_BYTES,
    }
}

/// The frame of `kind` with `lights` (a light "shadows" when it has a map layer: see
/// `maps::planned_lights`), pass by pass (no stencil anywhere: there is no reference path).
pub fn plan(kind: ShadowKind, lights: &[PlannedLight]) -> PassPlan<AtlasKinds> {
    let moved = When::If(LIGHT_OR_CASTERS_MOVED);
    let mut plan = PassPlan::new();
    for (index, light) in lights.iter().enumerate().filter(|(_, l)| l.shadows) {
        plan.push(
            PlannedPass::offscreen(
                light_loop::pass_name(light, "shadow map"),
                shadow_map_desc(),
                AtlasDraw::ShadowMap,
                "object transform, light index",
                AtlasTarget::ShadowMap,
            )
            .or_variant(MaterialVariant::Masked, shadow_map_desc().name, shadow_map_masked_desc())
            // The frame's set first: its joint palettes skin the casters on the GPU.
            .with_sets(&[SetRole::Frame, SetRole::Material, LIGHT])
            .for_light(index as u8)
            .when(moved),
        );
    }
    if !lights.iter().any(|l| l.shadows) {
        // The scene pass binds the map array all the same: its one layer is cleared, so that
        // it is in a layout to sample (every light's weight ignores it).
        plan.push(
            PlannedPass::commands("shadow map (no light has one)", AtlasDraw::ClearMap, AtlasTarget::ShadowMap)
                .when(moved),
        );
    }
    let scene_sets = match kind {
        ShadowKind::Map => vec![SetRole::Frame, SetRole::Material, LIGHT],
        ShadowKind::Atlas => {
            // Every model's texture is a tile of one page: one raster bake (models that are not
            // geometry images), one page pass (geometry images baked by their texels, the
            // others dilated), one mip chain, however many models.
            plan.push(
                PlannedPass::offscreen(
                    "atlas bake",
                    bake_desc(),
                    AtlasDraw::Bake,
                    "object transform",
                    AtlasTarget::AtlasSpace,
                )
                // The frame's set first: its joint palettes skin the models on the GPU.
                .with_sets(&[SetRole::Frame, LIGHT])
                .when(When::If(RASTERISED_TILES_STALE)),
            );
            plan.push(
                PlannedPass::offscreen("atlas page", page_desc(), AtlasDraw::Page, "page size", AtlasTarget::PageMip0)
                    .or_pipeline(page_dilate_desc())
                    .with_sets(&[LIGHT, PAGE_TILES, RAW_BAKE])
                    .when(moved),
            );
            plan.push(PlannedPass::commands("atlas mips", AtlasDraw::Mips, AtlasTarget::PageMip0).when(moved));
            vec![SetRole::Frame, SetRole::Material, SHADOW_TEXTURE, LIGHT]
        }
        ShadowKind::Projective => {
            plan.push(
                PlannedPass::offscreen(
                    "projective bake",
                    projective_bake_desc(),
                    AtlasDraw::ProjectiveBake,
                    "object transform",
                    AtlasTarget::LightSpace,
                )
                // The frame's set first: its joint palettes skin the models on the GPU.
                .with_sets(&[SetRole::Frame, LIGHT])
                .when(moved),
            );
            // Radius 0, a copy (uncovered texels are lit, not a gutter).
            plan.push(
                PlannedPass::offscreen(
                    "atlas dilate",
                    dilate_desc(),
                    AtlasDraw::Dilate,
                    "dilation radius",
                    AtlasTarget::TextureMip0,
                )
                .with_sets(&[RAW_BAKE])
                .when(moved),
            );
            plan.push(PlannedPass::commands("atlas mips", AtlasDraw::Mips, AtlasTarget::TextureMip0).when(moved));
            // Set 3: which light each baked channel holds (atlas), the projection from the
            // primary light (projective).
            vec![SetRole::Frame, SetRole::Material, SHADOW_TEXTURE, LIGHT]
        }
    };
    let scene = scene_desc(kind);
    let pass = PlannedPass::own("scene", scene.clone(), AtlasDraw::Scene, "object transform and colour");
    plan.push(with_surface_variants(pass, &scene).with_sets(&scene_sets));
    plan
}
