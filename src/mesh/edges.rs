//! Edge classification for ink lines (seed 002, Game Programming Gems 2, 5.1): silhouette,
//! crease and boundary edges.
//!
//! Silhouettes depend on the view and are found every frame; creases only change when the mesh
//! deforms; attribute seams never change, so, as the seed suggests, they are found once at load
//! time ([`attribute_seams`]) and passed to [`classify`] as a list.

use glam::{Vec2, Vec3};

use super::adjacency::{EdgeAdjacency, NO_FACE};
use crate::error::{Error, Result};

/// Where the edges are seen from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum View {
    /// A perspective camera at this point.
    Perspective { eye: Vec3 },
    /// An orthographic camera looking along this direction (need not be unit length): the
    /// tests' view, where the silhouette is known by hand.
    #[cfg(test)]
    Orthographic { direction: Vec3 },
}

/// Edge indices (into `EdgeAdjacency::edges`, ascending) by class. One edge can be in
/// several lists.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EdgeClasses {
    /// Two-face edges with `(N1.V) * (N2.V) <= 0`.
    pub silhouette: Vec<u32>,
    /// Two-face edges whose fold angle passes the crease threshold.
    pub crease: Vec<u32>,
    /// One-face edges, and the attribute seams handed to [`classify`].
    pub boundary: Vec<u32>,
}

/// Per-vertex attributes of the mesh *before* welding, and the way from welded faces back to
/// them. Any attribute left `None` is not compared.
#[derive(Debug, Clone, Copy)]
pub struct CornerAttributes<'a> {
    /// For each corner of the welded triangle list (aligned with `EdgeAdjacency::indices`),
    /// the original vertex it came from: `Welded::original_corners`.
    pub original_corners: &'a [u32],
    pub uvs: Option<&'a [Vec2]>,
    pub normals: Option<&'a [Vec3]>,
    pub materials: Option<&'a [u32]>,
    /// UVs further apart than this on either axis differ.
    pub uv_tolerance: f32,
    /// Normals further apart than this angle differ.
    pub normal_tolerance_deg: f32,
}

impl<'a> CornerAttributes<'a> {
    /// No attributes yet, tolerances at 1e-5 (UV) and 1 degree (normal).
    pub fn new(original_corners: &'a [u32]) -> Self {
        Self {
            original_corners,
            uvs: None,
            normals: None,
            materials: None,
            uv_tolerance: 1e-5,
            normal_tolerance_deg: 1.0,
        }
    }
}

/// Two-face edges across which the attributes jump: the faces on either side reach an
/// endpoint through different original vertices whose UV, normal or material differ.
///
/// Comparing original vertex indices alone would not do: exporters also split vertices
/// whose attributes agree, so the attributes themselves are compared.
///
/// Refuses, naming `mesh_name`, corners that do not match the adjacency's triangle list and
/// original vertices missing from an attribute array.
pub fn attribute_seams(mesh_name: &str, adjacency: &EdgeAdjacency, attributes: &CornerAttributes) -> Result<Vec<u32>> {
    let corners = attributes.original_corners;
    let mesh_error = |problem: String| Error::Mesh { mesh: mesh_name.to_owned(), problem };
    if corners.len() != adjacency.indices.len() {
        return Err(mesh_error(format!(
            "{} original corners for {} welded corners",
            corners.len(),
            adjacency.indices.len()
        )));
    }
    let max_original = corners.iter().copied().max().map_or(0, |m| m as usize + 1);
    for (name, len) in [
        ("uvs", attributes.uvs.map(<[Vec2]>::len)),
        ("normals", attributes.normals.map(<[Vec3]>::len)),
        ("materials", attributes.materials.map(<[u32]>::len)),
    ] {
        if let Some(len) = len.filter(|&len| len < max_original) {
            return Err(mesh_error(format!("{len} {name} but corners use original vertex {}", max_original - 1)));
        }
    }

    let normal_cos = attributes.normal_tolerance_deg.to_radians().cos();
    let differ = |a: usize, b: usize| {
        a != b
            && (attributes.uvs.is_some_and(|uv| (uv[a] - uv[b]).abs().max_element() > attributes.uv_tolerance)
                || attributes
                    .normals
                    .is_some_and(|n| n[a].normalize_or_zero().dot(n[b].normalize_or_zero()) < normal_cos)
                || attributes.materials.is_some_and(|m| m[a] != m[b]))
    };
    // The original vertex through which `face` reaches welded vertex `welded`.
    let original_at = |face: u32, welded: u32| {
        let base = 3 * face as usize;
        (base..base + 3).find(|&corner| adjacency.indices[corner] == welded).map(|corner| corners[corner] as usize)
    };

    let mut seams = Vec::new();
    for (index, edge) in adjacency.edges.iter().enumerate() {
        let [f1, f2] = edge.faces;
        if f2 == NO_FACE {
            continue;
        }
        let seam = edge
            .v
            .iter()
            .any(|&w| matches!((original_at(f1, w), original_at(f2, w)), (Some(a), Some(b)) if differ(a, b)));
        if seam {
            seams.push(index as u32);
        }
    }
    Ok(seams)
}

/// Classifies every edge: silhouette from `view`, crease when the faces fold by more than
/// `crease_deg` degrees (the angle between their normals: 0 for flat, 90 for a cube edge,
/// convex or concave alike), boundary for one-face edges plus the precomputed `seams` (from
/// [`attribute_seams`]; pass `&[]` for none).
///
/// `seams` must be ascending, as [`attribute_seams`] returns them.
///
/// `face_normals` are this frame's (see `adjacency::face_normals`). Boundary edges are never
/// silhouettes or creases: they have one normal. On a face seen exactly edge-on `N.V = 0`, so
/// the seed's test `(N1.V) * (N2.V) <= 0` marks all its edges as silhouettes.
#[cfg(test)]
pub fn classify(
    adjacency: &EdgeAdjacency,
    positions: &[Vec3],
    face_normals: &[Vec3],
    view: View,
    crease_deg: f32,
    seams: &[u32],
) -> EdgeClasses {
    let mut classes = EdgeClasses::default();
    classify_into(adjacency, positions, face_normals, view, crease_deg, seams, &mut classes);
    classes
}

/// [`classify`] into lists that are cleared and reused, so a per-frame call does not allocate:
/// [`classify_creases_into`] then [`classify_view_into`].
///
/// # Panics
/// If `face_normals` or `positions` are shorter than the mesh.
#[cfg(test)]
pub fn classify_into(
    adjacency: &EdgeAdjacency,
    positions: &[Vec3],
    face_normals: &[Vec3],
    view: View,
    crease_deg: f32,
    seams: &[u32],
    out: &mut EdgeClasses,
) {
    classify_creases_into(adjacency, face_normals, crease_deg, &mut out.crease);
    classify_view_into(adjacency, positions, face_normals, view, seams, out);
}

/// The creases alone (into `out`, cleared): they depend on the face normals only, so a mesh
/// that does not deform keeps them from frame to frame.
///
/// # Panics
/// If `face_normals` is shorter than the mesh.
pub fn classify_creases_into(adjacency: &EdgeAdjacency, face_normals: &[Vec3], crease_deg: f32, out: &mut Vec<u32>) {
    assert!(
        face_normals.len() >= adjacency.face_count(),
        "mesh '{}': creases need {} face normals (got {})",
        adjacency.mesh_name,
        adjacency.face_count(),
        face_normals.len()
    );
    out.clear();
    let crease_cos = crease_deg.to_radians().cos();
    for (index, edge) in adjacency.edges.iter().enumerate() {
        let [f1, f2] = edge.faces;
        if f2 != NO_FACE && face_normals[f1 as usize].dot(face_normals[f2 as usize]) < crease_cos {
            out.push(index as u32);
        }
    }
}

/// What depends on the view, and the boundaries: `out.silhouette` and `out.boundary` are
/// rebuilt, `out.crease` is left as it is (see [`classify_creases_into`]).
///
/// # Panics
/// If `face_normals` or `positions` are shorter than the mesh.
pub fn classify_view_into(
    adjacency: &EdgeAdjacency,
    positions: &[Vec3],
    face_normals: &[Vec3],
    view: View,
    seams: &[u32],
    out: &mut EdgeClasses,
) {
    assert!(
        face_normals.len() >= adjacency.face_count() && positions.len() >= adjacency.vertex_count,
        "mesh '{}': classify needs {} face normals and {} positions (got {}, {})",
        adjacency.mesh_name,
        adjacency.face_count(),
        adjacency.vertex_count,
        face_normals.len(),
        positions.len()
    );
    debug_assert!(seams.windows(2).all(|pair| pair[0] < pair[1]), "seams must be ascending");
    out.silhouette.clear();
    out.boundary.clear();
    let mut seams = seams.iter().copied().peekable();

    for (index, edge) in adjacency.edges.iter().enumerate() {
        let index = index as u32;
        let mut is_boundary = false;
        while let Some(seam) = seams.next_if(|&seam| seam <= index) {
            is_boundary |= seam == index;
        }
        let [f1, f2] = edge.faces;
        if f2 == NO_FACE {
            out.boundary.push(index);
            continue;
        }
        if is_boundary {
            out.boundary.push(index);
        }
        let (n1, n2) = (face_normals[f1 as usize], face_normals[f2 as usize]);
        // N.V has the same value at every point of a face's plane, so any point of the edge
        // does; the seed uses its first vertex.
        let to_edge = match view {
            View::Perspective { eye } => positions[edge.v[0] as usize] - eye,
            #[cfg(test)]
            View::Orthographic { direction } => direction,
        };
        if n1.dot(to_edge) * n2.dot(to_edge) <= 0.0 {
            out.silhouette.push(index);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::adjacency::face_normals;
    use crate::mesh::shapes;
    use crate::mesh::weld::{weld_by_position, Welded};
    use std::f32::consts::PI;

    fn weld_and_link(name: &str, mesh: &shapes::MeshData) -> Result<(Welded, EdgeAdjacency)> {
        let welded = weld_by_position(name, &mesh.positions, &mesh.indices, 1e-6)?;
        let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
        Ok((welded, adjacency))
    }

    fn silhouette_of(welded: &Welded, adjacency: &EdgeAdjacency, view: View) -> Vec<[Vec3; 2]> {
        let classes = classify(adjacency, &welded.positions, &adjacency.face_normals, view, 30.0, &[]);
        classes
            .silhouette
            .iter()
            .map(|&e| adjacency.edges[e as usize].v.map(|v| welded.positions[v as usize]))
            .collect()
    }

    #[test]
    fn cube_on_axis_shows_its_front_face_outline() -> Result<()> {
        let (welded, adjacency) = weld_and_link("cube", &shapes::cube(1.0))?;
        let edges = silhouette_of(&welded, &adjacency, View::Perspective { eye: Vec3::new(0.0, 0.0, 5.0) });
        // Side faces are seen from behind at a finite distance: only the front square remains.
        assert_eq!(edges.len(), 4);
        for [a, b] in edges {
            assert_eq!((a.z, b.z), (0.5, 0.5));
        }
        Ok(())
    }

    #[test]
    fn cube_from_a_corner_shows_a_hexagon() -> Result<()> {
        let (welded, adjacency) = weld_and_link("cube", &shapes::cube(1.0))?;
        for view in [
            View::Perspective { eye: Vec3::splat(10.0) },
            View::Orthographic { direction: Vec3::new(-1.0, -2.0, -3.0) },
        ] {
            let edges = silhouette_of(&welded, &adjacency, view);
            assert_eq!(edges.len(), 6, "{view:?}");
            // The hexagon avoids the nearest and farthest corners.
            for [a, b] in edges {
                for corner in [Vec3::splat(0.5), Vec3::splat(-0.5)] {
                    assert!(a != corner && b != corner, "{view:?}");
                }
            }
        }
        Ok(())
    }

    #[test]
    fn orthographic_edge_on_faces_count_as_silhouette() -> Result<()> {
        // Looking straight down -Z, the side faces have N.V = 0: every edge passes `<= 0`.
        let (welded, adjacency) = weld_and_link("cube", &shapes::cube(1.0))?;
        let view = View::Orthographic { direction: Vec3::NEG_Z };
        let classes = classify(&adjacency, &welded.positions, &adjacency.face_normals, view, 30.0, &[]);
        let cube_edges = classes.crease.len();
        assert_eq!(cube_edges, 12);
        assert!(classes.silhouette.len() >= 12);
        Ok(())
    }

    #[test]
    fn sphere_silhouette_hugs_the_tangent_cone() -> Result<()> {
        let (rings, segments) = (16, 32);
        let (welded, adjacency) = weld_and_link("sphere", &shapes::uv_sphere(rings, segments)?)?;
        // Tessellation error: a silhouette edge borders a face the true contour crosses, so its
        // midpoint is within one band (11.25 degrees) of it; measured at most 5.6 degrees.
        let tolerance = PI / rings as f32;
        for (eye, exact_count) in [
            (Vec3::new(0.0, 4.0, 0.0), Some(segments)),
            (Vec3::new(0.0, -10.0, 0.0), Some(segments)),
            (Vec3::new(3.0, 2.0, -4.0), None),
        ] {
            let edges = silhouette_of(&welded, &adjacency, View::Perspective { eye });
            if let Some(count) = exact_count {
                // On the pole axis every band is uniformly front- or back-facing, so the
                // silhouette is exactly one ring of latitude.
                assert_eq!(edges.len(), count as usize, "eye {eye}");
            } else {
                let n = edges.len() as f32;
                assert!(n >= segments as f32 * 0.75 && n <= segments as f32 * 3.0, "{n}");
            }
            for [a, b] in edges {
                let mid = 0.5 * (a + b);
                let normal = mid.normalize();
                let to_eye = (eye - mid).normalize();
                let off_tangent = normal.dot(to_eye).asin().abs();
                assert!(off_tangent < tolerance, "eye {eye}: {off_tangent} rad off");
            }
        }
        Ok(())
    }

    /// Two unit quads sharing the edge x = 0 (from (0,0,0) to (0,1,0)); the second folded by
    /// `fold_deg` about it.
    fn folded_quads(fold_deg: f32) -> (Vec<Vec3>, Vec<u32>) {
        let (sin, cos) = fold_deg.to_radians().sin_cos();
        let positions = vec![
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(cos, 0.0, sin),
            Vec3::new(cos, 1.0, sin),
        ];
        let indices = vec![0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2];
        (positions, indices)
    }

    #[test]
    fn crease_depends_on_the_fold_angle() -> Result<()> {
        for (fold, threshold, expect_crease) in [(90.0, 30.0, true), (10.0, 30.0, false), (35.0, 30.0, true)] {
            let (positions, indices) = folded_quads(fold);
            let adjacency = EdgeAdjacency::build("fold", &positions, &indices)?;
            let view = View::Orthographic { direction: Vec3::NEG_Z };
            let classes = classify(&adjacency, &positions, &adjacency.face_normals, view, threshold, &[]);
            let hinge: Vec<[u32; 2]> = classes.crease.iter().map(|&e| adjacency.edges[e as usize].v).collect();
            let expected: Vec<[u32; 2]> = if expect_crease { vec![[1, 2]] } else { vec![] };
            assert_eq!(hinge, expected, "fold {fold}");
            assert_eq!(classes.boundary.len(), 6, "the outline of the pair");
        }
        Ok(())
    }

    #[test]
    fn crease_follows_normals_recomputed_per_frame() -> Result<()> {
        // Built flat, then "animated" to a 90 degree fold: the new normals decide.
        let (flat, indices) = folded_quads(0.0);
        let adjacency = EdgeAdjacency::build("hinge", &flat, &indices)?;
        let (folded, _) = folded_quads(90.0);
        let mut normals = Vec::new();
        face_normals(&folded, &indices, &mut normals);
        let view = View::Orthographic { direction: Vec3::NEG_Z };
        let before = classify(&adjacency, &flat, &adjacency.face_normals, view, 30.0, &[]);
        let after = classify(&adjacency, &folded, &normals, view, 30.0, &[]);
        assert!(before.crease.is_empty());
        assert_eq!(after.crease.len(), 1);
        Ok(())
    }

    #[test]
    fn sphere_uv_seam_is_a_boundary_but_its_normals_are_smooth() -> Result<()> {
        let (rings, segments) = (8, 16);
        let sphere = shapes::uv_sphere(rings, segments)?;
        let (welded, adjacency) = weld_and_link("sphere", &sphere)?;
        let mut attributes = CornerAttributes::new(&welded.original_corners);
        attributes.normals = Some(&sphere.normals);
        assert!(attribute_seams("sphere", &adjacency, &attributes)?.is_empty());

        attributes.uvs = Some(&sphere.uvs);
        let seams = attribute_seams("sphere", &adjacency, &attributes)?;
        // The u = 0 / u = 1 meridian (one edge per band), and every edge to a pole: each
        // column has its own pole vertex with its own u.
        assert_eq!(seams.len(), (rings + 2 * (segments - 1)) as usize);
        for &e in &seams {
            let ends = adjacency.edges[e as usize].v.map(|v| welded.positions[v as usize]);
            let on_meridian = ends.iter().all(|p| p.z == 0.0 && p.x >= 0.0);
            let at_pole = ends.iter().any(|p| p.y.abs() == 1.0);
            assert!(on_meridian || at_pole, "seam {ends:?} is neither meridian nor pole");
        }
        let view = View::Perspective { eye: Vec3::new(0.0, 0.0, 5.0) };
        let classes = classify(&adjacency, &welded.positions, &adjacency.face_normals, view, 60.0, &seams);
        assert_eq!(classes.boundary, seams);
        Ok(())
    }

    #[test]
    fn cube_split_normals_make_every_cube_edge_a_seam() -> Result<()> {
        let cube = shapes::cube(1.0);
        let (welded, adjacency) = weld_and_link("cube", &cube)?;
        let mut attributes = CornerAttributes::new(&welded.original_corners);
        attributes.normals = Some(&cube.normals);
        let seams = attribute_seams("cube", &adjacency, &attributes)?;
        // The 12 cube edges, not the 6 face diagonals (both sides share one original vertex).
        assert_eq!(seams.len(), 12);
        let classes = classify(
            &adjacency,
            &welded.positions,
            &adjacency.face_normals,
            View::Orthographic { direction: Vec3::ONE },
            45.0,
            &[],
        );
        assert_eq!(seams, classes.crease, "on a cube the seams are the creases");
        Ok(())
    }

    #[test]
    fn material_change_across_an_edge_is_a_seam() -> Result<()> {
        // Two triangles over a shared edge, exported as separate primitives (6 vertices).
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let indices = [0, 1, 2, 3, 4, 5];
        let welded = weld_by_position("decal", &positions, &indices, 0.0)?;
        let adjacency = EdgeAdjacency::build("decal", &welded.positions, &welded.indices)?;
        for (materials, expected) in [([0, 0, 0, 0, 0, 0], 0), ([0, 0, 0, 1, 1, 1], 1)] {
            let mut attributes = CornerAttributes::new(&welded.original_corners);
            attributes.materials = Some(&materials);
            assert_eq!(attribute_seams("decal", &adjacency, &attributes)?.len(), expected);
        }
        // An attribute array that misses vertices is refused with the mesh name.
        let mut attributes = CornerAttributes::new(&welded.original_corners);
        attributes.materials = Some(&[0, 0]);
        let error = attribute_seams("decal", &adjacency, &attributes).expect_err("short attribute array").to_string();
        assert!(error.contains("mesh 'decal'") && error.contains("materials"), "{error}");
        Ok(())
    }
}
