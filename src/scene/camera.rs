//! Cameras and lights.

use glam::{Mat4, Vec3, Vec4};

/// Depth of a point at infinity: just below 1 so that geometry pushed to infinity (shadow
/// volume far caps) never passes a GREATER_OR_EQUAL test against the cleared depth of 1.0,
/// which is what keeps the background out of z-fail counts.
pub const INFINITY_DEPTH: f32 = 1.0 - 1.0 / (1 << 20) as f32;
const _: () = assert!(INFINITY_DEPTH < 1.0);

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_radians: f32,
    pub near: f32,
}

impl Camera {
    pub fn look_at(eye: Vec3, target: Vec3) -> Self {
        Camera { eye, target, up: Vec3::Y, fov_y_radians: 50f32.to_radians(), near: 0.1 }
    }

    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.eye, self.target, self.up)
    }

    /// Infinite-far perspective for Vulkan (depth 0..1, y down): no far plane clips anything,
    /// so shadow volumes extruded to infinity need no depthClamp (not in the mobile profile).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let f = 1.0 / (0.5 * self.fov_y_radians).tan();
        // depth = INFINITY_DEPTH - near / distance: 0 just past the near plane, INFINITY_DEPTH at w = 0.
        Mat4::from_cols(
            Vec4::new(f / aspect, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -f, 0.0, 0.0),
            Vec4::new(0.0, 0.0, -INFINITY_DEPTH, -1.0),
            Vec4::new(0.0, 0.0, -self.near, 0.0),
        )
    }

    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// `direction`: the way the light travels (from the light into the scene).
    Directional {
        direction: Vec3,
    },
    Point {
        position: Vec3,
    },
}

impl Light {
    /// xyz + w as the shaders read it: (direction, 0) or (position, 1).
    pub fn as_vec4(&self) -> Vec4 {
        match *self {
            Light::Directional { direction } => direction.normalize().extend(0.0),
            Light::Point { position } => position.extend(1.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_maps_near_to_zero_and_infinity_below_one() {
        let camera = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z);
        let p = camera.projection(1.0);
        let depth = |v: Vec4| {
            let c = p * v;
            c.z / c.w
        };
        assert!(depth(Vec4::new(0.0, 0.0, -camera.near, 1.0)).abs() < 1e-5);
        assert!(depth(Vec4::new(0.0, 0.0, -10.0, 1.0)) < INFINITY_DEPTH);
        assert_eq!(depth(Vec4::new(0.0, 0.0, -1.0, 0.0)), INFINITY_DEPTH);
        // y is flipped for Vulkan: up in the world is up on screen (negative NDC y).
        let up = p * Vec4::new(0.0, 1.0, -5.0, 1.0);
        assert!(up.y / up.w < 0.0);
    }
}
