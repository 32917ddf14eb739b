//! Shadow volumes of any triangle mesh (docs/design/any-mesh-volumes.md): open, non-manifold,
//! inconsistently wound or touching meshes cast through edge multiplicities.
//!
//! Every triangle is turned to face the light (the ones seen from behind are flipped) and casts
//! its own closed prism: the triangle (near cap), its three edges extruded away from the light
//! (sides), and the triangle at infinity, reversed (far cap). The count at a point is then the
//! number of triangles between it and the light: at least 1 exactly where it is shadowed,
//! whatever the topology. Side walls shared by neighbouring prisms cancel: the side of a
//! directed edge a -> b is drawn `m` times, `m` being the number of oriented triangles that run
//! a -> b minus those that run b -> a ([`edge_multiplicities`]).
//!
//! An edge with `|m| > 1` (every silhouette edge of a closed part, whose front and back faces
//! both cast; a non-manifold fan; two sheets stacked) keeps its wall once, in a list per `|m|`
//! (`VolumeGeometry::repeated_walls`). The real-stencil reference draws such a list `|m|` times
//! (its wrap ops add 1 per fragment); the alpha counter draws it once with an increment of
//! `|m| k`, which blends to the same count (ADD and REVERSE_SUBTRACT clamp alike whether the
//! increment comes at once or in steps) for a fraction of the fill: on a real assembly of open
//! parts, where every silhouette is such an edge, about a quarter of the volumes' fragments.
//!
//! The multiplicities come from the edge list built once per mesh (`EdgeAdjacency`, which keeps
//! only two faces per edge, so each triangle corner is mapped to its edge once, in
//! [`CornerEdges`]); per light they are one linear sweep over the triangles, on the CPU (the
//! mobile profile has no geometry shaders).

use glam::Vec3;

use super::adjacency::EdgeAdjacency;
use super::shadow_volume::{start_volume, Light, Reach, VolumeGeometry};
use crate::error::{Error, Result};

/// Per triangle corner, the edge that leaves it (`corner k -> corner k + 1`): its index in
/// `EdgeAdjacency::edges` and whether the triangle runs it `v[0] -> v[1]`. Built once.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CornerEdges {
    /// `edge index << 1 | runs v[0] -> v[1]`, three per triangle.
    packed: Vec<u32>,
    /// Each edge's endpoints (`Edge::v`), packed apart from the rest of `Edge`: the walls'
    /// sweep reads only these, every frame, for every edge that casts.
    ends: Vec<[u32; 2]>,
}

impl CornerEdges {
    /// Maps every corner of `adjacency`'s triangles to its edge (edges are sorted by their
    /// vertex pair, so a binary search finds each).
    pub fn build(adjacency: &EdgeAdjacency) -> Result<Self> {
        if adjacency.edges.len() > (u32::MAX >> 1) as usize {
            return Err(Error::Mesh {
                mesh: adjacency.mesh_name.clone(),
                problem: format!("{} edges is more than two-sided shadow volumes handle (2^31)", adjacency.edges.len()),
            });
        }
        let mut packed = Vec::with_capacity(adjacency.indices.len());
        for t in adjacency.indices.chunks_exact(3) {
            for k in 0..3 {
                let (from, to) = (t[k], t[(k + 1) % 3]);
                let edge = adjacency.edge_between(from, to)?;
                packed.push(((edge as u32) << 1) | u32::from(from < to));
            }
        }
        let ends = adjacency.edges.iter().map(|edge| edge.v).collect();
        Ok(CornerEdges { packed, ends })
    }

    /// A corner's edge, as `packed` holds it: its index and whether the face runs it
    /// `v[0] -> v[1]`.
    fn unpack(packed: u32) -> (usize, bool) {
        ((packed >> 1) as usize, packed & 1 == 1)
    }
}

/// Per edge of `adjacency`, its multiplicity `m` with every triangle turned to face the light
/// (`lit[face]` false: the face is flipped): oriented faces that run it `v[0] -> v[1]` count
/// +1, those that run it `v[1] -> v[0]` count -1.
pub fn edge_multiplicities(adjacency: &EdgeAdjacency, corners: &CornerEdges, lit: &[bool], out: &mut Vec<i32>) {
    out.clear();
    out.resize(adjacency.edges.len(), 0);
    // Every frame over every corner of every casting mesh: one pass, the sign without a branch.
    for (face, &faces_light) in corners.packed.chunks_exact(3).zip(lit.iter().take(adjacency.face_count())) {
        for &packed in face {
            let (edge, forward) = CornerEdges::unpack(packed);
            if let Some(m) = out.get_mut(edge) {
                *m += 2 * i32::from(forward == faces_light) - 1;
            }
        }
    }
}

/// The two-sided shadow volume of any triangle mesh, with both caps (the near cap is needed in
/// z-pass too: a ray may pass a triangle the scene pass culled, as through the hole of an open
/// box). Same vertex layout as [`super::build_shadow_volume`]; `multiplicities` is a buffer
/// reused frame to frame.
///
/// # Panics
/// If `positions` or `face_normals` are shorter than the mesh, or `corners` was built from
/// another mesh.
#[allow(clippy::too_many_arguments)] // buffers reused frame to frame
pub fn build_two_sided_volume_into(
    adjacency: &EdgeAdjacency,
    corners: &CornerEdges,
    positions: &[Vec3],
    face_normals: &[Vec3],
    light: Light,
    reach: Reach,
    multiplicities: &mut Vec<i32>,
    out: &mut VolumeGeometry,
) {
    let vertex_count = adjacency.vertex_count;
    assert!(
        positions.len() >= vertex_count
            && face_normals.len() >= adjacency.face_count()
            && corners.packed.len() == adjacency.indices.len()
            && corners.ends.len() == adjacency.edges.len(),
        "mesh '{}': two-sided volume needs {} positions, {} face normals and its corner edges",
        adjacency.mesh_name,
        vertex_count,
        adjacency.face_count()
    );
    let extrusion = start_volume(adjacency, positions, face_normals, light, reach, out);
    edge_multiplicities(adjacency, corners, &out.lit_faces, multiplicities);
    for (&[v0, v1], &m) in corners.ends.iter().zip(multiplicities.iter()) {
        if m == 0 {
            continue;
        }
        // (a, b) as the oriented faces run it on balance; its wall runs b -> a.
        let [a, b] = if m > 0 { [v0, v1] } else { [v1, v0] };
        match m.unsigned_abs() {
            1 => extrusion.push_wall(a, b, &mut out.sides, &mut out.far_cap),
            times => {
                // A wall and its fan triangle in one list: a list is counted whole, in any
                // order (each pipeline's blend, and the stencil's wrapping ops, commute).
                extrusion.push_wall_and_fan(a, b, out.repeated_list(times));
            }
        }
    }

    // Every face, turned to the light: a face seen from behind keeps its first corner and swaps
    // the other two. Written in place (the near cap is most of a two-sided volume).
    out.near_cap.resize(3 * out.lit_faces.len(), 0);
    let faces = adjacency.indices.chunks_exact(3).zip(&out.lit_faces);
    for (turned, (corners, &faces_light)) in out.near_cap.chunks_exact_mut(3).zip(faces) {
        let (b, c) = if faces_light { (corners[1], corners[2]) } else { (corners[2], corners[1]) };
        turned.copy_from_slice(&[corners[0], b, c]);
    }
    if extrusion.caps_each_face() {
        for face in out.near_cap.chunks_exact(3) {
            extrusion.push_far_cap([face[0], face[1], face[2]], &mut out.far_cap);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::mesh::weld::weld_by_position;

    fn adjacency(name: &str, positions: &[Vec3], indices: &[u32]) -> Result<(Vec<Vec3>, EdgeAdjacency)> {
        let welded = weld_by_position(name, positions, indices, 1e-6)?;
        let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
        Ok((welded.positions, adjacency))
    }

    fn volume(positions: &[Vec3], adjacency: &EdgeAdjacency, light: Light) -> Result<VolumeGeometry> {
        let corners = CornerEdges::build(adjacency)?;
        let mut out = VolumeGeometry::default();
        build_two_sided_volume_into(
            adjacency,
            &corners,
            positions,
            &adjacency.face_normals,
            light,
            Reach::Infinite,
            &mut Vec::new(),
            &mut out,
        );
        Ok(out)
    }

    fn lights() -> [Light; 4] {
        [
            Light::Directional(Vec3::new(0.0, -1.0, 0.0)),
            Light::Directional(Vec3::new(0.3, -1.0, 0.5)),
            Light::Point(Vec3::new(0.2, 6.0, 0.1)),
            Light::Point(Vec3::new(4.0, -3.0, -5.0)),
        ]
    }

    fn quad() -> (Vec<Vec3>, Vec<u32>) {
        (vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, -1.0), Vec3::NEG_Z], vec![0, 1, 2, 0, 2, 3])
    }

    /// The quad twice, once reversed: two sheets sharing their rim.
    fn stacked_sheets() -> Result<(Vec<Vec3>, EdgeAdjacency)> {
        let (positions, indices) = quad();
        let mut doubled = indices.clone();
        doubled.extend([0, 2, 1, 0, 3, 2]);
        adjacency("double quad", &positions, &doubled)
    }

    /// Signed count of volume triangles a ray from `origin` along `dir` crosses: +1 entering
    /// (against a face's normal), -1 leaving. Points at infinity become far finite stand-ins.
    fn crossing_count(volume: &VolumeGeometry, light: Light, origin: Vec3, dir: Vec3) -> i32 {
        let finite = |v: glam::Vec4, anchor: Vec3| {
            if v.w != 0.0 {
                return v.truncate() / v.w;
            }
            match light {
                Light::Directional(direction) => anchor + direction.normalize() * 1000.0,
                Light::Point(at) => at + v.truncate() * 1000.0,
            }
        };
        let mut count = 0;
        let copies: Vec<u32> = volume.repeated_copies().collect();
        for t in [&volume.sides, &volume.near_cap, &volume.far_cap, &copies].into_iter().flat_map(|l| l.chunks_exact(3))
        {
            // The side's finite corner anchors its points at infinity (directional light).
            let anchor = t
                .iter()
                .map(|&i| volume.vertices[i as usize])
                .find(|v| v.w != 0.0)
                .map_or(Vec3::ZERO, |v| v.truncate());
            let [a, b, c] = [0, 1, 2].map(|k| finite(volume.vertices[t[k] as usize], anchor));
            if crate::mesh::ray::ray_hits_triangle(origin, dir, [a, b, c]).is_some() {
                let normal = (b - a).cross(c - a);
                count += if normal.dot(dir) < 0.0 { 1 } else { -1 };
            }
        }
        count
    }

    #[test]
    fn a_quad_casts_the_same_prism_from_either_side() -> Result<()> {
        let (positions, indices) = quad();
        let (positions, adjacency) = adjacency("quad", &positions, &indices)?;
        for light in [Light::Point(Vec3::new(0.5, 4.0, -0.5)), Light::Point(Vec3::new(0.5, -4.0, -0.5))] {
            let v = volume(&positions, &adjacency, light)?;
            assert_eq!(v.sides.len() / 6, 4, "{light:?}: the four rim edges, the diagonal cancels");
            assert_eq!((v.near_cap.len() / 3, v.far_cap.len() / 3), (2, 2), "{light:?}");
            assert!(v.is_closed(), "{light:?}");
        }
        Ok(())
    }

    #[test]
    fn volumes_of_open_non_manifold_and_flipped_meshes_are_closed() -> Result<()> {
        let cube = shapes::cube(1.0);
        let open_box = cube.indices[..cube.indices.len() - 6].to_vec();
        let mut flipped = cube.indices.clone();
        flipped.swap(1, 2);
        // Three fins on one edge.
        let fins_positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.5, -1.0, 0.3)];
        let fins = [0u32, 1, 2, 1, 0, 3, 0, 1, 4];
        let (quad_positions, quad_indices) = quad();
        let cases: [(&str, &[Vec3], &[u32]); 4] = [
            ("open box", &cube.positions, &open_box),
            ("flipped face", &cube.positions, &flipped),
            ("fins", &fins_positions, &fins),
            ("quad", &quad_positions, &quad_indices),
        ];
        for (name, positions, indices) in cases {
            let (positions, adjacency) = adjacency(name, positions, indices)?;
            assert!(adjacency.require_closed_manifold().is_err(), "{name} must need the two-sided path");
            for light in lights() {
                let v = volume(&positions, &adjacency, light)?;
                assert_eq!(v.unmatched_edges(), 0, "{name} {light:?}");
            }
        }
        Ok(())
    }

    #[test]
    fn a_closed_mesh_counts_two_per_crossing_and_an_open_one_counts_its_sheets() -> Result<()> {
        let cube = shapes::cube(1.0);
        // A point light: its points at infinity have finite stand-ins that stay watertight.
        let light = Light::Point(Vec3::new(0.05, 10.0, 0.03));
        let below = Vec3::new(0.1, -3.0, 0.2);
        // Counting along the ray from far below up to the point: the count at `below`.
        let count_at = |v: &VolumeGeometry, p: Vec3| {
            crossing_count(v, light, p + Vec3::new(0.0, 0.0, -50.0), Vec3::Z) - crossing_count(v, light, p, Vec3::Z)
        };
        let (positions, closed) = adjacency("cube", &cube.positions, &cube.indices)?;
        let v = volume(&positions, &closed, light)?;
        assert_eq!(count_at(&v, below), 2, "top and bottom faces both cast");
        assert_eq!(count_at(&v, Vec3::new(3.0, -3.0, 0.0)), 0, "beside the cube");

        let open_top: Vec<u32> = cube
            .indices
            .chunks_exact(3)
            .filter(|t| !t.iter().all(|&i| cube.positions[i as usize].y > 0.0))
            .flatten()
            .copied()
            .collect();
        assert_eq!(open_top.len(), cube.indices.len() - 6);
        let (positions, open) = adjacency("open box", &cube.positions, &open_top)?;
        let v = volume(&positions, &open, light)?;
        assert_eq!(count_at(&v, below), 1, "only the bottom is left over the point");
        let (positions, sheet) = adjacency("quad", &quad().0, &quad().1)?;
        let v = volume(&positions, &sheet, light)?;
        assert_eq!(count_at(&v, Vec3::new(0.5, -2.0, -0.5)), 1);
        assert_eq!(count_at(&v, Vec3::new(0.5, 2.0, -0.5)), 0, "above the quad is lit");
        Ok(())
    }

    #[test]
    fn a_volume_rebuilt_for_another_light_reuses_its_lists() -> Result<()> {
        // Stacked sheets: every rim wall is repeated, so the volume has a list per |m|.
        let (positions, adjacency) = stacked_sheets()?;
        let corners = CornerEdges::build(&adjacency)?;
        let (mut out, mut m) = (VolumeGeometry::default(), Vec::new());
        let mut build = |light: Light, out: &mut VolumeGeometry| {
            let normals = &adjacency.face_normals;
            let reach = Reach::Along(5.0);
            build_two_sided_volume_into(&adjacency, &corners, &positions, normals, light, reach, &mut m, out);
        };
        build(Light::Directional(Vec3::NEG_Y), &mut out);
        let first: Vec<*const u32> = out.repeated_walls.iter().map(|(_, list)| list.as_ptr()).collect();
        assert_eq!(first.len(), 1);
        for light in [Light::Directional(Vec3::new(0.2, -1.0, 0.1)), Light::Directional(Vec3::Y)] {
            build(light, &mut out);
            assert_eq!(out.repeated_walls.len(), 1, "{light:?}");
            assert_eq!(out.repeated_walls[0].1.len(), 4 * 9, "{light:?}: four walls, each with its fan triangle");
            assert_eq!(out.repeated_walls[0].1.as_ptr(), first[0], "{light:?}: the list was made again");
            assert!(out.is_closed(), "{light:?}");
        }
        Ok(())
    }

    #[test]
    fn two_stacked_sheets_sharing_a_rim_draw_doubled_walls() -> Result<()> {
        // The same quad twice, once reversed: every rim edge has m = +-2 once both face the light.
        let (positions, adjacency) = stacked_sheets()?;
        let corners = CornerEdges::build(&adjacency)?;
        let lit: Vec<bool> = adjacency.face_normals.iter().map(|n| n.y > 0.0).collect();
        let mut m = Vec::new();
        edge_multiplicities(&adjacency, &corners, &lit, &mut m);
        let rim: Vec<i32> =
            adjacency.edges.iter().zip(&m).filter(|(e, _)| e.v != [0, 2]).map(|(_, m)| m.abs()).collect();
        assert_eq!(rim, [2, 2, 2, 2]);
        let v = volume(&positions, &adjacency, Light::Directional(Vec3::NEG_Y))?;
        // The four rim walls once each, as one list a stencil draws twice.
        assert!(v.sides.is_empty(), "{:?}", v.sides);
        assert_eq!(v.repeated_walls.len(), 1);
        assert_eq!((v.repeated_walls[0].0, v.repeated_walls[0].1.len() / 3), (2, 4));
        assert_eq!(v.repeated_copies().count() / 3, 8, "two copies of each rim wall");
        assert!(v.is_closed());
        Ok(())
    }
}
