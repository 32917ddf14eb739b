//! A mesh prepared to cast shadow volumes: welded by position, its edge adjacency built, and
//! classified once (docs/design/any-mesh-volumes.md): a closed, consistently wound mesh keeps the classic
//! silhouette volume; any other casts two-sided, through edge multiplicities.

use glam::Vec3;

use super::adjacency::EdgeAdjacency;
use super::shadow_volume::{build_shadow_volume_into, Light, Reach, VolumeGeometry};
use super::two_sided_volume::{build_two_sided_volume_into, CornerEdges};
use super::weld::{weld_by_position, Welded};
use crate::error::{Error, Result};

/// Positions closer than this weld into one vertex (UV seams, split normals).
pub const WELD_EPSILON: f32 = 1e-5;

/// How a caster's volume is built.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CastPath {
    /// Closed and consistently wound: its light-facing triangles cast, silhouette edges are
    /// extruded (sections 1-2). Counts 1 per volume.
    Silhouette,
    /// Every triangle cast from whichever side the light sees, walls drawn by edge
    /// multiplicity. A closed part counts 2 per crossing, so the counter holds half as many.
    TwoSided {
        /// Why the silhouette path cannot be used: "open (4 boundary edges)", ...
        reason: String,
        corners: CornerEdges,
    },
}

impl CastPath {
    /// The short name reports use: "silhouette" or "two-sided".
    pub fn name(&self) -> &'static str {
        match self {
            CastPath::Silhouette => "silhouette",
            CastPath::TwoSided { .. } => "two-sided",
        }
    }

    /// Why this path was chosen.
    pub fn reason(&self) -> &str {
        match self {
            CastPath::Silhouette => "closed and consistently wound",
            CastPath::TwoSided { reason, .. } => reason,
        }
    }

    /// How much a crossing of a closed part adds to the counter, in units of k.
    pub fn count_per_crossing(&self) -> u32 {
        match self {
            CastPath::Silhouette => 1,
            CastPath::TwoSided { .. } => 2,
        }
    }
}

/// A caster's topology and path, built once.
pub struct CasterMesh {
    pub welded: Welded,
    pub adjacency: EdgeAdjacency,
    pub path: CastPath,
    /// Per welded face: its corners are the scene mesh's own positions, bit for bit, in the
    /// scene's order, so that a scene pass draws exactly this triangle (its near cap can then
    /// lie wholly under it: `technique::shadow_volume::near_caps`).
    pub faces_as_drawn: Vec<bool>,
}

impl CasterMesh {
    /// Welds `positions`/`indices`, builds the edge list and picks the path. Errors (naming
    /// `name`) only for what no path can use: bad indices, no triangle left after welding.
    pub fn prepare(name: &str, positions: &[Vec3], indices: &[u32]) -> Result<CasterMesh> {
        let welded = weld_by_position(name, positions, indices, WELD_EPSILON)?;
        if welded.indices.is_empty() {
            return Err(Error::Mesh {
                mesh: name.to_owned(),
                problem: format!("no triangle with an area ({} degenerate ones dropped)", welded.dropped_degenerate),
            });
        }
        let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
        let path = match why_not_closed(&adjacency).or_else(|| inside_out(&welded)) {
            None => CastPath::Silhouette,
            Some(reason) => CastPath::TwoSided { reason, corners: CornerEdges::build(&adjacency)? },
        };
        let faces_as_drawn = faces_as_drawn(&welded, positions);
        Ok(CasterMesh { welded, adjacency, path, faces_as_drawn })
    }

    /// This light's volume from `positions` (the welded vertices, posed) and their
    /// `face_normals`, reaching as far as `reach`, into reused buffers. The silhouette path
    /// adds the caps only with `caps`; the two-sided path always has them.
    #[allow(clippy::too_many_arguments)]
    pub fn build_volume_into(
        &self,
        positions: &[Vec3],
        face_normals: &[Vec3],
        light: Light,
        reach: Reach,
        caps: bool,
        multiplicities: &mut Vec<i32>,
        out: &mut VolumeGeometry,
    ) {
        match &self.path {
            CastPath::Silhouette => {
                build_shadow_volume_into(&self.adjacency, positions, face_normals, light, reach, caps, out)
            }
            CastPath::TwoSided { corners, .. } => build_two_sided_volume_into(
                &self.adjacency,
                corners,
                positions,
                face_normals,
                light,
                reach,
                multiplicities,
                out,
            ),
        }
    }
}

/// Per welded face, whether welding left its three corners where the original mesh has them
/// (a corner merged into a vertex a little way off has moved).
fn faces_as_drawn(welded: &Welded, original: &[Vec3]) -> Vec<bool> {
    let same = |a: Vec3, b: Vec3| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits);
    welded
        .indices
        .chunks_exact(3)
        .zip(welded.original_corners.chunks_exact(3))
        .map(|(corners, originals)| {
            corners.iter().zip(originals).all(|(&w, &o)| same(welded.positions[w as usize], original[o as usize]))
        })
        .collect()
}

/// `None` for a closed, consistently wound manifold; else what breaks it, in words.
fn why_not_closed(adjacency: &EdgeAdjacency) -> Option<String> {
    let boundary = adjacency.edges.iter().filter(|e| e.is_boundary()).count();
    let mut problems = Vec::new();
    if boundary > 0 {
        problems.push(format!("open ({})", counted(boundary, "boundary edge")));
    }
    if !adjacency.non_manifold_edges.is_empty() {
        let edges = counted(adjacency.non_manifold_edges.len(), "edge");
        problems.push(format!("non-manifold ({edges} with more than two faces)"));
    }
    if !adjacency.inconsistent_edges.is_empty() {
        problems.push(format!("inconsistently wound ({})", counted(adjacency.inconsistent_edges.len(), "edge")));
    }
    (!problems.is_empty()).then(|| problems.join(", "))
}

/// A closed mesh whose normals point in (negative signed volume): its silhouette volume would
/// count -1 inside, which the alpha counter clamps to nothing.
fn inside_out(welded: &Welded) -> Option<String> {
    let signed_volume: f64 = welded
        .indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| welded.positions[i as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    (signed_volume < 0.0).then(|| format!("closed but wound inside out (signed volume {signed_volume:.3e})"))
}

/// "1 edge", "3 edges".
fn counted(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn a_cube_takes_the_silhouette_path_and_an_open_box_the_two_sided_one() -> Result<()> {
        let cube = shapes::cube(1.0);
        let caster = CasterMesh::prepare("cube", &cube.positions, &cube.indices)?;
        assert_eq!((caster.welded.positions.len(), caster.adjacency.face_count()), (8, 12));
        assert_eq!(caster.path, CastPath::Silhouette);
        let open = &cube.indices[..cube.indices.len() - 6];
        let open_box = CasterMesh::prepare("open box", &cube.positions, open)?;
        assert_eq!(open_box.path.name(), "two-sided");
        assert_eq!(open_box.path.reason(), "open (4 boundary edges)");
        assert_eq!(open_box.path.count_per_crossing(), 2);
        Ok(())
    }

    #[test]
    fn a_face_whose_corner_welding_moved_is_not_drawn_as_the_scene_draws_it() -> Result<()> {
        // Two triangles sharing an edge; the second's copy of one shared corner lies 1e-6 off
        // (welded into the first's), the first's duplicate of its other corner is exact.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1e-6, 0.0), Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        let caster = CasterMesh::prepare("two triangles", &positions, &[0, 1, 2, 3, 5, 4])?;
        assert_eq!(caster.welded.positions.len(), 4, "both seams welded");
        assert_eq!(caster.faces_as_drawn, [true, false]);
        Ok(())
    }

    #[test]
    fn the_reason_names_every_defect() -> Result<()> {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.5, -1.0, 0.0)];
        let fins = CasterMesh::prepare("fins", &positions, &[0, 1, 2, 1, 0, 3, 0, 1, 4])?;
        assert!(fins.path.reason().contains("open (6 boundary edges)"), "{}", fins.path.reason());
        assert!(fins.path.reason().contains("non-manifold (1 edge with"), "{}", fins.path.reason());
        let cube = shapes::cube(1.0);
        let mut flipped = cube.indices.clone();
        flipped.swap(1, 2);
        let flipped = CasterMesh::prepare("flipped", &cube.positions, &flipped)?;
        assert_eq!(flipped.path.reason(), "inconsistently wound (3 edges)");
        Ok(())
    }

    #[test]
    fn an_inside_out_cube_casts_two_sided() -> Result<()> {
        let cube = shapes::cube(2.0);
        let mut reversed = cube.indices.clone();
        reversed.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
        let caster = CasterMesh::prepare("inside out", &cube.positions, &reversed)?;
        assert_eq!(caster.path.name(), "two-sided");
        assert!(
            caster.path.reason().starts_with("closed but wound inside out (signed volume -8"),
            "{}",
            caster.path.reason()
        );
        Ok(())
    }

    #[test]
    fn a_mesh_of_degenerate_triangles_is_refused_by_name() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let error = CasterMesh::prepare("needle", &positions, &[0, 1, 2]).err().map(|e| e.to_string());
        assert!(error.as_deref().is_some_and(|e| e.contains("needle") && e.contains("no triangle")), "{error:?}");
    }
}
