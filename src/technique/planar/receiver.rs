//! The ground every seed 001 shadow falls on: which objects receive (the others cast), the
//! plane's height, and the projection onto it on the CPU (the formulas of DESIGN.md section 3,
//! as `shaders/planar_project.glsl` computes them).

use glam::Vec3;

use crate::error::{Error, Result};
use crate::scene::{Light, Scene};

/// Projects world point `p` onto the plane y = `h` along `light` (DESIGN.md section 3), with the
/// shader's clamps: points below the plane stay on it, and a point level with or above a point
/// light is kept at a finite distance.
pub fn project_onto_plane(p: Vec3, light: &Light, h: f32) -> Vec3 {
    let q = match *light {
        Light::Directional { direction } => {
            let l = direction.normalize();
            p + l * ((p.y - h).max(0.0) / (-l.y).max(1e-3))
        }
        Light::Point { position: c } => {
            let py = p.y.max(h);
            let t = (c.y - h) / (c.y - py).max(1e-3 * (c.y - h));
            c + (Vec3::new(p.x, py, p.z) - c) * t
        }
    };
    Vec3::new(q.x, h, q.z)
}

/// Whether the light can cast onto the plane at all: a directional light must point down, a
/// point light must be above the plane.
pub fn light_reaches_plane(light: &Light, h: f32) -> bool {
    match *light {
        Light::Directional { direction } => direction.normalize().y < -1e-3,
        Light::Point { position } => position.y > h + 1e-4,
    }
}

/// The receiving plane y = `height` and which objects lie on it (they receive; all others cast).
#[derive(Debug, Clone, PartialEq)]
pub struct ReceiverPlane {
    pub height: f32,
    pub receivers: Vec<bool>,
}

/// The world-space height of a flat, horizontal, non-casting, unskinned object, if it is one.
fn flat_height(scene: &Scene, object: usize) -> Option<f32> {
    let o = &scene.objects[object];
    if o.casts_shadow || o.skin.is_some() {
        return None;
    }
    let data = &scene.meshes.get(o.mesh)?.data;
    if data.indices.len() < 3 {
        return None;
    }
    let ys: Vec<f32> = data.positions.iter().map(|p| o.transform.transform_point3(*p).y).collect();
    let (low, high) = ys.iter().fold((f32::MAX, f32::MIN), |(l, h), &y| (l.min(y), h.max(y)));
    let extent = data
        .positions
        .iter()
        .map(|p| o.transform.transform_point3(*p))
        .fold(0.0f32, |m, p| m.max(p.x.abs()).max(p.z.abs()));
    (high - low <= 1e-5 * (1.0 + extent + low.abs())).then_some(low)
}

/// The ground: the lowest flat, horizontal, non-casting object; every flat object at that height
/// receives. A scene without one has nothing to project onto.
pub fn receiver_plane(scene: &Scene) -> Result<ReceiverPlane> {
    let heights: Vec<Option<f32>> = (0..scene.objects.len()).map(|i| flat_height(scene, i)).collect();
    let height = heights.iter().flatten().copied().fold(None, |m: Option<f32>, y| Some(m.map_or(y, |m| m.min(y))));
    let Some(height) = height else {
        return Err(Error::InvalidInput(format!(
            "scene '{}' has no flat horizontal receiver (a ground plane) for planar shadows",
            scene.name
        )));
    };
    let tolerance = 1e-4 * (1.0 + height.abs());
    let receivers = heights.iter().map(|h| h.is_some_and(|h| (h - height).abs() <= tolerance)).collect();
    Ok(ReceiverPlane { height, receivers })
}

/// World-space bounds of the casters (CPU-skinned positions), `None` without casters.
pub fn caster_bounds(scene: &Scene, plane: &ReceiverPlane) -> Option<(Vec3, Vec3)> {
    (0..scene.objects.len())
        .filter(|i| !plane.receivers[*i])
        .filter_map(|i| scene.posed_bounds(i))
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_follows_the_formulas() {
        let h = 0.5;
        let l = Vec3::new(-0.45, -1.0, -0.35).normalize();
        let p = Vec3::new(1.0, 2.5, -0.5);
        let expected = p + l * (p.y - h) / -l.y;
        let q = project_onto_plane(p, &Light::Directional { direction: l }, h);
        assert!((q - expected).length() < 1e-5 && q.y == h, "{q} vs {expected}");
        // The projected point is on the ray from P along L.
        assert!((q - p).normalize().dot(l) > 0.99999);

        let c = Vec3::new(-1.0, 6.0, 2.0);
        let q = project_onto_plane(p, &Light::Point { position: c }, h);
        let expected = c + (p - c) * (c.y - h) / (c.y - p.y);
        assert!((q - expected).length() < 1e-5, "{q} vs {expected}");
        assert!((q - c).normalize().dot((p - c).normalize()) > 0.99999, "P' lies on the ray from C through P");

        // Points on or below the plane stay where they are (in x, z).
        let below = Vec3::new(0.3, 0.2, 0.1);
        let q = project_onto_plane(below, &Light::Directional { direction: l }, h);
        assert_eq!((q.x, q.y, q.z), (0.3, h, 0.1));
        assert!(!light_reaches_plane(&Light::Directional { direction: Vec3::Y }, 0.0));
        assert!(!light_reaches_plane(&Light::Point { position: Vec3::new(0.0, -1.0, 0.0) }, 0.0));
    }
}
