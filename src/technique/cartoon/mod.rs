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
use glam::{Mat4, Vec3, Vec4};

use self::ink::{InkMesh, InkQuads, InkVertex};
use super::Technique;
use crate::error::{Error, Result};
use crate::frame::{RgbaImage, StencilMode};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::texture::{Sampler, Texture};
use crate::gpu::Gpu;
use crate::pipeline::{
    BlendEquation, BlendState, DepthState, FixedFunction, Pipeline, PipelineDesc, RasterState, StencilFace,
    StencilState, VertexAttribute, VertexLayout,
};
use crate::render::{FrameOutput, FrameRecorder, FrameUniforms, GpuMesh, GpuScene, Renderer};
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

/// Which objects are selected, by index; an unknown name is refused with the scene's names.
pub fn resolve_selection(scene: &Scene, names: &[String]) -> Result<Vec<bool>> {
    let mut selected = vec![false; scene.objects.len()];
    if names.is_empty() {
        let first = scene.objects.iter().position(|o| o.casts_shadow).or((!scene.objects.is_empty()).then_some(0));
        if let Some(i) = first {
            selected[i] = true;
        }
        return Ok(selected);
    }
    for name in names {
        let index = scene.objects.iter().position(|o| &o.name == name).ok_or_else(|| {
            Error::InvalidInput(format!(
                "--select: scene '{}' has no object '{name}'; its objects: {}",
                scene.name,
                scene.objects.iter().map(|o| o.name.as_str()).collect::<Vec<_>>().join(", ")
            ))
        })?;
        selected[index] = true;
    }
    Ok(selected)
}

// ---------------------------------------------------------------------------------------------
// Fixed-function recipes, as data.

/// Mirrors `CartoonPush` in `shaders/cartoon_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CartoonPush {
    pub model: Mat4,
    pub colour: Vec4,
    pub params: Vec4,
    pub viewport: Vec4,
}

pub const CARTOON_PUSH_BYTES: u32 = std::mem::size_of::<CartoonPush>() as u32;

const RGB_ONLY: vk::ColorComponentFlags =
    vk::ColorComponentFlags::from_raw(vk::ColorComponentFlags::RGBA.as_raw() & !vk::ColorComponentFlags::A.as_raw());

/// position (vec3) a, b, c + corner (vec2): `InkVertex`.
pub const INK_LAYOUT: VertexLayout = VertexLayout {
    attributes: &[VertexAttribute::Vec3, VertexAttribute::Vec3, VertexAttribute::Vec3, VertexAttribute::Vec2],
};

fn desc(
    name: &'static str,
    vs: &'static str,
    fs: &'static str,
    layout: VertexLayout,
    fixed: FixedFunction,
) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: vs,
        fragment_shader: fs,
        vertex_layout: layout,
        fixed,
        push_constant_bytes: CARTOON_PUSH_BYTES,
        subpass: 0,
    }
}

/// The scene: Lambert or toon, optionally with the N.V rim; writes the alpha it is given.
pub fn shade_desc() -> PipelineDesc {
    desc("scene", "cartoon_shade.vert", "cartoon_shade.frag", VertexLayout::POSITION_NORMAL, FixedFunction::OPAQUE)
}

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
    desc("outline", "cartoon_extrude.vert", "cartoon_colour.frag", VertexLayout::POSITION_NORMAL, outline_fixed(blend))
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
    let mut d = desc(
        "outline (stencil)",
        "cartoon_extrude.vert",
        "cartoon_colour.frag",
        VertexLayout::POSITION_NORMAL,
        outline_fixed(blend),
    );
    d.fixed.stencil = Some(StencilState { front: not_one, back: not_one });
    d
}

/// Ink quads: depth tested (LESS_OR_EQUAL, pulled towards the eye in the vertex shader), no
/// depth write, colour only.
pub fn ink_desc() -> PipelineDesc {
    desc(
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
    desc(
        "inverted hull",
        "cartoon_extrude.vert",
        "cartoon_colour.frag",
        VertexLayout::POSITION_NORMAL,
        FixedFunction { raster: RasterState::CULL_FRONT, ..FixedFunction::OPAQUE },
    )
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
// Textures: the toon ramp and the dark rim, Nx1 RGBA8, nearest filtering.

/// N.L -> light: three flat bands (shadow, mid, lit), as cel painters use.
pub fn toon_ramp() -> RgbaImage {
    let mut pixels = Vec::new();
    for i in 0..16 {
        let level: u8 = match i {
            0..=4 => 110,
            5..=10 => 190,
            _ => 255,
        };
        pixels.extend_from_slice(&[level, level, level, 255]);
    }
    RgbaImage { width: 16, height: 1, pixels }
}

/// N.V -> ink: the first texels (grazing angles) black, the rest white (seed 002: "1x32, the
/// first few texels near u = 0 black"). N.V < 0.44 is dark: on a sphere that is the outer 10%
/// of its radius on screen (N.V falls fast near the contour, so fewer texels draw a hairline).
pub fn rim_ramp() -> RgbaImage {
    let mut pixels = Vec::new();
    for i in 0..32 {
        let level = if i < 14 { 0 } else { 255 };
        pixels.extend_from_slice(&[level, level, level, 255]);
    }
    RgbaImage { width: 32, height: 1, pixels }
}

struct Textures {
    set: DescriptorSet,
    _ramp: Texture,
    _rim: Texture,
}

impl Textures {
    fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let nearest = || Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE);
        let format = vk::Format::R8G8B8A8_UNORM;
        let ramp = Texture::from_rgba8(gpu, "toon ramp", &toon_ramp(), format, false, nearest()?)?;
        let rim = Texture::from_rgba8(gpu, "rim ramp", &rim_ramp(), format, false, nearest()?)?;
        let binding = |t: &Texture| Binding::Texture {
            view: t.image.view,
            sampler: t.sampler.raw,
            layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            stages: vk::ShaderStageFlags::FRAGMENT,
        };
        let set = DescriptorSet::new(gpu, &[binding(&ramp), binding(&rim)])?;
        Ok(Textures { set, _ramp: ramp, _rim: rim })
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
    meshes: GpuScene,
    /// Per object: welded mesh with smooth normals (outline copy, hull).
    extruded: Vec<GpuMesh>,
    /// Per object: its welded mesh and edge list (ink lines when `edges`; the extruded copy).
    ink: Vec<InkMesh>,
    /// Ink lines from the edge list (`--silhouette edges`).
    edges: bool,
    quads: InkQuads,
    selected: Vec<bool>,
    textures: Textures,
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
        let meshes = GpuScene::upload(gpu, scene)?;
        let textures = Textures::new(gpu)?;
        let render_pass = renderer.targets.render_pass;
        let frame_only = [renderer.frame.layout];
        let with_textures = [renderer.frame.layout, textures.set.layout];
        let edges = technique != Technique::Outline && options.silhouette == SilhouetteMethod::Edges;
        let hull = technique != Technique::Outline && options.silhouette == SilhouetteMethod::Hull;
        let reference = stencil == StencilMode::Reference;

        let mut extruded = Vec::new();
        let mut ink = Vec::new();
        for (index, object) in scene.objects.iter().enumerate() {
            let prepared = InkMesh::new(scene, index)?;
            extruded.push(GpuMesh::from_raw(
                gpu,
                &format!("{} (extruded)", object.name),
                &extruded_vertices(&prepared),
                &prepared.welded.indices,
            )?);
            ink.push(prepared);
        }

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
            meshes,
            extruded,
            ink,
            edges,
            quads: InkQuads::default(),
            selected,
            textures,
            pipelines,
        })
    }

    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// World size of one pixel at unit distance from the eye.
    fn pixel_at_unit_distance(&self, scene: &Scene) -> f32 {
        2.0 * (0.5 * scene.camera.fov_y_radians).tan() / self.renderer.extent().height as f32
    }

    fn viewport(&self, scene: &Scene) -> Vec4 {
        let extent = self.renderer.extent();
        Vec4::new(extent.width as f32, extent.height as f32, self.pixel_at_unit_distance(scene), 0.0)
    }

    /// Skinned objects whose palette changed (`Scene::pose_at`) get their lit mesh, welded
    /// positions (so the per-frame face normals and edges) and extruded copy re-posed.
    fn follow_pose(&mut self, scene: &Scene) -> Result<()> {
        for index in self.meshes.follow_pose(&self.gpu, scene)? {
            let object = &scene.objects[index];
            let (Some(skin), Some(ink)) = (&object.skin, self.ink.get_mut(index)) else { continue };
            if !ink.follow(skin) {
                continue;
            }
            if let Some(mesh) = self.extruded.get_mut(index) {
                mesh.vertices = Buffer::device_local(
                    &self.gpu,
                    &format!("{} (extruded, posed)", object.name),
                    &extruded_vertices(ink),
                    vk::BufferUsageFlags::VERTEX_BUFFER,
                )?;
            }
        }
        Ok(())
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
            let buffer = Buffer::with_data(&gpu, name, vertices, vk::BufferUsageFlags::VERTEX_BUFFER)?;
            Ok(Some((buffer, vertices.len() as u32)))
        };
        let ink_buffers = [
            ("ink silhouette", upload("ink silhouette quads", &self.quads.silhouette)?),
            ("ink crease", upload("ink crease quads", &self.quads.crease)?),
            ("ink boundary", upload("ink boundary quads", &self.quads.boundary)?),
        ];
        let uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        let viewport = self.viewport(scene);
        let toon = if self.technique == Technique::Toon { 1.0 } else { 0.0 };
        let rim = if self.technique != Technique::Outline && self.options.silhouette == SilhouetteMethod::Shader {
            1.0
        } else {
            0.0
        };
        let outline_pass = self.technique == Technique::Outline;
        let clear = scene.background.extend(if outline_pass { 0.0 } else { 1.0 }).to_array();
        let ink_colour = Vec4::new(0.04, 0.04, 0.06, 1.0);
        let [r, g, b] = self.options.outline_colour.map(|c| c as f32 / 255.0);
        let outline_colour = Vec4::new(r, g, b, 1.0);
        // Lines are pulled towards the eye by about one line width at any distance: enough for a
        // crease between faces tilted up to ~60 degrees, far too little to show through a solid.
        let pull = scene.camera.near * (self.options.line_width * self.pixel_at_unit_distance(scene)).max(1e-3);
        let (line_width, outline_width) = (self.options.line_width, self.options.outline_width);

        let (p, meshes, extruded, selected, texture_set) =
            (&self.pipelines, &self.meshes, &self.extruded, &self.selected, self.textures.set.set);
        let shade = |rec: &mut FrameRecorder, pipeline: &Pipeline, which: &dyn Fn(usize) -> bool, alpha: f32| {
            rec.bind(pipeline);
            unsafe {
                rec.device().cmd_bind_descriptor_sets(
                    rec.cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    pipeline.layout,
                    1,
                    &[texture_set],
                    &[],
                )
            };
            for (_, object) in scene.objects.iter().enumerate().filter(|(i, _)| which(*i)) {
                let push = CartoonPush {
                    model: object.transform,
                    colour: object.colour.extend(alpha),
                    params: Vec4::new(toon, rim, 0.0, 0.0),
                    viewport,
                };
                rec.push(pipeline, &push);
                rec.draw_mesh(&meshes.meshes[object.mesh]);
            }
        };
        let extrude = |rec: &mut FrameRecorder, pipeline: &Pipeline, which: &dyn Fn(usize) -> bool, px: f32, colour| {
            rec.bind(pipeline);
            for (index, object) in scene.objects.iter().enumerate().filter(|(i, _)| which(*i)) {
                let push =
                    CartoonPush { model: object.transform, colour, params: Vec4::new(px, 0.0, 0.0, 0.0), viewport };
                rec.push(pipeline, &push);
                rec.draw_mesh(&extruded[index]);
            }
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

/// The welded mesh with smooth normals, interleaved: the outline copy and the inverted hull.
fn extruded_vertices(ink: &InkMesh) -> Vec<[Vec3; 2]> {
    let normals = ink::smooth_normals(&ink.welded);
    ink.welded.positions.iter().zip(&normals).map(|(p, n)| [*p, *n]).collect()
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
