//! The outline renderer: the scene's meshes, the ramps and every object's extruded copy,
//! built once and kept in pose, drawn by the plan of `recipes`.

use std::sync::Arc;

use ash::vk;
use glam::Vec4;

use super::recipes::{NOT_SELECTED, SELECTED, SELECTED_EXTRUDED};
use super::{resolve_selection, Outline};
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::plan::{PlannedPass, SetRole};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, Renderer};
use crate::scene::Scene;
use crate::technique::cartoon::CartoonStats;
use crate::technique::cartoon_shading::{self, CartoonScene, Shading};
use crate::technique::extruded::{ExtrudedCopies, Extrusion};
use crate::technique::frame_renderer::{self, Passes};
use crate::technique::interface::RenderOptions;
use crate::technique::interface::{FrameStats, SceneRenderer};

/// Builds the renderer; an unknown selected name is refused before anything is uploaded.
pub fn build<'s>(
    technique: &Outline,
    gpu: &Arc<Gpu>,
    scene: &'s Scene,
    options: &RenderOptions,
) -> Result<Box<dyn SceneRenderer + 's>> {
    // The numbers are checked by `frame_renderer::build`; the selection needs the scene.
    let cartoon = &options.cartoon;
    let selected = resolve_selection(scene, &cartoon.select)?;
    // The colour is given in sRGB bytes, as the PNG shows it; the shader writes linear light.
    let [r, g, b] = cartoon.outline_colour.map(crate::frame::srgb::decode);
    let extrusion = Extrusion { width_px: cartoon.outline_width, colour: Vec4::new(r, g, b, 1.0) };
    frame_renderer::build(technique, gpu, scene, options, |ctx| {
        Ok(OutlinePasses {
            gpu: ctx.gpu.clone(),
            scene_pass: CartoonScene::new(ctx.gpu, scene, Shading::default())?,
            copies: ExtrudedCopies::new(ctx.gpu, scene)?,
            selected,
            extrusion,
            viewport: Vec4::ZERO,
        })
    })
}

struct OutlinePasses {
    gpu: Arc<Gpu>,
    scene_pass: CartoonScene,
    copies: ExtrudedCopies,
    /// Per object: whether it is outlined.
    selected: Vec<bool>,
    extrusion: Extrusion,
    /// This frame's `CartoonPush::viewport`.
    viewport: Vec4,
}

impl Passes for OutlinePasses {
    fn set_layout(&self, role: SetRole) -> Option<vk::DescriptorSetLayout> {
        self.scene_pass.set_layout(role)
    }

    fn set(&self, role: SetRole) -> Option<vk::DescriptorSet> {
        self.scene_pass.set(role)
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        let changed = self.scene_pass.meshes.follow_pose(&self.gpu, scene)?;
        self.copies.follow_pose(&self.gpu, scene, &changed)?;
        self.viewport = cartoon_shading::viewport(scene, renderer.extent());
        Ok(())
    }

    /// Alpha is the emulated stencil: 0 until a selected object marks it.
    fn clear_alpha(&self) -> f32 {
        0.0
    }

    fn draw(&self, rec: &mut FrameRecorder, scene: &Scene, pass: &PlannedPass, pipelines: &[&Pipeline]) -> Result<()> {
        let Some(pipeline) = pipelines.first() else {
            return Err(Error::Internal(format!("outline pass '{}' has no pipeline", pass.name)));
        };
        let selected = |i: usize| self.selected[i];
        match pass.draws {
            NOT_SELECTED => self.scene_pass.draw(rec, pass, pipelines, scene, |i| !selected(i), 0.0, self.viewport),
            SELECTED => self.scene_pass.draw(rec, pass, pipelines, scene, selected, 1.0, self.viewport),
            SELECTED_EXTRUDED => self.copies.draw(rec, pipeline, scene, selected, self.extrusion, self.viewport),
            _ => return Err(Error::Internal(format!("the outline cannot draw pass '{}'", pass.name))),
        }
        Ok(())
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
