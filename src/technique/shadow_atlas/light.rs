//! Fitting the light's view to the scene: the scene's bounds, the light's view-projection and
//! bias uniforms, and where a moving light is at a given frame.

use glam::{Mat4, Quat, Vec3, Vec4};

use crate::scene::{Light, Scene};
use crate::technique::options::LightMode;

/// Radians the moving light turns per frame.
pub const MOVING_LIGHT_STEP: f32 = 0.02;

/// Mirrors `ShadowLight` in `shaders/shadow_atlas_light.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadowLightUniforms {
    pub view_proj: Mat4,
    pub light: Vec4,
    pub bias: Vec4,
}

impl ShadowLightUniforms {
    /// `light`'s view of `scene` for a `map_size` shadow map.
    pub fn fitted(scene: &Scene, light: &Light, map_size: u32) -> Self {
        let (centre, radius) = scene_bounds(scene);
        let texel = 1.0 / map_size as f32;
        ShadowLightUniforms {
            view_proj: light_view_projection(light, centre, radius),
            light: light.as_vec4(),
            // Depth units of one map texel (orthographic: depth spans 2.2 radii, a texel
            // 2 radii / map size): half a texel flat, 1.5 texels per unit of slope.
            bias: Vec4::new(0.5 * texel, 1.5 * texel, 8.0, 0.0),
        }
    }
}

/// Centre and radius of a sphere around every object.
pub fn scene_bounds(scene: &Scene) -> (Vec3, f32) {
    let all =
        (0..scene.objects.len()).filter_map(|i| scene.posed_bounds(i)).reduce(|(a, b), (c, d)| (a.min(c), b.max(d)));
    let Some((lo, hi)) = all else { return (Vec3::ZERO, 1.0) };
    ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3))
}

/// The light's view-projection: orthographic around the scene's bounding sphere for a
/// directional light, a perspective frustum (a spot) aimed at the scene for a positional one.
/// Depth 0..1; NDC xy * 0.5 + 0.5 is the shadow-map UV.
pub fn light_view_projection(light: &Light, centre: Vec3, radius: f32) -> Mat4 {
    let up_for = |d: Vec3| if d.normalize().y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    match *light {
        Light::Directional { direction } => {
            let d = direction.normalize();
            let eye = centre - d * 2.0 * radius;
            let view = Mat4::look_at_rh(eye, centre, up_for(d));
            Mat4::orthographic_rh(-radius, radius, -radius, radius, radius * 0.9, radius * 3.1) * view
        }
        Light::Point { position } => {
            let to_centre = centre - position;
            let distance = to_centre.length().max(1e-3);
            let view = Mat4::look_at_rh(position, centre, up_for(to_centre));
            let (fov, near) = if distance > radius * 1.05 {
                (2.0 * (radius / distance).asin() * 1.05, distance - radius)
            } else {
                (120f32.to_radians(), 0.05 * radius)
            };
            Mat4::perspective_rh(fov, 1.0, near, distance + radius) * view
        }
    }
}

/// The scene's light at frame `index` under `mode`.
pub fn light_at(scene: &Scene, mode: LightMode, index: u32) -> Light {
    let turn = match mode {
        LightMode::Fixed => return scene.light(),
        LightMode::Moving => Quat::from_rotation_y(MOVING_LIGHT_STEP * index as f32),
    };
    match scene.light() {
        Light::Directional { direction } => Light::Directional { direction: turn * direction },
        Light::Point { position } => Light::Point { position: turn * position },
    }
}
