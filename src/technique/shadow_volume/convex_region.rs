//! Where two convex solids overlap, as the corners of that overlap: a spot light's cone (a
//! pyramid around it) inside the receivers' box, for the light's scissor rectangle.
//!
//! Every corner of the overlap lies on the boundary of one of the two solids, so clipping each
//! face of either solid by the other's planes yields them all (Sutherland-Hodgman, one plane
//! at a time).

use glam::Vec3;

/// A convex solid: its faces as polygons, and its planes as (outward normal, offset): a point
/// `p` is inside where `normal.dot(p) <= offset` for every plane.
#[derive(Debug, Clone)]
pub struct ConvexSolid {
    faces: Vec<Vec<Vec3>>,
    planes: Vec<(Vec3, f32)>,
}

impl ConvexSolid {
    /// The box `lo..hi`.
    pub fn of_box(lo: Vec3, hi: Vec3) -> Self {
        // Corner i has x from bit 0, y from bit 1, z from bit 2.
        let c: [Vec3; 8] = std::array::from_fn(|i| {
            Vec3::new([lo.x, hi.x][i & 1], [lo.y, hi.y][(i >> 1) & 1], [lo.z, hi.z][(i >> 2) & 1])
        });
        let faces = [[0, 2, 6, 4], [1, 3, 7, 5], [0, 1, 5, 4], [2, 3, 7, 6], [0, 1, 3, 2], [4, 5, 7, 6]];
        let planes = (0..3)
            .flat_map(|axis| {
                let normal = Vec3::AXES[axis];
                [(-normal, -lo[axis]), (normal, hi[axis])]
            })
            .collect();
        ConvexSolid { faces: faces.iter().map(|f| f.iter().map(|&i| c[i]).collect()).collect(), planes }
    }

    /// The pyramid with apex `corners[0]` over the planar convex base `corners[1..]` (in order
    /// around it).
    pub fn pyramid(corners: &[Vec3; 5]) -> Self {
        let (apex, base) = (corners[0], &corners[1..]);
        let centroid = corners.iter().copied().sum::<Vec3>() / 5.0;
        let mut faces: Vec<Vec<Vec3>> = (0..4).map(|i| vec![apex, base[i], base[(i + 1) % 4]]).collect();
        faces.push(base.to_vec());
        // Each face's plane, its normal turned away from the centroid (inside every face).
        let planes = faces
            .iter()
            .map(|face| {
                let normal = (face[1] - face[0]).cross(face[2] - face[0]).normalize_or_zero();
                let normal = if normal.dot(centroid - face[0]) > 0.0 { -normal } else { normal };
                (normal, normal.dot(face[0]))
            })
            .collect();
        ConvexSolid { faces, planes }
    }

    /// The corners of the overlap of the two solids; empty where they do not overlap.
    pub fn overlap_corners(&self, other: &ConvexSolid) -> Vec<Vec3> {
        let clipped_faces = |faces: &[Vec<Vec3>], planes: &[(Vec3, f32)]| -> Vec<Vec3> {
            faces
                .iter()
                .flat_map(|face| planes.iter().fold(face.clone(), |polygon, &plane| clip(&polygon, plane)))
                .collect()
        };
        let mut corners = clipped_faces(&self.faces, &other.planes);
        corners.extend(clipped_faces(&other.faces, &self.planes));
        corners
    }
}

/// The part of convex `polygon` on the inner side of `plane` (Sutherland-Hodgman).
fn clip(polygon: &[Vec3], (normal, offset): (Vec3, f32)) -> Vec<Vec3> {
    let mut kept = Vec::with_capacity(polygon.len() + 1);
    for (i, &p) in polygon.iter().enumerate() {
        let q = polygon[(i + 1) % polygon.len()];
        let (dp, dq) = (normal.dot(p) - offset, normal.dot(q) - offset);
        if dp <= 0.0 {
            kept.push(p);
        }
        if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
            kept.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_cube() -> ConvexSolid {
        ConvexSolid::of_box(Vec3::ZERO, Vec3::ONE)
    }

    fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
        points.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }

    #[test]
    fn a_box_overlapping_a_box_has_the_corners_of_their_common_box() {
        let shifted = ConvexSolid::of_box(Vec3::splat(0.5), Vec3::splat(2.0));
        let (lo, hi) = bounds(&unit_cube().overlap_corners(&shifted));
        assert!(lo.abs_diff_eq(Vec3::splat(0.5), 1e-6) && hi.abs_diff_eq(Vec3::ONE, 1e-6), "{lo} {hi}");
    }

    #[test]
    fn a_pyramid_over_a_slab_meets_it_in_the_pyramids_section() {
        // Apex at height 4 over a slab 0..1 thick; the base, 4 wide, at height -4: at height 0
        // the section is 2 wide, at height 1 it is 1.5 wide.
        let apex = Vec3::new(0.0, 4.0, 0.0);
        let base = |x: f32, z: f32| Vec3::new(x, -4.0, z);
        let pyramid = ConvexSolid::pyramid(&[apex, base(4.0, 4.0), base(4.0, -4.0), base(-4.0, -4.0), base(-4.0, 4.0)]);
        let slab = ConvexSolid::of_box(Vec3::new(-10.0, 0.0, -10.0), Vec3::new(10.0, 1.0, 10.0));
        let (lo, hi) = bounds(&pyramid.overlap_corners(&slab));
        assert!(lo.abs_diff_eq(Vec3::new(-2.0, 0.0, -2.0), 1e-5), "{lo}");
        assert!(hi.abs_diff_eq(Vec3::new(2.0, 1.0, 2.0), 1e-5), "{hi}");
    }

    #[test]
    fn solids_apart_have_no_overlap() {
        let far = ConvexSolid::of_box(Vec3::splat(3.0), Vec3::splat(4.0));
        assert!(unit_cube().overlap_corners(&far).is_empty());
    }

    #[test]
    fn a_solid_inside_another_is_the_overlap() {
        let (inner_lo, inner_hi) = (Vec3::splat(0.25), Vec3::splat(0.5));
        let (lo, hi) = bounds(&unit_cube().overlap_corners(&ConvexSolid::of_box(inner_lo, inner_hi)));
        assert_eq!((lo, hi), (inner_lo, inner_hi));
    }
}
