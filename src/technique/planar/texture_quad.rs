//! The quad the seed lays its render texture on: a rectangle on the receiving plane around the
//! casters' shadow. The shadow of a caster lies inside the projection of its bounding box (the
//! projection keeps convex hulls), so the rectangle bounding the eight projected box corners
//! holds every shadowed point; outside the texture the lookup reads "lit".

use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::receiver::{caster_bounds, ReceiverPlane};
use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::{GpuMesh, SceneVertex};
use crate::scene::Scene;

/// Margin around the projected bounds, as a fraction of the rectangle's sides: the texture's
/// linear filter reaches half a texel beyond the last covered one.
const MARGIN: f32 = 0.02;

/// The quad's corners on the plane, in order around it; `None` without casters.
pub fn shadow_quad(scene: &Scene, plane: &ReceiverPlane) -> Option<[Vec3; 4]> {
    let (low, high) = caster_bounds(scene, plane)?;
    let n = plane.plane.normal;
    let origin = -n * plane.plane.d;
    let (u, v) = n.any_orthonormal_pair();
    let corners = (0..8).map(|i| {
        let c = Vec3::new(
            if i & 1 == 0 { low.x } else { high.x },
            if i & 2 == 0 { low.y } else { high.y },
            if i & 4 == 0 { low.z } else { high.z },
        );
        let p = plane.plane.project(c, &scene.light()) - origin;
        (p.dot(u), p.dot(v))
    });
    let (mut lo, mut hi) = ((f32::MAX, f32::MAX), (f32::MIN, f32::MIN));
    for (a, b) in corners {
        lo = (lo.0.min(a), lo.1.min(b));
        hi = (hi.0.max(a), hi.1.max(b));
    }
    let margin = ((hi.0 - lo.0).max(hi.1 - lo.1) * MARGIN).max(1e-3);
    let (lo, hi) = ((lo.0 - margin, lo.1 - margin), (hi.0 + margin, hi.1 + margin));
    let at = |a: f32, b: f32| origin + u * a + v * b;
    Some([at(lo.0, lo.1), at(hi.0, lo.1), at(hi.0, hi.1), at(lo.0, hi.1)])
}

/// The model matrix that lays the unit square of [`unit_square`] on `corners` (its third
/// column is the plane's normal: the square's z = 0 stays on the plane).
pub fn quad_model(corners: &[Vec3; 4], normal: Vec3) -> Mat4 {
    let [c0, c1, _, c3] = *corners;
    Mat4::from_cols((c1 - c0).extend(0.0), (c3 - c0).extend(0.0), normal.extend(0.0), c0.extend(1.0))
}

/// The unit square (0..1 in x and y, z = 0), two triangles facing +z.
pub fn unit_square(gpu: &Arc<Gpu>) -> Result<GpuMesh> {
    let vertex = |x: f32, y: f32| SceneVertex {
        position: [x, y, 0.0],
        normal: [0.0, 0.0, 1.0],
        uv0: [x, y],
        uv1: [x, y],
        colour: [1.0; 4],
    };
    let vertices = [vertex(0.0, 0.0), vertex(1.0, 0.0), vertex(1.0, 1.0), vertex(0.0, 1.0)];
    GpuMesh::from_raw(gpu, "shadow texture quad", &vertices, &[0, 1, 2, 0, 2, 3])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin_scene_at;
    use crate::technique::planar::receiver::receiver_plane;

    #[test]
    fn the_quad_lies_on_the_plane_around_every_projected_caster_vertex() {
        let scene = builtin_scene_at("character", 0.3).expect("scene");
        let plane = receiver_plane(&scene, None).expect("plane");
        let corners = shadow_quad(&scene, &plane).expect("casters");
        let model = quad_model(&corners, plane.plane.normal);
        for (i, corner) in corners.iter().enumerate() {
            assert!(plane.plane.distance(*corner).abs() < 1e-5, "corner {i} off the plane");
            let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][i];
            assert!((model.transform_point3(Vec3::new(square.0, square.1, 0.0)) - *corner).length() < 1e-4);
        }
        let inverse = model.inverse();
        for (_, object) in scene.objects.iter().enumerate().filter(|(i, _)| !plane.receivers[*i]) {
            for p in &scene.meshes[object.mesh].data.positions {
                let shadow = plane.plane.project(object.transform.transform_point3(*p), &scene.light());
                let q = inverse.transform_point3(shadow);
                assert!((0.0..=1.0).contains(&q.x) && (0.0..=1.0).contains(&q.y), "{shadow} outside the quad ({q})");
            }
        }
    }
}
