//! CPU side of the edge-based ink lines (seed 002): per object, the welded mesh, its unique
//! edge list and its attribute seams are built once; per frame every edge is classified from
//! the eye and the flagged edges become screen-space quads. Face normals and creases live in
//! model space: a rigid mesh (moving or not: the eye is taken into its space) keeps them, only
//! a deformed (skinned, re-posed) mesh recomputes them, as the seed says.

use glam::{Mat4, Vec2, Vec3};

use crate::error::{Error, Result};
use crate::mesh::{self, CornerAttributes, EdgeAdjacency, EdgeClasses, View, Welded, NO_FACE};
use crate::scene::Scene;
use crate::technique::extruded::{object_mesh_name, WELD_EPSILON};
use crate::technique::options::Seams;

/// One corner of an ink quad (`shaders/cartoon_ink.vert`): both edge ends in world space, the
/// third corner of the front-facing face (silhouettes grow away from it), and which corner.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct InkVertex {
    pub a: Vec3,
    pub b: Vec3,
    pub c: Vec3,
    /// x: side (-1 or +1); y: 0 at `a`, 1 at `b`.
    pub corner: Vec2,
}

/// The six corners (two triangles) of one edge's quad.
const QUAD_CORNERS: [Vec2; 6] = [
    Vec2::new(-1.0, 0.0),
    Vec2::new(1.0, 0.0),
    Vec2::new(1.0, 1.0),
    Vec2::new(-1.0, 0.0),
    Vec2::new(1.0, 1.0),
    Vec2::new(-1.0, 1.0),
];

/// One mesh's topology, built once: an object's, or the welded whole of the primitives of one
/// glTF mesh instance, so that a material border inside it is an edge with two faces.
pub struct InkMesh {
    /// The objects drawn as this one mesh (they share the node's transform), in order.
    pub parts: Vec<usize>,
    pub welded: Welded,
    pub adjacency: EdgeAdjacency,
    /// Two-face edges across which the chosen attributes jump (found once, at load).
    pub seams: Vec<u32>,
    face_normals: Vec<Vec3>,
    /// `face_normals` and `classes.crease` are those of `welded.positions` at this crease angle.
    normals_for: Option<f32>,
    classes: EdgeClasses,
    drawn: Vec<bool>,
}

/// The parts' vertices one after another, and each vertex's material.
struct Joined {
    name: String,
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    materials: Vec<u32>,
    indices: Vec<u32>,
}

fn join_parts(scene: &Scene, parts: &[usize]) -> Result<Joined> {
    let first = *parts.first().ok_or_else(|| Error::InvalidInput("an ink mesh of no objects".into()))?;
    let mut name = object_mesh_name(scene, first);
    if parts.len() > 1 {
        name = format!("{name} and its {} other primitives", parts.len() - 1);
    }
    let mut joined = Joined {
        name,
        positions: Vec::new(),
        normals: Some(Vec::new()),
        uvs: Some(Vec::new()),
        materials: Vec::new(),
        indices: Vec::new(),
    };
    for &part in parts {
        let object = &scene.objects[part];
        let data = &scene.meshes[object.mesh].data;
        let (base, count) = (joined.positions.len() as u32, data.positions.len());
        if let Some(bad) = data.indices.iter().find(|&&i| i as usize >= count) {
            let mesh = object_mesh_name(scene, part);
            return Err(Error::Mesh { mesh, problem: format!("index {bad} is out of range for {count} vertices") });
        }
        joined.positions.extend_from_slice(&data.positions);
        joined.indices.extend(data.indices.iter().map(|&i| base + i));
        joined.materials.extend(std::iter::repeat(object.material as u32).take(count));
        append_attribute(&mut joined.normals, &data.normals, count);
        append_attribute(&mut joined.uvs, &data.uvs, count);
    }
    Ok(joined)
}

/// Appends a part's `count` values of an attribute: it counts only when every part has it for
/// every vertex.
fn append_attribute<T: Copy>(all: &mut Option<Vec<T>>, own: &[T], count: usize) {
    match all {
        Some(values) if own.len() >= count => values.extend_from_slice(&own[..count]),
        _ => *all = None,
    }
}

impl InkMesh {
    /// Welds the parts' meshes into one, builds its edge list and finds its attribute seams.
    /// Open meshes are fine: their one-face edges are boundaries.
    /// `seams` picks the attributes whose jumps are boundaries; one the mesh lacks is named in
    /// `warnings`.
    pub fn new(scene: &Scene, parts: Vec<usize>, seams: Seams, warnings: &mut Vec<String>) -> Result<Self> {
        let joined = join_parts(scene, &parts)?;
        let name = &joined.name;
        let welded = mesh::weld_by_position(name, &joined.positions, &joined.indices, WELD_EPSILON)?;
        let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
        // Normals and materials by default; UVs on request (a sphere's u = 0 meridian is a UV
        // seam nobody drew).
        let mut attributes = CornerAttributes::new(&welded.original_corners);
        for (wanted, attribute, present) in [
            (seams.normal, "normals", joined.normals.is_some()),
            (seams.uv, "texture coordinates", joined.uvs.is_some()),
        ] {
            if wanted && !present {
                warnings.push(format!("{name}: no {attribute}, so no {attribute} seams are drawn"));
            }
        }
        attributes.normals = joined.normals.as_deref().filter(|_| seams.normal);
        attributes.uvs = joined.uvs.as_deref().filter(|_| seams.uv);
        attributes.materials = seams.material.then_some(&joined.materials[..]);
        let seams = mesh::attribute_seams(name, &adjacency, &attributes)?;
        let edge_count = adjacency.edges.len();
        Ok(InkMesh {
            parts,
            welded,
            adjacency,
            seams,
            face_normals: Vec::new(),
            normals_for: None,
            classes: EdgeClasses::default(),
            drawn: vec![false; edge_count],
        })
    }

    /// Takes the parts' current pose (skinned parts re-posed) as the welded positions (the
    /// topology stays). False when a part's pose no longer matches the mesh this was built from.
    pub fn follow(&mut self, scene: &Scene) -> bool {
        let mut posed = Vec::with_capacity(self.welded.remap.len());
        for &part in &self.parts {
            let own = scene.posed_positions(part);
            let built_from =
                scene.objects.get(part).and_then(|o| scene.meshes.get(o.mesh)).map(|m| m.data.positions.len());
            if Some(own.len()) != built_from {
                return false;
            }
            posed.extend_from_slice(&own);
        }
        if posed.len() != self.welded.remap.len() {
            return false;
        }
        let mut positions = Vec::with_capacity(self.welded.positions.len());
        self.welded.gather_positions(&posed, &mut positions);
        self.welded.positions = positions;
        self.normals_for = None;
        true
    }

    /// Whether the next [`InkMesh::classify`] at `crease_deg` recomputes the face normals and
    /// creases (the first, and the first after the mesh deformed).
    pub fn needs_normals(&self, crease_deg: f32) -> bool {
        self.normals_for != Some(crease_deg)
    }

    /// This frame's classification from `eye` (world space): face normals and creases when
    /// [`InkMesh::needs_normals`], then silhouette and boundary flags.
    pub fn classify(&mut self, model: &Mat4, eye: Vec3, crease_deg: f32) -> &EdgeClasses {
        if self.needs_normals(crease_deg) {
            self.adjacency.recompute_face_normals(&self.welded.positions, &mut self.face_normals);
            mesh::classify_creases_into(&self.adjacency, &self.face_normals, crease_deg, &mut self.classes.crease);
            self.normals_for = Some(crease_deg);
        }
        let eye = model.inverse().transform_point3(eye);
        mesh::classify_view_into(
            &self.adjacency,
            &self.welded.positions,
            &self.face_normals,
            View::Perspective { eye },
            &self.seams,
            &mut self.classes,
        );
        &self.classes
    }

    /// Appends the quads of the last classification, each edge once: silhouette first, then
    /// crease, then boundary (a cube's outline is all three; drawing it three times would
    /// widen it).
    pub fn append_quads(&mut self, model: &Mat4, eye: Vec3, out: &mut InkQuads) {
        let eye = model.inverse().transform_point3(eye);
        self.drawn.iter_mut().for_each(|d| *d = false);
        let (adjacency, positions) = (&self.adjacency, &self.welded.positions);
        let world = |v: u32| model.transform_point3(positions[v as usize]);
        let third_corner = |face: u32, edge: [u32; 2]| {
            let t = &adjacency.indices[3 * face as usize..3 * face as usize + 3];
            t.iter().copied().find(|v| !edge.contains(v)).unwrap_or(t[0])
        };
        for (class, list) in [(0, &self.classes.silhouette), (1, &self.classes.crease), (2, &self.classes.boundary)] {
            for &e in list {
                if std::mem::replace(&mut self.drawn[e as usize], true) {
                    continue;
                }
                let edge = &adjacency.edges[e as usize];
                let [f1, f2] = edge.faces;
                // The face that looks at the eye (N.(p - eye) < 0); the other grows the line.
                let front =
                    if f2 == NO_FACE || self.face_normals[f1 as usize].dot(positions[edge.v[0] as usize] - eye) < 0.0 {
                        f1
                    } else {
                        f2
                    };
                let (a, b, c) = (world(edge.v[0]), world(edge.v[1]), world(third_corner(front, edge.v)));
                let target = match class {
                    0 => &mut out.silhouette,
                    1 => &mut out.crease,
                    _ => &mut out.boundary,
                };
                target.extend(QUAD_CORNERS.iter().map(|&corner| InkVertex { a, b, c, corner }));
            }
        }
    }
}

/// This frame's ink quads, one list per edge class (one draw each).
#[derive(Debug, Default, Clone)]
pub struct InkQuads {
    pub silhouette: Vec<InkVertex>,
    pub crease: Vec<InkVertex>,
    pub boundary: Vec<InkVertex>,
}

impl InkQuads {
    pub fn clear(&mut self) {
        self.silhouette.clear();
        self.crease.clear();
        self.boundary.clear();
    }

    /// Edges per class (six vertices each).
    pub fn edge_counts(&self) -> [usize; 3] {
        [self.silhouette.len() / 6, self.crease.len() / 6, self.boundary.len() / 6]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::scene::{Camera, Light};

    fn one_object_scene(data: crate::mesh::MeshData) -> Scene {
        let mut scene = crate::scene::Scene::empty(
            "test",
            Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO),
            Light::Directional { direction: Vec3::NEG_Y },
        );
        let mesh = scene.add_mesh("shape", data);
        scene.add_object("shape", mesh, Mat4::IDENTITY, Vec3::ONE, true);
        scene
    }

    #[test]
    fn cube_face_on_draws_its_front_square_once() -> Result<()> {
        let scene = one_object_scene(shapes::cube(1.0));
        let mut ink = InkMesh::new(&scene, vec![0], Seams::default(), &mut Vec::new())?;
        // Split normals: every cube edge is a seam, every cube edge a 90 degree crease.
        assert_eq!(ink.seams.len(), 12);
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let classes = ink.classify(&Mat4::IDENTITY, eye, 40.0).clone();
        assert_eq!((classes.silhouette.len(), classes.crease.len(), classes.boundary.len()), (4, 12, 12));
        let mut quads = InkQuads::default();
        ink.append_quads(&Mat4::IDENTITY, eye, &mut quads);
        // The front square as silhouettes, the other 8 cube edges as creases, nothing twice.
        assert_eq!(quads.edge_counts(), [4, 8, 0]);
        for v in &quads.silhouette {
            assert_eq!((v.a.z, v.b.z), (0.5, 0.5));
            // The third corner lies on the front face too: the line grows away from it.
            assert_eq!(v.c.z, 0.5);
        }
        Ok(())
    }

    #[test]
    fn every_edge_of_the_closed_scene_objects_has_exactly_two_faces() -> Result<()> {
        // Through the technique's own path: UV seams and pole fans weld shut.
        for name in ["default", "outline", "duck"] {
            let scene = crate::scene::builtin_scene(name)?;
            for (index, object) in scene.objects.iter().enumerate().filter(|(_, o)| o.casts_shadow) {
                let ink = InkMesh::new(&scene, vec![index], Seams::default(), &mut Vec::new())?;
                let mut uses = vec![0u32; ink.adjacency.face_count()];
                for edge in &ink.adjacency.edges {
                    assert!(edge.faces.iter().all(|&f| f != NO_FACE), "{name}/{}: open edge", object.name);
                    for &f in &edge.faces {
                        uses[f as usize] += 1;
                    }
                }
                assert!(uses.iter().all(|&u| u == 3), "{name}/{}: a face without 3 two-sided edges", object.name);
                assert_eq!(2 * ink.adjacency.edges.len(), 3 * ink.adjacency.face_count());
            }
        }
        Ok(())
    }

    /// A hand-made tent: two roof quads meeting at a 90 degree ridge (y = 1, along z), each
    /// with its own ridge vertices and flat normals (a normal seam), plus an apron quad that
    /// continues the left roof in its plane and shares its vertices and normals.
    fn tent() -> crate::mesh::MeshData {
        let s = std::f32::consts::FRAC_1_SQRT_2;
        let (left_n, right_n) = (Vec3::new(-s, s, 0.0), Vec3::new(s, s, 0.0));
        let positions = vec![
            // left roof: eaves (0, 1), ridge (2, 3)
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, -1.0),
            Vec3::new(0.0, 1.0, 0.0),
            // right roof: ridge (4, 5), eaves (6, 7)
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, -1.0),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, 0.0),
            // apron below the left eaves, same plane
            Vec3::new(-2.0, -1.0, 0.0),
            Vec3::new(-2.0, -1.0, -1.0),
        ];
        let normals = vec![left_n, left_n, left_n, left_n, right_n, right_n, right_n, right_n, left_n, left_n];
        let indices = vec![0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 1, 8, 1, 0];
        crate::mesh::MeshData { positions, normals, uvs: vec![Vec2::ZERO; 10], indices }
    }

    #[test]
    fn tent_ridge_is_a_crease_and_a_seam_its_rim_is_boundary() -> Result<()> {
        let scene = one_object_scene(tent());
        let mut ink = InkMesh::new(&scene, vec![0], Seams::default(), &mut Vec::new())?;
        let (edges, positions) = (ink.adjacency.edges.clone(), ink.welded.positions.clone());
        let ends = |e: u32| {
            let mut v = edges[e as usize].v.map(|i| positions[i as usize]);
            v.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap_or(std::cmp::Ordering::Equal));
            v
        };
        let ridge = [Vec3::new(0.0, 1.0, -1.0), Vec3::new(0.0, 1.0, 0.0)];
        // Welded: 8 vertices, 6 faces; the ridge is one two-face edge.
        assert_eq!((ink.welded.positions.len(), ink.adjacency.face_count()), (8, 6));
        assert_eq!(ink.seams.iter().map(|&e| ends(e)).collect::<Vec<_>>(), vec![ridge]);
        // Seen from high above the ridge: no silhouette (both roofs face up); only the ridge
        // folds by more than 40 degrees (90), the eaves line between roof and apron is flat.
        let classes = ink.classify(&Mat4::IDENTITY, Vec3::new(0.0, 10.0, 0.5), 40.0).clone();
        assert!(classes.silhouette.is_empty(), "{:?}", classes.silhouette);
        assert_eq!(classes.crease.iter().map(|&e| ends(e)).collect::<Vec<_>>(), vec![ridge]);
        // Boundary: the rim of the open surface (3 quads: 2 + 2 + 2 side edges + 2 far ends = 8)
        // and the ridge seam.
        let rim = ink.adjacency.boundary_edges().len();
        assert_eq!(rim, 8);
        assert_eq!(classes.boundary.len(), rim + 1);
        // Seen from the left, low: the right roof faces away, so the ridge is a silhouette.
        let side = ink.classify(&Mat4::IDENTITY, Vec3::new(-10.0, 0.5, -0.5), 40.0).clone();
        assert_eq!(side.silhouette.iter().map(|&e| ends(e)).collect::<Vec<_>>(), vec![ridge]);
        let mut quads = InkQuads::default();
        ink.append_quads(&Mat4::IDENTITY, Vec3::new(-10.0, 0.5, -0.5), &mut quads);
        // The ridge is drawn once, as a silhouette; the rest of the boundary as boundary.
        assert_eq!(quads.edge_counts(), [1, 0, 8]);
        Ok(())
    }
}
