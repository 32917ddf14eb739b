//! Welding: merge vertices that share a position, so that edge adjacency sees one mesh instead
//! of islands split along UV seams and hard normals.
//!
//! Exported meshes duplicate a vertex wherever any attribute changes (a cube has 24 vertices, a
//! UV sphere a column of twins along its seam). Adjacency and shadow volumes only care about
//! position, so they run on the welded mesh; `original_corners` keeps the way back to the
//! original vertices, which is what the attribute-seam test in `edges` needs.

use glam::Vec3;

use super::fast_hash::{u64_map_with_capacity, U64Map};
use crate::error::{Error, Result};

/// A triangle whose area is below `DEGENERATE_SINE * (longest edge)^2` is zero-area: its height
/// is a millionth of its length, at the edge of what f32 positions can resolve.
const DEGENERATE_SINE: f32 = 1e-6;

const NO_VERTEX: u32 = u32::MAX;

/// A mesh after [`weld_by_position`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Welded {
    /// One position per welded vertex: that of the first original vertex merged into it.
    pub positions: Vec<Vec3>,
    /// Triangle list over welded vertices; degenerate triangles are gone.
    pub indices: Vec<u32>,
    /// Original vertex -> welded vertex.
    pub remap: Vec<u32>,
    /// Welded vertex -> the original vertex whose position it took, so that animated
    /// (skinned) original positions can be gathered each frame ([`Welded::gather_positions`]).
    pub representative: Vec<u32>,
    /// Per corner of `indices`, the original vertex that corner used before welding: the
    /// link back to per-vertex UVs, normals and materials.
    pub original_corners: Vec<u32>,
    /// Per kept triangle, its index in the original triangle list.
    pub original_faces: Vec<u32>,
    /// Triangles dropped because welding collapsed them (two equal corners) or their area is
    /// zero.
    pub dropped_degenerate: usize,
}

impl Welded {
    /// Number of welded triangles.
    pub fn face_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Fills `out` with welded positions taken from new original positions (e.g. after CPU
    /// skinning), reusing `out`'s allocation.
    ///
    /// # Panics
    /// If `original_positions` is shorter than the mesh that was welded.
    pub fn gather_positions(&self, original_positions: &[Vec3], out: &mut Vec<Vec3>) {
        assert!(
            original_positions.len() >= self.remap.len(),
            "gather_positions: {} positions for a mesh welded from {}",
            original_positions.len(),
            self.remap.len()
        );
        out.clear();
        out.extend(self.representative.iter().map(|&original| original_positions[original as usize]));
    }
}

/// Merges vertices closer than `epsilon` (Euclidean distance, inclusive) and drops the
/// triangles that collapse.
///
/// A vertex joins the lowest-numbered welded vertex within `epsilon` of it, else starts a new
/// one. Merging is not transitive: with a chain of points each `epsilon` apart, the ends stay
/// apart. `epsilon = 0` merges exact duplicates only (`-0.0` equals `0.0`).
///
/// Candidates come from a hash grid of `2 * epsilon`-sized cells: anything within `epsilon` of
/// a point lies in the 2x2x2 block of cells around it, including across cell boundaries.
///
/// Errors name `mesh_name`: an index count that is not a multiple of 3, an index out of range,
/// a non-finite position, a negative or non-finite `epsilon`.
pub fn weld_by_position(mesh_name: &str, positions: &[Vec3], indices: &[u32], epsilon: f32) -> Result<Welded> {
    let mesh_error = |problem: String| Error::Mesh { mesh: mesh_name.to_owned(), problem };
    if !(epsilon.is_finite() && epsilon >= 0.0) {
        return Err(mesh_error(format!("weld epsilon must be finite and >= 0 (got {epsilon})")));
    }
    validate_triangle_list(mesh_name, positions.len(), indices)?;
    if let Some(bad) = positions.iter().position(|p| !p.is_finite()) {
        return Err(mesh_error(format!("vertex {bad} has a non-finite position {}", positions[bad])));
    }

    let (remap, representative) = cluster_vertices(positions, epsilon);
    let welded_positions: Vec<Vec3> = representative.iter().map(|&original| positions[original as usize]).collect();

    let face_count = indices.len() / 3;
    let mut welded = Welded {
        indices: Vec::with_capacity(indices.len()),
        original_corners: Vec::with_capacity(indices.len()),
        original_faces: Vec::with_capacity(face_count),
        positions: welded_positions,
        remap,
        representative,
        dropped_degenerate: 0,
    };
    for (face, corners) in indices.chunks_exact(3).enumerate() {
        let w = [0, 1, 2].map(|k| welded.remap[corners[k] as usize]);
        let collapsed = w[0] == w[1] || w[1] == w[2] || w[2] == w[0];
        if collapsed || is_zero_area(w.map(|v| welded.positions[v as usize])) {
            welded.dropped_degenerate += 1;
            continue;
        }
        welded.indices.extend_from_slice(&w);
        welded.original_corners.extend_from_slice(corners);
        welded.original_faces.push(face as u32);
    }
    Ok(welded)
}

/// Checks that `indices` is a triangle list over `vertex_count` vertices.
pub(crate) fn validate_triangle_list(mesh_name: &str, vertex_count: usize, indices: &[u32]) -> Result<()> {
    let mesh_error = |problem: String| Error::Mesh { mesh: mesh_name.to_owned(), problem };
    if indices.len() % 3 != 0 {
        return Err(mesh_error(format!("{} indices is not a triangle list (not a multiple of 3)", indices.len())));
    }
    if let Some(corner) = indices.iter().position(|&i| i as usize >= vertex_count) {
        return Err(mesh_error(format!(
            "triangle {} uses vertex {} but the mesh has {vertex_count} vertices",
            corner / 3,
            indices[corner]
        )));
    }
    Ok(())
}

fn is_zero_area([a, b, c]: [Vec3; 3]) -> bool {
    let longest_sq = (b - a).length_squared().max((c - b).length_squared()).max((a - c).length_squared());
    (b - a).cross(c - a).length() <= DEGENERATE_SINE * longest_sq
}

/// Returns (original -> welded, welded -> original representative).
fn cluster_vertices(positions: &[Vec3], epsilon: f32) -> (Vec<u32>, Vec<u32>) {
    let cell_size = grid_cell_size(positions, epsilon);
    let epsilon_sq = epsilon * epsilon;

    // Each grid key heads a singly linked list (through `next_in_cell`) of the welded vertices
    // in that cell: one allocation for all cells. Two cells whose keys collide share a list,
    // which costs a few distance tests and nothing else.
    let mut cell_head: U64Map<u32> = u64_map_with_capacity(positions.len());
    let mut next_in_cell: Vec<u32> = Vec::with_capacity(positions.len());
    let mut representative: Vec<u32> = Vec::with_capacity(positions.len());
    let mut remap = Vec::with_capacity(positions.len());

    for (original, &p) in positions.iter().enumerate() {
        let (cell, toward_nearest) = grid_cell(p, cell_size);
        let mut best = NO_VERTEX;
        for corner in 0..8 {
            let neighbour = [0, 1, 2].map(|axis| {
                let step = if corner & (1 << axis) != 0 { toward_nearest[axis] } else { 0 };
                cell[axis].wrapping_add(step)
            });
            let mut candidate = cell_head.get(&cell_key(neighbour)).copied().unwrap_or(NO_VERTEX);
            while candidate != NO_VERTEX {
                let q = positions[representative[candidate as usize] as usize];
                if candidate < best && (p - q).length_squared() <= epsilon_sq {
                    best = candidate;
                }
                candidate = next_in_cell[candidate as usize];
            }
        }
        if best == NO_VERTEX {
            best = representative.len() as u32;
            representative.push(original as u32);
            let head = cell_head.entry(cell_key(cell)).or_insert(NO_VERTEX);
            next_in_cell.push(*head);
            *head = best;
        }
        remap.push(best);
    }
    (remap, representative)
}

/// `2 * epsilon` when it is positive: then the `epsilon` ball around a point spans two cells
/// per axis, its own and the neighbour on the side of the nearer cell face, so 8 cells hold
/// every candidate (27 with `epsilon`-sized cells). For exact welding any size works: pick one
/// that puts about one vertex in each cell of the bounding box.
fn grid_cell_size(positions: &[Vec3], epsilon: f32) -> f32 {
    if epsilon > 0.0 {
        return 2.0 * epsilon;
    }
    let (min, max) =
        positions.iter().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let extent = (max - min).max_element();
    let cells_per_axis = (positions.len() as f32).cbrt().max(1.0);
    if extent.is_finite() && extent > 0.0 {
        extent / cells_per_axis
    } else {
        1.0
    }
}

/// The cell holding `p`, and per axis the step (-1 or +1) to the neighbour cell nearer to `p`.
fn grid_cell(p: Vec3, cell_size: f32) -> ([i64; 3], [i64; 3]) {
    let scaled = p / cell_size;
    let floor = scaled.floor();
    let toward_nearest = (scaled - floor).to_array().map(|fraction| if fraction < 0.5 { -1 } else { 1 });
    // `as` saturates, so huge coordinates share an end cell instead of wrapping around.
    (floor.to_array().map(|c| c as i64), toward_nearest)
}

fn cell_key([x, y, z]: [i64; 3]) -> u64 {
    (x as u64).wrapping_mul(0x8DA6_B343) ^ (y as u64).wrapping_mul(0xD816_3841) ^ (z as u64).wrapping_mul(0xCB1A_B31F)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn split_cube_welds_to_eight_vertices() -> Result<()> {
        let cube = shapes::cube(2.0);
        assert_eq!(cube.positions.len(), 24);
        let welded = weld_by_position("cube", &cube.positions, &cube.indices, 1e-5)?;
        assert_eq!(welded.positions.len(), 8);
        assert_eq!(welded.face_count(), 12);
        assert_eq!(welded.dropped_degenerate, 0);
        for (original, &w) in welded.remap.iter().enumerate() {
            assert_eq!(welded.positions[w as usize], cube.positions[original]);
        }
        // Corners lead back to original vertices at the same place.
        for (corner, &original) in welded.original_corners.iter().enumerate() {
            let w = welded.indices[corner];
            assert_eq!(welded.remap[original as usize], w);
        }
        Ok(())
    }

    #[test]
    fn exact_weld_merges_only_identical_positions() -> Result<()> {
        let positions = [Vec3::ZERO, Vec3::new(-0.0, 0.0, 0.0), Vec3::new(1e-7, 0.0, 0.0), Vec3::X];
        let welded = weld_by_position("points", &positions, &[], 0.0)?;
        assert_eq!(welded.remap, vec![0, 0, 1, 2]);
        Ok(())
    }

    #[test]
    fn neighbours_across_a_cell_boundary_merge() -> Result<()> {
        // With 0.02-sized cells, 0.999999 and 1.000001 sit in cells 49 and 50.
        let epsilon = 0.01;
        let positions = [
            Vec3::splat(1.0 - 1e-6),
            Vec3::splat(1.0 + 1e-6),
            Vec3::new(1.0 - 1e-6, 1.0 - 1e-6, 1.02), // 0.02 away on z: stays apart.
        ];
        let welded = weld_by_position("boundary", &positions, &[], epsilon)?;
        assert_eq!(welded.remap, vec![0, 0, 1]);
        Ok(())
    }

    #[test]
    fn vertex_joins_lowest_numbered_candidate() -> Result<()> {
        let positions = [Vec3::ZERO, Vec3::new(0.2, 0.0, 0.0), Vec3::new(0.1, 0.0, 0.0)];
        let welded = weld_by_position("chain", &positions, &[], 0.15)?;
        // 0 and 1 are 0.2 apart (separate); 2 is within 0.15 of both and joins 0.
        assert_eq!(welded.remap, vec![0, 1, 0]);
        Ok(())
    }

    #[test]
    fn collapsed_and_zero_area_triangles_are_dropped() -> Result<()> {
        let positions = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1e-9, 0.0, 0.0), // welds onto vertex 0
            Vec3::new(2.0, 0.0, 0.0),  // collinear with 0 and 1
        ];
        let indices = [
            0, 1, 2, // kept
            3, 0, 2, // collapses: 3 welds onto 0
            0, 1, 4, // zero area: collinear
        ];
        let welded = weld_by_position("degenerate", &positions, &indices, 1e-6)?;
        assert_eq!(welded.indices, vec![0, 1, 2]);
        assert_eq!(welded.original_faces, vec![0]);
        assert_eq!(welded.dropped_degenerate, 2);
        Ok(())
    }

    #[test]
    fn bad_input_is_refused_with_the_mesh_name() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let cases: [(&[u32], &[Vec3], f32, &str); 4] = [
            (&[0, 1], &positions, 0.0, "multiple of 3"),
            (&[0, 1, 3], &positions, 0.0, "uses vertex 3"),
            (&[0, 1, 2], &positions, -1.0, "epsilon"),
            (&[0, 1, 2], &[Vec3::ZERO, Vec3::NAN, Vec3::Y], 0.0, "non-finite"),
        ];
        for (indices, positions, epsilon, expected) in cases {
            let error = weld_by_position("crate", positions, indices, epsilon)
                .expect_err("bad input must be refused")
                .to_string();
            assert!(error.contains("mesh 'crate'"), "{error}");
            assert!(error.contains(expected), "{error}");
        }
    }

    #[test]
    fn gather_positions_follows_the_representatives() -> Result<()> {
        let cube = shapes::cube(1.0);
        let welded = weld_by_position("cube", &cube.positions, &cube.indices, 1e-5)?;
        let moved: Vec<Vec3> = cube.positions.iter().map(|p| *p * 3.0).collect();
        let mut out = Vec::new();
        welded.gather_positions(&moved, &mut out);
        let expected: Vec<Vec3> = welded.positions.iter().map(|p| *p * 3.0).collect();
        assert_eq!(out, expected);
        Ok(())
    }
}
