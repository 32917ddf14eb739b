//! Each object's welded copy with smooth normals, pushed out along them by `cartoon_extrude.vert`
//! by a width in pixels: the selection outline (seed 003) and the inverted hull (seed 002).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::cartoon_shading::{cartoon_desc, CartoonPush};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::mesh::{self, Welded};
use crate::pipeline::{FixedFunction, PipelineDesc, VertexLayout};
use crate::render::Pipeline;
use crate::render::{FrameRecorder, GpuMesh};
use crate::scene::{PoseTracker, Scene, SceneSkin, SlotPoses};
use crate::shaders;

/// Positions closer than this weld into one vertex (UV seams, split normals): a seam of the
/// vertex buffer is no seam of the surface, so it neither breaks a line nor cracks a copy open.
pub const WELD_EPSILON: f32 = 1e-5;

/// How errors name an object's mesh.
pub fn object_mesh_name(scene: &Scene, object: usize) -> String {
    let o = &scene.objects[object];
    format!("{} (object '{}')", scene.meshes[o.mesh].name, o.name)
}

/// The object's mesh welded by position.
pub fn weld_object(scene: &Scene, object: usize) -> Result<Welded> {
    let data = &scene.meshes[scene.objects[object].mesh].data;
    mesh::weld_by_position(&object_mesh_name(scene, object), &data.positions, &data.indices, WELD_EPSILON)
}

/// Takes the skin's current pose as the welded positions (the topology stays). False when the
/// skin does not cover the mesh `welded` was built from.
pub fn follow_skin(welded: &mut Welded, skin: &SceneSkin) -> bool {
    if skin.positions.len() < welded.remap.len() {
        return false;
    }
    let mut positions = Vec::with_capacity(welded.positions.len());
    welded.gather_positions(&skin.posed_positions(), &mut positions);
    welded.positions = positions;
    true
}

/// Angle-weighted smooth normals per welded vertex: what the extruded outline copy and the
/// inverted hull move along, so that split normals (a cube's corners) do not crack them open.
/// Angle weights make the result independent of how a face is split into triangles.
pub fn smooth_normals(welded: &Welded) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; welded.positions.len()];
    for t in welded.indices.chunks_exact(3) {
        let p = [t[0], t[1], t[2]].map(|i| welded.positions[i as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for k in 0..3 {
            let (u, v) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            normals[t[k] as usize] += normal * u.angle_between(v);
        }
    }
    normals.iter().map(|n| n.normalize_or(Vec3::Y)).collect()
}

/// The welded mesh with smooth normals, interleaved (`VertexLayout::POSITION_NORMAL`). A rigid
/// mesh under a mirroring transform is wound clockwise in its own space (the glTF loader turns
/// its triangles to face out in the world), so its winding's normals point in there: they are
/// turned back out.
fn vertices(welded: &Welded, mirrored: bool) -> Vec<[Vec3; 2]> {
    let out = if mirrored { -1.0 } else { 1.0 };
    let normals = smooth_normals(welded);
    welded.positions.iter().zip(&normals).map(|(p, n)| [*p, out * *n]).collect()
}

/// A pipeline that draws extruded copies in one colour.
pub fn extrude_desc(name: &'static str, fixed: FixedFunction) -> PipelineDesc {
    cartoon_desc(
        name,
        shaders::CARTOON_EXTRUDE_VERT,
        shaders::CARTOON_COLOUR_FRAG,
        VertexLayout::POSITION_NORMAL,
        fixed,
    )
}

/// How far copies are pushed out, and their colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extrusion {
    pub width_px: f32,
    pub colour: Vec4,
}

/// Every object's extruded copy on the GPU, kept in the pose of its skin.
pub struct ExtrudedCopies {
    /// The copies' welded vertices on the CPU, in the pose `cpu_pose` says.
    welded: Vec<Welded>,
    meshes: Vec<GpuMesh>,
    cpu_pose: PoseTracker,
    /// Per frame slot, the pose its copies on the GPU hold (`GpuMesh::write_posed`).
    slot_poses: SlotPoses,
}

impl ExtrudedCopies {
    pub fn new(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        let mut welded = Vec::with_capacity(scene.objects.len());
        let mut meshes = Vec::with_capacity(scene.objects.len());
        for (index, object) in scene.objects.iter().enumerate() {
            let mesh = weld_object(scene, index)?;
            let name = format!("{} (extruded)", object.name);
            meshes.push(GpuMesh::from_raw(gpu, &name, &vertices(&mesh, object.mirrored()), &mesh.indices)?);
            welded.push(mesh);
        }
        Ok(ExtrudedCopies { welded, meshes, cpu_pose: PoseTracker::new(scene), slot_poses: SlotPoses::new(scene) })
    }

    /// Re-poses the copies of the skinned objects whose palettes changed: on the CPU, and in
    /// frame slot `slot`'s copies on the GPU (which no frame in flight reads). Returns the
    /// objects whose CPU copy moved.
    pub fn follow_pose(&mut self, gpu: &Arc<Gpu>, scene: &Scene, slot: usize) -> Result<Vec<usize>> {
        let moved = self.cpu_pose.changed(scene);
        for &index in &moved {
            if let (Some(skin), Some(welded)) = (&scene.objects[index].skin, self.welded.get_mut(index)) {
                follow_skin(welded, skin);
            }
        }
        for index in self.slot_poses.changed(scene, slot) {
            let object = &scene.objects[index];
            let (Some(skin), Some(welded), Some(mesh)) =
                (&object.skin, self.welded.get(index), self.meshes.get_mut(index))
            else {
                continue;
            };
            if skin.positions.len() < welded.remap.len() {
                continue;
            }
            let name = format!("{} (extruded, posed)", object.name);
            mesh.write_posed(gpu, slot, &name, &vertices(welded, false))?;
        }
        Ok(moved)
    }

    /// The welded positions of object `index`'s copy, in its current pose.
    pub fn positions(&self, index: usize) -> &[Vec3] {
        self.welded.get(index).map_or(&[], |w| w.positions.as_slice())
    }

    /// Draws the copies of the objects `which` picks with the bound `pipeline`, as `extrusion`
    /// says.
    pub fn draw(
        &self,
        rec: &mut FrameRecorder,
        pipeline: &Pipeline,
        scene: &Scene,
        which: impl Fn(usize) -> bool,
        extrusion: Extrusion,
        viewport: Vec4,
    ) {
        let params = Vec4::new(extrusion.width_px, 0.0, 0.0, 0.0);
        self.draw_with(rec, pipeline, scene, which, extrusion.colour, viewport, |_| params);
    }

    /// Draws the copies of the objects `which` picks with the bound `pipeline` in `colour`, each
    /// with the `CartoonPush::params` that `params` gives for its index (the vertex shader's).
    #[allow(clippy::too_many_arguments)]
    pub fn draw_with(
        &self,
        rec: &mut FrameRecorder,
        pipeline: &Pipeline,
        scene: &Scene,
        which: impl Fn(usize) -> bool,
        colour: Vec4,
        viewport: Vec4,
        params: impl Fn(usize) -> Vec4,
    ) {
        for index in (0..scene.objects.len()).filter(|i| which(*i)) {
            self.draw_copy(
                rec,
                pipeline,
                scene,
                index,
                CartoonPush { model: Mat4::IDENTITY, colour, params: params(index), viewport },
            );
        }
    }

    /// Draws the copy of object `index` with the bound `pipeline`.
    pub fn draw_one(
        &self,
        rec: &mut FrameRecorder,
        pipeline: &Pipeline,
        scene: &Scene,
        index: usize,
        extrusion: Extrusion,
        viewport: Vec4,
    ) {
        let params = Vec4::new(extrusion.width_px, 0.0, 0.0, 0.0);
        self.draw_copy(
            rec,
            pipeline,
            scene,
            index,
            CartoonPush { model: Mat4::IDENTITY, colour: extrusion.colour, params, viewport },
        );
    }

    /// Draws object `index`'s copy with `push`, its model matrix filled in.
    fn draw_copy(&self, rec: &mut FrameRecorder, pipeline: &Pipeline, scene: &Scene, index: usize, push: CartoonPush) {
        let (Some(object), Some(mesh)) = (scene.objects.get(index), self.meshes.get(index)) else { return };
        rec.push(pipeline, &CartoonPush { model: object.transform, ..push });
        rec.draw_mesh(mesh);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn smooth_normals_of_a_cube_point_out_of_its_corners() -> Result<()> {
        let cube = shapes::cube(2.0);
        let welded = mesh::weld_by_position("cube", &cube.positions, &cube.indices, WELD_EPSILON)?;
        assert_eq!(welded.positions.len(), 8);
        for (p, n) in welded.positions.iter().zip(smooth_normals(&welded)) {
            assert!((n - p.normalize()).length() < 1e-5, "{p} {n}");
        }
        Ok(())
    }
}
