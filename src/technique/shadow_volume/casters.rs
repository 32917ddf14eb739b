//! Shadow casters: each casting object's welded mesh and edge adjacency, prepared once; its
//! volume built per frame for the current light and pose; and the camera-inside test that
//! picks z-fail.

use glam::{Mat4, Vec3};

use crate::error::{Error, Result};
use crate::mesh::{self, EdgeAdjacency, VolumeGeometry, Welded};
use crate::scene::{Light, Scene};
use crate::technique::options::{ShadowVolumeOptions, VolumeMethod};

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
