//! Planar projected shadows (seed 001, DESIGN.md section 3): every caster drawn a second time,
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

pub mod blob;
pub mod shadow_texture;
pub mod skin;

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3, Vec4};

use super::lit::{ObjectPush, OBJECT_PUSH_BYTES};
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::pipeline::{
    BlendEquation, BlendState, DepthBias, DepthState, FixedFunction, Pipeline, PipelineDesc, RasterState, StencilFace,
    StencilState, VertexLayout,
};
use crate::render::{FrameOutput, FrameRecorder, FrameUniforms, GpuScene, Renderer};
use crate::scene::{Light, Scene};
use skin::{SkinnedMesh, SKINNED_LAYOUT};

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PlanarOptions {
    /// Shadowed receiver colour = colour x shadow_factor/255 (`1 - s` as an 8-bit value, so that
    /// both paths multiply by exactly the same number).
    pub shadow_factor: u8,
    /// Draw the projected shadows (off: the scene pass alone, GPU-skinned, with the receiver
    /// mask in alpha: what the tests compare against).
    pub shadows: bool,
}

impl Default for PlanarOptions {
    fn default() -> Self {
        PlanarOptions { shadow_factor: 102, shadows: true }
    }
}

/// Mirrors `PlanarPush` in `shaders/planar_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlanarPush {
    pub model: Mat4,
    pub colour: Vec4,
    /// x: plane height h.
    pub plane: Vec4,
}

pub const PLANAR_PUSH_BYTES: u32 = std::mem::size_of::<PlanarPush>() as u32;

// ---------------------------------------------------------------------------------------------
// The projection, on the CPU: the same formula as `shaders/planar_project.glsl`.

/// Projects world point `p` onto the plane y = `h` along `light` (DESIGN.md section 3), with the
/// shader's clamps: points below the plane stay on it, and a point level with or above a point
/// light is kept at a finite distance.
pub fn project_onto_plane(p: Vec3, light: &Light, h: f32) -> Vec3 {
    let q = match *light {
        Light::Directional { direction } => {
            let l = direction.normalize();
            p + l * ((p.y - h).max(0.0) / (-l.y).max(1e-3))
        }
        Light::Point { position: c } => {
            let py = p.y.max(h);
            let t = (c.y - h) / (c.y - py).max(1e-3 * (c.y - h));
            c + (Vec3::new(p.x, py, p.z) - c) * t
        }
    };
    Vec3::new(q.x, h, q.z)
}

/// Whether the light can cast onto the plane at all: a directional light must point down, a
/// point light must be above the plane.
pub fn light_reaches_plane(light: &Light, h: f32) -> bool {
    match *light {
        Light::Directional { direction } => direction.normalize().y < -1e-3,
        Light::Point { position } => position.y > h + 1e-4,
    }
}

// ---------------------------------------------------------------------------------------------
// Receivers and casters.

/// The receiving plane y = `height` and which objects lie on it (they receive; all others cast).
#[derive(Debug, Clone, PartialEq)]
pub struct ReceiverPlane {
    pub height: f32,
    pub receivers: Vec<bool>,
}

/// The world-space height of a flat, horizontal, non-casting, unskinned object, if it is one.
fn flat_height(scene: &Scene, object: usize) -> Option<f32> {
    let o = &scene.objects[object];
    if o.casts_shadow || o.skin.is_some() {
        return None;
    }
    let data = &scene.meshes.get(o.mesh)?.data;
    if data.indices.len() < 3 {
        return None;
    }
    let ys: Vec<f32> = data.positions.iter().map(|p| o.transform.transform_point3(*p).y).collect();
    let (low, high) = ys.iter().fold((f32::MAX, f32::MIN), |(l, h), &y| (l.min(y), h.max(y)));
    let extent = data
        .positions
        .iter()
        .map(|p| o.transform.transform_point3(*p))
        .fold(0.0f32, |m, p| m.max(p.x.abs()).max(p.z.abs()));
    (high - low <= 1e-5 * (1.0 + extent + low.abs())).then_some(low)
}

/// The ground: the lowest flat, horizontal, non-casting object; every flat object at that height
/// receives. A scene without one has nothing to project onto.
pub fn receiver_plane(scene: &Scene) -> Result<ReceiverPlane> {
    let heights: Vec<Option<f32>> = (0..scene.objects.len()).map(|i| flat_height(scene, i)).collect();
    let height = heights.iter().flatten().copied().fold(None, |m: Option<f32>, y| Some(m.map_or(y, |m| m.min(y))));
    let Some(height) = height else {
        return Err(Error::InvalidInput(format!(
            "scene '{}' has no flat horizontal receiver (a ground plane) for planar shadows",
            scene.name
        )));
    };
    let tolerance = 1e-4 * (1.0 + height.abs());
    let receivers = heights.iter().map(|h| h.is_some_and(|h| (h - height).abs() <= tolerance)).collect();
    Ok(ReceiverPlane { height, receivers })
}

// ---------------------------------------------------------------------------------------------
// Fixed-function recipes (DESIGN.md section 3), as data.

/// Pulls the flattened mesh towards the camera so it wins LESS_OR_EQUAL against the ground it
/// lies on (same plane, different triangles: depths differ in the last bits).
const SHADOW_BIAS: DepthBias = DepthBias { constant: -4.0, slope: -1.5 };

const RGB_ONLY: vk::ColorComponentFlags =
    vk::ColorComponentFlags::from_raw(vk::ColorComponentFlags::RGBA.as_raw() & !vk::ColorComponentFlags::A.as_raw());

/// Stencil values of the reference path: receivers not yet shadowed hold 0.
const STENCIL_RECEIVER: u32 = 0;
const STENCIL_OTHER: u32 = 1;

fn replace_stencil(reference: u32) -> StencilState {
    let face = StencilFace {
        compare: vk::CompareOp::ALWAYS,
        reference,
        compare_mask: 0xff,
        write_mask: 0xff,
        fail: vk::StencilOp::KEEP,
        pass: vk::StencilOp::REPLACE,
        depth_fail: vk::StencilOp::KEEP,
    };
    StencilState { front: face, back: face }
}

/// The seed's `Stencil { Ref 0 Comp Equal Pass IncrWrap ZFail Keep }`.
fn shadow_stencil() -> StencilState {
    let face = StencilFace {
        compare: vk::CompareOp::EQUAL,
        reference: STENCIL_RECEIVER,
        compare_mask: 0xff,
        write_mask: 0xff,
        fail: vk::StencilOp::KEEP,
        pass: vk::StencilOp::INCREMENT_AND_WRAP,
        depth_fail: vk::StencilOp::KEEP,
    };
    StencilState { front: face, back: face }
}

fn scene_desc(name: &'static str, skinned: bool, stencil: Option<StencilState>) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: if skinned { "planar_skinned_lit.vert" } else { "lit.vert" },
        fragment_shader: "lit.frag",
        vertex_layout: if skinned { SKINNED_LAYOUT } else { VertexLayout::POSITION_NORMAL },
        fixed: FixedFunction { stencil, ..FixedFunction::OPAQUE },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

fn shadow_desc(name: &'static str, skinned: bool, reference: bool) -> PipelineDesc {
    let blend = if reference {
        // colour *= the fragment's alpha, F/255; the stencil lets one fragment per pixel through.
        BlendState {
            colour: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_ALPHA)),
            alpha: None,
            write_mask: vk::ColorComponentFlags::RGBA,
        }
    } else {
        // colour *= dst alpha (F/255 on an unshadowed receiver, else 1); alpha := 1.
        BlendState {
            colour: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::DST_ALPHA)),
            alpha: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ONE, vk::BlendFactor::ZERO)),
            write_mask: vk::ColorComponentFlags::RGBA,
        }
    };
    PipelineDesc {
        name,
        vertex_shader: if skinned { "planar_shadow_skinned.vert" } else { "planar_shadow.vert" },
        fragment_shader: "object_colour.frag",
        vertex_layout: if skinned { SKINNED_LAYOUT } else { VertexLayout::POSITION_NORMAL },
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            // Flattened, front and back faces both land on the plane: both are drawn, which is
            // exactly the overlap the blend (or the stencil) must not count twice.
            raster: RasterState { depth_bias: Some(SHADOW_BIAS), ..RasterState::CULL_NONE },
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil: reference.then(shadow_stencil),
            blend,
        },
        push_constant_bytes: PLANAR_PUSH_BYTES,
        subpass: 0,
    }
}

/// The pipelines of one path: [receivers' scene, others' scene, skinned scene, shadow, skinned
/// shadow].
pub fn path_descs(stencil: StencilMode) -> [PipelineDesc; 5] {
    match stencil {
        StencilMode::Emulated => [
            scene_desc("scene", false, None),
            scene_desc("scene", false, None),
            scene_desc("scene (skinned)", true, None),
            shadow_desc("planar shadow", false, false),
            shadow_desc("planar shadow (skinned)", true, false),
        ],
        StencilMode::Reference => [
            scene_desc("scene (receivers, stencil 0)", false, Some(replace_stencil(STENCIL_RECEIVER))),
            scene_desc("scene (stencil 1)", false, Some(replace_stencil(STENCIL_OTHER))),
            scene_desc("scene (skinned, stencil 1)", true, Some(replace_stencil(STENCIL_OTHER))),
            shadow_desc("planar shadow (stencil)", false, true),
            shadow_desc("planar shadow (skinned, stencil)", true, true),
        ],
    }
}

/// Every pipeline of every pass, emulated then reference (for `nostencil passes`).
pub fn pipeline_descs() -> Vec<PipelineDesc> {
    let [_, scene, skinned, shadow, skinned_shadow] = path_descs(StencilMode::Emulated);
    let mut descs = vec![scene, skinned, shadow, skinned_shadow];
    descs.extend(path_descs(StencilMode::Reference));
    descs
}

// ---------------------------------------------------------------------------------------------
// The renderer.

struct Pipelines {
    scene_receiver: Pipeline,
    scene: Pipeline,
    scene_skinned: Pipeline,
    shadow: Pipeline,
    shadow_skinned: Pipeline,
}

/// What the frame did, beyond its image and counters.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct PlanarStats {
    pub plane_height: f32,
    pub casters: usize,
    pub skinned_casters: usize,
    pub shadow_factor: u8,
}

pub struct PlanarFrame {
    pub output: FrameOutput,
    pub stats: PlanarStats,
}

/// Everything a planar-shadow frame needs, built once; `frame` renders one frame (joint palettes
/// are uploaded each frame, as an animated character needs).
pub struct PlanarRenderer<'s> {
    scene: &'s Scene,
    options: PlanarOptions,
    stencil: StencilMode,
    renderer: Renderer,
    meshes: SceneMeshes,
    plane: ReceiverPlane,
    pipelines: Pipelines,
}

impl<'s> PlanarRenderer<'s> {
    pub fn new(
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        width: u32,
        height: u32,
        stencil: StencilMode,
        options: &PlanarOptions,
    ) -> Result<Self> {
        let plane = receiver_plane(scene)?;
        let renderer = Renderer::new(gpu, width, height, stencil, false)?;
        let meshes = SceneMeshes::upload(gpu, scene)?;
        let frame_layout = [renderer.frame.layout];
        let skinned_layouts = [renderer.frame.layout, meshes.template.descriptors.layout];
        let render_pass = renderer.targets.render_pass;
        let [receiver, scene_desc, skinned_desc, shadow, shadow_skinned] = path_descs(stencil);
        let pipelines = Pipelines {
            scene_receiver: Pipeline::new(gpu, &receiver, render_pass, &frame_layout)?,
            scene: Pipeline::new(gpu, &scene_desc, render_pass, &frame_layout)?,
            scene_skinned: Pipeline::new(gpu, &skinned_desc, render_pass, &skinned_layouts)?,
            shadow: Pipeline::new(gpu, &shadow, render_pass, &frame_layout)?,
            shadow_skinned: Pipeline::new(gpu, &shadow_skinned, render_pass, &skinned_layouts)?,
        };
        Ok(PlanarRenderer { scene, options: *options, stencil, renderer, meshes, plane, pipelines })
    }

    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    pub fn plane(&self) -> &ReceiverPlane {
        &self.plane
    }

    /// Renders the scene this renderer was built for.
    pub fn frame(&mut self) -> Result<PlanarFrame> {
        let scene = self.scene;
        self.frame_with(scene)
    }

    /// Renders `scene`: the one this renderer was built for, camera, light, object transforms
    /// and joint palettes free to change (see `technique::check_same_scene`).
    pub fn frame_with(&mut self, scene: &Scene) -> Result<PlanarFrame> {
        crate::technique::check_same_scene(self.scene, scene, "planar")?;
        self.meshes.update_palettes(scene)?;
        let uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        let factor = self.options.shadow_factor as f32 / 255.0;
        let clear = scene.background.extend(1.0).to_array();
        let reference = self.stencil == StencilMode::Reference;
        let draw_shadows = self.options.shadows && light_reaches_plane(&scene.light, self.plane.height);
        let (pipelines, meshes, plane) = (&self.pipelines, &self.meshes, &self.plane);
        let output = self.renderer.render(&uniforms, clear, |rec| {
            rec.pass("scene", |rec| {
                if reference {
                    clear_stencil(rec, STENCIL_OTHER);
                }
                for (index, object) in scene.objects.iter().enumerate() {
                    let receiver = plane.receivers[index];
                    let alpha = if receiver { factor } else { 1.0 };
                    let push = ObjectPush { model: object.transform, colour: object.colour.extend(alpha) };
                    let pipeline = if receiver { &pipelines.scene_receiver } else { &pipelines.scene };
                    meshes.draw(rec, scene, index, pipeline, &pipelines.scene_skinned, &push);
                }
                Ok(())
            })?;
            if !draw_shadows {
                return Ok(());
            }
            let shadow_pass = if reference { pipelines.shadow.desc.name } else { "planar shadow" };
            rec.pass(shadow_pass, |rec| {
                let colour = Vec4::new(0.0, 0.0, 0.0, if reference { factor } else { 1.0 });
                for (index, object) in scene.objects.iter().enumerate() {
                    if plane.receivers[index] {
                        continue;
                    }
                    let push =
                        PlanarPush { model: object.transform, colour, plane: Vec4::new(plane.height, 0.0, 0.0, 0.0) };
                    meshes.draw(rec, scene, index, &pipelines.shadow, &pipelines.shadow_skinned, &push);
                }
                Ok(())
            })
        })?;
        Ok(PlanarFrame { output, stats: stats(&self.plane, &self.meshes, self.options.shadow_factor) })
    }
}

pub(crate) fn stats(plane: &ReceiverPlane, meshes: &SceneMeshes, shadow_factor: u8) -> PlanarStats {
    PlanarStats {
        plane_height: plane.height,
        casters: plane.receivers.iter().filter(|r| !**r).count(),
        skinned_casters: meshes.skinned.iter().filter(|s| s.is_some()).count(),
        shadow_factor,
    }
}

/// Binds a skinned pipeline: the frame uniforms at set 0 and the object's palette at set 1.
pub(crate) fn bind_skinned(rec: &mut FrameRecorder, pipeline: &Pipeline, skinned: &SkinnedMesh) {
    bind_set1(rec, pipeline, skinned.palette.descriptors.set);
}

/// Binds a pipeline with the frame uniforms at set 0 and a set of the technique's at set 1.
pub(crate) fn bind_set1(rec: &mut FrameRecorder, pipeline: &Pipeline, set: vk::DescriptorSet) {
    rec.bind(pipeline);
    unsafe {
        rec.device().cmd_bind_descriptor_sets(rec.cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.layout, 1, &[set], &[])
    };
}

/// The lit scene pass of the blob and shadow-texture techniques: [static, skinned].
pub fn lit_descs() -> [PipelineDesc; 2] {
    [scene_desc("scene", false, None), scene_desc("scene (skinned)", true, None)]
}

/// The scene's meshes on the GPU, skinned objects with their palettes: what every planar
/// technique draws its lit pass (and its casters) from.
pub(crate) struct SceneMeshes {
    pub meshes: GpuScene,
    /// Per object: its GPU skin when it is skinned.
    pub skinned: Vec<Option<SkinnedMesh>>,
    /// Gives skinned pipelines their palette layout even when the scene has no skinned object
    /// (every palette's layout is defined identically).
    pub template: skin::Palette,
}

impl SceneMeshes {
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        let skinned = scene
            .objects
            .iter()
            .map(|o| match &o.skin {
                Some(skin) => {
                    let indices = &scene.meshes[o.mesh].data.indices;
                    SkinnedMesh::upload(gpu, &o.name, skin, indices).map(Some)
                }
                None => Ok(None),
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(SceneMeshes {
            meshes: GpuScene::upload(gpu, scene)?,
            skinned,
            template: skin::Palette::new(gpu, "layout template")?,
        })
    }

    /// This frame's joint palettes.
    pub fn update_palettes(&mut self, scene: &Scene) -> Result<()> {
        for (object, skinned) in scene.objects.iter().zip(&mut self.skinned) {
            if let (Some(skin), Some(gpu_skin)) = (&object.skin, skinned.as_mut()) {
                gpu_skin.palette.update(&object.name, &skin.joint_matrices)?;
            }
        }
        Ok(())
    }

    /// Draws object `index` with `static_pipeline` or, skinned, `skinned_pipeline`.
    pub fn draw<T: bytemuck::Pod>(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        index: usize,
        static_pipeline: &Pipeline,
        skinned_pipeline: &Pipeline,
        push: &T,
    ) {
        match &self.skinned[index] {
            Some(gpu_skin) => {
                bind_skinned(rec, skinned_pipeline, gpu_skin);
                rec.push(skinned_pipeline, push);
                rec.draw_mesh(&gpu_skin.mesh);
            }
            None => {
                rec.bind(static_pipeline);
                rec.push(static_pipeline, push);
                rec.draw_mesh(&self.meshes.meshes[scene.objects[index].mesh]);
            }
        }
    }
}

/// World-space bounds of the casters (CPU-skinned positions), `None` without casters.
pub fn caster_bounds(scene: &Scene, plane: &ReceiverPlane) -> Option<(Vec3, Vec3)> {
    (0..scene.objects.len())
        .filter(|i| !plane.receivers[*i])
        .filter_map(|i| scene.posed_bounds(i))
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

/// Sets the whole stencil aspect to `value` inside the render pass (the frame clears it to 0).
fn clear_stencil(rec: &mut FrameRecorder, value: u32) {
    let attachment = vk::ClearAttachment {
        aspect_mask: vk::ImageAspectFlags::STENCIL,
        color_attachment: 0,
        clear_value: vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: value } },
    };
    let rect = vk::ClearRect {
        rect: vk::Rect2D { offset: vk::Offset2D::default(), extent: rec.extent },
        base_array_layer: 0,
        layer_count: 1,
    };
    unsafe { rec.device().cmd_clear_attachments(rec.cmd, &[attachment], &[rect]) };
}

/// Renders `scene` with planar projected shadows, emulated in alpha or with the real stencil.
pub fn render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    width: u32,
    height: u32,
    stencil: StencilMode,
    options: &PlanarOptions,
) -> Result<PlanarFrame> {
    PlanarRenderer::new(gpu, scene, width, height, stencil, options)?.frame()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_follows_the_formulas() {
        let h = 0.5;
        let l = Vec3::new(-0.45, -1.0, -0.35).normalize();
        let p = Vec3::new(1.0, 2.5, -0.5);
        let expected = p + l * (p.y - h) / -l.y;
        let q = project_onto_plane(p, &Light::Directional { direction: l }, h);
        assert!((q - expected).length() < 1e-5 && q.y == h, "{q} vs {expected}");
        // The projected point is on the ray from P along L.
        assert!((q - p).normalize().dot(l) > 0.99999);

        let c = Vec3::new(-1.0, 6.0, 2.0);
        let q = project_onto_plane(p, &Light::Point { position: c }, h);
        let expected = c + (p - c) * (c.y - h) / (c.y - p.y);
        assert!((q - expected).length() < 1e-5, "{q} vs {expected}");
        assert!((q - c).normalize().dot((p - c).normalize()) > 0.99999, "P' lies on the ray from C through P");

        // Points on or below the plane stay where they are (in x, z).
        let below = Vec3::new(0.3, 0.2, 0.1);
        let q = project_onto_plane(below, &Light::Directional { direction: l }, h);
        assert_eq!((q.x, q.y, q.z), (0.3, h, 0.1));
        assert!(!light_reaches_plane(&Light::Directional { direction: Vec3::Y }, 0.0));
        assert!(!light_reaches_plane(&Light::Point { position: Vec3::new(0.0, -1.0, 0.0) }, 0.0));
    }

    #[test]
    fn push_constants_fit_the_profile() {
        assert_eq!(PLANAR_PUSH_BYTES, 96);
        assert!(pipeline_descs().iter().all(|d| d.push_constant_bytes <= 128));
    }
}
