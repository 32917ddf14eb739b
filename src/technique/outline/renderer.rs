//! The outline renderer: the scene's meshes, the ramps and every object's welded copy (pushed
//! out along its normals, or scaled about its centre, by the vertex shader), built once and
//! kept in pose, drawn by the plan of `recipes`.

use std::sync::Arc;

use ash::vk;
use glam::Vec4;

use super::blur::{blur_push, BlurTargets};
use super::kinds::{OutlineDraw, OutlineKinds, OutlineSet, OutlineTarget};
use super::recipes;
use super::scaled::Bounds;
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::descriptors::DescriptorSet;
use crate::gpu::Gpu;
use crate::render::passes::{Clear, Passes};
use crate::render::per_slot::slot_copy;
use crate::render::plan::{PlannedPass, Target};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, Renderer};
use crate::scene::Scene;
use crate::technique::cartoon::CartoonStats;
use crate::technique::cartoon_shading::{self, CartoonScene, Shading};
use crate::technique::extruded::{ExtrudedCopies, Extrusion};
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::FrameStats;
use crate::technique::options::OutlineMethod;

/// The technique's part of the renderer: the copies, their bounds, the blur's targets. The
/// selection was resolved by `setup`, before anything was uploaded.
pub fn make(ctx: BuildContext<'_>, scene: &Scene, selected: Vec<bool>) -> Result<OutlinePasses> {
    let cartoon = &ctx.options.cartoon;
    // The colour is given in sRGB bytes, as the PNG shows it; the shader writes linear light.
    let extrusion = Extrusion { width_px: cartoon.outline_width, colour: recipes::linear_colour(cartoon) };
    let copies = ExtrudedCopies::new(ctx.gpu, scene)?;
    let bounds = (0..scene.objects.len()).map(|i| Bounds::of(copies.positions(i))).collect();
    let blur = if cartoon.outline_blur > 0 {
        let (stencil, extent) = (ctx.options.stencil, ctx.renderer.extent());
        Some(Blur { targets: vec![BlurTargets::new(ctx.gpu, stencil, extent)?], stencil, extent, slot: 0 })
    } else {
        None
    };
    Ok(OutlinePasses {
        gpu: ctx.gpu.clone(),
        scene_pass: CartoonScene::new(ctx.gpu, scene, Shading::default(), ctx.options.skinning)?,
        copies,
        bounds,
        scales: vec![1.0; scene.objects.len()],
        selected,
        extrusion,
        method: cartoon.outline_method,
        blur,
        viewport: Vec4::ZERO,
    })
}

pub struct OutlinePasses {
    gpu: Arc<Gpu>,
    scene_pass: CartoonScene,
    copies: ExtrudedCopies,
    /// Per object: its copy's centre and radius, in its current pose (`--outline-method scale`).
    bounds: Vec<Bounds>,
    /// Per object: this frame's scale about its centre, for the width in pixels.
    scales: Vec<f32>,
    /// Per object: whether it is outlined.
    selected: Vec<bool>,
    extrusion: Extrusion,
    method: OutlineMethod,
    /// The blur's targets (`--outline-blur`).
    blur: Option<Blur>,
    /// This frame's `CartoonPush::viewport`.
    viewport: Vec4,
}

/// The blur's offscreen targets, a set per frame slot (a frame in flight samples its own).
struct Blur {
    targets: Vec<BlurTargets>,
    stencil: StencilMode,
    extent: vk::Extent2D,
    /// The slot of the frame being recorded (`prepare`'s).
    slot: usize,
}

impl Blur {
    /// The targets of the frame being recorded.
    fn current(&self) -> &BlurTargets {
        self.targets.get(self.slot).unwrap_or(&self.targets[0])
    }

    /// The frame about to be recorded is in slot `slot`: its targets, made if it has none.
    fn use_slot(&mut self, gpu: &Arc<Gpu>, slot: usize) -> Result<()> {
        let (stencil, extent) = (self.stencil, self.extent);
        slot_copy(&mut self.targets, slot, || BlurTargets::new(gpu, stencil, extent))?;
        self.slot = slot;
        Ok(())
    }
}

impl OutlinePasses {
    /// The selected objects' copies of `self.method` in `colour`, with the bound `pipeline`.
    fn draw_copies(&self, rec: &mut FrameRecorder, pipeline: &Pipeline, scene: &Scene, colour: Vec4) {
        let selected = |i: usize| self.selected[i];
        match self.method {
            OutlineMethod::Extrude => {
                let extrusion = Extrusion { colour, ..self.extrusion };
                self.copies.draw(rec, pipeline, scene, selected, extrusion, self.viewport)
            }
            OutlineMethod::Scale => {
                // `outline_scale.vert`: x = scale, yzw = centre.
                let params = |i: usize| {
                    let c = self.bounds[i].centre;
                    Vec4::new(self.scales[i], c.x, c.y, c.z)
                };
                self.copies.draw_with(rec, pipeline, scene, selected, colour, self.viewport, params)
            }
        }
    }

    /// The blur's passes: the mask (the selection marked in alpha or the stencil, then the
    /// copies writing R = 1 where it is not), and the two 1D blur passes.
    fn draw_offscreen(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: OutlineDraw,
        pass: &PlannedPass<OutlineKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let (Some(blur), Target::Offscreen(target)) = (self.blur.as_ref().map(Blur::current), pass.target) else {
            return Err(Error::Internal(format!("outline pass '{}' needs the blur's targets", pass.name)));
        };
        let (render_pass, framebuffer, clear) = blur.begin(target);
        rec.begin_offscreen_pass(render_pass, framebuffer, blur.extent, &clear);
        match (draw, pipelines) {
            (OutlineDraw::Mask, &[mark, copy, ..]) => {
                rec.bind_with_sets(mark, &[rec.frame_set()]);
                // Scale 1 about the origin: the selected objects as they are.
                let as_is = |_: usize| Vec4::new(1.0, 0.0, 0.0, 0.0);
                let selected = |i: usize| self.selected[i];
                self.copies.draw_with(rec, mark, scene, selected, Vec4::new(0.0, 0.0, 0.0, 1.0), self.viewport, as_is);
                rec.bind_with_sets(copy, &[rec.frame_set()]);
                self.draw_copies(rec, copy, scene, Vec4::ONE);
            }
            (OutlineDraw::Blur { along_x, radius }, &[pipeline, ..]) => {
                let source = if along_x { OutlineSet::Mask } else { OutlineSet::BlurredAlongX };
                if let Some(source) = blur.set(source) {
                    rec.bind_with_sets(pipeline, &[source.set]);
                    rec.push(pipeline, &blur_push(along_x, radius));
                    rec.draw(3, 1, 0, 0);
                }
            }
            // The frame's draws and a pass without its pipelines draw nothing offscreen.
            _ => {}
        }
        rec.end_render_pass();
        Ok(())
    }
}

impl Passes<OutlineKinds> for OutlinePasses {
    fn set(&self, set: OutlineSet) -> Option<&DescriptorSet> {
        match set {
            OutlineSet::Ramps => Some(self.scene_pass.ramps()),
            _ => self.blur.as_ref().and_then(|b| b.current().set(set)),
        }
    }

    fn meshes(&self) -> Option<&crate::render::GpuScene> {
        Some(&self.scene_pass.meshes)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: OutlineDraw,
        pass: &PlannedPass<OutlineKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        if pass.target != Target::Frame {
            return self.draw_offscreen(rec, scene, draw, pass, pipelines);
        }
        let Some(pipeline) = pipelines.first() else {
            return Err(Error::Internal(format!("outline pass '{}' has no pipeline", pass.name)));
        };
        let selected = |i: usize| self.selected[i];
        match draw {
            OutlineDraw::NotSelected => {
                self.scene_pass.draw(rec, pass, pipelines, scene, |i| !selected(i), 0.0, self.viewport)?
            }
            OutlineDraw::Selected => self.scene_pass.draw(rec, pass, pipelines, scene, selected, 1.0, self.viewport)?,
            OutlineDraw::Copies(_) => self.draw_copies(rec, pipeline, scene, self.extrusion.colour),
            // Offscreen only: handled above.
            OutlineDraw::Mask | OutlineDraw::Blur { .. } => {}
        }
        Ok(())
    }

    fn offscreen_pass(&self, target: OutlineTarget) -> Option<(vk::RenderPass, usize)> {
        // Every slot's render passes are made alike: the pipelines built for slot 0's fit all.
        self.blur.as_ref().map(|b| b.targets[0].render_pass(target))
    }

    /// Posed vertices, copies and the blur's targets are the slot's own.
    fn writes_per_slot(&self) -> bool {
        true
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        let slot = renderer.slot();
        if let Some(blur) = &mut self.blur {
            blur.use_slot(&self.gpu, slot)?;
        }
        self.scene_pass.meshes.follow_pose(&self.gpu, scene, slot)?;
        let moved = self.copies.follow_pose(&self.gpu, scene, slot)?;
        for &index in &moved {
            self.bounds[index] = Bounds::of(self.copies.positions(index));
        }
        self.viewport = cartoon_shading::viewport(scene, renderer.extent());
        let eye = scene.camera.eye;
        for (index, object) in scene.objects.iter().enumerate() {
            let bounds = &self.bounds[index];
            self.scales[index] =
                bounds.scale_for_width(&object.transform, eye, self.viewport.z, self.extrusion.width_px);
        }
        Ok(())
    }

    /// Alpha is the emulated stencil: 0 until a selected object marks it.
    fn clear(&self) -> Clear {
        Clear { alpha: 0.0, ..Clear::default() }
    }

    fn stats(&mut self, _output: &FrameOutput, scene: &Scene) -> Box<dyn FrameStats> {
        Box::new(CartoonStats {
            method: None,
            selected: scene
                .objects
                .iter()
                .zip(&self.selected)
                .filter(|(_, s)| **s)
                .map(|(o, _)| o.name.clone())
                .collect(),
            silhouette_edges: 0,
            crease_edges: 0,
            boundary_edges: 0,
            edge_cpu_ms: 0.0,
            total_edges: 0,
            face_normal_updates: 0,
        })
    }
}
