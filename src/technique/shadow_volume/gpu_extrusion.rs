//! Volumes extruded in the vertex shader (`--volume-extrusion gpu`, the default): every rigid
//! caster's tables (`mesh::shadow_mesh`) uploaded once, into one storage buffer that every
//! volume draw reads through one descriptor set, and one static index buffer per mesh. A frame
//! pushes the light in the caster's space and how far the volume reaches; the CPU builds
//! nothing, whether the light, the caster or both move.
//!
//! Skinned casters (posed on the CPU, which the near caps must match), casters whose transform
//! mirrors (their windings would turn) and meshes too large for the tables keep the CPU form.

use std::ops::Range;
use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec4};

use super::casters::{per_rigid_mesh, Caster};
use super::shadow_mesh::ShadowMesh;
use crate::error::{Error, Result};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::mesh::caster::CastPath;
use crate::mesh::shadow_volume::bounds_volume;
use crate::mesh::{Light, Reach};
use crate::render::{FrameRecorder, IndexedDraw, Pipeline};
use crate::scene::Scene;

/// Mirrors `VolumePush` in `shaders/volume_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct VolumePush {
    pub model: Mat4,
    pub colour: Vec4,
    pub light: Vec4,
    /// xyz: where a GPU-skinned caster's apex vertex (its bounded far cap's) starts: its
    /// centroid in this frame's pose, which no vertex of its bind pose follows.
    pub apex: Vec4,
    pub mesh: u32,
    pub flags: u32,
    pub reach: f32,
    pub unused: u32,
}

pub const VOLUME_PUSH_BYTES: u32 = std::mem::size_of::<VolumePush>() as u32;

impl VolumePush {
    /// What a volume of a caster placed by `model` pushes for `light` (in the caster's space)
    /// reaching `reach`: the far end as `shadow_volume::start_volume` picks it, bounded only
    /// where the reach fits the light (else infinity). The colour is the draw's to set.
    pub fn new(model: Mat4, light_in_space: Light, reach: Reach) -> Self {
        let light = match light_in_space {
            Light::Directional(direction) => direction.extend(0.0),
            Light::Point(at) => at.extend(1.0),
        };
        let (far_end, reach) = match reach {
            _ if !bounds_volume(light_in_space, reach) => (0, 0.0),
            Reach::Along(t) => (FAR_ALONG, t),
            Reach::Scaled(scale) => (FAR_SCALED, scale),
            Reach::Infinite => (0, 0.0),
        };
        VolumePush { model, colour: Vec4::ZERO, light, apex: Vec4::ZERO, mesh: 0, flags: far_end, reach, unused: 0 }
    }

    fn bounded(&self) -> bool {
        self.flags & (3 << 1) != 0
    }

    fn point_light(&self) -> bool {
        self.light.w != 0.0
    }
}

/// The shader draws each wall `|m|` times as instances (the stencil's +1 ops).
const INSTANCED: u32 = 1;
const FAR_ALONG: u32 = 1 << 1;
const FAR_SCALED: u32 = 2 << 1;

/// The mobile profile's `maxStorageBufferRange` (2^27 bytes): the tables stay inside it on any
/// device the profile allows.
const PROFILE_STORAGE_RANGE: u64 = 1 << 27;

/// One mesh's tables on the GPU.
struct UploadedMesh {
    /// Its first word in the shared storage buffer.
    first_word: u32,
    indices: Buffer,
    walls: Range<u32>,
    fans: Range<u32>,
    near_caps: Range<u32>,
    far_caps: Range<u32>,
    /// Instances the stencil draws (the largest multiplicity of a two-sided mesh, else 1).
    copies: u32,
}

/// Every rigid caster's tables, uploaded at build.
pub struct ShadowMeshes {
    /// Binds `tables` at set 1 (declared first, so that it is dropped before the buffer).
    set: DescriptorSet,
    #[allow(dead_code)] // kept alive for the set
    tables: Buffer,
    meshes: Vec<UploadedMesh>,
    /// Per caster: its mesh in `meshes`, or `None` where it keeps the CPU form.
    of_caster: Vec<Option<usize>>,
}

/// One volume extruded on the GPU this frame: what its draws push and which index ranges they
/// draw.
#[derive(Debug, Clone)]
pub struct ExtrudedVolume {
    mesh: usize,
    push: VolumePush,
    ranges: [Option<Range<u32>>; 3],
}

impl ShadowMeshes {
    /// The tables of every caster that can have them (a warning names each that cannot, and
    /// why: it casts through the CPU form instead). The set is made even without any, so that
    /// the volume pipelines' layout always has it.
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene, casters: &[Caster], warnings: &mut Vec<String>) -> Result<Self> {
        let range = PROFILE_STORAGE_RANGE.min(u64::from(gpu.device.info.limits.max_storage_buffer_range));
        let mut words: Vec<u32> = Vec::new();
        let (meshes, of_caster) = per_rigid_mesh(scene, casters, |caster| {
            let object = &scene.objects[caster.object];
            let two_sided = matches!(caster.mesh.path, CastPath::TwoSided { .. });
            let built =
                ShadowMesh::build(&caster.mesh.adjacency, &caster.mesh.welded.positions, two_sided).and_then(|mesh| {
                    let bytes = 4 * (words.len() + mesh.words.len()) as u64;
                    if bytes > range {
                        return Err(Error::InvalidInput(format!(
                            "the shadow-mesh tables would need {bytes} bytes, past the {range} a storage buffer holds"
                        )));
                    }
                    Ok(mesh)
                });
            let mesh = match built {
                Ok(mesh) => mesh,
                Err(e) => {
                    warnings.push(format!(
                        "{} (object '{}'): its volume is extruded on the CPU: {e}",
                        scene.meshes[object.mesh].name, object.name
                    ));
                    return Ok(None);
                }
            };
            let first_word = words.len() as u32;
            words.extend_from_slice(&mesh.words);
            let name = format!("shadow mesh indices ({})", scene.meshes[object.mesh].name);
            let indices = Buffer::device_local(gpu, &name, &mesh.indices, vk::BufferUsageFlags::INDEX_BUFFER)?;
            Ok(Some(UploadedMesh {
                first_word,
                indices,
                walls: mesh.walls,
                fans: mesh.fans,
                near_caps: mesh.near_caps,
                far_caps: mesh.far_caps,
                copies: if two_sided { mesh.max_multiplicity.max(1) } else { 1 },
            }))
        })?;
        if words.is_empty() {
            words.push(0);
        }
        let tables = Buffer::device_local(gpu, "shadow mesh tables", &words, vk::BufferUsageFlags::STORAGE_BUFFER)?;
        let set = DescriptorSet::new(
            gpu,
            &[Binding::ReadOnlyStorage {
                buffer: tables.raw,
                range: tables.size,
                stages: vk::ShaderStageFlags::VERTEX,
            }],
        )?;
        Ok(ShadowMeshes { set, tables, meshes, of_caster })
    }

    /// The set that binds the tables (set 1 of the volume pipelines).
    pub fn set(&self) -> &DescriptorSet {
        &self.set
    }

    /// Caster `caster`'s volume for `light` (in the caster's space) reaching `reach`, if it is
    /// extruded on the GPU this frame: its transform `model` must not mirror. `caps`: the near
    /// caps are drawn (z-fail, and every two-sided caster).
    pub fn volume(
        &self,
        caster: usize,
        model: Mat4,
        light: Light,
        reach: Reach,
        caps: bool,
        stencil: bool,
    ) -> Option<ExtrudedVolume> {
        let mesh_index = (*self.of_caster.get(caster)?)?;
        if model.determinant() < 0.0 {
            return None;
        }
        let mesh = &self.meshes[mesh_index];
        let mut push = VolumePush::new(model, light, reach);
        push.mesh = mesh.first_word;
        if stencil {
            push.flags |= INSTANCED;
        }
        // The far end closes with the fan of a bounded volume, or with the casting faces at
        // infinity for a point light; a directional light's walls meet at one point.
        let far = match (push.bounded(), push.point_light()) {
            (true, _) => Some(mesh.fans.clone()),
            (false, true) => Some(mesh.far_caps.clone()),
            (false, false) => None,
        };
        let near = caps.then(|| mesh.near_caps.clone());
        let volume = ExtrudedVolume { mesh: mesh_index, push, ranges: [Some(mesh.walls.clone()), far, near] };
        Some(volume)
    }

    /// Binds the tables for `pipeline`, bound last: before a pass's volumes.
    pub fn bind(&self, rec: &mut FrameRecorder, pipeline: &Pipeline) {
        rec.bind_sets(pipeline, 1, &[self.set.set]);
    }

    /// Draws `volume` with `pipeline` (bound last, the tables bound), each count adding
    /// `alpha`.
    pub fn draw(&self, rec: &mut FrameRecorder, pipeline: &Pipeline, volume: &ExtrudedVolume, alpha: f32) {
        let mesh = &self.meshes[volume.mesh];
        let push = VolumePush { colour: Vec4::new(0.0, 0.0, 0.0, alpha), ..volume.push };
        rec.push(pipeline, &push);
        let copies = if volume.push.flags & INSTANCED != 0 { mesh.copies } else { 1 };
        // An empty range binds nothing either.
        for range in volume.ranges.iter().flatten().filter(|range| !range.is_empty() && copies > 0) {
            rec.bind_indices(&mesh.indices);
            let draw = IndexedDraw::range(range.start, range.end - range.start);
            rec.draw_indexed(IndexedDraw { instance_count: copies, ..draw });
        }
    }
}
