//! Cartoon rendering (seeds 002 and 003, DESIGN.md section 4): ink lines on silhouette, crease
//! and boundary edges, toon shading, and the stencil-style selection outline without a stencil.
//!
//! `outline` (seed 003), emulated frame, one render pass:
//! 1. scene: the objects that are not selected, alpha 0 (the clear's alpha is 0 too);
//! 2. selected: the selected objects, alpha 1;
//! 3. outline: the selected objects again, pushed out along their smooth normals, depth test
//!    off, colour blend `ADD, ONE_MINUS_DST_ALPHA, DST_ALPHA`, write mask RGB: where alpha is 1
//!    the pixel keeps its colour, where it is 0 it takes the outline colour, which is exactly
//!    where a stencil test `NOT_EQUAL 1` would pass.
//!
//! The reference is the document's: the selected objects write stencil 1 (`ALWAYS`, `REPLACE`),
//! then the same pushed-out copy is drawn opaque where the stencil is `NOT_EQUAL 1`. Both draw
//! unselected objects first, as the document does, so the mark means "the visible surface here
//! is selected" in both.
//!
//! `silhouette` and `toon` (seed 002): the scene (Lambert, or N.L through a 1D ramp texture),
//! then the ink, by one of three methods:
//! - `edges`: per frame on the CPU, each object's unique edge list is classified from the eye
//!   (`mesh::classify`), and the flagged edges are drawn as screen-space quads, one draw per
//!   class (the mobile profile has no wideLines);
//! - `shader`: the scene's vertex shader computes N.V and the fragment shader looks it up in a
//!   1D texture whose first texels are dark (a rim);
//! - `hull`: the two-pass inverted hull: the mesh pushed out along its normals, front faces
//!   culled, drawn in ink behind the model.

pub mod ink;

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec4};

use self::ink::{InkMesh, InkQuads, InkVertex};
use super::cartoon_shading::{self, cartoon_desc, shade_desc, CartoonPush, CartoonScene, Shading};
use super::extruded::{extrude_desc, ExtrudedCopies, Extrusion};
use super::legacy::CartoonStyle as Technique;
use super::outline::resolve_selection;
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::memory::{as_bytes, Buffer};
use crate::gpu::Gpu;
use crate::pipeline::{
    BlendEquation, BlendState, DepthState, FixedFunction, Pipeline, PipelineDesc, RasterState, StencilFace,
    StencilState, VertexLayout,
};
use crate::render::{FrameOutput, FrameRecorder, FrameUniforms, Renderer};
use crate::scene::Scene;

/// How `silhouette` and `toon` find their ink.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SilhouetteMethod {
    /// CPU edge classification, screen-space quads.
    #[default]
    Edges,
    /// N.V per vertex looked up in a 1D texture (dark rim).
    Shader,
    /// Normal-extruded inverted hull.
    Hull,
}

impl SilhouetteMethod {
    pub const ALL: [SilhouetteMethod; 3] = [SilhouetteMethod::Edges, SilhouetteMethod::Shader, SilhouetteMethod::Hull];

    pub fn parse(text: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == text)
            .ok_or_else(|| Error::InvalidInput(format!("--silhouette {text}: use edges, shader or hull")))
    }

    pub fn name(self) -> &'static str {
        match self {
            SilhouetteMethod::Edges => "edges",
            SilhouetteMethod::Shader => "shader",
            SilhouetteMethod::Hull => "hull",
        }
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CartoonOptions {
    /// Objects to outline (`outline`); empty: the scene's first closed object.
    pub select: Vec<String>,
    pub silhouette: SilhouetteMethod,
    /// Edges whose faces fold by more than this many degrees are creases.
    pub crease_deg: f32,
    /// Ink line width in pixels (edges), and the width of the hull rim.
    pub line_width: f32,
    /// Outline width in pixels (`outline`).
    pub outline_width: f32,
    /// Outline colour, 8-bit RGB (so every path writes the same bytes).
    pub outline_colour: [u8; 3],
}

impl Default for CartoonOptions {
    fn default() -> Self {
        CartoonOptions {
            select: Vec::new(),
            silhouette: SilhouetteMethod::Edges,
            crease_deg: 40.0,
            line_width: 2.0,
            outline_width: 4.0,
            outline_colour: [255, 160, 0],
        }
    }
}

impl CartoonOptions {
    /// Checks the numbers a user typed.
    pub fn check(&self) -> Result<()> {
        if !(self.line_width.is_finite() && (0.5..=64.0).contains(&self.line_width)) {
            return Err(Error::InvalidInput(format!("--line-width {}: use 0.5 to 64 pixels", self.line_width)));
        }
        if !(self.outline_width.is_finite() && (0.5..=64.0).contains(&self.outline_width)) {
            return Err(Error::InvalidInput(format!("--outline-width {}: use 0.5 to 64 pixels", self.outline_width)));
        }
        if !(self.crease_deg.is_finite() && (0.0..=180.0).contains(&self.crease_deg)) {
            return Err(Error::InvalidInput(format!("--crease-angle {}: use 0 to 180 degrees", self.crease_deg)));
        }
        Ok(())
    }

    /// Parses `--select NAME,NAME,...` (empty: the default selection).
    pub fn parse_select(text: &str) -> Vec<String> {
        text.split(',').map(str::trim).filter(|s| !s.is_empty()).map(str::to_owned).collect()
    }
}

// ---------------------------------------------------------------------------------------------
// Fixed-function recipes, as data.

const RGB_ONLY: vk::ColorComponentFlags =
    vk::ColorComponentFlags::from_raw(vk::ColorComponentFlags::RGBA.as_raw() & !vk::ColorComponentFlags::A.as_raw());

/// position (vec3) a, b, c + corner (vec2): `InkVertex`.
pub const INK_LAYOUT: VertexLayout = VertexLayout {
    attributes: &[
        vk::Format::R32G32B32_SFLOAT,
        vk::Format::R32G32B32_SFLOAT,
        vk::Format::R32G32B32_SFLOAT,
        vk::Format::R32G32_SFLOAT,
    ],
};

/// Reference only: selected objects also write stencil 1.
pub fn selected_stencil_desc() -> PipelineDesc {
    let replace = StencilFace {
        compare: vk::CompareOp::ALWAYS,
        reference: 1,
        compare_mask: 0xff,
        write_mask: 0xff,
        fail: vk::StencilOp::KEEP,
        pass: vk::StencilOp::REPLACE,
        depth_fail: vk::StencilOp::KEEP,
    };
    let mut d = shade_desc();
    d.name = "selected (stencil)";
    d.fixed.stencil = Some(StencilState { front: replace, back: replace });
    d
}

fn outline_fixed(blend: BlendState) -> FixedFunction {
    FixedFunction {
        topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        raster: RasterState::CULL_NONE,
        depth: DepthState::OFF,
        stencil: None,
        blend,
    }
}

/// The pushed-out copy, blended by destination alpha: colour = outline * (1 - a) + dst * a.
pub fn outline_desc() -> PipelineDesc {
    let blend = BlendState {
        colour: Some(BlendEquation::new(
            vk::BlendOp::ADD,
            vk::BlendFactor::ONE_MINUS_DST_ALPHA,
            vk::BlendFactor::DST_ALPHA,
        )),
        alpha: None,
        write_mask: RGB_ONLY,
    };
    extrude_desc("outline", outline_fixed(blend))
}

/// Reference: the same copy, opaque, where the stencil is not 1.
pub fn outline_stencil_desc() -> PipelineDesc {
    let not_one = StencilFace {
        compare: vk::CompareOp::NOT_EQUAL,
        reference: 1,
        compare_mask: 0xff,
        write_mask: 0,
        fail: vk::StencilOp::KEEP,
        pass: vk::StencilOp::KEEP,
        depth_fail: vk::StencilOp::KEEP,
    };
    let blend = BlendState { colour: None, alpha: None, write_mask: RGB_ONLY };
    let mut d = extrude_desc("outline (stencil)", outline_fixed(blend));
    d.fixed.stencil = Some(StencilState { front: not_one, back: not_one });
    d
}

/// Ink quads: depth tested (LESS_OR_EQUAL, pulled towards the eye in the vertex shader), no
/// depth write, colour only.
pub fn ink_desc() -> PipelineDesc {
    cartoon_desc(
        "ink lines",
        "cartoon_ink.vert",
        "cartoon_colour.frag",
        INK_LAYOUT,
        FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState::CULL_NONE,
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil: None,
            blend: BlendState { colour: None, alpha: None, write_mask: RGB_ONLY },
        },
    )
}

/// Inverted hull: the pushed-out copy with its front faces culled, depth tested and written, so
/// only the rim around the model (and at its folds) shows.
pub fn hull_desc() -> PipelineDesc {
    extrude_desc("inverted hull", FixedFunction { raster: RasterState::CULL_FRONT, ..FixedFunction::OPAQUE })
}

/// Every pipeline of every pass of a cartoon technique (emulated and reference), for
/// `nostencil passes`.
pub fn pipeline_descs(technique: Technique) -> Vec<PipelineDesc> {
    match technique {
        Technique::Outline => {
            let mut selected = shade_desc();
            selected.name = "selected";
            vec![shade_desc(), selected, outline_desc(), selected_stencil_desc(), outline_stencil_desc()]
        }
        _ => vec![shade_desc(), ink_desc(), hull_desc()],
    }
}

// ---------------------------------------------------------------------------------------------
// The renderer.

/// What a cartoon frame reports beyond its image and counters.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CartoonStats {
    pub method: Option<SilhouetteMethod>,
    pub selected: Vec<String>,
    /// Edges drawn per class (edges method), each edge once.
    pub silhouette_edges: usize,
    pub crease_edges: usize,
    pub boundary_edges: usize,
    /// CPU time of this frame's edge work: face normals, classification, quads (ms).
    pub edge_cpu_ms: f64,
    /// Edges in the unique edge lists of all objects.
    pub total_edges: usize,
}

pub struct CartoonFrame {
    pub output: FrameOutput,
    pub stats: CartoonStats,
}

struct Pipelines {
    shade: Pipeline,
    /// outline: the selected objects' scene pass (reference: with the stencil write).
    selected: Option<Pipeline>,
    outline: Option<Pipeline>,
    ink: Option<Pipeline>,
    hull: Option<Pipeline>,
}

/// Everything a cartoon frame needs, built once; `frame` renders one frame (edges are
/// classified and their quads rebuilt every frame, as a moving camera or mesh needs).
pub struct CartoonRenderer<'s> {
    gpu: Arc<Gpu>,
    scene: &'s Scene,
    technique: Technique,
    options: CartoonOptions,
    renderer: Renderer,
    scene_pass: CartoonScene,
    /// Per object: welded mesh with smooth normals (outline copy, hull).
    extruded: ExtrudedCopies,
    /// Per object: its welded mesh and edge list (ink lines when `edges`; the extruded copy).
    ink: Vec<InkMesh>,
    /// Ink lines from the edge list (`--silhouette edges`).
    edges: bool,
    quads: InkQuads,
    selected: Vec<bool>,
    pipelines: Pipelines,
}

impl<'s> CartoonRenderer<'s> {
    pub fn new(
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        width: u32,
        height: u32,
        stencil: StencilMode,
        technique: Technique,
        options: &CartoonOptions,
    ) -> Result<Self> {
        if !matches!(technique, Technique::Outline | Technique::Silhouette | Technique::Toon) {
            return Err(Error::InvalidInput(format!("'{}' is not a cartoon technique", technique.name())));
        }
        options.check()?;
        let selected = resolve_selection(scene, &options.select)?;
        let renderer = Renderer::new(gpu, width, height, stencil, false)?;
        let shading = Shading {
            toon: technique == Technique::Toon,
            rim: technique != Technique::Outline && options.silhouette == SilhouetteMethod::Shader,
        };
        let scene_pass = CartoonScene::new(gpu, scene, shading)?;
        let render_pass = renderer.targets.render_pass;
        let frame_only = [renderer.frame.layout];
        let with_textures = [renderer.frame.layout, scene_pass.ramps.set.layout];
        let edges = technique != Technique::Outline && options.silhouette == SilhouetteMethod::Edges;
        let hull = technique != Technique::Outline && options.silhouette == SilhouetteMethod::Hull;
        let reference = stencil == StencilMode::Reference;

        let ink = (0..scene.objects.len()).map(|index| InkMesh::new(scene, index)).collect::<Result<Vec<_>>>()?;
        let extruded = ExtrudedCopies::new(gpu, scene)?;

        let outline = technique == Technique::Outline;
        let pipelines = Pipelines {
            shade: Pipeline::new(gpu, &shade_desc(), render_pass, &with_textures)?,
            selected: match (outline, reference) {
                (true, true) => Some(Pipeline::new(gpu, &selected_stencil_desc(), render_pass, &with_textures)?),
                _ => None,
            },
            outline: match (outline, reference) {
                (true, false) => Some(Pipeline::new(gpu, &outline_desc(), render_pass, &frame_only)?),
                (true, true) => Some(Pipeline::new(gpu, &outline_stencil_desc(), render_pass, &frame_only)?),
                _ => None,
            },
            ink: if edges { Some(Pipeline::new(gpu, &ink_desc(), render_pass, &frame_only)?) } else { None },
            hull: if hull { Some(Pipeline::new(gpu, &hull_desc(), render_pass, &frame_only)?) } else { None },
        };
        Ok(CartoonRenderer {
            gpu: gpu.clone(),
            scene,
            technique,
            options: options.clone(),
            renderer,
            scene_pass,
            extruded,
            ink,
            edges,
            quads: InkQuads::default(),
            selected,
            pipelines,
        })
    }

    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// Skinned objects whose palette changed (`Scene::pose_at`) get their lit mesh, welded
    /// positions (so the per-frame face normals and edges) and extruded copy re-posed.
    fn follow_pose(&mut self, scene: &Scene) -> Result<()> {
        let changed = self.scene_pass.meshes.follow_pose(&self.gpu, scene)?;
        for &index in &changed {
            let (Some(skin), Some(ink)) = (&scene.objects[index].skin, self.ink.get_mut(index)) else { continue };
            ink.follow(skin);
        }
        self.extruded.follow_pose(&self.gpu, scene, &changed)
    }

    /// Per-frame CPU edge work for every object; returns its time in ms.
    fn build_quads(&mut self, scene: &Scene) -> f64 {
        let start = Instant::now();
        let crease = self.options.crease_deg;
        let eye = scene.camera.eye;
        self.quads.clear();
        for mesh in &mut self.ink {
            let model = scene.objects[mesh.object].transform;
            mesh.classify(&model, eye, crease);
            mesh.append_quads(&model, eye, &mut self.quads);
        }
        start.elapsed().as_secs_f64() * 1e3
    }

    /// Renders the scene this renderer was built for.
    pub fn frame(&mut self) -> Result<CartoonFrame> {
        let scene = self.scene;
        self.frame_with(scene)
    }

    /// Renders `scene`, a moved pose of the one this renderer was built for (edges are
    /// classified against its camera and transforms).
    pub fn frame_with(&mut self, scene: &Scene) -> Result<CartoonFrame> {
        crate::technique::check_same_scene(self.scene, scene, self.technique.name())?;
        self.follow_pose(scene)?;
        let edge_cpu_ms = if self.edges { self.build_quads(scene) } else { 0.0 };
        let gpu = self.gpu.clone();
        let upload = |name: &str, vertices: &[InkVertex]| -> Result<Option<(Buffer, u32)>> {
            if vertices.is_empty() {
                return Ok(None);
            }
            let buffer = Buffer::with_data(&gpu, name, as_bytes(vertices), vk::BufferUsageFlags::VERTEX_BUFFER)?;
            Ok(Some((buffer, vertices.len() as u32)))
        };
        let ink_buffers = [
            ("ink silhouette", upload("ink silhouette quads", &self.quads.silhouette)?),
            ("ink crease", upload("ink crease quads", &self.quads.crease)?),
            ("ink boundary", upload("ink boundary quads", &self.quads.boundary)?),
        ];
        let uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        let viewport = cartoon_shading::viewport(scene, self.renderer.extent());
        let outline_pass = self.technique == Technique::Outline;
        let clear = scene.background.extend(if outline_pass { 0.0 } else { 1.0 }).to_array();
        let ink_colour = Vec4::new(0.04, 0.04, 0.06, 1.0);
        let [r, g, b] = self.options.outline_colour.map(|c| c as f32 / 255.0);
        let outline_colour = Vec4::new(r, g, b, 1.0);
        // Lines are pulled towards the eye by about one line width at any distance: enough for a
        // crease between faces tilted up to ~60 degrees, far too little to show through a solid.
        let pixel = cartoon_shading::pixel_at_unit_distance(scene, self.renderer.extent().height);
        let pull = scene.camera.near * (self.options.line_width * pixel).max(1e-3);
        let (line_width, outline_width) = (self.options.line_width, self.options.outline_width);

        let (p, scene_pass, extruded, selected) = (&self.pipelines, &self.scene_pass, &self.extruded, &self.selected);
        let texture_set = scene_pass.ramps.set.set;
        let shade = |rec: &mut FrameRecorder, pipeline: &Pipeline, which: &dyn Fn(usize) -> bool, alpha: f32| {
            rec.bind(pipeline);
            rec.bind_sets(pipeline, 1, &[texture_set]);
            scene_pass.draw(rec, pipeline, scene, which, alpha, viewport);
        };
        let extrude = |rec: &mut FrameRecorder, pipeline: &Pipeline, which: &dyn Fn(usize) -> bool, px: f32, colour| {
            rec.bind(pipeline);
            extruded.draw(rec, pipeline, scene, which, Extrusion { width_px: px, colour }, viewport);
        };

        let output = self.renderer.render(&uniforms, clear, |rec| {
            if outline_pass {
                // Unselected first (the document draws the floor before the containers).
                rec.pass("scene", |rec| {
                    shade(rec, &p.shade, &|i| !selected[i], 0.0);
                    Ok(())
                })?;
                let selected_pipeline = p.selected.as_ref().unwrap_or(&p.shade);
                let name = if p.selected.is_some() { "selected (stencil)" } else { "selected" };
                rec.pass(name, |rec| {
                    shade(rec, selected_pipeline, &|i| selected[i], 1.0);
                    Ok(())
                })?;
                if let Some(outline) = &p.outline {
                    rec.pass(outline.desc.name, |rec| {
                        extrude(rec, outline, &|i| selected[i], outline_width, outline_colour);
                        Ok(())
                    })?;
                }
                return Ok(());
            }
            rec.pass("scene", |rec| {
                shade(rec, &p.shade, &|_| true, 1.0);
                Ok(())
            })?;
            if let Some(hull) = &p.hull {
                rec.pass("inverted hull", |rec| {
                    extrude(rec, hull, &|_| true, line_width, ink_colour);
                    Ok(())
                })?;
            }
            if let Some(pipeline) = &p.ink {
                for (class, (name, buffer)) in ink_buffers.iter().enumerate() {
                    rec.pass(name, |rec| {
                        rec.bind(pipeline);
                        let push = CartoonPush {
                            model: Mat4::IDENTITY,
                            colour: ink_colour,
                            params: Vec4::new(line_width, if class == 0 { 1.0 } else { 0.0 }, pull, 0.0),
                            viewport,
                        };
                        rec.push(pipeline, &push);
                        if let Some((buffer, count)) = buffer {
                            rec.draw_vertices(buffer, *count);
                        }
                        Ok(())
                    })?;
                }
            }
            Ok(())
        })?;

        let [silhouette_edges, crease_edges, boundary_edges] = self.quads.edge_counts();
        let stats = CartoonStats {
            method: (self.technique != Technique::Outline).then_some(self.options.silhouette),
            selected: scene
                .objects
                .iter()
                .zip(&self.selected)
                .filter(|(_, s)| **s && outline_pass)
                .map(|(o, _)| o.name.clone())
                .collect(),
            silhouette_edges,
            crease_edges,
            boundary_edges,
            edge_cpu_ms,
            total_edges: if self.edges { self.ink.iter().map(|m| m.adjacency.edges.len()).sum() } else { 0 },
        };
        Ok(CartoonFrame { output, stats })
    }
}

/// Renders one cartoon frame.
pub fn render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    width: u32,
    height: u32,
    stencil: StencilMode,
    technique: Technique,
    options: &CartoonOptions,
) -> Result<CartoonFrame> {
    CartoonRenderer::new(gpu, scene, width, height, stencil, technique, options)?.frame()
}
