//! Ray casting against triangle meshes on the CPU: whether a point lies in a mesh's shadow
//! (the shadow-volume technique's camera-inside test, and tests' ground truth).

use glam::{Mat4, Vec3};

use super::Light;

/// Triangles `indices` over `positions` (object space), placed in the world by `model`.
#[derive(Clone, Copy)]
pub struct PlacedMesh<'a> {
    pub positions: &'a [Vec3],
    pub indices: &'a [u32],
    pub model: Mat4,
}

/// Whether a world-space point lies in the shadow of some mesh (inside its shadow volume):
/// the ray from the point towards `light` (world space) hits one of its triangles before it
/// reaches the light.
pub fn in_shadow(light: Light, meshes: &[PlacedMesh], point: Vec3) -> bool {
    let (towards_light, max_t) = match light {
        Light::Directional(direction) => (-direction.normalize(), f32::INFINITY),
        Light::Point(position) => ((position - point).normalize(), (position - point).length()),
    };
    meshes.iter().any(|mesh| {
        let p = |i: u32| mesh.model.transform_point3(mesh.positions[i as usize]);
        mesh.indices
            .chunks_exact(3)
            .any(|t| ray_hits_triangle(point, towards_light, [p(t[0]), p(t[1]), p(t[2])]).is_some_and(|d| d < max_t))
    })
}

/// Möller–Trumbore; the distance along `dir` to the hit.
pub fn ray_hits_triangle(origin: Vec3, dir: Vec3, t: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - t[0];
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    let d = e2.dot(q) * inv;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && d > 0.0).then_some(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn a_point_under_a_box_is_in_its_shadow_and_one_beside_it_is_not() {
        let cube = shapes::cube(1.0);
        let placed = [PlacedMesh {
            positions: &cube.positions,
            indices: &cube.indices,
            model: Mat4::from_translation(Vec3::Y * 2.0),
        }];
        let down = Light::Directional(Vec3::NEG_Y);
        assert!(in_shadow(down, &placed, Vec3::ZERO));
        assert!(!in_shadow(down, &placed, Vec3::new(3.0, 0.0, 0.0)));
        // A point light between the box and the point casts no shadow of the box on it.
        assert!(!in_shadow(Light::Point(Vec3::Y * 1.0), &placed, Vec3::ZERO));
        assert!(in_shadow(Light::Point(Vec3::Y * 5.0), &placed, Vec3::ZERO));
    }
}
