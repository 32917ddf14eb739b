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
    /// Dragged or zoomed since loaded: until then the scene's own eye is kept to the bit (the
    /// spherical round trip would move an edge pixel against `render`).
    moved: bool,
}

impl Orbit {
    pub fn of(scene: &Scene) -> Self {
        let offset = scene.camera.eye - scene.camera.target;
        let distance = offset.length().max(1e-3);
        Orbit {
            azimuth: offset.x.atan2(offset.z),
            elevation: (offset.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
            moved: false,
        }
    }

    /// The eye for the loaded camera `base`.
    fn eye_for(&self, base: &crate::scene::Camera) -> Vec3 {
        if self.moved {
            self.eye(base.target)
        } else {
            base.eye
        }
    }

    fn eye(&self, target: Vec3) -> Vec3 {
        let (sa, ca) = self.azimuth.sin_cos();
        let (se, ce) = self.elevation.sin_cos();
        target + Vec3::new(sa * ce, se, ca * ce) * self.distance
    }

    /// A mouse drag by (dx, dy) pixels turns the camera around the target; it stops short of
    /// the poles, where the azimuth would flip.
    pub fn drag(&mut self, dx: f64, dy: f64) {
        self.moved = true;
        self.azimuth -= (dx * 0.01) as f32;
        self.elevation = (self.elevation + (dy * 0.01) as f32).clamp(-1.45, 1.45);
    }

    /// A wheel turn by `lines` moves the camera closer (or back), never nearer than `closest`.
    pub fn zoom(&mut self, lines: f32, closest: f32) {
        self.moved = true;
        self.distance = (self.distance * 0.9f32.powf(lines)).max(closest);
    }
}

/// How a person has moved one light: rotation about the vertical axis, and tilt (radians).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LightTurn {
    pub yaw: f32,
    pub tilt: f32,
}

/// The live state a person changes, applied to a copy of the loaded scene each frame.
pub struct Live {
    pub orbit: Orbit,
    /// Per light of the scene: how it has been turned.
    pub light_turns: Vec<LightTurn>,
    /// Per light: switched off (it adds nothing; its passes stay, so nothing is rebuilt).
    pub lights_off: Vec<bool>,
    /// The light the arrows move.
    pub selected_light: usize,
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
        let lights = base.lights.len();
        Live {
            orbit: Orbit::of(base),
            light_turns: vec![LightTurn::default(); lights],
            lights_off: vec![false; lights],
            selected_light: base.primary_light_index().unwrap_or(0),
            paused,
            time: 0.0,
            start_time,
        }
    }

    /// The selected light's turn.
    pub fn selected_turn(&mut self) -> Option<&mut LightTurn> {
        self.light_turns.get_mut(self.selected_light)
    }

    /// Selects the light `step` places after the selected one, wrapping.
    pub fn select_light(&mut self, step: isize) {
        let n = self.light_turns.len() as isize;
        if n > 0 {
            self.selected_light = (self.selected_light as isize + step).rem_euclid(n) as usize;
        }
    }

    /// "light 2/3 'lamp'" for the title (and "off" when it is switched off).
    pub fn describe_light(&self, scene: &Scene) -> String {
        match scene.lights.get(self.selected_light) {
            Some(light) => format!(
                "light {}/{} '{}'{}",
                self.selected_light + 1,
                scene.lights.len(),
                light.name,
                if self.lights_off.get(self.selected_light).copied().unwrap_or(false) { " off" } else { "" }
            ),
            None => "no light".into(),
        }
    }

    /// Back to the loaded camera, light and animation time (the pause stays as it is).
    pub fn reset(&mut self, base: &Scene) {
        self.orbit = Orbit::of(base);
        self.light_turns.iter_mut().for_each(|turn| *turn = LightTurn::default());
        self.lights_off.iter_mut().for_each(|off| *off = false);
        self.time = 0.0;
    }

    pub fn apply(&self, base: &Scene, scene: &mut Scene) -> Result<()> {
        scene.camera.eye = self.orbit.eye_for(&base.camera);
        for (index, (light, original)) in scene.lights.iter_mut().zip(&base.lights).enumerate() {
            let turn = self.light_turns.get(index).copied().unwrap_or_default();
            // An unturned light keeps its loaded geometry to the bit (a renormalised direction
            // would move a shadow edge by a pixel against `render`).
            if turn != LightTurn::default() {
                light.set_geometry(turned(original.geometry(), turn));
                // A spot turns with its position: its axis turns about the vertical alike.
                light.direction = Mat4::from_rotation_y(turn.yaw).transform_vector3(original.direction);
            }
            let off = self.lights_off.get(index).copied().unwrap_or(false);
            light.intensity = if off { 0.0 } else { original.intensity };
        }
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

/// `light` turned by `turn`: a direction yawed and tilted (kept above the horizon), a position
/// orbited about the vertical axis and raised or lowered.
fn turned(light: Light, turn: LightTurn) -> Light {
    match light {
        Light::Directional { direction } => {
            let yawed = Mat4::from_rotation_y(turn.yaw).transform_vector3(direction);
            let side = yawed.cross(Vec3::Y).normalize_or_zero();
            let tilted =
                if side == Vec3::ZERO { yawed } else { Mat4::from_axis_angle(side, turn.tilt).transform_vector3(yawed) };
            // Keep the light above the horizon.
            Light::Directional { direction: Vec3::new(tilted.x, tilted.y.min(-0.05), tilted.z).normalize() }
        }
        Light::Point { position } => Light::Point {
            position: Mat4::from_rotation_y(turn.yaw).transform_point3(position) + Vec3::Y * turn.tilt * 2.0,
        },
    }
}
