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
//! With several lights (`--shadow-mode additive`, the default), Doom 3's and Ogre's loop on the
//! same flag: the scene with ambient light only; then per light, its casters flattened along it
//! writing alpha 0 (colour masked: a flag, so overlaps cannot count twice), and its shading,
//! which adds the light on receivers through `DST_ALPHA` and resets alpha to 1 with the same
//! blend; casters and skinned objects add it unmasked. The reference clears its stencil per
//! light, marks the flattened casters `EQUAL 0, INCR_WRAP` and shades receivers where it is 0.
//!
//! Reference frame (`--stencil reference`), as the seed does it: stencil cleared to 1, receivers
//! write 0 and everything else 1 (REPLACE); the shadow draws with stencil Ref 0, Comp Equal,
//! Pass IncrWrap, ZFail Keep, blending `ADD, ZERO, SRC_ALPHA` with fragment alpha `F/255`. Both
//! multiply each shadowed pixel once by the same 8-bit factor, so their RGB are identical.

use glam::Vec4;

use super::flattened::{flattened_desc, PlanarDraw, PlanarKinds, PlanarPush};
use super::lod::CasterLods;
use super::receiver::{
    light_reaches_plane, receiver_plane, Plane, ReceiverPlane, LIGHT_ABOVE_PLANE, LIGHT_REACHES_PLANE,
};
use super::scene_meshes::{scene_desc, scene_pass, scene_sets, SceneMeshes};
use super::shared::{Planar, PlanarStats, DEFAULT_SHADOW_LOD};
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::pipeline::recipes::{
    stencil_replace, MODULATE_BY_DST_ALPHA_ONCE, MODULATE_BY_SRC_ALPHA_WRITING_ALPHA, STENCIL_EQUAL_ZERO_THEN_INCREMENT,
};
use crate::pipeline::PipelineDesc;
use crate::render::passes::Passes;
use crate::render::plan::{MaterialVariant, PassPlan, PlannedPass, When};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, GpuScene, Renderer};
use crate::scene::{Scene, SceneLight};
use crate::shaders;
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::{stencil_variants, FrameStats, Variant};
use crate::technique::interface::{RenderOptions, TechniqueInfo};
use crate::technique::light_loop::{PlannedLight, ShadowedLights};
use crate::technique::options::{PlanarOptions, ShadowMode};
use crate::technique::shadow_tone::ShadowTone;
use crate::technique::unit::{Prepared, TechniqueUnit};

/// Stencil values of the reference path: receivers not yet shadowed hold 0.
const STENCIL_RECEIVER: u32 = 0;
const STENCIL_OTHER: u32 = 1;

// ---------------------------------------------------------------------------------------------
// Pipelines (docs/design/planar-shadows.md) and the frame's plan.

fn shadow_desc(name: &'static str, skinned: bool, reference: bool) -> PipelineDesc {
    // The reference: the stencil lets one fragment per receiver pixel through, which
    // multiplies by its alpha F/255. Emulated: the first fragment multiplies by the
    // receiver's alpha F/255 and sets it to 1.
    let stencil = reference.then_some(STENCIL_EQUAL_ZERO_THEN_INCREMENT);
    let blend = if reference { MODULATE_BY_SRC_ALPHA_WRITING_ALPHA } else { MODULATE_BY_DST_ALPHA_ONCE };
    flattened_desc(name, skinned, blend, stencil)
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
    shadow_pass_along(stencil, lod, None)
}

/// [`shadow_pass_of`] along `light` (none: the primary light).
fn shadow_pass_along(stencil: StencilMode, lod: bool, light: Option<u8>) -> PlannedPass<PlanarKinds> {
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
    let cut_out = |name: &'static str, vertex_shader: shaders::Shader, skinned: bool| PipelineDesc {
        name,
        vertex_shader,
        fragment_shader: shaders::OBJECT_COLOUR_MASKED_FRAG,
        ..shadow_desc(name, skinned, reference)
    };
    PlannedPass::own(name, shadow_desc(name, false, reference), PlanarDraw::ProjectedCasters { lod, light }, push)
        .or_pipeline(shadow_desc(skinned, true, reference))
        .or_variant(MaterialVariant::Masked, name, cut_out(masked, shaders::PLANAR_SHADOW_MASKED_VERT, false))
        .or_variant(
            MaterialVariant::Masked,
            skinned,
            cut_out(skinned_masked, shaders::PLANAR_SHADOW_MASKED_SKINNED_VERT, true),
        )
        .with_sets(&scene_sets())
        .when(When::If(LIGHT_ABOVE_PLANE))
}

/// The frame's passes: the seed's (the scene, then unless `options.shadows` is off the
/// shadow), or with shadows in `additive` mode the per-light loop.
pub fn plan(
    options: &PlanarOptions,
    stencil: StencilMode,
    mode: ShadowMode,
    lights: &[PlannedLight],
) -> PassPlan<PlanarKinds> {
    if options.shadows && mode == ShadowMode::Additive {
        return super::per_light::plan(options, stencil, lights);
    }
    let mut plan = PassPlan::new();
    plan.push(scene_pass_of(stencil));
    if options.shadows {
        plan.push(shadow_pass_of(stencil, options.shadow_lod.is_some()));
    }
    plan
}

// ---------------------------------------------------------------------------------------------
// The technique.

impl TechniqueInfo for Planar {
    fn name(&self) -> &'static str {
        "planar"
    }

    fn shadowed_lights(&self, options: &RenderOptions, _lights: &[PlannedLight]) -> ShadowedLights {
        options.shadow_mode.shadowed_lights()
    }

    fn about(&self) -> &'static str {
        "casters skinned on the GPU and projected onto the ground, double darkening stopped in alpha (seed 001)"
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        super::shared::bench_variants(options)
    }

    /// Each path: in the additive loop and as the seed draws it (modulate), with and without
    /// the shadow pass, and each with the shadow cast from simplified meshes.
    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        let mut variants = stencil_variants(self.name(), options);
        for stencil in [StencilMode::Reference, StencilMode::Emulated] {
            variants.push(Variant {
                label: format!("{} ({}, modulate)", self.name(), stencil.name()),
                options: RenderOptions { stencil, shadow_mode: ShadowMode::Modulate, ..options.clone() },
            });
        }
        let lod = PlanarOptions {
            shadow_lod: Some(options.planar.shadow_lod.unwrap_or(DEFAULT_SHADOW_LOD)),
            ..options.planar
        };
        for stencil in [StencilMode::Reference, StencilMode::Emulated] {
            variants.push(Variant {
                label: format!("{} ({}, shadow LOD)", self.name(), stencil.name()),
                options: RenderOptions { stencil, planar: lod, ..options.clone() },
            });
        }
        let scene_only = PlanarOptions { shadows: false, ..options.planar };
        for stencil in [StencilMode::Reference, StencilMode::Emulated] {
            variants.push(Variant {
                label: format!("{} ({}, no shadows)", self.name(), stencil.name()),
                options: RenderOptions { stencil, planar: scene_only, ..options.clone() },
            });
        }
        variants
    }
}

impl TechniqueUnit for Planar {
    type Kinds = PlanarKinds;
    type Setup = ();
    type Passes = PlanarPasses;

    fn plan(&self, options: &RenderOptions, lights: &[PlannedLight]) -> Result<PassPlan<PlanarKinds>> {
        Ok(plan(&options.planar, options.stencil, options.shadow_mode, lights))
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, _setup: ()) -> Result<PlanarPasses> {
        PlanarPasses::new(&ctx, scene)
    }
}

/// The planar renderer's own part: the receiver plane and the scene's meshes (joint palettes
/// are uploaded each frame, as an animated character needs).
pub struct PlanarPasses {
    tone: ShadowTone,
    stencil: StencilMode,
    mode: ShadowMode,
    /// The lights that cast no shadow on the plane (below it, or level with it).
    warnings: Vec<String>,
    plane: ReceiverPlane,
    meshes: SceneMeshes,
    /// The casters' simplified meshes, with `--shadow-lod`.
    lods: Option<CasterLods>,
}

impl PlanarPasses {
    fn new(ctx: &BuildContext, scene: &Scene) -> Result<Self> {
        let plane = receiver_plane(scene, ctx.options.planar.plane.as_ref())?;
        let mode = ctx.options.shadow_mode;
        let mut warnings = Vec::new();
        match mode {
            ShadowMode::Modulate => plane.plane.check_light(&scene.light())?,
            ShadowMode::Additive => warnings.extend(
                scene.lights.iter().filter(|l| l.casts_shadow).filter_map(|l| unreached_warning(l, &plane.plane)),
            ),
        }
        let meshes = SceneMeshes::upload(ctx.gpu, scene, ctx.options.skinning)?;
        let lods = match ctx.options.planar.shadow_lod {
            Some(ratio) => Some(CasterLods::build(ctx.gpu, scene, &plane.receivers, ratio)?),
            None => None,
        };
        let tone = ctx.options.shadow_tone;
        Ok(PlanarPasses { tone, stencil: ctx.options.stencil, mode, warnings, plane, meshes, lods })
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
        light: Option<u8>,
    ) -> Result<()> {
        let &[shadow, skinned, ..] = pipelines else {
            return Err(Error::Internal(format!("the planar shadow pass has {} pipelines", pipelines.len())));
        };
        let alpha = match (self.stencil, light) {
            (StencilMode::Reference, None) => self.factor(),
            (StencilMode::Emulated, None) => 1.0,
            // The additive loop's flag: alpha 0 (emulated); the reference writes no colour.
            (_, Some(_)) => 0.0,
        };
        let colour = Vec4::new(0.0, 0.0, 0.0, alpha);
        let plane = self.plane.plane.as_vec4();
        let light = light.map_or(scene.primary_light_index().unwrap_or(0) as u32, u32::from);
        for (index, object) in scene.objects.iter().enumerate() {
            if self.plane.receivers[index] {
                continue;
            }
            let push = PlanarPush { model: object.transform, colour, plane, light: [light, 0, 0, 0] };
            let casters = SceneMeshes::caster_pipelines(scene, index, pass, pipelines, [shadow, skinned]);
            self.meshes.draw_caster(rec, scene, index, casters, &push, self.lods.as_ref());
        }
        Ok(())
    }
}

impl Passes<PlanarKinds> for PlanarPasses {
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
            PlanarDraw::ProjectedCasters { light, .. } => self.draw_shadow(rec, scene, pass, pipelines, light),
            PlanarDraw::Ambient => {
                if self.stencil == StencilMode::Reference {
                    // Ogre's loop starts each light on a cleared stencil.
                    rec.clear_stencil(0);
                }
                self.meshes.draw_scene(rec, scene, &self.plane, pass, pipelines, 1.0)
            }
            PlanarDraw::Shading { light, shadowed } => {
                self.meshes.draw_scene_for(rec, scene, &self.plane, pass, pipelines, 1.0, Some(light))?;
                if shadowed && self.stencil == StencilMode::Reference {
                    // The next light starts on a cleared stencil, whether its flag is drawn or
                    // (its light below the plane) not.
                    rec.clear_stencil(0);
                }
                Ok(())
            }
            PlanarDraw::Transparent => self.meshes.draw_scene(rec, scene, &self.plane, pass, pipelines, 1.0),
        }
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        if self.mode == ShadowMode::Modulate {
            self.plane.plane.check_light(&scene.light())?;
        }
        self.meshes.follow_pose(&renderer.gpu, scene, renderer.slot())
    }

    /// The joint palettes are its only per-frame data, a copy per slot.
    fn writes_per_slot(&self) -> bool {
        true
    }

    /// Its plans name the skinned pipelines of their own (`scene_desc`, `flattened_desc`).
    fn skinned_twins(&self) -> bool {
        false
    }

    fn conditions(&self, scene: &Scene) -> Vec<When> {
        let plane = &self.plane.plane;
        let mut conditions = Vec::new();
        if light_reaches_plane(&scene.light(), plane) {
            conditions.push(When::If(LIGHT_ABOVE_PLANE));
        }
        if self.mode == ShadowMode::Additive {
            let reaching = scene.lights.iter().enumerate().filter(|(_, l)| l.casts_shadow);
            conditions.extend(
                reaching
                    .filter(|(_, l)| light_reaches_plane(&l.geometry(), plane))
                    .map(|(i, _)| When::If(LIGHT_REACHES_PLANE.for_light(i as u8))),
            );
        }
        conditions
    }

    fn warnings(&self) -> &[String] {
        &self.warnings
    }

    fn stats(&mut self, _output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        Box::new(PlanarStats::of(&self.plane, &self.meshes, self.tone).with_lods(self.lods.as_ref()))
    }
}

/// The warning for a shadowing `light` that casts no planar shadow on `plane`.
fn unreached_warning(light: &SceneLight, plane: &Plane) -> Option<String> {
    let geometry = light.geometry();
    if light_reaches_plane(&geometry, plane) {
        return None;
    }
    let why = match plane.check_light(&geometry) {
        Err(e) => e.to_string(),
        Ok(()) => "it lies below the receiving plane".to_string(),
    };
    Some(format!("planar: '{}' casts no shadow ({why}); it still shades", light.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_constants_fit_the_profile() {
        let lights = crate::technique::light_loop::PlannedLight::default_lights();
        for stencil in [StencilMode::Emulated, StencilMode::Reference] {
            for mode in ShadowMode::ALL {
                let plan = plan(&PlanarOptions::default(), stencil, *mode, &lights);
                assert!(plan.passes.iter().flat_map(|p| &p.pipelines).all(|d| d.push_constant_bytes <= 128));
            }
        }
    }
}
