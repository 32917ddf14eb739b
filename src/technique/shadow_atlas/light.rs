//! Fitting each light's view to the scene: the scene's bounds, the lights' view-projections and
//! bias uniforms (a spot's from its cone), and where a moving light is at a given frame.

use glam::{IVec4, Mat4, Quat, Vec3, Vec4};

use super::maps::{scene_box, Coverage, BAKED_CHANNELS};
use crate::scene::model::LightKind;
use crate::scene::{Light, Scene, SceneLight, MAX_LIGHTS};
use crate::technique::options::LightMode;

/// Radians the moving light turns per frame.
pub const MOVING_LIGHT_STEP: f32 = 0.02;

/// Mirrors `ShadowLight` in `shaders/shadow_atlas_light.glsl` (std140: 112 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadowLight {
    pub view_proj: Mat4,
    pub light: Vec4,
    pub bias: Vec4,
    /// x: the light's layer of the map array, -1 without a map.
    pub slot: IVec4,
}

/// Mirrors `ShadowLights` in `shaders/shadow_atlas_light.glsl`: per scene light its view and
/// map layer; which light is primary (the projective texture's); which light each baked
/// channel holds.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadowLightUniforms {
    pub lights: [ShadowLight; MAX_LIGHTS],
    /// x: the primary light's index.
    pub primary: IVec4,
    /// Per channel R, G, B of a baked texel: the light it holds, -1 for none.
    pub channels: IVec4,
}

impl ShadowLightUniforms {
    /// Every light's view of `scene` for a `map_size` shadow map, the primary light at
    /// `primary` (a moving light's turn), each in its `coverage` layer.
    pub fn fitted(scene: &Scene, primary: &Light, coverage: &[Coverage], map_size: u32) -> Self {
        let (centre, radius) = scene_bounds(scene);
        let texel = 1.0 / map_size as f32;
        let primary_index = scene.primary_light_index();
        let mut uniforms = ShadowLightUniforms {
            lights: [ShadowLight::default(); MAX_LIGHTS],
            primary: IVec4::new(primary_index.unwrap_or(0) as i32, 0, 0, 0),
            channels: IVec4::splat(-1),
        };
        for (i, (light, cover)) in scene.lights.iter().zip(coverage).enumerate().take(MAX_LIGHTS) {
            let mut light = light.clone();
            if Some(i) == primary_index {
                light.set_geometry(*primary);
            }
            let layer = cover.layer();
            if let Some(channel) = layer.filter(|&l| (l as usize) < BAKED_CHANNELS) {
                uniforms.channels[channel as usize] = i as i32;
            }
            uniforms.lights[i] = ShadowLight {
                view_proj: scene_light_view_projection(scene, &light, centre, radius),
                light: light.geometry().as_vec4(),
                // Depth units of one map texel (orthographic: depth spans 2.2 radii, a texel
                // 2 radii / map size): half a texel flat, 1.5 texels per unit of slope.
                bias: Vec4::new(0.5 * texel, 1.5 * texel, 8.0, 0.0),
                slot: IVec4::new(layer.map_or(-1, |l| l as i32), 0, 0, 0),
            };
        }
        uniforms
    }
}

/// A scene light's view: a spot light's from its cone, the others as `light_view_projection`.
fn scene_light_view_projection(scene: &Scene, light: &SceneLight, centre: Vec3, radius: f32) -> Mat4 {
    match (light.kind, scene_box(scene)) {
        (LightKind::Spot { outer_cone_angle, .. }, Some(bounds)) => {
            spot_view_projection(light.position, light.direction, outer_cone_angle, light.range, bounds)
        }
        _ => light_view_projection(&light.geometry(), centre, radius),
    }
}

/// A spot light's frustum: along its axis, wide enough for its outer cone (and a margin, so
/// the cone's edge is inside the map), from just short of the scene's box to where the box or
/// the light's range ends.
pub fn spot_view_projection(
    position: Vec3,
    direction: Vec3,
    outer_cone_angle: f32,
    range: Option<f32>,
    (lo, hi): (Vec3, Vec3),
) -> Mat4 {
    let axis = direction.normalize_or(Vec3::NEG_Y);
    let up = if axis.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let view = Mat4::look_at_rh(position, position + axis, up);
    let fov = (2.0 * outer_cone_angle * 1.1).clamp(1f32.to_radians(), 170f32.to_radians());
    let corners = (0..8).map(|k| Vec3::new([lo.x, hi.x][k & 1], [lo.y, hi.y][(k >> 1) & 1], [lo.z, hi.z][k >> 2]));
    let deepest = corners.map(|c| (c - position).dot(axis)).fold(0f32, f32::max);
    let far = deepest.min(range.unwrap_or(f32::INFINITY)).max(1e-2);
    // Nothing of the scene is nearer than its box: the near plane just short of it keeps the
    // 16-bit depth's precision for the casters.
    let to_box = position.clamp(lo, hi).distance(position);
    let near = (0.9 * to_box).max(0.01 * far);
    Mat4::perspective_rh(fov, 1.0, near, far) * view
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
