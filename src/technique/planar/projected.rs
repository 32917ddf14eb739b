//! Planar projected shadows (seed 001, docs/design/planar-shadows.md): every caster drawn a second time,
//! flattened onto the ground plane along the light in the vertex shader (after GPU skinning for
//! skinned characters), with double darkening stopped in one pass and no stencil.
//!
//! Emulated frame, one render pass:
//! 1. scene: lit objects; receivers (the ground) write alpha `F/255 = 1 - s`, everything else
//!    (and the clear) alpha 1;
//! 2. planar shadow: casters projected onto y = h, colour 0, colour blend `ADD, ZERO, DST_ALPHA`
//!    and alpha blend `ADD, ONE, ZERO` with fragment alpha 1. The first fragment on a receiver
//!    pixel multiplies it by `1 - s` and sets its alpha to 1, so every later one multiplies by 1;
//!    fragments on non-receivers multiply by 1: the shadow is clipped to the receivers. Depth
//!    LESS_OR_EQUAL with a small bias towards the camera keeps occluders in front of it.
//!
//! Reference frame (`--stencil reference`), as the seed does it: stencil cleared to 1, receivers
//! write 0 and everything else 1 (REPLACE); the shadow draws with stencil Ref 0, Comp Equal,
//! Pass IncrWrap, ZFail Keep, blending `ADD, ZERO, SRC_ALPHA` with fragment alpha `F/255`. Both
//! multiply each shadowed pixel once by the same 8-bit factor, so their RGB are identical.

use ash::vk;
use glam::{Mat4, Vec4};

use super::lod::CasterLods;
use super::receiver::{light_reaches_plane, receiver_plane, ReceiverPlane};
use super::scene_meshes::{scene_desc, scene_pass, scene_sets, SceneMeshes, WithPalette};
use super::shared::{Planar, PlanarStats, DEFAULT_SHADOW_LOD, SHADOW_BIAS};
use super::skin::SKINNED_LAYOUT;
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::pipeline::recipes::{
    stencil_replace, MODULATE_BY_DST_ALPHA_ONCE, MODULATE_BY_SRC_ALPHA_WRITING_ALPHA, STENCIL_EQUAL_ZERO_THEN_INCREMENT,
};
use crate::pipeline::{DepthState, FixedFunction, PipelineDesc, RasterState, VertexLayout};
use crate::render::plan::{DrawKind, Label, MaterialVariant, NoOwn, PassDraws, PassKinds, PassPlan, PlannedPass, When};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, GpuScene, Renderer};
use crate::scene::Scene;
use crate::technique::frame_renderer::{BuildContext, Passes};
use crate::technique::interface::RenderOptions;
use crate::technique::interface::{stencil_variants, FrameStats, Variant};
use crate::technique::options::PlanarOptions;
use crate::technique::unit::{Prepared, ShadowedLights, TechniqueUnit};
use crate::technique::shadow_tone::ShadowTone;

/// Mirrors `PlanarPush` in `shaders/planar_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlanarPush {
    pub model: Mat4,
    pub colour: Vec4,
    /// The receiving plane (n, d): n.x + d = 0.
    pub plane: Vec4,
}

pub const PLANAR_PUSH_BYTES: u32 = std::mem::size_of::<PlanarPush>() as u32;

/// Stencil values of the reference path: receivers not yet shadowed hold 0.
const STENCIL_RECEIVER: u32 = 0;
const STENCIL_OTHER: u32 = 1;

/// The kinds of the planar plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PlanarKinds;

impl PassKinds for PlanarKinds {
    type Draw = PlanarDraw;
    type Set = PlanarSet;
    type Target = NoOwn;
}

/// What the planar renderer draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlanarDraw {
    /// Every object, receivers writing the shadow factor into alpha (or marking the stencil).
    Scene,
    /// The casters flattened onto the plane, or (`lod`) their simplified meshes.
    ProjectedCasters { lod: bool },
}

impl DrawKind for PlanarDraw {
    fn describe(self) -> &'static str {
        match self {
            PlanarDraw::Scene => "objects",
            PlanarDraw::ProjectedCasters { lod: false } => "casters flattened onto the plane",
            PlanarDraw::ProjectedCasters { lod: true } => "simplified casters (meshoptimizer) flattened onto the plane",
        }
    }
}

/// The planar plan's descriptor sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PlanarSet {
    JointPalette,
}

impl Label for PlanarSet {
    fn label(self) -> &'static str {
        match self {
            PlanarSet::JointPalette => "joint palette",
        }
    }
}

impl WithPalette for PlanarSet {
    const JOINT_PALETTE: Self = PlanarSet::JointPalette;
}

// ---------------------------------------------------------------------------------------------
// Pipelines (docs/design/planar-shadows.md) and the frame's plan.

fn shadow_desc(name: &'static str, skinned: bool, reference: bool) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: if skinned { "planar_shadow_skinned.vert" } else { "planar_shadow.vert" },
        fragment_shader: "object_colour.frag",
        vertex_layout: if skinned { SKINNED_LAYOUT } else { VertexLayout::SCENE },
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            // Flattened, front and back faces both land on the plane: both are drawn, which is
            // exactly the overlap the blend (or the stencil) must not count twice.
            raster: RasterState { depth_bias: Some(SHADOW_BIAS), ..RasterState::CULL_NONE },
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            // The reference: the stencil lets one fragment per receiver pixel through, which
            // multiplies by its alpha F/255. Emulated: the first fragment multiplies by the
            // receiver's alpha F/255 and sets it to 1.
            stencil: reference.then_some(STENCIL_EQUAL_ZERO_THEN_INCREMENT),
            blend: if reference { MODULATE_BY_SRC_ALPHA_WRITING_ALPHA } else { MODULATE_BY_DST_ALPHA_ONCE },
        },
        push_constant_bytes: PLANAR_PUSH_BYTES,
        subpass: 0,
    }
}

/// The scene pass of one path: receivers, other static objects and skinned objects (the
/// emulated path draws the first two alike), each writing alpha F/255 on receivers, else 1.
pub fn scene_pass_of(stencil: StencilMode) -> PlannedPass<PlanarKinds> {
    let push = "object transform and colour, alpha F/255 on receivers, 1 elsewhere";
    match stencil {
        StencilMode::Emulated => {
            let scene = scene_desc("scene", false, None);
            scene_pass(scene.clone(), scene, scene_desc("scene (skinned)", true, None), push, PlanarDraw::Scene)
        }
        StencilMode::Reference => scene_pass(
            scene_desc("scene (receivers, stencil 0)", false, Some(stencil_replace(STENCIL_RECEIVER))),
            scene_desc("scene (stencil 1)", false, Some(stencil_replace(STENCIL_OTHER))),
            scene_desc("scene (skinned, stencil 1)", true, Some(stencil_replace(STENCIL_OTHER))),
            push,
            PlanarDraw::Scene,
        ),
    }
}

/// The shadow pass of one path, run where the light reaches the plane: [static, skinned];
/// `lod`: from the casters' simplified meshes.
pub fn shadow_pass_of(stencil: StencilMode, lod: bool) -> PlannedPass<PlanarKinds> {
    let (name, skinned, reference, push) = match stencil {
        StencilMode::Emulated => {
            ("planar shadow", "planar shadow (skinned)", false, "caster transform, black with alpha 1, plane (n, d)")
        }
        StencilMode::Reference => (
            "planar shadow (stencil)",
            "planar shadow (skinned, stencil)",
            true,
            "caster transform, black with alpha F/255, plane (n, d)",
        ),
    };
    let (masked, skinned_masked) = match stencil {
        StencilMode::Emulated => ("planar shadow (alpha mask)", "planar shadow (skinned, alpha mask)"),
        StencilMode::Reference => {
            ("planar shadow (stencil, alpha mask)", "planar shadow (skinned, stencil, alpha mask)")
        }
    };
    let cut_out = |name: &'static str, vertex_shader: &'static str, skinned: bool| PipelineDesc {
        name,
        vertex_shader,
        fragment_shader: "object_colour_masked.frag",
        ..shadow_desc(name, skinned, reference)
    };
    PlannedPass::own(name, shadow_desc(name, false, reference), PlanarDraw::ProjectedCasters { lod }, push)
        .or_pipeline(shadow_desc(skinned, true, reference))
        .or_variant(MaterialVariant::Masked, name, cut_out(masked, "planar_shadow_masked.vert", false))
        .or_variant(
            MaterialVariant::Masked,
            skinned,
            cut_out(skinned_masked, "planar_shadow_skinned_masked.vert", true),
        )
        .with_sets(&scene_sets())
        .when(When::LightAbovePlane)
}

/// The frame's passes: the scene, then (unless `options.shadows` is off) the shadow.
pub fn plan(options: &PlanarOptions, stencil: StencilMode) -> PassPlan<PlanarKinds> {
    let mut plan = PassPlan::new();
    plan.push(scene_pass_of(stencil));
    if options.shadows {
        plan.push(shadow_pass_of(stencil, options.shadow_lod.is_some()));
    }
    plan
}

// ---------------------------------------------------------------------------------------------
// The technique.

impl TechniqueUnit for Planar {
    type Kinds = PlanarKinds;
    type Setup = ();
    type Passes = PlanarPasses;

    fn name(&self) -> &'static str {
        "planar"
    }

    fn shadowed_lights(&self, _options: &RenderOptions) -> ShadowedLights {
        ShadowedLights::Primary
    }

    fn about(&self) -> &'static str {
        "casters skinned on the GPU and projected onto the ground, double darkening stopped in alpha (seed 001)"
    }

    fn plan(&self, options: &RenderOptions) -> Result<PassPlan<PlanarKinds>> {
        Ok(plan(&options.planar, options.stencil))
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_, PlanarKinds>, scene: &Scene, _setup: ()) -> Result<PlanarPasses> {
        PlanarPasses::new(&ctx, scene)
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        super::shared::bench_variants(options)
    }

    /// Each path, with and without the shadow pass, and each with the shadow cast from
    /// simplified meshes.
    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        let mut variants = stencil_variants(TechniqueUnit::name(self), options);
        let lod = PlanarOptions {
            shadow_lod: Some(options.planar.shadow_lod.unwrap_or(DEFAULT_SHADOW_LOD)),
            ..options.planar
        };
        for stencil in [StencilMode::Reference, StencilMode::Emulated] {
            variants.push(Variant {
                label: format!("{} ({}, shadow LOD)", TechniqueUnit::name(self), stencil.name()),
                options: RenderOptions { stencil, planar: lod, ..options.clone() },
            });
        }
        let scene_only = PlanarOptions { shadows: false, ..options.planar };
        for stencil in [StencilMode::Reference, StencilMode::Emulated] {
            variants.push(Variant {
                label: format!("{} ({}, no shadows)", TechniqueUnit::name(self), stencil.name()),
                options: RenderOptions { stencil, planar: scene_only, ..options.clone() },
            });
        }
        variants
    }
}

/// The planar renderer's own part: the receiver plane and the scene's meshes (joint palettes
/// are uploaded each frame, as an animated character needs).
pub struct PlanarPasses {
    tone: ShadowTone,
    stencil: StencilMode,
    plane: ReceiverPlane,
    meshes: SceneMeshes,
    /// The casters' simplified meshes, with `--shadow-lod`.
    lods: Option<CasterLods>,
}

impl PlanarPasses {
    fn new(ctx: &BuildContext<PlanarKinds>, scene: &Scene) -> Result<Self> {
        let plane = receiver_plane(scene, ctx.options.planar.plane.as_ref())?;
        plane.plane.check_light(&scene.light())?;
        let meshes = SceneMeshes::upload(ctx.gpu, scene)?;
        let lods = match ctx.options.planar.shadow_lod {
            Some(ratio) => Some(CasterLods::build(ctx.gpu, scene, &plane.receivers, ratio)?),
            None => None,
        };
        Ok(PlanarPasses { tone: ctx.options.shadow_tone, stencil: ctx.options.stencil, plane, meshes, lods })
    }

    fn factor(&self) -> f32 {
        self.tone.darkest_factor()
    }

    /// Every caster flattened onto the plane: `[static, skinned]` pipelines.
    fn draw_shadow(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        pass: &PlannedPass<PlanarKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let &[shadow, skinned, ..] = pipelines else {
            return Err(Error::Internal(format!("the planar shadow pass has {} pipelines", pipelines.len())));
        };
        let alpha = match self.stencil {
            StencilMode::Reference => self.factor(),
            StencilMode::Emulated => 1.0,
        };
        let colour = Vec4::new(0.0, 0.0, 0.0, alpha);
        let plane = self.plane.plane.as_vec4();
        for (index, object) in scene.objects.iter().enumerate() {
            if self.plane.receivers[index] {
                continue;
            }
            let push = PlanarPush { model: object.transform, colour, plane };
            let casters = SceneMeshes::caster_pipelines(scene, index, pass, pipelines, [shadow, skinned]);
            self.meshes.draw_caster(rec, scene, index, casters, &push, self.lods.as_ref());
        }
        Ok(())
    }
}

impl PassDraws<PlanarKinds> for PlanarPasses {
    fn set(&self, set: PlanarSet) -> Option<vk::DescriptorSet> {
        match set {
            PlanarSet::JointPalette => Some(self.meshes.palette_set()),
        }
    }

    fn meshes(&self) -> Option<&GpuScene> {
        Some(&self.meshes.meshes)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: PlanarDraw,
        pass: &PlannedPass<PlanarKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        match draw {
            PlanarDraw::Scene => {
                if self.stencil == StencilMode::Reference {
                    // Everything starts as "not a receiver"; the receivers' draws write 0.
                    rec.clear_stencil(STENCIL_OTHER);
                }
                self.meshes.draw_scene(rec, scene, &self.plane, pass, pipelines, self.factor())
            }
            PlanarDraw::ProjectedCasters { .. } => self.draw_shadow(rec, scene, pass, pipelines),
        }
    }
}

impl Passes<PlanarKinds> for PlanarPasses {
    fn set_layout(&self, set: PlanarSet) -> Option<vk::DescriptorSetLayout> {
        match set {
            PlanarSet::JointPalette => Some(self.meshes.palette_layout()),
        }
    }

    fn prepare(&mut self, _renderer: &Renderer, scene: &Scene) -> Result<()> {
        self.plane.plane.check_light(&scene.light())?;
        self.meshes.update_palettes(scene)
    }

    fn conditions(&self, scene: &Scene) -> Vec<When> {
        if light_reaches_plane(&scene.light(), &self.plane.plane) {
            vec![When::LightAbovePlane]
        } else {
            Vec::new()
        }
    }

    fn stats(&mut self, _output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        Box::new(PlanarStats::of(&self.plane, &self.meshes, self.tone).with_lods(self.lods.as_ref()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_constants_fit_the_profile() {
        assert_eq!(PLANAR_PUSH_BYTES, 96);
        for stencil in [StencilMode::Emulated, StencilMode::Reference] {
            let plan = plan(&PlanarOptions::default(), stencil);
            assert!(plan.passes.iter().flat_map(|p| &p.pipelines).all(|d| d.push_constant_bytes <= 128));
        }
    }
}
