//! Shadow textures baked into a per-model atlas (seed 004, DESIGN.md section 5), and the plain
//! shadow map they are compared with.
//!
//! Pre-pass (outside the frame's render pass, skipped when neither light nor models moved):
//! 1. shadow map: casters from the light, depth only, stored for sampling;
//! 2. (atlas) bake: per model, its triangles drawn at their atlas UV (`uv * 2 - 1`), each texel
//!    compared against the shadow map (hardware compare, slope-scaled bias): lit or shadowed;
//! 3. (atlas) dilate: texels no triangle covered take their nearest chart's value;
//! 4. (atlas) mips: built with blits.
//!
//! Frame: the scene lit with Lambert + ambient, the Lambert term scaled by the model's shadow
//! texture (sampled trilinearly) or by the shadow-map compare.

pub mod atlas;
pub mod targets;

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gpu_allocator::MemoryLocation;

use self::atlas::{mesh_atlas, AtlasSource, MeshAtlas};
use self::targets::{CompareSampler, Framebuffer, ImageView, RenderPass};
use crate::error::{Error, Result};
use crate::frame::{image_from_rgba8, StencilMode};
use crate::gpu::commands::submit_and_wait;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{Buffer, Image};
use crate::gpu::texture::{record_mip_chain, transition, Sampler};
use crate::gpu::Gpu;
use crate::pipeline::{
    BlendState, DepthState, FixedFunction, PipelineDesc, RasterState, VertexAttribute, VertexLayout,
};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, FrameUniforms, GpuMesh, Renderer};
use crate::render::{ObjectPush, OBJECT_PUSH_BYTES};
use crate::scene::{Light, PoseTracker, Scene};
use image::RgbaImage;

/// Which of the two shadow techniques a renderer draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowKind {
    /// Shadow textures baked into each model's atlas (the paper's method).
    Atlas,
    /// The shadow map sampled in the scene pass.
    Map,
}

impl ShadowKind {
    pub fn name(self) -> &'static str {
        match self {
            ShadowKind::Atlas => "shadow-texture-atlas",
            ShadowKind::Map => "shadow-map",
        }
    }
}

/// `--light`: whether the light turns from frame to frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LightMode {
    /// Turns about the vertical by `MOVING_LIGHT_STEP` radians a frame: every frame re-bakes.
    Moving,
    /// Stays put: after the first frame the shadow map and bake are skipped.
    #[default]
    Fixed,
}

impl LightMode {
    pub fn parse(text: &str) -> Result<Self> {
        match text {
            "moving" => Ok(LightMode::Moving),
            "fixed" => Ok(LightMode::Fixed),
            _ => Err(Error::InvalidInput(format!("--light {text}: use moving or fixed"))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            LightMode::Moving => "moving",
            LightMode::Fixed => "fixed",
        }
    }
}

/// Radians the moving light turns per frame.
pub const MOVING_LIGHT_STEP: f32 = 0.02;

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ShadowAtlasOptions {
    /// Shadow map side in texels (the paper: 512).
    pub map_size: u32,
    /// Shadow texture side for meshes that are not geometry images (those use n - 1 rounded
    /// up to a power of two: 256 for 257x257, 64 for 64x64).
    pub texture_size: u32,
    pub light: LightMode,
}

impl Default for ShadowAtlasOptions {
    fn default() -> Self {
        ShadowAtlasOptions { map_size: 512, texture_size: 256, light: LightMode::Fixed }
    }
}

/// Checks a map or texture side: a power of two in 16..=4096.
pub fn check_size(what: &str, size: u32) -> Result<u32> {
    if !(16..=4096).contains(&size) || !size.is_power_of_two() {
        return Err(Error::InvalidInput(format!("{what} {size}: use a power of two from 16 to 4096")));
    }
    Ok(size)
}

// ---------------------------------------------------------------------------------------------
// Pipelines, as data.

/// position (vec3) + normal (vec3) + atlas UV (vec2).
pub const ATLAS_VERTEX: VertexLayout =
    VertexLayout { attributes: &[VertexAttribute::Vec3, VertexAttribute::Vec3, VertexAttribute::Vec2] };

pub fn shadow_map_desc() -> PipelineDesc {
    PipelineDesc {
        name: "shadow map",
        vertex_shader: "shadow_map.vert",
        fragment_shader: "shadow_map.frag",
        vertex_layout: ATLAS_VERTEX,
        fixed: FixedFunction {
            raster: RasterState::CULL_NONE,
            blend: BlendState { write_mask: vk::ColorComponentFlags::empty(), ..BlendState::OPAQUE },
            ..FixedFunction::OPAQUE
        },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

pub fn bake_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas bake",
        vertex_shader: "shadow_atlas_bake.vert",
        fragment_shader: "shadow_atlas_bake.frag",
        vertex_layout: ATLAS_VERTEX,
        // Atlas space has no facing and no depth: every triangle writes its texels.
        fixed: FixedFunction { raster: RasterState::CULL_NONE, depth: DepthState::OFF, ..FixedFunction::OPAQUE },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

pub fn dilate_desc() -> PipelineDesc {
    PipelineDesc {
        name: "atlas dilate",
        vertex_shader: "fullscreen.vert",
        fragment_shader: "shadow_atlas_dilate.frag",
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction::FULLSCREEN,
        push_constant_bytes: 16,
        subpass: 0,
    }
}

pub fn scene_desc(kind: ShadowKind) -> PipelineDesc {
    PipelineDesc {
        name: "scene",
        vertex_shader: "shadow_atlas_scene.vert",
        fragment_shader: match kind {
            ShadowKind::Atlas => "shadow_atlas_scene.frag",
            ShadowKind::Map => "shadow_map_scene.frag",
        },
        vertex_layout: ATLAS_VERTEX,
        fixed: FixedFunction::OPAQUE,
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

/// Every pipeline of a technique, pass by pass, labelled with the target it draws into (no
/// stencil anywhere: there is no reference path).
pub fn pipeline_descs(kind: ShadowKind) -> Vec<(&'static str, PipelineDesc)> {
    match kind {
        ShadowKind::Atlas => vec![
            ("shadow map (depth only)", shadow_map_desc()),
            ("shadow texture (atlas space)", bake_desc()),
            ("shadow texture mip 0", dilate_desc()),
            ("frame", scene_desc(kind)),
        ],
        ShadowKind::Map => vec![("shadow map (depth only)", shadow_map_desc()), ("frame", scene_desc(kind))],
    }
}

// ---------------------------------------------------------------------------------------------
// The light's view.

/// Mirrors `ShadowLight` in `shaders/shadow_atlas_light.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadowLightUniforms {
    pub view_proj: Mat4,
    pub light: Vec4,
    pub bias: Vec4,
}

/// Centre and radius of a sphere around every object.
pub fn scene_bounds(scene: &Scene) -> (Vec3, f32) {
    let all =
        (0..scene.objects.len()).filter_map(|i| scene.posed_bounds(i)).reduce(|(a, b), (c, d)| (a.min(c), b.max(d)));
    let Some((lo, hi)) = all else { return (Vec3::ZERO, 1.0) };
    ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3))
}

/// Per mesh: the mesh vertex and the atlas UV of each GPU vertex, to lay a re-posed skin out
/// again.
struct PosedLayout {
    sources: Vec<u32>,
    uvs: Vec<Vec2>,
}

/// Position, normal and atlas UV per vertex, interleaved as the bake and scene pipelines read.
fn atlas_vertices(positions: &[Vec3], normals: &[Vec3], uvs: &[Vec2]) -> Vec<[f32; 8]> {
    (0..positions.len())
        .map(|i| {
            let (p, n, uv) = (positions[i], normals.get(i).copied().unwrap_or(Vec3::Y), uvs[i]);
            [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y]
        })
        .collect()
}

/// The light's view-projection: orthographic around the scene's bounding sphere for a
/// directional light, a perspective frustum (a spot) aimed at the scene for a positional one.
/// Depth 0..1; NDC xy * 0.5 + 0.5 is the shadow-map UV.
pub fn light_view_projection(light: &Light, centre: Vec3, radius: f32) -> Mat4 {
    let up_for = |d: Vec3| if d.normalize().y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    match *light {
        Light::Directional { direction } => {
            let d = direction.normalize();
            let eye = centre - d * 2.0 * radius;
            let view = Mat4::look_at_rh(eye, centre, up_for(d));
            Mat4::orthographic_rh(-radius, radius, -radius, radius, radius * 0.9, radius * 3.1) * view
        }
        Light::Point { position } => {
            let to_centre = centre - position;
            let distance = to_centre.length().max(1e-3);
            let view = Mat4::look_at_rh(position, centre, up_for(to_centre));
            let (fov, near) = if distance > radius * 1.05 {
                (2.0 * (radius / distance).asin() * 1.05, distance - radius)
            } else {
                (120f32.to_radians(), 0.05 * radius)
            };
            Mat4::perspective_rh(fov, 1.0, near, distance + radius) * view
        }
    }
}

/// The scene's light at frame `index` under `mode`.
pub fn light_at(scene: &Scene, mode: LightMode, index: u32) -> Light {
    let turn = match mode {
        LightMode::Fixed => return scene.light,
        LightMode::Moving => Quat::from_rotation_y(MOVING_LIGHT_STEP * index as f32),
    };
    match scene.light {
        Light::Directional { direction } => Light::Directional { direction: turn * direction },
        Light::Point { position } => Light::Point { position: turn * position },
    }
}

// ---------------------------------------------------------------------------------------------
// GPU resources.

/// One model instance's shadow texture and everything that writes and reads it.
struct ObjectShadow {
    object: usize,
    size: u32,
    mip_levels: u32,
    dilate_radius: u32,
    // Field order is drop order: sets and framebuffers before the views and images.
    scene_set: DescriptorSet,
    dilate_set: DescriptorSet,
    bake_framebuffer: Framebuffer,
    dilate_framebuffer: Framebuffer,
    _mip0: ImageView,
    _raw: Image,
    texture: Image,
}

struct AtlasPasses {
    bake: Pipeline,
    dilate: Pipeline,
    objects: Vec<ObjectShadow>,
    bake_pass: RenderPass,
    dilate_pass: RenderPass,
    _trilinear: Sampler,
    _nearest: Sampler,
}

/// One mesh laid out in its atlas.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AtlasInfo {
    pub mesh: String,
    pub source: AtlasSource,
    pub size: u32,
    pub mip_levels: u32,
    /// Why the file's TEXCOORD_1 was not used (overlapping), when it has one.
    pub rejected_uv1: Option<String>,
}

impl AtlasInfo {
    pub fn describe(&self) -> String {
        match &self.rejected_uv1 {
            None => self.source.describe(),
            Some(why) => format!("{} (TEXCOORD_1 rejected: {why})", self.source.describe()),
        }
    }
}

/// What a frame did besides its image.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ShadowAtlasStats {
    pub technique: ShadowKind,
    pub light: LightMode,
    /// Frames rendered by this renderer, this one included.
    pub frame: u32,
    /// The shadow map (and bake) were skipped: neither light nor models moved.
    pub cached: bool,
    pub map_size: u32,
    pub atlases: Vec<AtlasInfo>,
}

pub struct ShadowAtlasFrame {
    pub output: FrameOutput,
    pub stats: ShadowAtlasStats,
}

#[derive(Debug, Clone, PartialEq)]
struct CacheKey {
    light: Vec4,
    transforms: Vec<Mat4>,
    /// Skinned objects' palettes: a new pose is a moved model.
    palettes: Vec<Vec<Mat4>>,
}

/// Everything a frame needs, built once; `frame` renders one frame, re-baking only when the
/// light or a model moved since the last.
pub struct ShadowAtlasRenderer<'s> {
    gpu: Arc<Gpu>,
    scene: &'s Scene,
    kind: ShadowKind,
    options: ShadowAtlasOptions,
    scene_pipeline: Pipeline,
    map_pipeline: Pipeline,
    atlas: Option<AtlasPasses>,
    light_set: DescriptorSet,
    light_buffer: Buffer,
    map_framebuffer: Framebuffer,
    map_pass: RenderPass,
    _compare: CompareSampler,
    _map: Image,
    meshes: Vec<GpuMesh>,
    layouts: Vec<PosedLayout>,
    /// The pose the skinned objects' atlas vertices hold.
    posed: PoseTracker,
    atlases: Vec<AtlasInfo>,
    renderer: Renderer,
    frames: u32,
    cache: Option<CacheKey>,
}

impl<'s> ShadowAtlasRenderer<'s> {
    pub fn new(
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        width: u32,
        height: u32,
        stencil: StencilMode,
        kind: ShadowKind,
        options: &ShadowAtlasOptions,
    ) -> Result<Self> {
        Self::with_progress(gpu, scene, (width, height), stencil, kind, options, &mut |_, _| {})
    }

    /// As `new`, calling `progress(done, total)` as each mesh's atlas is laid out (generating
    /// atlases for many or large meshes takes a while).
    pub fn with_progress(
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        (width, height): (u32, u32),
        stencil: StencilMode,
        kind: ShadowKind,
        options: &ShadowAtlasOptions,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self> {
        let map_size = check_size("--shadow-map-size", options.map_size)?;
        let texture_size = check_size("--shadow-texture-size", options.texture_size)?;
        let renderer = Renderer::new(gpu, width, height, stencil, false)?;

        let total = scene.meshes.len();
        let layouts: Vec<MeshAtlas> = scene
            .meshes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let atlas = mesh_atlas(&m.name, &m.data, m.uv1.as_deref(), texture_size);
                progress(i + 1, total);
                atlas
            })
            .collect::<Result<_>>()?;
        let meshes = scene
            .meshes
            .iter()
            .zip(&layouts)
            .map(|(m, a)| {
                let interleaved = atlas_vertices(&a.positions, &a.normals, &a.uvs);
                GpuMesh::from_raw(gpu, &m.name, &interleaved, &a.indices)
            })
            .collect::<Result<Vec<_>>>()?;
        let posed_layouts: Vec<PosedLayout> =
            layouts.iter().map(|a| PosedLayout { sources: a.source_vertices.clone(), uvs: a.uvs.clone() }).collect();
        let atlases = scene
            .meshes
            .iter()
            .zip(&layouts)
            .map(|(m, a)| AtlasInfo {
                mesh: m.name.clone(),
                source: a.source,
                size: a.size,
                mip_levels: a.mip_levels,
                rejected_uv1: a.rejected_uv1.clone(),
            })
            .collect::<Vec<_>>();

        let map = targets::shadow_map_image(gpu, map_size)?;
        let map_pass = targets::shadow_map_render_pass(gpu)?;
        let map_extent = vk::Extent2D { width: map_size, height: map_size };
        let map_framebuffer = Framebuffer::new(gpu, &map_pass, map.view, map_extent)?;
        let compare = CompareSampler::new(gpu)?;
        let light_size = std::mem::size_of::<ShadowLightUniforms>() as u64;
        let light_buffer = Buffer::new(
            gpu,
            "shadow light",
            light_size,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let light_set = DescriptorSet::new(
            gpu,
            &[
                Binding::UniformBuffer {
                    buffer: light_buffer.raw,
                    range: light_size,
                    stages: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                },
                Binding::Texture {
                    view: map.view,
                    sampler: compare.raw,
                    layout: vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                    stages: vk::ShaderStageFlags::FRAGMENT,
                },
            ],
        )?;
        let map_pipeline =
            Pipeline::with_colour_attachments(gpu, &shadow_map_desc(), map_pass.raw, &[light_set.layout], 0)?;

        let (atlas, scene_pipeline) = match kind {
            ShadowKind::Map => {
                let pipeline = Pipeline::new(
                    gpu,
                    &scene_desc(kind),
                    renderer.targets.render_pass,
                    &[renderer.frame.layout, light_set.layout],
                )?;
                (None, pipeline)
            }
            ShadowKind::Atlas => {
                let passes = AtlasPasses::new(gpu, scene, &layouts, light_set.layout)?;
                let texture_layout = match passes.objects.first() {
                    Some(o) => o.scene_set.layout,
                    None => return Err(Error::InvalidInput(format!("scene '{}' has no objects", scene.name))),
                };
                let pipeline = Pipeline::new(
                    gpu,
                    &scene_desc(kind),
                    renderer.targets.render_pass,
                    &[renderer.frame.layout, texture_layout],
                )?;
                (Some(passes), pipeline)
            }
        };
        Ok(ShadowAtlasRenderer {
            gpu: gpu.clone(),
            scene,
            kind,
            options: ShadowAtlasOptions { map_size, texture_size, ..*options },
            scene_pipeline,
            map_pipeline,
            atlas,
            light_set,
            light_buffer,
            map_framebuffer,
            map_pass,
            _compare: compare,
            _map: map,
            meshes,
            layouts: posed_layouts,
            posed: PoseTracker::new(scene),
            atlases,
            renderer,
            frames: 0,
            cache: None,
        })
    }

    pub fn light_mode(&self) -> LightMode {
        self.options.light
    }

    pub fn atlases(&self) -> &[AtlasInfo] {
        &self.atlases
    }

    /// Heat-map frames (see `Renderer::count_overdraw`): only the frame's passes are counted.
    pub fn count_overdraw(&mut self, on: bool) {
        self.renderer.count_overdraw = on;
    }

    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// Renders the next frame (the light turns between frames when it is `moving`).
    pub fn frame(&mut self) -> Result<ShadowAtlasFrame> {
        let scene = self.scene;
        self.frame_with(scene)
    }

    /// Skinned objects whose palette changed (`Scene::pose_at`) get their atlas vertices
    /// re-posed on the CPU and uploaded again (the atlas layout stays).
    fn follow_pose(&mut self, scene: &Scene) -> Result<()> {
        for index in self.posed.changed(scene) {
            let object = &scene.objects[index];
            let (Some(skin), Some(mesh), Some(layout)) =
                (&object.skin, self.meshes.get_mut(object.mesh), self.layouts.get(object.mesh))
            else {
                continue;
            };
            let (positions, normals) = skin.posed_positions_normals();
            let pick = |list: &[Vec3], fallback: Vec3| -> Vec<Vec3> {
                layout.sources.iter().map(|&v| list.get(v as usize).copied().unwrap_or(fallback)).collect()
            };
            let interleaved = atlas_vertices(&pick(&positions, Vec3::ZERO), &pick(&normals, Vec3::Y), &layout.uvs);
            mesh.vertices = Buffer::device_local(
                &self.gpu,
                &format!("{} atlas vertices (posed)", object.name),
                &interleaved,
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?;
        }
        Ok(())
    }

    /// Renders `scene`, a moved pose of the one this renderer was built for; the shadow map and
    /// the atlases are re-baked only when its light or an object moved.
    pub fn frame_with(&mut self, scene: &Scene) -> Result<ShadowAtlasFrame> {
        crate::technique::check_same_scene(self.scene, scene, self.kind.name())?;
        self.follow_pose(scene)?;
        let light = light_at(scene, self.options.light, self.frames);
        let key = CacheKey {
            light: light.as_vec4(),
            transforms: scene.objects.iter().map(|o| o.transform).collect(),
            palettes: scene.objects.iter().filter_map(|o| o.skin.as_ref().map(|s| s.joint_matrices.clone())).collect(),
        };
        let fresh = self.cache.as_ref() != Some(&key);
        if fresh {
            let (centre, radius) = scene_bounds(scene);
            let texel = 1.0 / self.options.map_size as f32;
            let uniforms = ShadowLightUniforms {
                view_proj: light_view_projection(&light, centre, radius),
                light: light.as_vec4(),
                // Depth units of one map texel (orthographic: depth spans 2.2 radii, a texel
                // 2 radii / map size): half a texel flat, 1.5 texels per unit of slope.
                bias: Vec4::new(0.5 * texel, 1.5 * texel, 8.0, 0.0),
            };
            self.light_buffer.write(0, bytemuck::bytes_of(&uniforms))?;
        }
        let mut uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        uniforms.light = light.as_vec4();
        let clear = scene.background.extend(1.0).to_array();
        let frame_set = self.renderer.frame.set;
        let map_extent = vk::Extent2D { width: self.options.map_size, height: self.options.map_size };
        let (gpu, kind) = (&self.gpu, self.kind);
        let (meshes, map_pipeline, light_set) = (&self.meshes, &self.map_pipeline, self.light_set.set);
        let (map_pass, map_framebuffer) = (&self.map_pass, self.map_framebuffer.raw);
        let (atlas, scene_pipeline) = (&self.atlas, &self.scene_pipeline);
        let output = self.renderer.render_with_prepass(
            &uniforms,
            clear,
            |rec| {
                if !fresh {
                    return Ok(());
                }
                rec.pass("shadow map", |rec| {
                    let clear =
                        [vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } }];
                    rec.begin_offscreen_pass(map_pass, map_framebuffer, map_extent, &clear);
                    rec.bind_with_sets(map_pipeline, &[light_set]);
                    for object in scene.objects.iter().filter(|o| o.casts_shadow) {
                        rec.push(map_pipeline, &ObjectPush { model: object.transform, colour: Vec4::ONE });
                        rec.draw_mesh(&meshes[object.mesh]);
                    }
                    rec.end_render_pass();
                    Ok(())
                })?;
                if let Some(atlas) = atlas {
                    atlas.record(gpu, rec, scene, meshes, light_set)?;
                }
                Ok(())
            },
            |rec| {
                rec.pass("scene", |rec| {
                    for (index, object) in scene.objects.iter().enumerate() {
                        match (kind, atlas) {
                            (ShadowKind::Atlas, Some(atlas)) => {
                                rec.bind_with_sets(scene_pipeline, &[frame_set, atlas.objects[index].scene_set.set])
                            }
                            _ => rec.bind_with_sets(scene_pipeline, &[frame_set, light_set]),
                        }
                        rec.push(
                            scene_pipeline,
                            &ObjectPush { model: object.transform, colour: object.colour.extend(1.0) },
                        );
                        rec.draw_mesh(&meshes[object.mesh]);
                    }
                    Ok(())
                })
            },
        )?;
        self.cache = Some(key);
        self.frames += 1;
        Ok(ShadowAtlasFrame {
            output,
            stats: ShadowAtlasStats {
                technique: self.kind,
                light: self.options.light,
                frame: self.frames,
                cached: !fresh,
                map_size: self.options.map_size,
                atlases: self.atlases.clone(),
            },
        })
    }

    /// Reads back mip `mip` of object `object`'s shadow texture (R: 255 lit, 0 shadowed; A: 255
    /// where a triangle covers the texel or dilation reached it).
    pub fn read_shadow_texture(&self, object: usize, mip: u32) -> Result<RgbaImage> {
        let atlas = self
            .atlas
            .as_ref()
            .ok_or_else(|| Error::InvalidInput("only shadow-texture-atlas bakes shadow textures".into()))?;
        let shadow = atlas
            .objects
            .get(object)
            .ok_or_else(|| Error::InvalidInput(format!("no object {object} in scene '{}'", self.scene.name)))?;
        if mip >= shadow.mip_levels {
            return Err(Error::InvalidInput(format!("mip {mip}: the shadow texture has {}", shadow.mip_levels)));
        }
        if self.frames == 0 {
            return Err(Error::InvalidInput("no frame rendered yet: nothing is baked".into()));
        }
        let side = (shadow.size >> mip).max(1);
        let readback = Buffer::new(
            &self.gpu,
            "shadow texture readback",
            side as u64 * side as u64 * 4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let image = shadow.texture.raw;
        submit_and_wait(&self.gpu, |cmd| {
            let (read, src) = (vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL, vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
            transition(&self.gpu, cmd, image, mip, 1, read, src);
            let region = vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: mip,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_extent(vk::Extent3D { width: side, height: side, depth: 1 });
            unsafe { self.gpu.raw().cmd_copy_image_to_buffer(cmd, image, src, readback.raw, &[region]) };
            transition(&self.gpu, cmd, image, mip, 1, src, read);
            Ok(())
        })?;
        image_from_rgba8(side, side, readback.read()?.to_vec())
    }
}

impl AtlasPasses {
    fn new(
        gpu: &Arc<Gpu>,
        scene: &Scene,
        layouts: &[MeshAtlas],
        light_layout: vk::DescriptorSetLayout,
    ) -> Result<Self> {
        let bake_pass = targets::colour_render_pass(gpu, true, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let dilate_pass = targets::colour_render_pass(gpu, false, vk::ImageLayout::TRANSFER_DST_OPTIMAL)?;
        let trilinear = Sampler::new(gpu, vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let nearest = Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let objects = scene
            .objects
            .iter()
            .enumerate()
            .map(|(index, object)| {
                let layout = &layouts[object.mesh];
                let extent = vk::Extent2D { width: layout.size, height: layout.size };
                let name = format!("shadow texture of '{}'", object.name);
                let raw = targets::shadow_texture_image(gpu, &format!("{name} (bake)"), layout.size, 1)?;
                let texture = targets::shadow_texture_image(gpu, &name, layout.size, layout.mip_levels)?;
                let mip0 = ImageView::mip(gpu, &texture, 0)?;
                let texture_binding = |view, sampler: &Sampler| Binding::Texture {
                    view,
                    sampler: sampler.raw,
                    layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    stages: vk::ShaderStageFlags::FRAGMENT,
                };
                Ok(ObjectShadow {
                    object: index,
                    size: layout.size,
                    mip_levels: layout.mip_levels,
                    dilate_radius: layout.dilate_radius,
                    scene_set: DescriptorSet::new(gpu, &[texture_binding(texture.view, &trilinear)])?,
                    dilate_set: DescriptorSet::new(gpu, &[texture_binding(raw.view, &nearest)])?,
                    bake_framebuffer: Framebuffer::new(gpu, &bake_pass, raw.view, extent)?,
                    dilate_framebuffer: Framebuffer::new(gpu, &dilate_pass, mip0.raw, extent)?,
                    _mip0: mip0,
                    _raw: raw,
                    texture,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let dilate_layout = match objects.first() {
            Some(o) => o.dilate_set.layout,
            None => return Err(Error::InvalidInput(format!("scene '{}' has no objects", scene.name))),
        };
        Ok(AtlasPasses {
            bake: Pipeline::new(gpu, &bake_desc(), bake_pass.raw, &[light_layout])?,
            dilate: Pipeline::new(gpu, &dilate_desc(), dilate_pass.raw, &[dilate_layout])?,
            objects,
            bake_pass,
            dilate_pass,
            _trilinear: trilinear,
            _nearest: nearest,
        })
    }

    /// Bake, dilate and mips for every model, each step one measured pass over all models.
    fn record(
        &self,
        gpu: &Gpu,
        rec: &mut FrameRecorder,
        scene: &Scene,
        meshes: &[GpuMesh],
        light_set: vk::DescriptorSet,
    ) -> Result<()> {
        let extent = |o: &ObjectShadow| vk::Extent2D { width: o.size, height: o.size };
        rec.pass("atlas bake", |rec| {
            // Alpha 0: no triangle covers the texel (yet).
            let clear = [vk::ClearValue { color: vk::ClearColorValue { float32: [1.0, 1.0, 1.0, 0.0] } }];
            for o in &self.objects {
                let object = &scene.objects[o.object];
                rec.begin_offscreen_pass(&self.bake_pass, o.bake_framebuffer.raw, extent(o), &clear);
                rec.bind_with_sets(&self.bake, &[light_set]);
                rec.push(&self.bake, &ObjectPush { model: object.transform, colour: Vec4::ONE });
                rec.draw_mesh(&meshes[object.mesh]);
                rec.end_render_pass();
            }
            Ok(())
        })?;
        rec.pass("atlas dilate", |rec| {
            for o in &self.objects {
                rec.begin_offscreen_pass(&self.dilate_pass, o.dilate_framebuffer.raw, extent(o), &[]);
                rec.bind_with_sets(&self.dilate, &[o.dilate_set.set]);
                rec.push(&self.dilate, &[o.dilate_radius as i32, 0, 0, 0]);
                rec.draw_fullscreen();
                rec.end_render_pass();
            }
            Ok(())
        })?;
        rec.pass("atlas mips", |rec| {
            let cmd = rec.cmd;
            for o in &self.objects {
                let image = o.texture.raw;
                if o.mip_levels > 1 {
                    let (undefined, dst) = (vk::ImageLayout::UNDEFINED, vk::ImageLayout::TRANSFER_DST_OPTIMAL);
                    transition(gpu, cmd, image, 1, o.mip_levels - 1, undefined, dst);
                }
                let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
                record_mip_chain(gpu, cmd, image, o.size, o.size, o.mip_levels, read);
            }
            Ok(())
        })
    }
}
