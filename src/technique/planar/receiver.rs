//! The ground every seed 001 shadow falls on: which objects receive (the others cast), the
//! plane's height, and the projection onto it on the CPU (the formulas of docs/design/planar-shadows.md,
//! as `shaders/planar_project.glsl` computes them).

use glam::{Mat4, Vec3, Vec4};

use crate::error::{Error, Result};
use crate::render::plan::Condition;
use crate::scene::{Light, Scene};
use crate::technique::options::GivenPlane;

/// A receiving plane `n.x + d = 0` with a unit normal `n` pointing to the side the casters
/// stand on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub normal: Vec3,
    pub d: f32,
}

/// How close to parallel (|n.L| for a unit light direction) or how close to the plane (for a
/// point light) a light may come before its projection is refused: beyond this the shadow
/// runs off towards infinity.
const PARALLEL: f32 = 1e-3;

impl Plane {
    /// The plane y = `h`.
    pub fn horizontal(h: f32) -> Self {
        Plane { normal: Vec3::Y, d: -h }
    }

    /// The plane a user gave: through (0, H, 0) with the given normal (checked non-zero).
    pub fn given(given: &GivenPlane) -> Result<Self> {
        given.check()?;
        let normal = Vec3::from_array(given.normal).normalize();
        Ok(Plane { normal, d: -normal.y * given.height })
    }

    /// `(n, d)`, as the shaders take it.
    pub fn as_vec4(&self) -> Vec4 {
        self.normal.extend(self.d)
    }

    /// Signed distance of `p` from the plane (positive on the casters' side).
    pub fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) + self.d
    }

    /// Blinn's shadow matrix `M = (P.L) I - L P^T` for the plane `P = (n, d)` and the light
    /// `L` in homogeneous form (towards a directional light `(-dir, 0)`, a point light
    /// `(C, 1)`): `M x` is `x` projected from the light onto the plane (docs/design/planar-shadows.md).
    pub fn shadow_matrix(&self, light: &Light) -> Mat4 {
        let (p, l) = (self.as_vec4(), light_vec4(light));
        Mat4::from_diagonal(Vec4::splat(p.dot(l))) - Mat4::from_cols(l * p.x, l * p.y, l * p.z, l * p.w)
    }

    /// Projects world point `p` onto the plane along `light` through the shadow matrix, with the
    /// shader's clamps (`shaders/planar_project.glsl`): points behind the plane are first moved
    /// onto it, and a point level with or beyond a point light is kept at a finite distance.
    pub fn project(&self, p: Vec3, light: &Light) -> Vec3 {
        let p = p - self.normal * self.distance(p).min(0.0);
        let q = self.shadow_matrix(light) * p.extend(1.0);
        let w = q.w.max(PARALLEL * self.as_vec4().dot(light_vec4(light)));
        let q = q.truncate() / w;
        // Exactly on the plane (the division leaves rounding off it).
        q - self.normal * self.distance(q)
    }

    /// Whether the light can cast onto the plane at all: a directional light must point
    /// towards it, a point light must be on the casters' side.
    pub fn reached_by(&self, light: &Light) -> bool {
        self.as_vec4().dot(light_vec4(light)) > self.threshold(light)
    }

    /// Refuses a light parallel to the plane (directional) or lying in it (point): no finite
    /// projection exists.
    pub fn check_light(&self, light: &Light) -> Result<()> {
        if self.as_vec4().dot(light_vec4(light)).abs() > self.threshold(light) {
            return Ok(());
        }
        let n = self.normal;
        Err(Error::InvalidInput(match *light {
            Light::Directional { direction } => format!(
                "the light direction ({:.3}, {:.3}, {:.3}) is parallel to the planar shadow plane (normal ({:.3}, {:.3}, {:.3})): shadows would be infinitely long",
                direction.x, direction.y, direction.z, n.x, n.y, n.z
            ),
            Light::Point { position: c } => format!(
                "the point light at ({:.3}, {:.3}, {:.3}) lies in the planar shadow plane (normal ({:.3}, {:.3}, {:.3})): nothing can be projected from it",
                c.x, c.y, c.z, n.x, n.y, n.z
            ),
        }))
    }

    fn threshold(&self, light: &Light) -> f32 {
        match light {
            Light::Directional { .. } => PARALLEL,
            Light::Point { .. } => 1e-4,
        }
    }
}

/// The light in homogeneous form, seen from the plane: the direction towards a directional
/// light with w = 0, a point light's position with w = 1.
fn light_vec4(light: &Light) -> Vec4 {
    match *light {
        Light::Directional { direction } => (-direction.normalize()).extend(0.0),
        Light::Point { position } => position.extend(1.0),
    }
}

/// Projects world point `p` onto the plane y = `h` along `light` (docs/design/planar-shadows.md): the
/// shadow matrix of [`Plane::horizontal`].
#[cfg(test)]
pub fn project_onto_plane(p: Vec3, light: &Light, h: f32) -> Vec3 {
    Plane::horizontal(h).project(p, light)
}

/// The frames in which the light reaches the receiver plane from above: the planar shadow is
/// drawn only then.
pub const LIGHT_ABOVE_PLANE: Condition = Condition::named("when the light is above the plane");
/// Per light: the frames in which light `n` casts shadows and reaches the receiver plane from
/// above (the additive planar loop's per-light shadow; `Condition::for_light`).
pub const LIGHT_REACHES_PLANE: Condition = Condition::named("when this light is above the plane");

/// Whether the light can cast onto `plane` at all.
pub fn light_reaches_plane(light: &Light, plane: &Plane) -> bool {
    plane.reached_by(light)
}

/// The receiving plane and which objects lie on it (they receive; all others cast).
/// `height` is where the plane crosses the y axis (the ground's height when it is horizontal).
#[derive(Debug, Clone, PartialEq)]
pub struct ReceiverPlane {
    pub height: f32,
    pub plane: Plane,
    pub receivers: Vec<bool>,
}

impl ReceiverPlane {
    /// Whether the plane is horizontal (what blobs, flat quads on the ground, need).
    pub fn is_horizontal(&self) -> bool {
        self.plane.normal.y > 1.0 - 1e-6
    }
}

/// Whether object `object` may receive: flat, non-casting and unskinned.
fn may_receive(scene: &Scene, object: usize) -> Option<Vec<Vec3>> {
    let o = &scene.objects[object];
    if o.casts_shadow || o.skin.is_some() {
        return None;
    }
    let data = &scene.meshes.get(o.mesh)?.data;
    if data.indices.len() < 3 {
        return None;
    }
    Some(data.positions.iter().map(|p| o.transform.transform_point3(*p)).collect())
}

/// Whether every point lies in `plane`, up to rounding relative to their extent.
fn lies_in(points: &[Vec3], plane: &Plane) -> bool {
    let extent = points.iter().fold(plane.d.abs(), |m, p| m.max(p.abs().max_element()));
    points.iter().all(|p| plane.distance(*p).abs() <= 1e-5 * (1.0 + extent))
}

/// The world-space height of a flat, horizontal, non-casting, unskinned object, if it is one.
fn flat_height(scene: &Scene, object: usize) -> Option<f32> {
    let points = may_receive(scene, object)?;
    let low = points.iter().map(|p| p.y).fold(f32::MAX, f32::min);
    lies_in(&points, &Plane::horizontal(low)).then_some(low)
}

/// The ground: `given`, or else the lowest flat, horizontal, non-casting object. Every flat
/// non-caster lying in the plane receives. A plane without one has nothing to receive on.
pub fn receiver_plane(scene: &Scene, given: Option<&GivenPlane>) -> Result<ReceiverPlane> {
    if let Some(given) = given {
        let plane = Plane::given(given)?;
        let receivers: Vec<bool> =
            (0..scene.objects.len()).map(|i| may_receive(scene, i).is_some_and(|p| lies_in(&p, &plane))).collect();
        if !receivers.contains(&true) {
            let [x, y, z] = given.normal;
            return Err(Error::InvalidInput(format!(
                "scene '{}': no flat non-casting object lies in the plane --plane-normal {x},{y},{z} --plane-height {} (planar shadows need a receiver in it)",
                scene.name, given.height
            )));
        }
        return Ok(ReceiverPlane { height: given.height, plane, receivers });
    }
    let heights: Vec<Option<f32>> = (0..scene.objects.len()).map(|i| flat_height(scene, i)).collect();
    let height = heights.iter().flatten().copied().fold(None, |m: Option<f32>, y| Some(m.map_or(y, |m| m.min(y))));
    let Some(height) = height else {
        return Err(Error::InvalidInput(format!(
            "scene '{}' has no flat horizontal receiver (a ground plane) for planar shadows; give a tilted one with --plane-normal and --plane-height",
            scene.name
        )));
    };
    let tolerance = 1e-4 * (1.0 + height.abs());
    let receivers = heights.iter().map(|h| h.is_some_and(|h| (h - height).abs() <= tolerance)).collect();
    Ok(ReceiverPlane { height, plane: Plane::horizontal(height), receivers })
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
        assert!((q - expected).length() < 1e-5 && (q.y - h).abs() < 1e-6, "{q} vs {expected}");
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
        assert!((q - Vec3::new(0.3, h, 0.1)).length() < 1e-6, "{q}");
        let ground = Plane::horizontal(0.0);
        assert!(!light_reaches_plane(&Light::Directional { direction: Vec3::Y }, &ground));
        assert!(!light_reaches_plane(&Light::Point { position: Vec3::new(0.0, -1.0, 0.0) }, &ground));
    }

    #[test]
    fn the_shadow_matrix_projects_along_the_light_onto_a_tilted_plane() {
        let plane = Plane::given(&GivenPlane { normal: [0.0, 3.0, 1.0], height: 0.4 }).expect("plane");
        let p = Vec3::new(0.7, 2.0, -0.3);
        for light in [
            Light::Directional { direction: Vec3::new(-0.4, -1.0, -0.2) },
            Light::Point { position: Vec3::new(-1.0, 5.0, 1.5) },
        ] {
            let q = plane.project(p, &light);
            assert!(plane.distance(q).abs() < 1e-5, "{q} is off the plane");
            // The projected point is on the line through the light and P.
            let along = match light {
                Light::Directional { direction } => direction.normalize(),
                Light::Point { position } => (p - position).normalize(),
            };
            assert!((q - p).normalize().dot(along) > 0.99999, "{q} is not along the light from {p}");
            // The matrix form agrees with the ray-plane intersection.
            let t = -plane.distance(p) / plane.normal.dot(along);
            assert!((q - (p + along * t)).length() < 1e-4, "{q} vs {}", p + along * t);
        }
        let parallel = Light::Directional { direction: Vec3::new(1.0, 0.0, 0.0) };
        let error = plane.check_light(&parallel).expect_err("a light along the plane");
        assert!(error.to_string().contains("parallel"), "{error}");
        assert!(Plane::given(&GivenPlane { normal: [0.0; 3], height: 0.0 }).is_err());
    }
}
