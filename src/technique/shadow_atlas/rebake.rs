//! Which models' shadow textures a frame re-bakes. Everything when a light moved (every texel
//! sees it anew) or the maps' fit changed; when only some models moved, the moved models and
//! the models they could shadow, before or after the move, and no others: a texel whose light
//! ray (and its shadow-map filter footprint) meets neither the moved model's old nor its new
//! bounding sphere reads the same map depths as before, so its baked value cannot change.

use glam::{Mat4, Vec3};

use crate::scene::{Light, Scene};

/// A sphere that holds a mesh, in its object space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub centre: Vec3,
    pub radius: f32,
}

impl Sphere {
    /// The sphere around `positions`' box (empty: a point at the origin).
    pub fn around(positions: &[Vec3]) -> Sphere {
        let (lo, hi) = positions
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        if positions.is_empty() {
            return Sphere { centre: Vec3::ZERO, radius: 0.0 };
        }
        let centre = (lo + hi) * 0.5;
        let radius = positions.iter().map(|p| p.distance(centre)).fold(0.0, f32::max);
        Sphere { centre, radius }
    }

    /// This sphere placed by `transform` (its largest axis scale).
    pub fn placed(&self, transform: &Mat4) -> Sphere {
        let scale = [transform.x_axis, transform.y_axis, transform.z_axis]
            .iter()
            .map(|axis| axis.truncate().length())
            .fold(0.0, f32::max);
        Sphere { centre: transform.transform_point3(self.centre), radius: self.radius * scale }
    }
}

/// The models to re-bake when only the models `moved` changed place, from `before` to the
/// scene's transforms now: the moved ones, and every model a moved one can shadow from any of
/// `lights` (those with a map) at either place. `bounds`: each mesh's sphere; `map_size`: the
/// maps' side, whose texels widen every test (the compare's filter reaches a texel aside).
pub fn stale_after_moves(
    scene: &Scene,
    before: &[Mat4],
    moved: &[usize],
    bounds: &[Sphere],
    lights: &[Light],
    map_size: u32,
) -> Vec<usize> {
    let sphere = |index: usize, transform: &Mat4| {
        let mesh = scene.objects[index].mesh;
        bounds.get(mesh).copied().unwrap_or(Sphere { centre: Vec3::ZERO, radius: f32::INFINITY }).placed(transform)
    };
    let casters: Vec<Sphere> = moved
        .iter()
        .flat_map(|&m| {
            let old = before.get(m).copied().unwrap_or(scene.objects[m].transform);
            [sphere(m, &old), sphere(m, &scene.objects[m].transform)]
        })
        .collect();
    let scene_radius = {
        let all: Vec<Sphere> = (0..scene.objects.len()).map(|i| sphere(i, &scene.objects[i].transform)).collect();
        let centre = all.iter().map(|s| s.centre).sum::<Vec3>() / all.len().max(1) as f32;
        all.iter().map(|s| s.centre.distance(centre) + s.radius).fold(0.0, f32::max)
    };
    (0..scene.objects.len())
        .filter(|&r| {
            if moved.contains(&r) {
                return true;
            }
            let receiver = sphere(r, &scene.objects[r].transform);
            casters
                .iter()
                .any(|caster| lights.iter().any(|light| can_shadow(light, caster, &receiver, scene_radius, map_size)))
        })
        .collect()
}

/// Whether `caster` can put any point of `receiver` in `light`'s shadow: the caster meets the
/// light's rays to the receiver, widened by two map texels either side (the compare's filter and
/// the rasteriser's coverage of the map).
fn can_shadow(light: &Light, caster: &Sphere, receiver: &Sphere, scene_radius: f32, map_size: u32) -> bool {
    let texels = 4.0 / map_size.max(1) as f32;
    match *light {
        Light::Directional { direction } => {
            // Rays travel along `direction`: from the receiver back toward the light.
            let toward = -direction.normalize_or_zero();
            let v = caster.centre - receiver.centre;
            let along = v.dot(toward);
            let reach = caster.radius + receiver.radius + 2.0 * scene_radius * texels;
            along >= -reach && (v - toward * along).length() <= reach
        }
        Light::Point { position: at } => {
            let to_receiver = receiver.centre - at;
            let distance = to_receiver.length();
            if distance <= receiver.radius {
                return true; // the light is inside the receiver's sphere: every direction
            }
            // The cone from the light tangent to the receiver's sphere, widened by the map's
            // texels (a field of view up to about 150 degrees: 8 map texels per unit).
            let axis = to_receiver / distance;
            let v = caster.centre - at;
            let along = v.dot(axis);
            if along < -caster.radius {
                return false; // behind the light
            }
            let half_angle = (receiver.radius / distance).asin() + 2.0 * texels;
            let off_axis = (v - axis * along).length();
            // Distance from the caster's centre to the cone's surface, along the normal.
            let angle_to_centre = off_axis.atan2(along.max(0.0));
            let gap = v.length() * (angle_to_centre - half_angle).max(0.0).sin();
            gap <= caster.radius && along <= distance + receiver.radius + caster.radius
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_caster_shadows_what_lies_downlight_of_it_only() {
        let light = Light::Directional { direction: Vec3::NEG_Y };
        let caster = Sphere { centre: Vec3::new(0.0, 2.0, 0.0), radius: 0.5 };
        let below = Sphere { centre: Vec3::ZERO, radius: 0.5 };
        let above = Sphere { centre: Vec3::new(0.0, 4.0, 0.0), radius: 0.5 };
        let beside = Sphere { centre: Vec3::new(3.0, 0.0, 0.0), radius: 0.5 };
        assert!(can_shadow(&light, &caster, &below, 5.0, 512));
        assert!(!can_shadow(&light, &caster, &above, 5.0, 512));
        assert!(!can_shadow(&light, &caster, &beside, 5.0, 512));
    }

    #[test]
    fn a_point_lights_shadow_spreads_with_distance() {
        let light = Light::Point { position: Vec3::new(0.0, 4.0, 0.0) };
        let caster = Sphere { centre: Vec3::new(0.0, 3.0, 0.0), radius: 0.5 };
        // The caster's shadow cone reaches x = 2 at y = 0 (half-angle ~30 degrees at 1 unit).
        let spread = Sphere { centre: Vec3::new(1.9, 0.0, 0.0), radius: 0.2 };
        let far_out = Sphere { centre: Vec3::new(5.0, 0.0, 0.0), radius: 0.2 };
        let behind_light = Sphere { centre: Vec3::new(0.0, 8.0, 0.0), radius: 0.5 };
        assert!(can_shadow(&light, &caster, &spread, 5.0, 512));
        assert!(!can_shadow(&light, &caster, &far_out, 5.0, 512));
        assert!(!can_shadow(&light, &caster, &behind_light, 5.0, 512));
    }
}
