//! What a person steers live (the camera orbit, the light, the animation clock), and how it
//! poses a copy of the loaded scene each frame.

use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::scene::{Light, Scene};

/// Camera orbit around the scene camera's target, in spherical coordinates.
#[derive(Debug, Clone, Copy)]
pub struct Orbit {
    azimuth: f32,
    elevation: f32,
    distance: f32,
}

impl Orbit {
    pub fn of(scene: &Scene) -> Self {
        let offset = scene.camera.eye - scene.camera.target;
        let distance = offset.length().max(1e-3);
        Orbit { azimuth: offset.x.atan2(offset.z), elevation: (offset.y / distance).clamp(-1.0, 1.0).asin(), distance }
    }

    fn eye(&self, target: Vec3) -> Vec3 {
        let (sa, ca) = self.azimuth.sin_cos();
        let (se, ce) = self.elevation.sin_cos();
        target + Vec3::new(sa * ce, se, ca * ce) * self.distance
    }

    /// A mouse drag by (dx, dy) pixels turns the camera around the target; it stops short of
    /// the poles, where the azimuth would flip.
    pub fn drag(&mut self, dx: f64, dy: f64) {
        self.azimuth -= (dx * 0.01) as f32;
        self.elevation = (self.elevation + (dy * 0.01) as f32).clamp(-1.45, 1.45);
    }

    /// A wheel turn by `lines` moves the camera closer (or back), never nearer than `closest`.
    pub fn zoom(&mut self, lines: f32, closest: f32) {
        self.distance = (self.distance * 0.9f32.powf(lines)).max(closest);
    }
}

/// The live state a person changes, applied to a copy of the loaded scene each frame.
pub struct Live {
    pub orbit: Orbit,
    /// Light rotation about the vertical axis, and tilt (radians).
    pub light_yaw: f32,
    pub light_tilt: f32,
    pub paused: bool,
    /// Seconds of animation since the viewer started: animated models (glTF animations, the
    /// built-in character's walk) move, and shadow casters turn about their vertical axis.
    pub time: f32,
    /// The animation time the scene was built at.
    start_time: f32,
}

impl Live {
    /// The scene as loaded, seen from its own camera, at `start_time`.
    pub fn new(base: &Scene, paused: bool, start_time: f32) -> Self {
        Live { orbit: Orbit::of(base), light_yaw: 0.0, light_tilt: 0.0, paused, time: 0.0, start_time }
    }

    /// Back to the loaded camera, light and animation time (the pause stays as it is).
    pub fn reset(&mut self, base: &Scene) {
        self.orbit = Orbit::of(base);
        self.light_yaw = 0.0;
        self.light_tilt = 0.0;
        self.time = 0.0;
    }

    pub fn apply(&self, base: &Scene, scene: &mut Scene) -> Result<()> {
        scene.camera.eye = self.orbit.eye(base.camera.target);
        scene.set_light(match base.light() {
            Light::Directional { direction } => {
                let yawed = Mat4::from_rotation_y(self.light_yaw).transform_vector3(direction);
                let side = yawed.cross(Vec3::Y).normalize_or_zero();
                let tilted = if side == Vec3::ZERO {
                    yawed
                } else {
                    Mat4::from_axis_angle(side, self.light_tilt).transform_vector3(yawed)
                };
                // Keep the light above the horizon.
                Light::Directional { direction: Vec3::new(tilted.x, tilted.y.min(-0.05), tilted.z).normalize() }
            }
            Light::Point { position } => Light::Point {
                position: Mat4::from_rotation_y(self.light_yaw).transform_point3(position)
                    + Vec3::Y * self.light_tilt * 2.0,
            },
        });
        // Animated objects take their pose at this time (transforms and joint palettes; GPU
        // skinning shows the new palettes, CPU-skinned meshes keep the starting pose). Every
        // frame: the turn below is applied to the posed transforms.
        if scene.is_animated() {
            scene.pose_at(self.start_time + self.time)?;
        }
        let posed: Vec<Mat4> = scene
            .objects
            .iter()
            .zip(&base.objects)
            .map(|(object, original)| if object.rig.is_some() { object.transform } else { original.transform })
            .collect();
        let angle = self.time * 0.6;
        for ((object, original), placed) in scene.objects.iter_mut().zip(&base.objects).zip(posed) {
            object.transform = if original.casts_shadow && angle != 0.0 {
                let centre = placed.w_axis.truncate();
                Mat4::from_translation(centre) * Mat4::from_rotation_y(angle) * Mat4::from_translation(-centre) * placed
            } else {
                placed
            };
        }
        Ok(())
    }
}
