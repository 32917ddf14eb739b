//! Meshes uploaded to device-local vertex and index buffers, and skinned meshes' posed copies
//! (one per frame slot, host-visible, rewritten in place).

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;
use glam::{Vec2, Vec3, Vec4};

use super::materials::GpuMaterials;
use super::per_slot::slot_copy;
use super::pipeline_object::Pipeline;
use crate::error::{Error, Result};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::scene::objects::{SceneMesh, SceneSkin};
use crate::scene::{JointPalettes, Scene, SlotPoses, MAX_JOINTS};

pub struct GpuMesh {
    /// The mesh as uploaded (device-local): its vertices from `vertex_offset` on, in a buffer
    /// it may share with other meshes of the same layout (`GpuMesh::packed`).
    vertices: Arc<Buffer>,
    vertex_offset: i32,
    /// Per frame slot, a skinned mesh's posed vertices (host-visible, written in place) once it
    /// moved from the pose it was uploaded in; empty for a mesh that never moved.
    posed: Vec<Option<Buffer>>,
    /// Its indices `first_index..first_index + index_count` of `indices` (maybe shared too).
    indices: Arc<Buffer>,
    pub first_index: u32,
    pub index_count: u32,
}

impl GpuMesh {
    /// Any interleaved vertex type (it must match the pipeline's `VertexLayout`), in buffers of
    /// its own.
    pub fn from_raw<V: Pod>(gpu: &Arc<Gpu>, name: &str, vertices: &[V], indices: &[u32]) -> Result<Self> {
        let mut packed = Self::packed(gpu, name, &[(vertices, indices)])?;
        packed.pop().ok_or_else(|| Error::Internal(format!("mesh '{name}' was not uploaded")))
    }

    /// `meshes` (vertices and indices, one vertex type) one after another in one vertex and
    /// one index buffer, named after `name`: a pass that draws them binds those once, where
    /// buffers of their own would be bound again for every object (commands a driver records
    /// and validates one by one).
    pub fn packed<V: Pod>(gpu: &Arc<Gpu>, name: &str, meshes: &[(&[V], &[u32])]) -> Result<Vec<Self>> {
        let (mut all_vertices, mut all_indices) = (Vec::new(), Vec::new());
        let mut ranges = Vec::with_capacity(meshes.len());
        for (vertices, indices) in meshes {
            let too_many = || Error::InvalidInput(format!("{name}: more than {} vertices or indices", i32::MAX));
            let vertex_offset = i32::try_from(all_vertices.len()).map_err(|_| too_many())?;
            let first_index = u32::try_from(all_indices.len()).map_err(|_| too_many())?;
            let index_count = u32::try_from(indices.len()).map_err(|_| too_many())?;
            all_vertices.extend_from_slice(vertices);
            all_indices.extend_from_slice(indices);
            ranges.push((vertex_offset, first_index, index_count));
        }
        let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
        let vertices = Arc::new(Buffer::device_local(gpu, &format!("{name} vertices"), &all_vertices, usage)?);
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        let indices = Arc::new(Buffer::device_local(gpu, &format!("{name} indices"), &all_indices, usage)?);
        Ok(ranges
            .into_iter()
            .map(|(vertex_offset, first_index, index_count)| GpuMesh {
                vertices: vertices.clone(),
                vertex_offset,
                posed: Vec::new(),
                indices: indices.clone(),
                first_index,
                index_count,
            })
            .collect())
    }

    /// Writes `vertices` (the mesh posed, same layout and count) into frame slot `slot`'s copy,
    /// made host-visible at its first pose and written in place after it. No frame in flight
    /// may read that copy.
    pub fn write_posed<V: Pod>(&mut self, gpu: &Arc<Gpu>, slot: usize, name: &str, vertices: &[V]) -> Result<()> {
        match slot_copy(&mut self.posed, slot, || Ok(None))? {
            Some(buffer) => buffer.rewrite(gpu, name, vertices, vk::BufferUsageFlags::VERTEX_BUFFER),
            copy @ None => {
                *copy = Some(Buffer::with_data(gpu, name, vertices, vk::BufferUsageFlags::VERTEX_BUFFER)?);
                Ok(())
            }
        }
    }

    /// The vertices frame slot `slot` draws, and where the mesh's start among them (the draws'
    /// vertex offset): its posed copy (of its own), else the mesh as uploaded.
    pub fn vertices_in(&self, slot: usize) -> (&Buffer, i32) {
        match self.posed.get(slot).and_then(Option::as_ref) {
            Some(posed) => (posed, 0),
            None => (&self.vertices, self.vertex_offset),
        }
    }

    /// The buffer holding the mesh's indices (`first_index..first_index + index_count`).
    pub fn indices(&self) -> &Buffer {
        &self.indices
    }
}

crate::names::named_enum! {
    /// Where skinned objects are posed each frame.
    pub enum Skinning {
        /// In the vertex stage: each skinned object's bind pose is uploaded once with its joints
        /// and weights, and every stage that draws it skins it from the frame's joint palettes
        /// (the shaders' skinned twins).
        #[default]
        Gpu = "gpu",
        /// On the CPU, into a host-visible copy per frame slot (the proven oracle).
        Cpu = "cpu",
    }
}

/// The scene's meshes on the GPU, in the scene's mesh order, and its materials.
pub struct GpuScene {
    /// `VertexLayout::SCENE` vertices.
    pub meshes: Vec<GpuMesh>,
    /// Per object, skinning on the GPU: a skinned object's bind pose
    /// (`VertexLayout::SKINNED_SCENE`), its joints moved to its palette among the frame's.
    skinned: Vec<Option<GpuMesh>>,
    /// Where each skinned object's palette lies, skinning on the GPU.
    palettes: Option<JointPalettes>,
    pub materials: GpuMaterials,
    /// Per frame slot, the pose its copy of the skinned objects' vertices holds.
    posed: SlotPoses,
}

impl GpuScene {
    /// The scene's meshes, skinned objects posed on the CPU.
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        Self::upload_for(gpu, scene, Skinning::Cpu)
    }

    /// The scene's meshes, skinned objects posed as `skinning` says: on the GPU, every pass
    /// that draws them must bind its pipelines' skinned twins (`draw_objects` does), and the
    /// frame must carry the palettes (`Renderer::write_joint_palettes`).
    pub fn upload_for(gpu: &Arc<Gpu>, scene: &Scene, skinning: Skinning) -> Result<Self> {
        let vertices: Vec<_> =
            scene.meshes.iter().map(|m| scene_vertices(m, &m.data.positions, &m.data.normals)).collect();
        let packed: Vec<_> =
            scene.meshes.iter().zip(&vertices).map(|(m, v)| (v.as_slice(), m.data.indices.as_slice())).collect();
        let meshes = if packed.is_empty() { Vec::new() } else { GpuMesh::packed(gpu, "scene meshes", &packed)? };
        let materials = GpuMaterials::upload(gpu, scene)?;
        let (skinned, palettes) = match skinning {
            Skinning::Cpu => (Vec::new(), None),
            Skinning::Gpu => {
                let palettes = JointPalettes::of(scene);
                (upload_bind_poses(gpu, scene, &palettes)?, Some(palettes))
            }
        };
        Ok(GpuScene { meshes, skinned, palettes, materials, posed: SlotPoses::new(scene) })
    }

    /// Where the skinned objects' palettes lie, when they are skinned on the GPU.
    pub fn joint_palettes(&self) -> Option<&JointPalettes> {
        self.palettes.as_ref()
    }

    /// Object `index`'s bind pose, when it is skinned on the GPU: drawn with a skinned twin.
    pub fn skinned_mesh(&self, index: usize) -> Option<&GpuMesh> {
        self.skinned.get(index).and_then(Option::as_ref)
    }

    /// Objects skinned on the GPU.
    pub fn skinned_on_gpu(&self) -> usize {
        self.skinned.iter().flatten().count()
    }

    /// What draws object `index` of `scene` with `pipeline`'s state: its mesh and `pipeline`,
    /// or, for an object skinned on the GPU, its bind pose and `pipeline`'s skinned twin (an
    /// error when the pipeline was built without one).
    pub fn object_draw<'m, 'p>(
        &'m self,
        scene: &Scene,
        index: usize,
        pipeline: &'p Pipeline,
    ) -> Result<(&'m GpuMesh, &'p Pipeline)> {
        object_draw(scene, index, (&self.meshes, &self.skinned), pipeline)
    }

    /// Re-poses the skinned objects whose palette changed since frame slot `slot`'s copies
    /// were posed (`Scene::pose_at` moves palettes, not meshes): skinned on the CPU, written
    /// into that slot's host-visible copy (`GpuMesh::write_posed`), which the slot's draws read
    /// (`FrameRecorder::draw_mesh`). The frame that last used `slot` must be complete; the other
    /// slots' copies may still be read by frames in flight.
    pub fn follow_pose(&mut self, gpu: &Arc<Gpu>, scene: &Scene, slot: usize) -> Result<()> {
        if self.palettes.is_some() {
            // Every skinned object is skinned in the vertex stage: no copy to pose.
            return Ok(());
        }
        for index in self.posed.changed(scene, slot) {
            if let Some((mesh, vertices, name)) = self.posed_vertices(scene, index) {
                mesh.write_posed(gpu, slot, &name, &vertices)?;
            }
        }
        Ok(())
    }

    /// Object `index`'s mesh and its vertices skinned by the object's palette now.
    fn posed_vertices(&mut self, scene: &Scene, index: usize) -> Option<(&mut GpuMesh, Vec<SceneVertex>, String)> {
        let object = &scene.objects[index];
        let (Some(skin), Some(mesh), Some(source)) =
            (&object.skin, self.meshes.get_mut(object.mesh), scene.meshes.get(object.mesh))
        else {
            return None;
        };
        let (positions, normals) = skin.posed_positions_normals();
        let name = format!("{} vertices (posed)", object.name);
        Some((mesh, scene_vertices(source, &positions, &normals), name))
    }
}

/// What draws object `index` of `scene` with `pipeline`'s state, from `(meshes, bind_poses)`
/// (per scene mesh, and per object skinned on the GPU): its bind pose and `pipeline`'s skinned
/// twin when it is skinned on the GPU, else its mesh and `pipeline`. An error when the pipeline
/// was built without a twin, or the object or its mesh is missing.
pub fn object_draw<'m, 'p>(
    scene: &Scene,
    index: usize,
    (meshes, bind_poses): (&'m [GpuMesh], &'m [Option<GpuMesh>]),
    pipeline: &'p Pipeline,
) -> Result<(&'m GpuMesh, &'p Pipeline)> {
    let object = scene.objects.get(index).ok_or_else(|| Error::Internal(format!("no object {index}")))?;
    let name = &object.name;
    if let Some(bind_pose) = bind_poses.get(index).and_then(Option::as_ref) {
        let twin = pipeline.skinned().ok_or_else(|| {
            Error::Internal(format!(
                "'{name}' is skinned on the GPU, but pipeline '{}' has no skinned twin",
                pipeline.desc.name
            ))
        })?;
        return Ok((bind_pose, twin));
    }
    let mesh = meshes.get(object.mesh).ok_or_else(|| Error::Internal(format!("'{name}' has no mesh on the GPU")))?;
    Ok((mesh, pipeline))
}

/// Per object, a skinned object's bind pose with its joints moved to its palette (`None` for
/// the others).
fn upload_bind_poses(gpu: &Arc<Gpu>, scene: &Scene, palettes: &JointPalettes) -> Result<Vec<Option<GpuMesh>>> {
    scene
        .objects
        .iter()
        .zip(&palettes.first_joint)
        .map(|(object, first)| {
            let (Some(skin), Some(first), Some(source)) = (&object.skin, first, scene.meshes.get(object.mesh)) else {
                return Ok(None);
            };
            let vertices = skinned_vertices(&object.name, source, skin, *first)?;
            let name = format!("{} (bind pose)", object.name);
            GpuMesh::from_raw(gpu, &name, &vertices, &source.data.indices).map(Some)
        })
        .collect()
}

/// One vertex of `VertexLayout::SCENE`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SceneVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv0: [f32; 2],
    pub uv1: [f32; 2],
    pub colour: [f32; 4],
}

/// One vertex of `VertexLayout::SKINNED_SCENE`: the scene's, then JOINTS_0 and WEIGHTS_0.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SkinnedVertex {
    pub scene: SceneVertex,
    pub joints: [u16; 4],
    pub weights: [f32; 4],
}

/// `source`'s vertices in `skin`'s bind pose with its joints and weights, each joint index
/// moved up by `joint_base` (where the object's palette starts among the frame's palettes).
/// An error names the mesh when the skin's lists disagree with its vertices, a vertex uses a
/// joint outside the palette, or the palette has more than `MAX_JOINTS` joints.
pub fn skinned_vertices(
    name: &str,
    source: &SceneMesh,
    skin: &SceneSkin,
    joint_base: u32,
) -> Result<Vec<SkinnedVertex>> {
    if skin.joint_matrices.len() > MAX_JOINTS {
        // The loader refuses such a skin; a scene built by hand may still hold one.
        return Err(Error::InvalidInput(format!(
            "'{name}' has {} joints; the GPU palette holds at most {MAX_JOINTS}",
            skin.joint_matrices.len()
        )));
    }
    let n = skin.positions.len();
    let problem = |problem: String| Error::Mesh { mesh: name.to_owned(), problem };
    if skin.joints.len() != n || skin.weights.len() != n {
        return Err(problem(format!(
            "{n} vertices but {} joint and {} weight entries",
            skin.joints.len(),
            skin.weights.len()
        )));
    }
    let palette_len = skin.joint_matrices.len();
    let vertices = scene_vertices(source, &skin.positions, &skin.normals);
    (0..n)
        .map(|v| {
            let mut joints = skin.joints[v];
            for joint in &mut joints {
                if usize::from(*joint) >= palette_len {
                    return Err(problem(format!(
                        "vertex {v} uses joint {joint}, but the palette has {} joints",
                        skin.joint_matrices.len()
                    )));
                }
                *joint = u16::try_from(u32::from(*joint) + joint_base).map_err(|_| {
                    problem(format!("the frame's joint palettes pass {} joints at vertex {v}", u16::MAX))
                })?;
            }
            Ok(SkinnedVertex { scene: vertices[v], joints, weights: skin.weights[v] })
        })
        .collect()
}

/// `mesh`'s vertices at `positions` and `normals` (its own, or a posed copy) with its UV sets
/// and COLOR_0; what is missing is zero UV, white colour, +Y normal.
pub fn scene_vertices(mesh: &SceneMesh, positions: &[Vec3], normals: &[Vec3]) -> Vec<SceneVertex> {
    let at = |list: Option<&[Vec2]>, v: usize| list.and_then(|l| l.get(v)).copied().unwrap_or(Vec2::ZERO);
    positions
        .iter()
        .enumerate()
        .map(|(v, &position)| SceneVertex {
            position: position.to_array(),
            normal: normals.get(v).copied().unwrap_or(Vec3::Y).to_array(),
            uv0: at(Some(&mesh.data.uvs), v).to_array(),
            uv1: at(mesh.uv1.as_deref(), v).to_array(),
            colour: mesh.colors.as_ref().and_then(|c| c.get(v)).copied().unwrap_or(Vec4::ONE).to_array(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn scene_vertex_matches_the_scene_layout() {
        assert_eq!(crate::pipeline::VertexLayout::SCENE.stride() as usize, std::mem::size_of::<super::SceneVertex>());
        assert_eq!(
            crate::pipeline::VertexLayout::SKINNED_SCENE.stride() as usize,
            std::mem::size_of::<super::SkinnedVertex>()
        );
    }
}
