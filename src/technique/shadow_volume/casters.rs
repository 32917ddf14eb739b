//! Shadow casters: each casting object's welded mesh, edge adjacency and volume path
//! (silhouette or two-sided, docs/design/any-mesh-volumes.md), prepared once; its volume built per frame
//! for the current light and pose; and the camera-inside test that picks z-fail.

use glam::{Mat4, Vec3};

use crate::mesh::caster::CasterMesh;
use crate::mesh::ray::{self, PlacedMesh};
use crate::mesh::{self, Reach, VolumeGeometry};
use crate::scene::{Light, Scene};
use crate::technique::options::{ShadowVolumeOptions, VolumeMethod};

/// A shadow-casting object with its mesh's topology and volume path, built once.
pub struct Caster {
    pub object: usize,
    pub mesh: CasterMesh,
}

/// Every shadow-casting object prepared, whatever its topology (open and non-manifold meshes
/// cast two-sided), and one warning per object that cannot cast at all, naming it and why.
pub fn prepare_casters(scene: &Scene) -> (Vec<Caster>, Vec<String>) {
    let (mut casters, mut warnings) = (Vec::new(), Vec::new());
    for (object, o) in scene.objects.iter().enumerate().filter(|(_, o)| o.casts_shadow) {
        let data = &scene.meshes[o.mesh].data;
        let name = format!("{} (object '{}')", scene.meshes[o.mesh].name, o.name);
        // A rigid mesh under a mirroring transform is wound clockwise in its own space (faces
        // out in the world: `scene::place`): its caster takes it turned back, wound as a solid's
        // own space is, and `volume_for` turns the volume's triangles for the mirror.
        let indices = if o.mirrored() {
            std::borrow::Cow::Owned(data.indices.chunks_exact(3).flat_map(|t| [t[0], t[2], t[1]]).collect())
        } else {
            std::borrow::Cow::Borrowed(data.indices.as_slice())
        };
        match CasterMesh::prepare(&name, &data.positions, &indices) {
            Ok(mesh) => casters.push(Caster { object, mesh }),
            Err(e) => warnings.push(format!("casts no shadow: {e}")),
        }
    }
    (casters, warnings)
}

/// One `T` per scene mesh that a rigid (unskinned) caster uses, made by `make` for the first
/// such caster (`None`: that mesh gets none), and per caster the index of its mesh's `T`
/// (`None` for a skinned caster, or a mesh that got none): what is uploaded once per mesh.
pub(super) fn per_rigid_mesh<T>(
    scene: &Scene,
    casters: &[Caster],
    mut make: impl FnMut(&Caster) -> crate::error::Result<Option<T>>,
) -> crate::error::Result<(Vec<T>, Vec<Option<usize>>)> {
    let (mut made, mut of_caster) = (Vec::new(), Vec::with_capacity(casters.len()));
    let mut of_scene_mesh: std::collections::HashMap<usize, Option<usize>> = std::collections::HashMap::new();
    for caster in casters {
        let object = &scene.objects[caster.object];
        if object.skin.is_some() {
            of_caster.push(None);
            continue;
        }
        let index = match of_scene_mesh.get(&object.mesh) {
            Some(&index) => index,
            None => {
                let index = make(caster)?.map(|value| {
                    made.push(value);
                    made.len() - 1
                });
                of_scene_mesh.insert(object.mesh, index);
                index
            }
        };
        of_caster.push(index);
    }
    Ok((made, of_caster))
}

/// The light in an object's own space (volumes are built there and transformed like the mesh).
pub(super) fn light_in_object_space(light: &Light, model: &Mat4) -> mesh::Light {
    let inverse = model.inverse();
    match *light {
        Light::Directional { direction } => mesh::Light::Directional(inverse.transform_vector3(direction)),
        Light::Point { position } => mesh::Light::Point(inverse.transform_point3(position)),
    }
}

/// The caster's volume for the scene's primary light in its current pose, reaching as far as
/// `reach`: caps with `caps` (the two-sided path always has them).
#[cfg(test)]
pub fn build_volume(scene: &Scene, caster: &Caster, reach: Reach, caps: bool) -> VolumeGeometry {
    build_volume_for(scene, caster, &scene.light(), reach, caps)
}

/// [`build_volume`] for the light `light`.
#[cfg(test)]
pub fn build_volume_for(scene: &Scene, caster: &Caster, light: &Light, reach: Reach, caps: bool) -> VolumeGeometry {
    let mut scratch = VolumeScratch::default();
    build_volume_into(scene, caster, light, reach, caps, &mut scratch);
    scratch.volume
}

/// What building a volume writes besides the volume, and the volume itself: kept from caster
/// to caster and frame to frame, so that a frame's volumes allocate nothing once it has grown.
#[derive(Default)]
pub struct VolumeScratch {
    pub volume: VolumeGeometry,
    multiplicities: Vec<i32>,
    /// A skinned caster's posed welded positions and their face normals.
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    /// An `indices_only` volume of a skinned caster posed on the CPU: its posed vertices,
    /// doubled (`mesh::shadow_volume::doubled_vertices`), which the frame uploads with the
    /// indices. Left empty when `skinned_on_gpu`.
    pub doubled: Vec<glam::Vec4>,
    /// The caster being built is skinned on the GPU: its bind pose is uploaded already.
    pub skinned_on_gpu: bool,
}

impl VolumeScratch {
    /// The centroid of the skinned caster last built, in its current pose (`None` after a rigid
    /// one): where the apex of its bounded far cap starts.
    pub fn posed_centroid(&self, vertex_count: usize) -> Option<Vec3> {
        let posed = &self.positions[..vertex_count.min(self.positions.len())];
        (!posed.is_empty()).then(|| posed.iter().copied().sum::<Vec3>() / posed.len() as f32)
    }
}

/// [`build_volume_for`] into `scratch.volume`, reusing its buffers.
pub fn build_volume_into(
    scene: &Scene,
    caster: &Caster,
    light: &Light,
    reach: Reach,
    caps: bool,
    scratch: &mut VolumeScratch,
) {
    let object = &scene.objects[caster.object];
    let light = light_in_object_space(light, &object.transform);
    let (adjacency, welded) = (&caster.mesh.adjacency, &caster.mesh.welded);
    let VolumeScratch { volume, multiplicities, positions, normals, doubled, skinned_on_gpu } = scratch;
    doubled.clear();
    positions.clear();
    if gather_posed_welded_positions(scene, caster, positions) {
        adjacency.recompute_face_normals(positions, normals);
        if volume.indices_only && !*skinned_on_gpu {
            crate::mesh::shadow_volume::doubled_vertices(&positions[..adjacency.vertex_count], doubled);
        }
        caster.mesh.build_volume_into(positions, normals, light, reach, caps, multiplicities, volume);
    } else {
        let normals = &adjacency.face_normals;
        caster.mesh.build_volume_into(&welded.positions, normals, light, reach, caps, multiplicities, volume);
    }
}

/// A skinned caster's welded vertices in its current pose, into `out`; false (and `out`
/// untouched) for a rigid caster.
fn gather_posed_welded_positions(scene: &Scene, caster: &Caster, out: &mut Vec<Vec3>) -> bool {
    let Some(skin) = scene.objects[caster.object].skin.as_ref() else { return false };
    if skin.positions.len() < caster.mesh.welded.remap.len() {
        return false;
    }
    caster.mesh.welded.gather_positions(&skin.posed_positions(), out);
    true
}

/// A skinned caster's welded vertices in its current pose (`Scene::pose_at` moves palettes,
/// not meshes; the welded topology stays); `None` for a rigid caster.
pub(super) fn posed_welded_positions(scene: &Scene, caster: &Caster) -> Option<Vec<Vec3>> {
    let mut positions = Vec::new();
    gather_posed_welded_positions(scene, caster, &mut positions).then_some(positions)
}

/// z-pass breaks when the near plane cuts a volume: test the eye and the near-plane corners,
/// against the volumes of every light that casts shadows.
pub fn camera_inside_volume(scene: &Scene, casters: &[Caster], aspect: f32) -> bool {
    let lights: Vec<Light> = scene.lights.iter().filter(|l| l.casts_shadow).map(|l| l.geometry()).collect();
    lights.iter().any(|light| camera_inside_volume_of(scene, casters, aspect, light))
}

/// [`camera_inside_volume`] for one light.
pub fn camera_inside_volume_of(scene: &Scene, casters: &[Caster], aspect: f32, light: &Light) -> bool {
    let camera = &scene.camera;
    let inverse = camera.view_projection(aspect).inverse();
    let corners =
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| inverse.project_point3(Vec3::new(x, y, 0.0)));
    // Skinned casters are posed once for the five points.
    let posed: Vec<Option<Vec<Vec3>>> = casters.iter().map(|c| posed_welded_positions(scene, c)).collect();
    let placed: Vec<PlacedMesh> = casters
        .iter()
        .zip(&posed)
        .map(|(caster, posed)| PlacedMesh {
            positions: posed.as_deref().unwrap_or(&caster.mesh.welded.positions),
            indices: &caster.mesh.welded.indices,
            model: scene.objects[caster.object].transform,
        })
        .collect();
    let light = match *light {
        Light::Directional { direction } => mesh::Light::Directional(direction),
        Light::Point { position } => mesh::Light::Point(position),
    };
    std::iter::once(camera.eye).chain(corners).any(|p| ray::in_shadow(light, &placed, p))
}

pub fn choose_zfail(options: &ShadowVolumeOptions, scene: &Scene, casters: &[Caster], aspect: f32) -> bool {
    match options.method {
        VolumeMethod::ZPass => false,
        VolumeMethod::ZFail => true,
        VolumeMethod::Auto => camera_inside_volume(scene, casters, aspect),
    }
}
