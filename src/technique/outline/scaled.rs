//! The document's outline copy (seed 003): the object scaled up about its centre. The scale is
//! chosen so that the object's bounding sphere grows by the outline width in pixels at the
//! distance of its centre, which keeps `--outline-width` meaningful for both methods. On a
//! sphere this is a ring of that width; on a concave object the copy also moves the concave
//! parts outwards, where the normal extrusion would have met them (docs/outline.md, "Outline methods").

use glam::{Mat4, Vec3};

/// An object's centre (its bounding box's) and the largest distance of a vertex from it, in
/// the mesh's own coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub centre: Vec3,
    pub radius: f32,
}

impl Bounds {
    /// The bounds of `positions` (a single point at the origin for none).
    pub fn of(positions: &[Vec3]) -> Bounds {
        let (min, max) = positions
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let centre = if positions.is_empty() { Vec3::ZERO } else { 0.5 * (min + max) };
        let radius = positions.iter().map(|p| p.distance(centre)).fold(0.0, f32::max);
        Bounds { centre, radius }
    }

    /// The scale about `centre` that grows the bounding sphere, placed by `model` and seen from
    /// `eye`, by `width_px` pixels of `pixel_at_unit_distance` (world size of a pixel one unit
    /// from the eye). 1 for a degenerate object (no size, or a model that flattens it).
    pub fn scale_for_width(&self, model: &Mat4, eye: Vec3, pixel_at_unit_distance: f32, width_px: f32) -> f32 {
        let axes = [model.x_axis, model.y_axis, model.z_axis].map(|a| a.truncate().length());
        let world_radius = self.radius * axes.into_iter().fold(0.0, f32::max);
        let distance = model.transform_point3(self.centre).distance(eye);
        let grow = width_px * pixel_at_unit_distance * distance;
        if world_radius > 0.0 && grow.is_finite() {
            1.0 + grow / world_radius
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_of_a_box_and_the_scale_that_grows_it_by_the_width() {
        let corners = [Vec3::new(1.0, 2.0, 3.0), Vec3::new(3.0, 4.0, 7.0)];
        let bounds = Bounds::of(&corners);
        assert_eq!(bounds.centre, Vec3::new(2.0, 3.0, 5.0));
        assert!((bounds.radius - 6.0f32.sqrt()).abs() < 1e-6);
        // Placed at 10 units from the eye, doubled in size: a pixel there is 0.01 * 10 = 0.1,
        // so 4 pixels grow the world radius 2 * sqrt(6) by 0.4.
        let model = Mat4::from_scale(Vec3::splat(2.0)) * Mat4::from_translation(-bounds.centre);
        let scale = bounds.scale_for_width(&model, Vec3::new(0.0, 0.0, 10.0), 0.01, 4.0);
        assert!((scale - (1.0 + 0.4 / (2.0 * 6.0f32.sqrt()))).abs() < 1e-6, "{scale}");
        assert_eq!(Bounds::of(&[]).scale_for_width(&Mat4::IDENTITY, Vec3::Z, 0.01, 4.0), 1.0);
    }
}
