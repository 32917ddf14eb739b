//! Unique edge list with the faces on each side (Game Programming Gems 2, 5.1): built once,
//! then walked linearly every frame for silhouettes, creases and shadow volumes.
//!
//! Face normals are kept apart from the topology, in a plain `Vec<Vec3>` that
//! [`face_normals`] refills from new (skinned) positions each frame; the edge list never
//! changes.

use glam::Vec3;

use super::weld::validate_triangle_list;
use crate::error::{Error, Result};

/// `Edge::faces[1]` of a boundary edge (one face only).
pub const NO_FACE: u32 = u32::MAX;

/// An undirected edge and the (first two) faces that use it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// Endpoints, `v[0] < v[1]`.
    pub v: [u32; 2],
    /// The faces on either side; `faces[1] == NO_FACE` on a boundary edge.
    pub faces: [u32; 2],
    /// `forward[i]`: face `faces[i]` runs `v[0] -> v[1]` in its winding (else `v[1] -> v[0]`).
    /// On a consistently wound manifold the two differ. Shadow-volume sides take their winding
    /// from this.
    pub forward: [bool; 2],
}

impl Edge {
    pub fn is_boundary(&self) -> bool {
        self.faces[1] == NO_FACE
    }

    /// The endpoints in the order face `faces[side]` runs them.
    pub fn directed_by(&self, side: usize) -> [u32; 2] {
        if self.forward[side] {
            self.v
        } else {
            [self.v[1], self.v[0]]
        }
    }
}

/// Edge topology of one triangle mesh.
#[derive(Debug, Clone)]
pub struct EdgeAdjacency {
    /// Name used in error messages.
    pub mesh_name: String,
    /// Unique edges, sorted by `v` (so by smaller vertex); `faces[0] < faces[1]`.
    pub edges: Vec<Edge>,
    /// The triangle list the edges were built from (kept for caps and normals).
    pub indices: Vec<u32>,
    /// Normals of the positions given to [`EdgeAdjacency::build`] (rest pose); animated meshes
    /// refill their own buffer with [`face_normals`].
    pub face_normals: Vec<Vec3>,
    /// Number of vertices the indices refer to.
    pub vertex_count: usize,
    /// Edges used by more than two faces (only the first two are in `Edge::faces`).
    pub non_manifold_edges: Vec<u32>,
    /// Two-face edges whose faces both run it the same way: one of them is flipped.
    pub inconsistent_edges: Vec<u32>,
}

impl EdgeAdjacency {
    /// Builds the unique edge list of a triangle list.
    ///
    /// Refuses (naming `mesh_name`) an index count that is not a multiple of 3, an index out
    /// of range, and a triangle that repeats a vertex (weld first: welding drops them).
    /// Open, non-manifold and inconsistently wound meshes are accepted and reported; see
    /// [`EdgeAdjacency::require_closed_manifold`].
    pub fn build(mesh_name: &str, positions: &[Vec3], indices: &[u32]) -> Result<Self> {
        validate_triangle_list(mesh_name, positions.len(), indices)?;
        let vertex_count = positions.len();
        let face_count = indices.len() / 3;
        if face_count > (u32::MAX >> 1) as usize {
            return Err(Error::Mesh {
                mesh: mesh_name.to_owned(),
                problem: format!("{face_count} triangles is more than edge adjacency handles (2^31)"),
            });
        }
        // Seed 002 puts every face edge in a hash table keyed by its vertex pair. Here the
        // table's hash is the edge's smaller vertex and a counting pass sizes each bucket, so
        // filling it is two linear sweeps with no probing: 2 to 5 times faster than a HashMap
        // at 131k faces (the map's random accesses miss the cache).
        let mut bucket_start = vec![0u32; vertex_count + 1];
        for (face, t) in indices.chunks_exact(3).enumerate() {
            for (from, to) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                if from == to {
                    return Err(Error::Mesh {
                        mesh: mesh_name.to_owned(),
                        problem: format!(
                            "triangle {face} uses vertex {from} twice (weld_by_position drops such triangles)"
                        ),
                    });
                }
                bucket_start[from.min(to) as usize + 1] += 1;
            }
        }
        for v in 0..vertex_count {
            bucket_start[v + 1] += bucket_start[v];
        }
        // Each half edge as (larger vertex, face, runs small -> large) packed in a u64, so that
        // sorting a bucket groups an edge's faces together, in face order.
        let mut half_edges = vec![0u64; indices.len()];
        let mut fill = bucket_start.clone();
        for (face, t) in indices.chunks_exact(3).enumerate() {
            for (from, to) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let slot = &mut fill[from.min(to) as usize];
                let forward = u64::from(from < to);
                half_edges[*slot as usize] = (u64::from(from.max(to)) << 32) | ((face as u64) << 1) | forward;
                *slot += 1;
            }
        }
        let mut edges: Vec<Edge> = Vec::with_capacity(face_count * 3 / 2 + 16);
        let mut non_manifold_edges = Vec::new();
        let mut inconsistent_edges = Vec::new();
        for low in 0..vertex_count {
            let bucket = &mut half_edges[bucket_start[low] as usize..bucket_start[low + 1] as usize];
            bucket.sort_unstable();
            for (i, &half_edge) in bucket.iter().enumerate() {
                let high = (half_edge >> 32) as u32;
                let face = (half_edge as u32) >> 1;
                let forward = half_edge & 1 == 1;
                let previous_high = i.checked_sub(1).map(|j| (bucket[j] >> 32) as u32);
                if previous_high != Some(high) {
                    edges.push(Edge { v: [low as u32, high], faces: [face, NO_FACE], forward: [forward, false] });
                    continue;
                }
                let index = edges.len() as u32 - 1;
                let edge = &mut edges[index as usize];
                if edge.faces[1] == NO_FACE {
                    edge.faces[1] = face;
                    edge.forward[1] = forward;
                    if edge.forward[0] == forward {
                        inconsistent_edges.push(index);
                    }
                } else if non_manifold_edges.last() != Some(&index) {
                    non_manifold_edges.push(index);
                }
            }
        }

        let mut face_normals_rest = Vec::with_capacity(face_count);
        face_normals(positions, indices, &mut face_normals_rest);
        Ok(Self {
            mesh_name: mesh_name.to_owned(),
            edges,
            indices: indices.to_vec(),
            face_normals: face_normals_rest,
            vertex_count,
            non_manifold_edges,
            inconsistent_edges,
        })
    }

    /// The index in `edges` of the edge between vertices `from` and `to` (either way round).
    pub fn edge_between(&self, from: u32, to: u32) -> Result<usize> {
        let key = [from.min(to), from.max(to)];
        self.edges.binary_search_by(|e| e.v.cmp(&key)).map_err(|_| Error::Mesh {
            mesh: self.mesh_name.clone(),
            problem: format!("edge {from}-{to} is missing from its edge list"),
        })
    }

    pub fn face_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Every edge has exactly two faces.
    #[cfg(test)]
    pub fn is_closed(&self) -> bool {
        self.non_manifold_edges.is_empty() && self.edges.iter().all(|e| !e.is_boundary())
    }

    /// Indices of the edges with a single face.
    #[cfg(test)]
    pub fn boundary_edges(&self) -> Vec<u32> {
        (0..self.edges.len() as u32).filter(|&e| self.edges[e as usize].is_boundary()).collect()
    }

    /// `Ok` when every edge has exactly two faces that run it in opposite directions: what
    /// z-fail shadow volumes need to be closed. Otherwise an [`Error::Mesh`] that counts the
    /// boundary, non-manifold and inconsistently wound edges and shows the first of each.
    ///
    /// (Vertices where two sheets touch, as in a bow tie, are allowed: they do not open a
    /// volume built edge by edge.)
    #[cfg(test)]
    pub fn require_closed_manifold(&self) -> Result<()> {
        let boundary = self.boundary_edges();
        let mut problems = Vec::new();
        for (list, what) in [
            (&boundary, "boundary edge(s) (one face: the mesh is open)"),
            (&self.non_manifold_edges, "non-manifold edge(s) (more than two faces)"),
            (&self.inconsistent_edges, "edge(s) with inconsistent winding (both faces run them the same way)"),
        ] {
            if let Some(&first) = list.first() {
                let [a, b] = self.edges[first as usize].v;
                problems.push(format!("{} {what}, first {a}-{b}", list.len()));
            }
        }
        if problems.is_empty() {
            return Ok(());
        }
        Err(Error::Mesh {
            mesh: self.mesh_name.clone(),
            problem: format!("not a closed manifold: {}", problems.join("; ")),
        })
    }

    /// [`face_normals`] over this mesh's triangles.
    ///
    /// # Panics
    /// If `positions` has fewer vertices than the mesh was built with.
    pub fn recompute_face_normals(&self, positions: &[Vec3], out: &mut Vec<Vec3>) {
        assert!(
            positions.len() >= self.vertex_count,
            "mesh '{}': {} positions for {} vertices",
            self.mesh_name,
            positions.len(),
            self.vertex_count
        );
        face_normals(positions, &self.indices, out);
    }
}

/// Unit normal of each triangle (right-hand rule: CCW seen from the side it points to),
/// written into `out` so that the buffer is reused frame to frame. Zero-area triangles get a
/// zero normal.
///
/// # Panics
/// If an index is out of range for `positions` (indices checked by
/// [`EdgeAdjacency::build`] are not).
pub fn face_normals(positions: &[Vec3], indices: &[u32], out: &mut Vec<Vec3>) {
    out.clear();
    out.extend(indices.chunks_exact(3).map(|t| {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    }));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::mesh::weld::weld_by_position;

    fn welded_cube() -> Result<(Vec<Vec3>, Vec<u32>)> {
        let cube = shapes::cube(1.0);
        let welded = weld_by_position("cube", &cube.positions, &cube.indices, 1e-6)?;
        Ok((welded.positions, welded.indices))
    }

    #[test]
    fn closed_cube_has_twelve_two_sided_edges() -> Result<()> {
        let (positions, indices) = welded_cube()?;
        let adjacency = EdgeAdjacency::build("cube", &positions, &indices)?;
        assert_eq!(adjacency.edges.len(), 18, "12 cube edges + 6 face diagonals");
        assert!(adjacency.is_closed());
        adjacency.require_closed_manifold()?;
        assert!(adjacency.edges.windows(2).all(|pair| pair[0].v < pair[1].v));
        for edge in &adjacency.edges {
            assert!(edge.faces[0] < edge.faces[1]);
            assert!(edge.v[0] < edge.v[1]);
            assert_ne!(edge.faces[1], NO_FACE);
            assert_ne!(edge.forward[0], edge.forward[1]);
            // `forward` matches the winding actually found in each face.
            for side in 0..2 {
                let [from, to] = edge.directed_by(side);
                let f = edge.faces[side] as usize;
                let t = &indices[3 * f..3 * f + 3];
                let runs = (0..3).any(|k| t[k] == from && t[(k + 1) % 3] == to);
                assert!(runs, "face {f} does not run {from}->{to}");
            }
        }
        Ok(())
    }

    #[test]
    fn face_normals_of_the_cube_are_axes() -> Result<()> {
        let (positions, indices) = welded_cube()?;
        let adjacency = EdgeAdjacency::build("cube", &positions, &indices)?;
        for n in &adjacency.face_normals {
            assert!((n.abs().max_element() - 1.0).abs() < 1e-6, "{n}");
        }
        // Recomputed from moved positions into a reused buffer: a mirror flips the normals.
        let mirrored: Vec<Vec3> = positions.iter().map(|p| *p * Vec3::new(-1.0, 1.0, 1.0)).collect();
        let mut normals = vec![Vec3::ZERO; 3];
        adjacency.recompute_face_normals(&mirrored, &mut normals);
        assert_eq!(normals.len(), adjacency.face_count());
        for (flipped, rest) in normals.iter().zip(&adjacency.face_normals) {
            let centre_side = *rest * Vec3::new(-1.0, 1.0, 1.0);
            assert!(flipped.dot(centre_side) < -0.99);
        }
        Ok(())
    }

    #[test]
    fn single_quad_is_open_and_named() -> Result<()> {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let adjacency = EdgeAdjacency::build("sign", &positions, &[0, 1, 2, 0, 2, 3])?;
        assert!(!adjacency.is_closed());
        assert_eq!(adjacency.boundary_edges().len(), 4);
        let error = adjacency.require_closed_manifold().expect_err("an open quad is not closed").to_string();
        assert!(error.contains("mesh 'sign'"), "{error}");
        assert!(error.contains("4 boundary edge"), "{error}");
        Ok(())
    }

    #[test]
    fn three_faces_on_one_edge_are_non_manifold() -> Result<()> {
        // Three fins on the edge 0-1.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.5, -1.0, 0.0)];
        let indices = [0, 1, 2, 1, 0, 3, 0, 1, 4];
        let adjacency = EdgeAdjacency::build("fins", &positions, &indices)?;
        assert_eq!(adjacency.non_manifold_edges.len(), 1);
        assert_eq!(adjacency.edges[adjacency.non_manifold_edges[0] as usize].v, [0, 1]);
        assert!(!adjacency.is_closed());
        let error = adjacency.require_closed_manifold().expect_err("three fins are non-manifold").to_string();
        assert!(error.contains("mesh 'fins'"), "{error}");
        assert!(error.contains("1 non-manifold edge"), "{error}");
        Ok(())
    }

    #[test]
    fn a_flipped_face_is_inconsistent_winding() -> Result<()> {
        let (positions, mut indices) = welded_cube()?;
        indices.swap(1, 2); // flip triangle 0
        let adjacency = EdgeAdjacency::build("flipped", &positions, &indices)?;
        assert!(adjacency.is_closed(), "still two faces per edge");
        assert_eq!(adjacency.inconsistent_edges.len(), 3);
        let error = adjacency.require_closed_manifold().expect_err("a flipped face breaks the winding").to_string();
        assert!(error.contains("3 edge(s) with inconsistent winding"), "{error}");
        Ok(())
    }

    #[test]
    fn bad_triangle_lists_are_refused() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
        for (indices, expected) in
            [(&[0u32, 1][..], "multiple of 3"), (&[0, 1, 7][..], "uses vertex 7"), (&[0, 1, 1][..], "twice")]
        {
            let error =
                EdgeAdjacency::build("junk", &positions, indices).expect_err("bad input must be refused").to_string();
            assert!(error.contains("mesh 'junk'") && error.contains(expected), "{error}");
        }
    }

    #[test]
    fn euler_characteristic_of_generated_shapes() -> Result<()> {
        let cases = [
            ("cube", shapes::cube(1.0), 2),
            ("sphere", shapes::uv_sphere(12, 24)?, 2),
            ("torus", shapes::torus(2.0, 0.5, 24, 12)?, 0),
        ];
        for (name, mesh, expected) in cases {
            let welded = weld_by_position(name, &mesh.positions, &mesh.indices, 1e-6)?;
            let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
            assert!(adjacency.is_closed(), "{name}");
            for edge in &adjacency.edges {
                assert!(edge.faces.iter().all(|&f| f != NO_FACE), "{name}");
            }
            let f = adjacency.face_count() as i64;
            let e = adjacency.edges.len() as i64;
            assert_eq!(2 * e, 3 * f, "{name}");
            assert_eq!(welded.positions.len() as i64 - e + f, expected, "{name}");
        }
        Ok(())
    }
}
