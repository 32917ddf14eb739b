//! Shadow volumes counted in the colour alpha channel (seed 000, DESIGN.md section 2), and the
//! real-stencil reference they are proven against.
//!
//! Emulated frame, one render pass:
//! 1. scene: lit objects, every pixel's alpha set to 0 (the counter);
//! 2. volume increments (+k/255 per wall), then the saturation probe, then volume decrements:
//!    all increments come first because alpha clamps at 0 where a stencil would wrap;
//! 3. normalisation, one of: `seed` (N0, n iterations, REVERSE_SUBTRACT D, ADD D), `max`
//!    (N0, n iterations, MAX D) or `subpass` (read the count as an input attachment);
//! 4. apply: colour *= alpha (or, for `subpass`, *= the factor the shader outputs).
//!
//! Reference frame: scene, volumes with a two-sided INCREMENT_AND_WRAP / DECREMENT_AND_WRAP
//! stencil, and a full-screen apply pass with stencil test NOT_EQUAL 0.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3, Vec4};

use super::alpha_counter;
use super::lit::{LitPass, ObjectPush, OBJECT_PUSH_BYTES};
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::mesh::{self, EdgeAdjacency, VolumeGeometry, Welded};
use crate::pipeline::{
    BlendEquation, BlendState, DepthState, FixedFunction, Pipeline, PipelineDesc, RasterState, StencilFace,
    StencilState, VertexLayout,
};
use crate::render::{FrameOutput, FrameRecorder, FrameUniforms, GpuScene, Renderer};
use crate::scene::{Light, Scene};

/// How volume walls are counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum VolumeMethod {
    /// z-fail when the camera (or its near plane) is inside a volume, else z-pass.
    #[default]
    Auto,
    ZPass,
    ZFail,
}

/// How the count becomes a shadow mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Normalize {
    /// The seed's fixed-function sequence: N0, iterations, REVERSE_SUBTRACT D, ADD D, apply.
    #[default]
    Seed,
    /// As `seed`, with one MAX pass in place of the two D passes.
    Max,
    /// One full-screen pass reading the count as an input attachment.
    Subpass,
}

impl VolumeMethod {
    pub fn parse(text: &str) -> Result<Self> {
        match text {
            "auto" => Ok(VolumeMethod::Auto),
            "zpass" => Ok(VolumeMethod::ZPass),
            "zfail" => Ok(VolumeMethod::ZFail),
            _ => Err(Error::InvalidInput(format!("--volume-method {text}: use auto, zpass or zfail"))),
        }
    }
}

impl Normalize {
    pub const ALL: [Normalize; 3] = [Normalize::Seed, Normalize::Max, Normalize::Subpass];

    pub fn parse(text: &str) -> Result<Self> {
        match text {
            "seed" => Ok(Normalize::Seed),
            "max" => Ok(Normalize::Max),
            "subpass" => Ok(Normalize::Subpass),
            _ => Err(Error::InvalidInput(format!("--normalize {text}: use seed, max or subpass"))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Normalize::Seed => "seed",
            Normalize::Max => "max",
            Normalize::Subpass => "subpass",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ShadowVolumeOptions {
    /// k: each volume wall adds or removes k/255 of alpha (1..=8).
    pub increment: u8,
    pub method: VolumeMethod,
    pub normalize: Normalize,
    /// Shadowed colour = colour x shadow_factor/255. An 8-bit value, so that every path
    /// multiplies by exactly the same number.
    pub shadow_factor: u8,
}

impl Default for ShadowVolumeOptions {
    fn default() -> Self {
        ShadowVolumeOptions { increment: 1, method: VolumeMethod::Auto, normalize: Normalize::Seed, shadow_factor: 102 }
    }
}

// ---------------------------------------------------------------------------------------------
// Fixed-function recipes (DESIGN.md section 2), as data.

const ALPHA_ONLY: vk::ColorComponentFlags = vk::ColorComponentFlags::A;
const RGB_ONLY: vk::ColorComponentFlags =
    vk::ColorComponentFlags::from_raw(vk::ColorComponentFlags::RGBA.as_raw() & !vk::ColorComponentFlags::A.as_raw());

const fn alpha_blend(op: vk::BlendOp, src: vk::BlendFactor, dst: vk::BlendFactor) -> BlendState {
    BlendState { colour: None, alpha: Some(BlendEquation::new(op, src, dst)), write_mask: ALPHA_ONLY }
}

const fn colour_blend(op: vk::BlendOp, src: vk::BlendFactor, dst: vk::BlendFactor) -> BlendState {
    BlendState { colour: Some(BlendEquation::new(op, src, dst)), alpha: None, write_mask: RGB_ONLY }
}

const ONE: vk::BlendFactor = vk::BlendFactor::ONE;

fn volume_desc(name: &'static str, raster: RasterState, compare: vk::CompareOp, op: vk::BlendOp) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: "shadow_volume.vert",
        fragment_shader: "object_colour.frag",
        vertex_layout: VertexLayout::POSITION4,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster,
            depth: DepthState { compare: Some(compare), write: false },
            stencil: None,
            blend: alpha_blend(op, ONE, ONE),
        },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

fn fullscreen_desc(name: &'static str, fragment_shader: &'static str, blend: BlendState) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: "fullscreen.vert",
        fragment_shader,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction { blend, ..FixedFunction::FULLSCREEN },
        push_constant_bytes: 16,
        subpass: 0,
    }
}

/// Increment and decrement pipelines for one counting method.
pub fn volume_descs(zfail: bool) -> [PipelineDesc; 2] {
    const ADD: vk::BlendOp = vk::BlendOp::ADD;
    const REVERSE_SUBTRACT: vk::BlendOp = vk::BlendOp::REVERSE_SUBTRACT;
    const GREATER_OR_EQUAL: vk::CompareOp = vk::CompareOp::GREATER_OR_EQUAL;
    const LESS: vk::CompareOp = vk::CompareOp::LESS;
    if zfail {
        // Walls behind the visible surface count: back faces up, front faces down.
        [
            volume_desc("volume increment (z-fail)", RasterState::CULL_FRONT, GREATER_OR_EQUAL, ADD),
            volume_desc("volume decrement (z-fail)", RasterState::CULL_BACK, GREATER_OR_EQUAL, REVERSE_SUBTRACT),
        ]
    } else {
        // Walls in front of the visible surface count: front faces up, back faces down.
        [
            volume_desc("volume increment (z-pass)", RasterState::CULL_BACK, LESS, ADD),
            volume_desc("volume decrement (z-pass)", RasterState::CULL_FRONT, LESS, REVERSE_SUBTRACT),
        ]
    }
}

pub fn n0_desc() -> PipelineDesc {
    // 1 - 2a: lit pixels (a = 0) become 1.
    fullscreen_desc(
        "normalise N0",
        "solid.frag",
        alpha_blend(vk::BlendOp::SUBTRACT, vk::BlendFactor::ONE_MINUS_DST_ALPHA, ONE),
    )
}

pub fn iteration_desc() -> PipelineDesc {
    // a*a - (1 - a): 1 stays 1, a deficit d grows to 3d - d*d.
    fullscreen_desc(
        "normalise iteration",
        "solid.frag",
        alpha_blend(vk::BlendOp::REVERSE_SUBTRACT, vk::BlendFactor::ONE_MINUS_DST_ALPHA, vk::BlendFactor::DST_ALPHA),
    )
}

pub fn darkness_descs(normalize: Normalize) -> Vec<PipelineDesc> {
    match normalize {
        Normalize::Seed => vec![
            fullscreen_desc("darkness subtract D", "solid.frag", alpha_blend(vk::BlendOp::REVERSE_SUBTRACT, ONE, ONE)),
            fullscreen_desc("darkness add D", "solid.frag", alpha_blend(vk::BlendOp::ADD, ONE, ONE)),
        ],
        Normalize::Max => {
            vec![fullscreen_desc("darkness max D", "solid.frag", alpha_blend(vk::BlendOp::MAX, ONE, ONE))]
        }
        Normalize::Subpass => vec![],
    }
}

pub fn apply_desc(normalize: Normalize) -> PipelineDesc {
    match normalize {
        // colour *= dst alpha (1 where lit, D where shadowed).
        Normalize::Seed | Normalize::Max => fullscreen_desc(
            "apply",
            "solid.frag",
            colour_blend(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::DST_ALPHA),
        ),
        // colour *= the factor the shader read from the count.
        Normalize::Subpass => fullscreen_desc(
            "apply (subpass)",
            "shadow_subpass.frag",
            colour_blend(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_ALPHA),
        ),
    }
}

pub fn saturation_probe_desc() -> PipelineDesc {
    let mut desc = fullscreen_desc("saturation probe", "saturation_probe.frag", BlendState::OPAQUE);
    desc.fixed.blend.write_mask = vk::ColorComponentFlags::empty();
    desc.push_constant_bytes = 0;
    desc
}

pub fn reference_volume_desc(zfail: bool) -> PipelineDesc {
    let face = |pass, depth_fail| StencilFace {
        compare: vk::CompareOp::ALWAYS,
        reference: 0,
        compare_mask: 0xff,
        write_mask: 0xff,
        fail: vk::StencilOp::KEEP,
        pass,
        depth_fail,
    };
    const INC: vk::StencilOp = vk::StencilOp::INCREMENT_AND_WRAP;
    const DEC: vk::StencilOp = vk::StencilOp::DECREMENT_AND_WRAP;
    const KEEP: vk::StencilOp = vk::StencilOp::KEEP;
    let (front, back, compare) = if zfail {
        (face(KEEP, DEC), face(KEEP, INC), vk::CompareOp::LESS)
    } else {
        (face(INC, KEEP), face(DEC, KEEP), vk::CompareOp::LESS)
    };
    let mut desc = volume_desc(
        if zfail { "volumes (stencil, z-fail)" } else { "volumes (stencil, z-pass)" },
        RasterState::CULL_NONE,
        compare,
        vk::BlendOp::ADD,
    );
    desc.fixed.stencil = Some(StencilState { front, back });
    desc.fixed.blend = BlendState { colour: None, alpha: None, write_mask: vk::ColorComponentFlags::empty() };
    desc
}

/// Counts below zero (the stencil wraps them to 128..255) can only come from rasterisation
/// precision where volume walls meet their caster. The alpha counter clamps them to 0, so the
/// reference sets them to 0 as well before applying: both paths then shade exactly
/// `max(0, increments - decrements)`, and agree bit for bit.
pub fn reference_clear_negative_desc() -> PipelineDesc {
    let negative_to_zero = StencilFace {
        // 128 <= stencil: a wrapped negative count.
        compare: vk::CompareOp::LESS_OR_EQUAL,
        reference: 0x80,
        compare_mask: 0xff,
        write_mask: 0xff,
        fail: vk::StencilOp::KEEP,
        pass: vk::StencilOp::ZERO,
        depth_fail: vk::StencilOp::KEEP,
    };
    let mut desc = fullscreen_desc(
        "clear negative counts (stencil)",
        "solid.frag",
        BlendState { colour: None, alpha: None, write_mask: vk::ColorComponentFlags::empty() },
    );
    desc.fixed.stencil = Some(StencilState { front: negative_to_zero, back: negative_to_zero });
    desc
}

pub fn reference_apply_desc() -> PipelineDesc {
    let not_zero = StencilFace {
        compare: vk::CompareOp::NOT_EQUAL,
        reference: 0,
        compare_mask: 0xff,
        write_mask: 0,
        fail: vk::StencilOp::KEEP,
        pass: vk::StencilOp::KEEP,
        depth_fail: vk::StencilOp::KEEP,
    };
    let mut desc = fullscreen_desc(
        "apply (stencil)",
        "solid.frag",
        colour_blend(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_ALPHA),
    );
    desc.fixed.stencil = Some(StencilState { front: not_zero, back: not_zero });
    desc
}

/// Every pipeline the technique can build, in pass order, labelled with its path: what
/// `nostencil passes` prints.
pub fn pipeline_descs(options: &ShadowVolumeOptions) -> Vec<(&'static str, PipelineDesc)> {
    let mut descs = vec![("emulated", super::lit::scene_pipeline_desc())];
    for zfail in [false, true] {
        let [increment, decrement] = volume_descs(zfail);
        descs.push(("emulated", increment));
        if !zfail {
            descs.push(("emulated", saturation_probe_desc()));
        }
        descs.push(("emulated", decrement));
    }
    if options.normalize != Normalize::Subpass {
        descs.push(("emulated seed/max", n0_desc()));
        descs.push(("emulated seed/max", iteration_desc()));
    }
    descs.extend(darkness_descs(options.normalize).into_iter().map(|d| ("emulated", d)));
    descs.push(("emulated", apply_desc(options.normalize)));
    descs.push(("reference", super::lit::scene_pipeline_desc()));
    descs.push(("reference", reference_volume_desc(false)));
    descs.push(("reference", reference_volume_desc(true)));
    descs.push(("reference", reference_clear_negative_desc()));
    descs.push(("reference", reference_apply_desc()));
    descs
}

// ---------------------------------------------------------------------------------------------
// CPU side: casters and their volumes.

/// Positions closer than this weld into one vertex (UV seams, split normals).
const WELD_EPSILON: f32 = 1e-5;

/// A shadow caster with its topology, built once.
pub struct Caster {
    pub object: usize,
    pub welded: Welded,
    pub adjacency: EdgeAdjacency,
}

/// Welds and checks every shadow-casting object; an open or non-manifold mesh is refused with
/// its name.
pub fn prepare_casters(scene: &Scene) -> Result<Vec<Caster>> {
    scene
        .objects
        .iter()
        .enumerate()
        .filter(|(_, o)| o.casts_shadow)
        .map(|(object, o)| {
            let data = &scene.meshes[o.mesh].data;
            let name = format!("{} (object '{}')", scene.meshes[o.mesh].name, o.name);
            let welded = mesh::weld_by_position(&name, &data.positions, &data.indices, WELD_EPSILON)?;
            let adjacency = EdgeAdjacency::build(&name, &welded.positions, &welded.indices)?;
            adjacency.require_closed_manifold().map_err(|e| match e {
                Error::Mesh { mesh, problem } => Error::Mesh {
                    mesh,
                    problem: format!("{problem}; shadow volumes need closed meshes (mark it as not casting shadows)"),
                },
                other => other,
            })?;
            Ok(Caster { object, welded, adjacency })
        })
        .collect()
}

/// The light in an object's own space (volumes are built there and transformed like the mesh).
fn light_in_object_space(light: &Light, model: &Mat4) -> mesh::Light {
    let inverse = model.inverse();
    match *light {
        Light::Directional { direction } => mesh::Light::Directional(inverse.transform_vector3(direction)),
        Light::Point { position } => mesh::Light::Point(inverse.transform_point3(position)),
    }
}

pub fn build_volume(scene: &Scene, caster: &Caster, caps: bool) -> VolumeGeometry {
    let object = &scene.objects[caster.object];
    let light = light_in_object_space(&scene.light, &object.transform);
    if let Some(positions) = posed_welded_positions(scene, caster) {
        let mut normals = Vec::new();
        caster.adjacency.recompute_face_normals(&positions, &mut normals);
        return mesh::build_shadow_volume(&caster.adjacency, &positions, &normals, light, caps);
    }
    mesh::build_shadow_volume(&caster.adjacency, &caster.welded.positions, &caster.adjacency.face_normals, light, caps)
}

/// A skinned caster's welded vertices in its current pose (`Scene::pose_at` moves palettes,
/// not meshes; the welded topology stays); `None` for a rigid caster.
fn posed_welded_positions(scene: &Scene, caster: &Caster) -> Option<Vec<Vec3>> {
    let skin = scene.objects[caster.object].skin.as_ref()?;
    if skin.positions.len() < caster.welded.remap.len() {
        return None;
    }
    let mut positions = Vec::new();
    caster.welded.gather_positions(&skin.posed_positions(), &mut positions);
    Some(positions)
}

/// Whether a world-space point lies in some caster's shadow (inside its volume): the ray from
/// the point towards the light hits the caster. `posed` holds each caster's welded vertices in
/// their current pose (see [`posed_welded_positions`]), or `None` for the welded mesh as built.
fn in_shadow(scene: &Scene, casters: &[Caster], posed: &[Option<Vec<Vec3>>], point: Vec3) -> bool {
    let (towards_light, max_t) = match scene.light {
        Light::Directional { direction } => (-direction.normalize(), f32::INFINITY),
        Light::Point { position } => ((position - point).normalize(), (position - point).length()),
    };
    casters.iter().zip(posed).any(|(caster, posed)| {
        let model = scene.objects[caster.object].transform;
        let positions = posed.as_deref().unwrap_or(&caster.welded.positions);
        let p = |i: u32| model.transform_point3(positions[i as usize]);
        caster
            .welded
            .indices
            .chunks_exact(3)
            .any(|t| ray_hits_triangle(point, towards_light, [p(t[0]), p(t[1]), p(t[2])]).is_some_and(|d| d < max_t))
    })
}

/// Möller–Trumbore; the distance along `dir` to the hit.
fn ray_hits_triangle(origin: Vec3, dir: Vec3, t: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - t[0];
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    let d = e2.dot(q) * inv;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && d > 0.0).then_some(d)
}

/// z-pass breaks when the near plane cuts a volume: test the eye and the near-plane corners.
pub fn camera_inside_volume(scene: &Scene, casters: &[Caster], aspect: f32) -> bool {
    let camera = &scene.camera;
    let inverse = camera.view_projection(aspect).inverse();
    let corners =
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| inverse.project_point3(Vec3::new(x, y, 0.0)));
    // Skinned casters are posed once for the five points.
    let posed: Vec<Option<Vec<Vec3>>> = casters.iter().map(|c| posed_welded_positions(scene, c)).collect();
    std::iter::once(camera.eye).chain(corners).any(|p| in_shadow(scene, casters, &posed, p))
}

pub fn choose_zfail(options: &ShadowVolumeOptions, scene: &Scene, casters: &[Caster], aspect: f32) -> bool {
    match options.method {
        VolumeMethod::ZPass => false,
        VolumeMethod::ZFail => true,
        VolumeMethod::Auto => camera_inside_volume(scene, casters, aspect),
    }
}

// ---------------------------------------------------------------------------------------------
// GPU side.

/// One caster's volume, uploaded for this frame.
struct GpuVolume {
    object: usize,
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
}

fn upload_volumes(gpu: &Arc<Gpu>, scene: &Scene, casters: &[Caster], zfail: bool) -> Result<Vec<GpuVolume>> {
    casters
        .iter()
        .map(|caster| {
            // Far caps close point-light volumes at infinity: drawn in both methods, so that
            // the background (depth 1) behind a volume never counts. Near caps only for z-fail.
            let volume = build_volume(scene, caster, true);
            let mut indices = volume.sides.clone();
            if zfail {
                indices.extend_from_slice(&volume.near_cap);
            }
            indices.extend_from_slice(&volume.far_cap);
            let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
            Ok(GpuVolume {
                object: caster.object,
                vertices: Buffer::with_data(gpu, "shadow volume vertices", &volume.vertices, usage)?,
                indices: Buffer::with_data(gpu, "shadow volume indices", &indices, vk::BufferUsageFlags::INDEX_BUFFER)?,
                index_count: indices.len() as u32,
            })
        })
        .collect()
}

fn draw_volumes(rec: &mut FrameRecorder, pipeline: &Pipeline, scene: &Scene, volumes: &[GpuVolume], alpha: f32) {
    rec.bind(pipeline);
    for volume in volumes {
        let push =
            ObjectPush { model: scene.objects[volume.object].transform, colour: Vec4::new(0.0, 0.0, 0.0, alpha) };
        rec.push(pipeline, &push);
        rec.draw_indexed(&volume.vertices, &volume.indices, volume.index_count);
    }
}

/// The colour attachment bound as an input attachment (for `subpass` and the saturation probe).
fn counter_input(gpu: &Arc<Gpu>, colour_view: vk::ImageView) -> Result<DescriptorSet> {
    DescriptorSet::new(gpu, &[Binding::InputAttachment { view: colour_view, layout: vk::ImageLayout::GENERAL }])
}

/// What the frame did, beyond its image and counters.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct ShadowVolumeStats {
    pub zfail: bool,
    pub seed_iterations: usize,
    /// The largest count the alpha counter holds: 255 / k.
    pub capacity: u32,
    /// Pixels whose counter reached 255 after the increments (emulated frames only).
    pub saturated_pixels: Option<u64>,
}

pub struct ShadowVolumeFrame {
    pub output: FrameOutput,
    pub stats: ShadowVolumeStats,
}

fn solid(alpha: f32) -> Vec4 {
    Vec4::new(0.0, 0.0, 0.0, alpha)
}

/// The pipelines of one frame kind (the reference's are the larger; there is one per renderer).
#[allow(clippy::large_enum_variant)]
enum Passes {
    Reference { volumes: Pipeline, clear_negative: Pipeline, apply: Pipeline },
    Emulated(Box<EmulatedPasses>),
}

struct EmulatedPasses {
    input: DescriptorSet,
    increment: Pipeline,
    decrement: Pipeline,
    probe: Pipeline,
    /// N0 and the iteration; None for `subpass`.
    seed: Option<(Pipeline, Pipeline)>,
    darkness: Vec<Pipeline>,
    apply: Pipeline,
}

/// Everything a shadow-volume frame needs, built once; `frame` renders one frame (volumes are
/// rebuilt and uploaded each frame, as a moving light or mesh would need).
pub struct ShadowVolumeRenderer<'s> {
    gpu: Arc<Gpu>,
    scene: &'s Scene,
    options: ShadowVolumeOptions,
    renderer: Renderer,
    casters: Vec<Caster>,
    meshes: GpuScene,
    lit: LitPass,
    passes: Passes,
    stats: ShadowVolumeStats,
}

impl<'s> ShadowVolumeRenderer<'s> {
    pub fn new(
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        width: u32,
        height: u32,
        stencil: StencilMode,
        options: &ShadowVolumeOptions,
    ) -> Result<Self> {
        let k = alpha_counter::check_increment(options.increment)?;
        let casters = prepare_casters(scene)?;
        let emulated = stencil == StencilMode::Emulated;
        let renderer = Renderer::new(gpu, width, height, stencil, emulated)?;
        let zfail = choose_zfail(options, scene, &casters, renderer.aspect());
        let meshes = GpuScene::upload(gpu, scene)?;
        let lit = LitPass::new(gpu, &renderer)?;
        let render_pass = renderer.targets.render_pass;
        let frame_layout = [renderer.frame.layout];
        let iterations = alpha_counter::seed_iterations(k)?;
        let passes = if emulated {
            let input = counter_input(gpu, renderer.targets.colour.view)?;
            let input_layout = [input.layout];
            let [increment_desc, decrement_desc] = volume_descs(zfail);
            let seed = match options.normalize {
                Normalize::Subpass => None,
                _ => Some((
                    Pipeline::new(gpu, &n0_desc(), render_pass, &[])?,
                    Pipeline::new(gpu, &iteration_desc(), render_pass, &[])?,
                )),
            };
            let apply_sets: &[vk::DescriptorSetLayout] =
                if options.normalize == Normalize::Subpass { &input_layout } else { &[] };
            Passes::Emulated(Box::new(EmulatedPasses {
                increment: Pipeline::new(gpu, &increment_desc, render_pass, &frame_layout)?,
                decrement: Pipeline::new(gpu, &decrement_desc, render_pass, &frame_layout)?,
                probe: Pipeline::new(gpu, &saturation_probe_desc(), render_pass, &input_layout)?,
                seed,
                darkness: darkness_descs(options.normalize)
                    .iter()
                    .map(|d| Pipeline::new(gpu, d, render_pass, &[]))
                    .collect::<Result<Vec<_>>>()?,
                apply: Pipeline::new(gpu, &apply_desc(options.normalize), render_pass, apply_sets)?,
                input,
            }))
        } else {
            Passes::Reference {
                volumes: Pipeline::new(gpu, &reference_volume_desc(zfail), render_pass, &frame_layout)?,
                clear_negative: Pipeline::new(gpu, &reference_clear_negative_desc(), render_pass, &[])?,
                apply: Pipeline::new(gpu, &reference_apply_desc(), render_pass, &[])?,
            }
        };
        Ok(ShadowVolumeRenderer {
            gpu: gpu.clone(),
            scene,
            options: *options,
            renderer,
            casters,
            meshes,
            lit,
            passes,
            stats: ShadowVolumeStats {
                zfail,
                seed_iterations: iterations,
                capacity: alpha_counter::capacity(k),
                saturated_pixels: None,
            },
        })
    }

    /// Heat-map frames (see `Renderer::count_overdraw`).
    pub fn count_overdraw(&mut self, on: bool) {
        self.renderer.count_overdraw = on;
    }

    pub fn frame(&mut self) -> Result<ShadowVolumeFrame> {
        self.frame_with(self.scene)
    }

    /// Renders `scene`: the scene this renderer was built for with the camera, the light or
    /// object transforms changed (the viewer orbits, moves the light, spins objects). Meshes
    /// and which objects cast shadows must be unchanged: casters were prepared once.
    pub fn frame_with(&mut self, scene: &Scene) -> Result<ShadowVolumeFrame> {
        crate::technique::check_same_scene(self.scene, scene, "shadow-volume")?;
        self.meshes.follow_pose(&self.gpu, scene)?;
        let volumes = upload_volumes(&self.gpu, scene, &self.casters, self.stats.zfail)?;
        let uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        let shadow_factor = self.options.shadow_factor as f32 / 255.0;
        // The scene writes alpha 0 everywhere: the counter starts at zero.
        let clear = scene.background.extend(0.0).to_array();
        let step = self.options.increment as f32 / 255.0;
        let iterations = self.stats.seed_iterations;
        let colour_image = self.renderer.targets.colour.raw;
        let (lit, meshes) = (&self.lit, &self.meshes);
        let output = match &self.passes {
            Passes::Reference { volumes: volumes_pipeline, clear_negative, apply } => {
                self.renderer.render(&uniforms, clear, |rec| {
                    lit.record(rec, scene, meshes, |_| 0.0)?;
                    rec.pass(volumes_pipeline.desc.name, |rec| {
                        draw_volumes(rec, volumes_pipeline, scene, &volumes, 0.0);
                        Ok(())
                    })?;
                    rec.pass(clear_negative.desc.name, |rec| {
                        rec.bind(clear_negative);
                        rec.push(clear_negative, &solid(0.0));
                        rec.draw_fullscreen();
                        Ok(())
                    })?;
                    rec.pass(apply.desc.name, |rec| {
                        rec.bind(apply);
                        rec.push(apply, &solid(shadow_factor));
                        rec.draw_fullscreen();
                        Ok(())
                    })
                })?
            }
            Passes::Emulated(emulated) => {
                let EmulatedPasses { input, increment, decrement, probe, seed, darkness, apply } = &**emulated;
                self.renderer.render(&uniforms, clear, |rec| {
                    lit.record(rec, scene, meshes, |_| 0.0)?;
                    rec.pass(increment.desc.name, |rec| {
                        draw_volumes(rec, increment, scene, &volumes, step);
                        Ok(())
                    })?;
                    rec.pass(probe.desc.name, |rec| {
                        rec.colour_feedback_barrier(colour_image);
                        rec.bind_with_sets(probe, &[input.set]);
                        rec.draw_fullscreen();
                        Ok(())
                    })?;
                    rec.pass(decrement.desc.name, |rec| {
                        draw_volumes(rec, decrement, scene, &volumes, step);
                        Ok(())
                    })?;
                    match seed {
                        Some((n0, iteration)) => {
                            record_seed_normalisation(rec, n0, iteration, iterations)?;
                            for pipeline in darkness {
                                rec.pass(pipeline.desc.name, |rec| {
                                    rec.bind(pipeline);
                                    rec.push(pipeline, &solid(shadow_factor));
                                    rec.draw_fullscreen();
                                    Ok(())
                                })?;
                            }
                            rec.pass(apply.desc.name, |rec| {
                                rec.bind(apply);
                                rec.push(apply, &solid(1.0));
                                rec.draw_fullscreen();
                                Ok(())
                            })
                        }
                        None => rec.pass(apply.desc.name, |rec| {
                            rec.colour_feedback_barrier(colour_image);
                            rec.bind_with_sets(apply, &[input.set]);
                            rec.push(apply, &Vec4::new(shadow_factor, 0.0, 0.0, 0.0));
                            rec.draw_fullscreen();
                            Ok(())
                        }),
                    }
                })?
            }
        };
        let mut stats = self.stats;
        stats.saturated_pixels = output.counters.pass("saturation probe").map(|p| p.samples_passed);
        Ok(ShadowVolumeFrame { output, stats })
    }
}

impl ShadowVolumeRenderer<'_> {
    /// Whether `scene` (a moved camera or light) needs the other counting method than the one
    /// this renderer was built with: with `--volume-method auto` the caller then rebuilds.
    pub fn wants_zfail(&self, scene: &Scene) -> bool {
        choose_zfail(&self.options, scene, &self.casters, self.renderer.aspect())
    }

    pub fn zfail(&self) -> bool {
        self.stats.zfail
    }

    /// The offscreen renderer underneath (its targets, `keep_on_gpu`).
    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }
}

/// Renders `scene` with shadow volumes, emulated in alpha or with the real-stencil reference.
pub fn render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    width: u32,
    height: u32,
    stencil: StencilMode,
    options: &ShadowVolumeOptions,
) -> Result<ShadowVolumeFrame> {
    ShadowVolumeRenderer::new(gpu, scene, width, height, stencil, options)?.frame()
}

/// N0 then `iterations` iterations, each a measured full-screen pass writing alpha only.
pub fn record_seed_normalisation(
    rec: &mut FrameRecorder,
    n0: &Pipeline,
    iteration: &Pipeline,
    iterations: usize,
) -> Result<()> {
    rec.pass("normalise N0", |rec| {
        rec.bind(n0);
        rec.push(n0, &solid(1.0));
        rec.draw_fullscreen();
        Ok(())
    })?;
    for i in 1..=iterations {
        rec.pass(&format!("normalise N{i}"), |rec| {
            rec.bind(iteration);
            rec.push(iteration, &solid(1.0));
            rec.draw_fullscreen();
            Ok(())
        })?;
    }
    Ok(())
}
