//! Smooth vertex normals for meshes that come without them.

use std::collections::HashMap;

use glam::Vec3;

/// Key for welding: the exact position bits, with -0.0 folded into 0.0.
fn weld_key(p: Vec3) -> [u32; 3] {
    let bits = |x: f32| if x == 0.0 { 0 } else { x.to_bits() };
    [bits(p.x), bits(p.y), bits(p.z)]
}

/// Area-weighted smooth normals. Vertices at the same position (bit-exact) share one normal,
/// so a cube split into per-face vertices still gets rounded corner normals and a seam in UVs
/// does not show in the lighting. Each triangle adds its unnormalised cross product (twice its
/// area, in the winding's direction) to its three corners. A vertex with no usable triangle
/// gets +Z. Indices out of range are ignored (the loader has already rejected them).
pub fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut welded: HashMap<[u32; 3], usize> = HashMap::with_capacity(positions.len());
    let group: Vec<usize> = positions
        .iter()
        .map(|&p| {
            let next = welded.len();
            *welded.entry(weld_key(p)).or_insert(next)
        })
        .collect();
    let mut sums = vec![Vec3::ZERO; welded.len()];
    for tri in indices.chunks_exact(3) {
        let (Some(&a), Some(&b), Some(&c)) =
            (positions.get(tri[0] as usize), positions.get(tri[1] as usize), positions.get(tri[2] as usize))
        else {
            continue;
        };
        let n = (b - a).cross(c - a);
        if !n.is_finite() {
            continue;
        }
        for &v in tri {
            if let Some(sum) = group.get(v as usize).and_then(|&g| sums.get_mut(g)) {
                *sum += n;
            }
        }
    }
    group.iter().map(|&g| sums.get(g).and_then(|s| s.try_normalize()).unwrap_or(Vec3::Z)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_quad_points_along_the_winding() {
        let p =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let n = smooth_normals(&p, &[0, 1, 2, 0, 2, 3]);
        assert!(n.iter().all(|n| (*n - Vec3::Z).length() < 1e-6), "{n:?}");
        let n = smooth_normals(&p, &[0, 2, 1, 0, 3, 2]);
        assert!(n.iter().all(|n| (*n + Vec3::Z).length() < 1e-6), "{n:?}");
    }

    #[test]
    fn split_vertices_at_one_position_share_an_area_weighted_normal() {
        // Two triangles meeting at the origin, each with its own copy of the origin vertex:
        // one in the XY plane (area 2), one in the XZ plane (area 0.5).
        let p = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(-0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 0.0),
        ];
        let n = smooth_normals(&p, &[0, 1, 2, 3, 4, 5]);
        // Sum of cross products: (0,0,4) + (0,1,0) -> normalised.
        let expected = Vec3::new(0.0, 1.0, 4.0).normalize();
        assert!((n[0] - expected).length() < 1e-6, "{:?}", n[0]);
        assert_eq!(n[0], n[3]);
        assert!((n[1] - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn unused_and_degenerate_vertices_get_a_unit_normal() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::Y];
        let n = smooth_normals(&p, &[0, 1, 2]);
        assert!(n.iter().all(|n| (n.length() - 1.0).abs() < 1e-6));
    }
}
