//! The ink renderer: the scene's meshes and the ramps, and what the `--silhouette` method
//! needs (each object's edge list, or its extruded copy), built once and kept in pose; drawn by
//! the plan of `recipes`. The edge lines are classified and rebuilt every frame, as a moving
//! camera or mesh needs.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec4};

use super::edges::{InkMesh, InkQuads};
use super::recipes::{InkDraw, InkKinds, InkSet, EDGE_CLASSES};
use crate::error::{Error, Result};
use crate::frame::srgb;
use crate::gpu::descriptors::DescriptorSet;
use crate::gpu::memory::ReusedBuffer;
use crate::gpu::Gpu;
use crate::render::object_push::draw_order;
use crate::render::passes::Passes;
use crate::render::per_slot::slot_copy;
use crate::render::plan::PlannedPass;
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, Renderer};
use crate::scene::{PoseTracker, Scene};
use crate::technique::cartoon::CartoonStats;
use crate::technique::cartoon_shading::{self, CartoonPush, CartoonScene, Shading};
use crate::technique::extruded::{ExtrudedCopies, Extrusion};
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::FrameStats;
use crate::technique::options::{CartoonOptions, Seams, SilhouetteMethod};

/// The ink, in every method.
/// Linear RGBA of ink lines.
pub const INK_COLOUR: Vec4 = Vec4::new(0.04, 0.04, 0.06, 1.0);

/// The technique's part of the renderer (`toon`: the scene through the toon ramp).
pub fn make(ctx: BuildContext<'_>, scene: &Scene, toon: bool) -> Result<InkPasses> {
    let cartoon = &ctx.options.cartoon;
    let method = cartoon.silhouette;
    let shading = Shading { toon, rim: method == SilhouetteMethod::Shader, ink_only: cartoon.ink_only };
    let scene_pass = CartoonScene::new(ctx.gpu, scene, shading, ctx.options.skinning)?;
    let lines = match method {
        SilhouetteMethod::Edges => Ink::Edges(Box::new(EdgeLines::new(scene, cartoon.crease_deg, cartoon.seams)?)),
        SilhouetteMethod::Shader => Ink::Rim,
        SilhouetteMethod::AlphaTest => Ink::AlphaTest(cartoon.alpha_ref),
        SilhouetteMethod::Hull | SilhouetteMethod::Extrusion => Ink::Hull(ExtrudedCopies::new(ctx.gpu, scene)?),
    };
    Ok(InkPasses {
        gpu: ctx.gpu.clone(),
        method,
        scene_pass,
        ink: lines,
        styles: [0, 1, 2].map(|class| class_style(cartoon, class)),
        viewport: Vec4::ZERO,
        pull: 0.0,
    })
}

/// Edge class `class`'s width and linear colour: its `--ink-*` style over `--line-width` and
/// [`INK_COLOUR`].
fn class_style(cartoon: &CartoonOptions, class: usize) -> (f32, Vec4) {
    let colour = cartoon
        .ink
        .get(class)
        .colour
        .map_or(INK_COLOUR, |rgb| Vec4::new(srgb::decode(rgb[0]), srgb::decode(rgb[1]), srgb::decode(rgb[2]), 1.0));
    (cartoon.ink_width(class), colour)
}

/// What draws the ink, per method.
enum Ink {
    Edges(Box<EdgeLines>),
    /// The scene pass's rim ramp: nothing of its own.
    Rim,
    /// Each object's extruded copy (`hull` and `extrusion`).
    Hull(ExtrudedCopies),
    /// The objects again, alpha-tested at this reference.
    AlphaTest(f32),
}

pub struct InkPasses {
    gpu: Arc<Gpu>,
    method: SilhouetteMethod,
    scene_pass: CartoonScene,
    ink: Ink,
    /// Per edge class (silhouette, crease, boundary): width in pixels and linear ink colour.
    styles: [(f32, Vec4); 3],
    /// This frame's `CartoonPush::viewport`.
    viewport: Vec4,
    /// This frame's pull of the edge lines towards the eye, in clip-space depth.
    pull: f32,
}

impl InkPasses {
    /// How `hull` and `extrusion` push their copies out: the silhouette's style.
    fn silhouette_extrusion(&self) -> Extrusion {
        Extrusion { width_px: self.styles[0].0, colour: self.styles[0].1 }
    }
}

impl Passes<InkKinds> for InkPasses {
    fn set(&self, set: InkSet) -> Option<&DescriptorSet> {
        match set {
            InkSet::Ramps => Some(self.scene_pass.ramps()),
        }
    }

    fn meshes(&self) -> Option<&crate::render::GpuScene> {
        Some(&self.scene_pass.meshes)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: InkDraw,
        pass: &PlannedPass<InkKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let Some(pipeline) = pipelines.first() else {
            return Err(Error::Internal(format!("ink pass '{}' has no pipeline", pass.name)));
        };
        match (draw, &self.ink) {
            (InkDraw::Scene, _) => self.scene_pass.draw(rec, pass, pipelines, scene, |_| true, 1.0, self.viewport)?,
            (InkDraw::AlphaTest, Ink::AlphaTest(reference)) => {
                let params = Vec4::new(*reference, 0.0, 0.0, 0.0);
                let mut bound: &Pipeline = pipeline;
                for index in draw_order(scene) {
                    let object = &scene.objects[index];
                    // A GPU-skinned object is drawn by the pipeline's skinned twin.
                    let (mesh, wanted) = self.scene_pass.meshes.object_draw(scene, index, pipeline)?;
                    if !std::ptr::eq(wanted, bound) {
                        rec.bind(wanted);
                        bound = wanted;
                    }
                    let colour = self.styles[0].1;
                    let push = CartoonPush { model: object.transform, colour, params, viewport: self.viewport };
                    rec.push(bound, &push);
                    rec.draw_mesh(mesh);
                }
            }
            (InkDraw::CopyThenObject, Ink::Hull(copies)) => {
                // The copy pipeline is the pass's last; the scene's (and its material variants)
                // come first.
                let copy = pipelines.last().copied().unwrap_or(pipeline);
                let extrusion = self.silhouette_extrusion();
                for index in draw_order(scene) {
                    rec.bind(copy);
                    copies.draw_one(rec, copy, scene, index, extrusion, self.viewport);
                    self.scene_pass.draw_object(rec, pass, pipelines, copy, scene, index, 1.0, self.viewport)?;
                }
            }
            (InkDraw::Hull, Ink::Hull(copies)) => {
                let extrusion = self.silhouette_extrusion();
                copies.draw(rec, pipeline, scene, |_| true, extrusion, self.viewport);
            }
            (InkDraw::EdgeQuads(class), Ink::Edges(lines)) => {
                let one_sided = if EDGE_CLASSES.get(class).is_some_and(|c| c.one_sided) { 1.0 } else { 0.0 };
                let style = self.styles.get(class).copied().unwrap_or(self.styles[0]);
                let push = CartoonPush {
                    model: Mat4::IDENTITY,
                    colour: style.1,
                    params: Vec4::new(style.0, one_sided, self.pull, 0.0),
                    viewport: self.viewport,
                };
                rec.push(pipeline, &push);
                let slot = lines.buffers.get(rec.slot());
                if let Some((buffer, count)) = slot.and_then(|b| b.get(class)).and_then(ReusedBuffer::filled) {
                    rec.bind_vertices(buffer);
                    rec.draw(count, 1, 0, 0);
                }
            }
            // The plan and the ink resources are both made from `self.method`: a draw of
            // another method has no resources here.
            (InkDraw::AlphaTest | InkDraw::CopyThenObject | InkDraw::Hull | InkDraw::EdgeQuads(_), _) => {
                return Err(Error::Internal(format!(
                    "ink pass '{}': this renderer was built for {} ink",
                    pass.name,
                    self.method.name()
                )))
            }
        }
        Ok(())
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        let slot = renderer.slot();
        self.scene_pass.meshes.follow_pose(&self.gpu, scene, slot)?;
        match &mut self.ink {
            Ink::Edges(lines) => {
                lines.follow_pose(scene);
                lines.rebuild(&self.gpu, scene, slot)?;
            }
            Ink::Rim | Ink::AlphaTest(_) => {}
            Ink::Hull(copies) => {
                copies.follow_pose(&self.gpu, scene, slot)?;
            }
        }
        let extent = renderer.extent();
        self.viewport = cartoon_shading::viewport(scene, extent);
        // Lines are pulled towards the eye by about one line width at any distance: enough for
        // a crease between faces tilted up to ~60 degrees, far too little to show through a
        // solid.
        let pixel = cartoon_shading::pixel_at_unit_distance(scene, extent.height);
        let widest = self.styles.iter().map(|s| s.0).fold(0.0, f32::max);
        self.pull = scene.camera.near * (widest * pixel).max(1e-3);
        Ok(())
    }

    /// Posed vertices, hull copies and edge quads are written per slot.
    fn writes_per_slot(&self) -> bool {
        true
    }

    fn warnings(&self) -> &[String] {
        match &self.ink {
            Ink::Edges(lines) => &lines.warnings,
            _ => &[],
        }
    }

    fn stats(&mut self, _output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        let mut stats = CartoonStats {
            method: Some(self.method),
            selected: Vec::new(),
            silhouette_edges: 0,
            crease_edges: 0,
            boundary_edges: 0,
            edge_cpu_ms: 0.0,
            total_edges: 0,
            face_normal_updates: 0,
        };
        if let Ink::Edges(lines) = &self.ink {
            [stats.silhouette_edges, stats.crease_edges, stats.boundary_edges] = lines.quads.edge_counts();
            stats.edge_cpu_ms = lines.cpu_ms;
            stats.face_normal_updates = lines.normal_updates;
            stats.total_edges = lines.meshes.iter().map(|m| m.adjacency.edges.len()).sum();
        }
        Box::new(stats)
    }
}

/// The edge-list ink: every object's edge list, and this frame's quads per edge class.
struct EdgeLines {
    meshes: Vec<InkMesh>,
    crease_deg: f32,
    quads: InkQuads,
    /// Per frame slot, that frame's quads on the GPU per class, in buffers kept from frame to
    /// frame (none filled where the class drew no edge).
    buffers: Vec<[ReusedBuffer; 3]>,
    /// The pose the meshes' welded positions (so their normals and edges) hold.
    pose: PoseTracker,
    /// CPU time of this frame's edge work (ms).
    cpu_ms: f64,
    /// Objects whose face normals and creases this frame recomputed.
    normal_updates: usize,
    /// Seams asked for that a mesh cannot show (it lacks the attribute).
    warnings: Vec<String>,
}

impl EdgeLines {
    fn new(scene: &Scene, crease_deg: f32, seams: Seams) -> Result<Self> {
        let mut warnings = Vec::new();
        let meshes = scene
            .mesh_instances()
            .into_iter()
            .map(|parts| InkMesh::new(scene, parts, seams, &mut warnings))
            .collect::<Result<Vec<_>>>()?;
        Ok(EdgeLines {
            meshes,
            crease_deg,
            quads: InkQuads::default(),
            buffers: Vec::new(),
            pose: PoseTracker::new(scene),
            cpu_ms: 0.0,
            normal_updates: 0,
            warnings,
        })
    }

    /// Meshes with a skinned part whose palette changed get their welded positions, so the face
    /// normals and edges, re-posed.
    fn follow_pose(&mut self, scene: &Scene) {
        let changed = self.pose.changed(scene);
        let skinned = |index: &usize| scene.objects.get(*index).is_some_and(|o| o.skin.is_some());
        for mesh in &mut self.meshes {
            if mesh.parts.iter().any(|part| changed.contains(part) && skinned(part)) {
                mesh.follow(scene);
            }
        }
    }

    /// Classifies every object's edges from this frame's eye, builds their quads and uploads
    /// them into frame slot `slot`'s buffers.
    fn rebuild(&mut self, gpu: &Arc<Gpu>, scene: &Scene, slot: usize) -> Result<()> {
        let start = Instant::now();
        let eye = scene.camera.eye;
        self.quads.clear();
        self.normal_updates = 0;
        for mesh in &mut self.meshes {
            let model = scene.objects[mesh.parts[0]].transform;
            self.normal_updates += usize::from(mesh.needs_normals(self.crease_deg));
            mesh.classify(&model, eye, self.crease_deg);
            mesh.append_quads(&model, eye, &mut self.quads);
        }
        self.cpu_ms = start.elapsed().as_secs_f64() * 1e3;
        // The frame that last used this slot has finished: its buffers are free.
        let buffers = slot_copy(&mut self.buffers, slot, || {
            Ok([
                ReusedBuffer::new("ink silhouette quads", vk::BufferUsageFlags::VERTEX_BUFFER),
                ReusedBuffer::new("ink crease quads", vk::BufferUsageFlags::VERTEX_BUFFER),
                ReusedBuffer::new("ink boundary quads", vk::BufferUsageFlags::VERTEX_BUFFER),
            ])
        })?;
        let classes = [&self.quads.silhouette, &self.quads.crease, &self.quads.boundary];
        for (buffer, vertices) in buffers.iter_mut().zip(classes) {
            buffer.fill(gpu, vertices)?;
        }
        Ok(())
    }
}
