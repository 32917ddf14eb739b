//! Shadow volumes extruded in the vertex shader (`shaders/shadow_volume_extrude.vert`) from
//! tables built once per caster mesh: no CPU work per frame, whatever moves (issue 42; the
//! shadow-mesh form of the Shadow Volumes Toolkit and ShaderX2, without its per-edge
//! degenerate quads in a vertex buffer: the vertex shader pulls what it needs by index).
//!
//! Every index of the static index buffer names one vertex of one candidate triangle: a corner
//! of a face (near cap, far cap) or an end of an edge (wall, and the far cap's fan triangle of
//! a bounded volume). The shader works out, from the face normals and the light in object
//! space, what the CPU builders (`shadow_volume`, `two_sided_volume`) decide per frame: which
//! faces cast (`cast`: +1 facing the light, 0 or -1 facing away, silhouette and two-sided
//! paths), each edge's multiplicity `m` (the sum over its faces of `cast` times +1 or -1 as the
//! face runs it), and from them each candidate's winding (the sign of `m`: the shader swaps the
//! ends of a wall, or a face's last two corners) and how many counts it adds (`|m|`). Every
//! candidate with `m = 0` collapses off screen. The triangles that survive are the CPU builders'
//! own, vertex for vertex and in the same winding, so the images are the same bytes.
//!
//! Index code (must match the shader): `id << 6 | slot << 4 | wall << 3 | role`, role 0 the
//! point itself, 1 its far image, 2 the far image of the mesh's centroid (a fan's apex); `slot`
//! is a face's corner (0..=2, corners 1 and 2 swapped for a face cast flipped) or a wall's end
//! (0: `a`, 1: `b`, the edge's `v[0]` and `v[1]` where `m > 0`, swapped where `m < 0`).

use std::ops::Range;

use glam::Vec3;

use crate::error::{Error, Result};
use crate::mesh::adjacency::EdgeAdjacency;

/// Where each table starts, in words from the mesh's first word (the header's slots).
pub const HEADER_WORDS: u32 = 8;
/// Faces and edges are named by 26 bits of an index.
const MAX_ID: usize = 1 << 26;

const ROLE_NEAR: u32 = 0;
const ROLE_FAR: u32 = 1;
const ROLE_APEX: u32 = 2;
const WALL: u32 = 1 << 3;

/// A caster mesh's tables and candidate triangles, built once.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowMesh {
    /// The tables, in 32-bit words, offsets relative to the first word: the header (faces,
    /// edges, incidences and positions offsets, the centroid, whether it casts two-sided),
    /// the welded positions (3 floats each), the faces (3 corners and the normal's 3 floats),
    /// the edges (`v[0]`, `v[1]`, first incidence, incidence count) and the incidences (`face
    /// << 1 | runs v[0] -> v[1]`).
    pub words: Vec<u32>,
    /// Candidate triangles, three index codes each, in the ranges below.
    pub indices: Vec<u32>,
    /// Walls: drawn always.
    pub walls: Range<u32>,
    /// The far cap's fan triangles of a bounded volume, one per wall.
    pub fans: Range<u32>,
    /// Near caps: z-fail, and the two-sided path always.
    pub near_caps: Range<u32>,
    /// Far caps of a volume reaching infinity from a point light.
    pub far_caps: Range<u32>,
    /// The most faces any edge has: the most times a wall is counted (the stencil draws that
    /// many instances).
    pub max_multiplicity: u32,
}

impl ShadowMesh {
    /// The tables of a mesh of `positions` (welded) with `adjacency` built from them;
    /// `two_sided` for a mesh that casts from both sides (`caster::CastPath::TwoSided`).
    pub fn build(adjacency: &EdgeAdjacency, positions: &[Vec3], two_sided: bool) -> Result<Self> {
        let (faces, edges, vertices) = (adjacency.face_count(), adjacency.edges.len(), adjacency.vertex_count);
        if faces >= MAX_ID || edges >= MAX_ID || positions.len() < vertices {
            return Err(Error::Mesh {
                mesh: adjacency.mesh_name.clone(),
                problem: format!(
                    "{faces} faces and {edges} edges is more than volumes extruded on the GPU name (2^26 each)"
                ),
            });
        }
        let incidences = incidences(adjacency)?;
        let positions = &positions[..vertices];
        let positions_at = HEADER_WORDS;
        let faces_at = positions_at + 3 * vertices as u32;
        let edges_at = faces_at + 6 * faces as u32;
        let incidences_at = edges_at + 4 * edges as u32;
        // The fan's apex, as `shadow_volume::start_volume` takes it.
        let centroid = positions.iter().copied().sum::<Vec3>() / vertices.max(1) as f32;
        let mut words = vec![faces_at, edges_at, incidences_at, positions_at];
        words.extend(centroid.to_array().map(f32::to_bits));
        words.push(u32::from(two_sided));
        words.extend(positions.iter().flat_map(|p| p.to_array().map(f32::to_bits)));
        for (corners, normal) in adjacency.indices.chunks_exact(3).zip(&adjacency.face_normals) {
            words.extend_from_slice(corners);
            words.extend(normal.to_array().map(f32::to_bits));
        }
        for (edge, faces) in adjacency.edges.iter().zip(&incidences.first) {
            words.extend_from_slice(&[edge.v[0], edge.v[1], faces.start, faces.end - faces.start]);
        }
        words.extend_from_slice(&incidences.entries);

        let mut indices = Vec::with_capacity(9 * edges + 6 * faces);
        let code = |id: usize, slot: u32, flags: u32| ((id as u32) << 6) | (slot << 4) | flags;
        // The wall runs b -> a (`shadow_volume::Extrusion::push_wall`).
        const A: u32 = 0;
        const B: u32 = 1;
        for edge in 0..edges {
            let at = |slot, role| code(edge, slot, WALL | role);
            let (a_far, b_far) = (at(A, ROLE_FAR), at(B, ROLE_FAR));
            indices.extend_from_slice(&[at(B, ROLE_NEAR), at(A, ROLE_NEAR), a_far, at(B, ROLE_NEAR), a_far, b_far]);
        }
        let walls = 0..indices.len() as u32;
        for edge in 0..edges {
            let at = |slot, role| code(edge, slot, WALL | role);
            indices.extend_from_slice(&[at(B, ROLE_FAR), at(A, ROLE_FAR), at(A, ROLE_APEX)]);
        }
        let fans = walls.end..indices.len() as u32;
        // The far cap is the face at the far end, reversed.
        for face in 0..faces {
            indices.extend_from_slice(&[0, 1, 2].map(|corner| code(face, corner, ROLE_NEAR)));
        }
        let near_caps = fans.end..indices.len() as u32;
        for face in 0..faces {
            indices.extend_from_slice(&[0, 2, 1].map(|corner| code(face, corner, ROLE_FAR)));
        }
        let far_caps = near_caps.end..indices.len() as u32;
        let max_multiplicity = incidences.first.iter().map(|r| r.end - r.start).max().unwrap_or(0);
        Ok(ShadowMesh { words, indices, walls, fans, near_caps, far_caps, max_multiplicity })
    }
}

/// Every face of every edge (non-manifold edges have more than the two `Edge::faces` keep),
/// with the way it runs the edge: built from the triangles' corners.
struct Incidences {
    /// Per edge, its entries' range in `entries`.
    first: Vec<Range<u32>>,
    /// `face << 1 | runs v[0] -> v[1]`.
    entries: Vec<u32>,
}

fn incidences(adjacency: &EdgeAdjacency) -> Result<Incidences> {
    let mut corner_edges = Vec::with_capacity(adjacency.indices.len());
    let mut counts = vec![0u32; adjacency.edges.len()];
    for t in adjacency.indices.chunks_exact(3) {
        for k in 0..3 {
            let (from, to) = (t[k], t[(k + 1) % 3]);
            let edge = adjacency.edge_between(from, to)?;
            counts[edge] += 1;
            corner_edges.push((edge, from < to));
        }
    }
    let mut first = Vec::with_capacity(counts.len());
    let mut start = 0;
    for &count in &counts {
        first.push(start..start + count);
        start += count;
    }
    let mut filled: Vec<u32> = first.iter().map(|r| r.start).collect();
    let mut entries = vec![0; start as usize];
    for (corner, &(edge, forward)) in corner_edges.iter().enumerate() {
        let face = (corner / 3) as u32;
        entries[filled[edge] as usize] = (face << 1) | u32::from(forward);
        filled[edge] += 1;
    }
    Ok(Incidences { first, entries })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::mesh::weld::weld_by_position;

    fn cube() -> Result<ShadowMesh> {
        let mesh = shapes::cube(1.0);
        let welded = weld_by_position("cube", &mesh.positions, &mesh.indices, 1e-6)?;
        let adjacency = EdgeAdjacency::build("cube", &welded.positions, &welded.indices)?;
        ShadowMesh::build(&adjacency, &welded.positions, false)
    }

    #[test]
    fn a_cube_has_one_candidate_of_each_kind_per_face_and_edge() -> Result<()> {
        let mesh = cube()?;
        // 12 faces, 18 edges.
        assert_eq!(mesh.walls.len(), 18 * 6);
        assert_eq!(mesh.fans.len(), 18 * 3);
        assert_eq!((mesh.near_caps.len(), mesh.far_caps.len()), (12 * 3, 12 * 3));
        assert_eq!(mesh.max_multiplicity, 2);
        // Header, 8 positions, 12 faces, 18 edges, 36 incidences.
        assert_eq!(mesh.words.len(), 8 + 3 * 8 + 6 * 12 + 4 * 18 + 36);
        Ok(())
    }

    #[test]
    fn every_index_names_an_existing_face_or_edge() -> Result<()> {
        let mesh = cube()?;
        for &code in &mesh.indices {
            let id = (code >> 6) as usize;
            let limit = if code & WALL != 0 { 18 } else { 12 };
            assert!(id < limit, "code {code:#x}");
            assert!(code & 3 <= ROLE_APEX && (code >> 4) & 3 <= 2);
        }
        Ok(())
    }

    #[test]
    fn every_edge_lists_its_faces_with_their_direction() -> Result<()> {
        let mesh = cube()?;
        let (edges_at, incidences_at) = (mesh.words[1] as usize, mesh.words[2] as usize);
        for edge in 0..18 {
            let [v0, v1, first, count] = [0, 1, 2, 3].map(|k| mesh.words[edges_at + 4 * edge + k]);
            assert_eq!(count, 2, "a closed cube: two faces an edge");
            let faces_at = mesh.words[0] as usize;
            let runs: Vec<bool> = (first..first + count)
                .map(|i| {
                    let entry = mesh.words[incidences_at + i as usize];
                    let face = (entry >> 1) as usize;
                    let corners = &mesh.words[faces_at + 6 * face..faces_at + 6 * face + 3];
                    let forward = (0..3).any(|k| corners[k] == v0 && corners[(k + 1) % 3] == v1);
                    assert_eq!(forward, entry & 1 == 1);
                    forward
                })
                .collect();
            assert_ne!(runs[0], runs[1], "consistently wound: the faces run the edge both ways");
        }
        Ok(())
    }
}
