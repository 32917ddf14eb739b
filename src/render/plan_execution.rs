//! Executing a [`PassPlan`]: its pipelines built once ([`PlanPipelines`]) and the recording
//! of its passes in order ([`record_plan`]) from what the technique supplies ([`Passes`]),
//! with the object passes the recorder draws itself ([`draw_objects`]).

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use super::gpu_mesh::GpuScene;
use super::materials::{MaterialVariant, MATERIAL_SET};
use super::object_push::{draw_order, object_push, LightPush};
use super::passes::Passes;
use super::pipeline_object::PipelineTarget;
use super::plan::{DrawKind, Draws, Label, PassKinds, PassPlan, PlannedPass, Scissor, SetRole, Target, When};
use super::recorder::FrameRecorder;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::pipeline_object::Pipeline;
use crate::scene::Scene;

/// The pipelines of a plan, built once: one per distinct (pipeline name, target), shared by the
/// passes that bind it (every normalisation iteration binds the same pipeline).
pub struct PlanPipelines {
    built: Vec<Pipeline>,
    /// Per pass, per pipeline of the pass: an index into `built`.
    by_pass: Vec<Vec<usize>>,
}

impl PlanPipelines {
    /// Builds every pipeline of `plan`; `render_pass(target)` names the render pass a target's
    /// pipelines are built for, with its colour attachment and sample counts, and
    /// `layout(role)` the set layout of each role. `skinned_twins`: every pipeline whose vertex
    /// shader has a skinned twin is built with it (`Pipeline::with_skinned_twin`).
    pub fn build<K: PassKinds>(
        gpu: &Arc<Gpu>,
        plan: &PassPlan<K>,
        skinned_twins: bool,
        render_pass: impl Fn(Target<K::Target>) -> Result<PipelineTarget>,
        layout: impl Fn(SetRole<K::Set>) -> Result<vk::DescriptorSetLayout>,
    ) -> Result<Self> {
        let mut built: Vec<Pipeline> = Vec::new();
        let mut index_of: HashMap<(&'static str, Target<K::Target>), usize> = HashMap::new();
        let mut by_pass = Vec::with_capacity(plan.passes.len());
        for pass in &plan.passes {
            if pass.sets.iter().position(|r| *r == SetRole::Material).is_some_and(|i| i as u32 != MATERIAL_SET) {
                return Err(Error::Internal(format!("pass '{}': the material must be set {MATERIAL_SET}", pass.name)));
            }
            let layouts = pass.sets.iter().map(|role| layout(*role)).collect::<Result<Vec<_>>>()?;
            let mut indices = Vec::with_capacity(pass.pipelines.len());
            for desc in &pass.pipelines {
                let key = (desc.name, pass.target);
                let index = match index_of.get(&key) {
                    Some(&index) => {
                        if built[index].desc != *desc {
                            return Err(Error::Internal(format!(
                                "two different pipelines are both called '{}' in one plan",
                                desc.name
                            )));
                        }
                        index
                    }
                    None => {
                        let mut pipeline = Pipeline::for_target(gpu, desc, render_pass(pass.target)?, &layouts)?;
                        if skinned_twins {
                            pipeline = pipeline.with_skinned_twin()?;
                        }
                        built.push(pipeline);
                        index_of.insert(key, built.len() - 1);
                        built.len() - 1
                    }
                };
                indices.push(index);
            }
            by_pass.push(indices);
        }
        Ok(PlanPipelines { built, by_pass })
    }

    /// The pipelines of pass `index`, in the plan's order.
    pub fn of_pass(&self, index: usize) -> Vec<&Pipeline> {
        self.by_pass.get(index).map_or_else(Vec::new, |indices| indices.iter().map(|&i| &self.built[i]).collect())
    }
}

/// Whether a conditional pass runs this frame.
pub type Conditions<'a> = &'a dyn Fn(When) -> bool;

/// Records the passes of `plan` in order, those whose condition holds: with `in_frame`, the
/// passes into the frame's render pass (which is open); otherwise the offscreen passes, whose
/// draws begin and end their own render passes.
pub fn record_plan<K: PassKinds>(
    rec: &mut FrameRecorder,
    plan: &PassPlan<K>,
    pipelines: &PlanPipelines,
    in_frame: bool,
    holds: Conditions,
    scene: &Scene,
    draws: &dyn Passes<K>,
) -> Result<()> {
    for (index, pass) in plan.passes.iter().enumerate() {
        if (pass.target == Target::Frame) != in_frame || !holds(pass.when) {
            continue;
        }
        let bound = pipelines.of_pass(index);
        let sets = pass
            .sets
            .iter()
            .map(|role| match role {
                SetRole::Frame => Ok(rec.frame_set()),
                SetRole::Own(set) => draws.set(*set).map(|s| s.set).ok_or_else(|| {
                    Error::Internal(format!(
                        "pass '{}': the renderer was built without set '{}'",
                        pass.name,
                        set.label()
                    ))
                }),
                SetRole::Material => draws
                    .materials()
                    .map(|m| m.template_set())
                    .ok_or_else(|| Error::Internal(format!("pass '{}': no materials", pass.name))),
            })
            .collect::<Result<Vec<_>>>()?;
        let recorded = rec.pass(&pass.name, |rec| {
            if pass.reads_colour {
                rec.colour_feedback_barrier();
            }
            if !in_frame {
                return match &pass.draws {
                    Draws::Own { draw, .. } => draws.draw(rec, scene, *draw, pass, &bound),
                    // `PlannedPass::offscreen` and `commands` make every offscreen pass the technique's own.
                    _ => Err(Error::Internal(format!("offscreen pass '{}' is not the technique's own", pass.name))),
                };
            }
            let Some(main) = bound.first().copied() else {
                return Err(Error::Internal(format!("pass '{}' has no pipeline", pass.name)));
            };
            rec.bind_with_sets(main, &sets);
            let scissor = if pass.scissored { draws.scissor(pass) } else { Scissor::Frame };
            match &pass.draws {
                Draws::FullScreen { push } => {
                    if let Some(value) = push {
                        rec.push(main, value);
                    }
                    match scissor {
                        Scissor::Frame => rec.draw(3, 1, 0, 0),
                        Scissor::Rects(rects) => {
                            for rect in drawn_rects(&rects, rec.frame_samples()) {
                                rec.set_scissor(rect);
                                rec.draw(3, 1, 0, 0);
                            }
                        }
                    }
                    Ok(())
                }
                Draws::Objects { alpha } => match draws.meshes() {
                    Some(meshes) => {
                        // Objects are drawn once, inside the bounding rectangle of the scissor.
                        if let Scissor::Rects(rects) = &scissor {
                            match bounding_rect(rects) {
                                Some(rect) => rec.set_scissor(rect),
                                None => return Ok(()),
                            }
                        }
                        draw_objects(rec, pass, &bound, scene, meshes, *alpha)
                    }
                    None => Err(Error::Internal(format!("pass '{}' draws objects but has no meshes", pass.name))),
                },
                Draws::Own { draw, .. } => draws.draw(rec, scene, *draw, pass, &bound),
            }
        });
        // The pipelines bound, in the plan's order (an unplanned one last): material variants
        // are bound in object order, which is the scene's business, not the plan's.
        if let Some(record) = rec.record.passes.last_mut() {
            if let Draws::Own { draw, .. } = &pass.draws {
                record.own_draw = Some(draw.describe());
            }
            record.light = pass.light;
            let rank = |name: &&'static str| pass.pipelines.iter().position(|d| d.name == *name).unwrap_or(usize::MAX);
            record.pipelines.sort_by_key(rank);
        }
        recorded?;
    }
    Ok(())
}

/// Draws every object of `scene` in [`draw_order`] with the pass's pipeline its material needs
/// (the main one, bound by the caller, or a variant: see `MaterialVariant`), each with its
/// transform, its base colour and the alpha `alpha`, and its material set when the pass has one.
/// An object skinned on the GPU (`GpuScene::skinned_mesh`) is drawn from its bind pose with the
/// pipeline's skinned twin.
pub fn draw_objects<K: PassKinds>(
    rec: &mut FrameRecorder,
    pass: &PlannedPass<K>,
    pipelines: &[&Pipeline],
    scene: &Scene,
    meshes: &GpuScene,
    alpha: f32,
) -> Result<()> {
    let with_material = pass.sets.contains(&SetRole::Material);
    // (variant, skinned twin) of the pipeline bound last: the caller bound the main one.
    let mut bound = (0, false);
    // The material set bound since that pipeline: objects of one material in a row bind it once.
    let mut material_bound = None;
    for index in draw_order(scene) {
        let object = &scene.objects[index];
        let material = scene.material_of(object);
        if !pass.only.draws(material) {
            continue;
        }
        let main = pipelines.first().map_or("", |p| p.desc.name);
        let wanted = pass.variant_index(main, MaterialVariant::for_surface(material)).unwrap_or(0);
        let Some(&variant) = pipelines.get(wanted) else { continue };
        let (mesh, pipeline) = meshes
            .object_draw(scene, index, variant)
            .map_err(|e| Error::Internal(format!("pass '{}': {e}", pass.name)))?;
        let skinned = !std::ptr::eq(pipeline, variant);
        if (wanted, skinned) != bound {
            rec.bind(pipeline);
            bound = (wanted, skinned);
            material_bound = None;
        }
        if with_material {
            let set = meshes.materials.set(object.material);
            if material_bound.replace(set) != Some(set) {
                rec.bind_material(pipeline, set);
            }
        }
        let push = object_push(scene, object, alpha);
        match pass.light {
            // A per-light pass says which light (`shaders/light_push.glsl`).
            Some(light) => rec.push(pipeline, &LightPush { object: push, light: [u32::from(light), 0, 0, 0] }),
            None => rec.push(pipeline, &push),
        }
        rec.draw_mesh(mesh);
    }
    Ok(())
}

/// The rectangles a full-screen pass of a scissored plan is drawn in: `rects`, or, at several
/// samples per pixel, their bounding rectangle once. lavapipe lets a multisampled scissored
/// draw reach samples of the pixels just past the scissor's edge, so two neighbouring
/// rectangles would both shade them (a multiply done twice; the 4x equality test found it).
fn drawn_rects(rects: &[vk::Rect2D], samples: u32) -> Vec<vk::Rect2D> {
    if samples <= 1 {
        return rects.to_vec();
    }
    bounding_rect(rects).into_iter().collect()
}

/// The smallest rectangle holding every one of `rects` (none for none).
fn bounding_rect(rects: &[vk::Rect2D]) -> Option<vk::Rect2D> {
    let span = |r: &vk::Rect2D| {
        let (x, y) = (i64::from(r.offset.x), i64::from(r.offset.y));
        (x, y, x + i64::from(r.extent.width), y + i64::from(r.extent.height))
    };
    let (x0, y0, x1, y1) =
        rects.iter().map(span).reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))?;
    Some(vk::Rect2D {
        offset: vk::Offset2D { x: x0 as i32, y: y0 as i32 },
        extent: vk::Extent2D { width: (x1 - x0) as u32, height: (y1 - y0) as u32 },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x: i32, y: i32, width: u32, height: u32) -> vk::Rect2D {
        vk::Rect2D { offset: vk::Offset2D { x, y }, extent: vk::Extent2D { width, height } }
    }

    #[test]
    fn multisampled_frames_draw_scissored_passes_once_in_the_bounds_of_the_rectangles() {
        let rects = [rect(0, 0, 10, 5), rect(10, 2, 4, 8)];
        assert_eq!(drawn_rects(&rects, 1), rects.to_vec());
        assert_eq!(drawn_rects(&rects, 4), vec![rect(0, 0, 14, 10)]);
        assert_eq!(drawn_rects(&[], 4), Vec::new());
    }
}
