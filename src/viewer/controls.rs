//! What a person steers live (the camera orbit, the light, the animation clock), and how it
//! poses a copy of the loaded scene each frame.

use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::scene::lights::{light_spec, parse_light_spec, unique_name};
use crate::scene::{Light, Scene, SceneLight, MAX_LIGHTS};

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

/// A light as a person has left it: as loaded (or added), turned, perhaps switched off.
#[derive(Debug, Clone)]
pub struct LiveLight {
    pub light: SceneLight,
    pub turn: LightTurn,
    /// Switched off: it adds nothing, and its passes stay, so nothing is rebuilt.
    pub off: bool,
}

impl LiveLight {
    fn of(light: &SceneLight) -> Self {
        LiveLight { light: light.clone(), turn: LightTurn::default(), off: false }
    }

    /// The light this frame.
    fn current(&self) -> SceneLight {
        let mut light = self.light.clone();
        // An unturned light keeps its loaded geometry to the bit (a renormalised direction
        // would move a shadow edge by a pixel against `render`).
        if self.turn != LightTurn::default() {
            light.set_geometry(turned(self.light.geometry(), self.turn));
            // A spot turns with its position: its axis turns about the vertical alike.
            light.direction = Mat4::from_rotation_y(self.turn.yaw).transform_vector3(self.light.direction);
        }
        if self.off {
            light.intensity = 0.0;
        }
        light
    }
}

/// The kinds of light a key adds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AddedLight {
    Point,
    Spot,
}

/// The live state a person changes, applied to a copy of the loaded scene each frame.
pub struct Live {
    pub orbit: Orbit,
    /// The scene's lights as a person has left them: turned, switched off, added, removed.
    /// Adding or removing one rebuilds the technique (its passes are planned per light).
    pub lights: Vec<LiveLight>,
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
        Live {
            orbit: Orbit::of(base),
            lights: base.lights.iter().map(LiveLight::of).collect(),
            selected_light: base.primary_light_index().unwrap_or(0),
            paused,
            time: 0.0,
            start_time,
        }
    }

    /// The selected light.
    pub fn selected(&mut self) -> Option<&mut LiveLight> {
        self.lights.get_mut(self.selected_light)
    }

    /// Selects the light `step` places after the selected one, wrapping.
    pub fn select_light(&mut self, step: isize) {
        let n = self.lights.len() as isize;
        if n > 0 {
            self.selected_light = (self.selected_light as isize + step).rem_euclid(n) as usize;
        }
    }

    /// Adds a light of `kind` near `target` (the camera's), white, as `--light` would with the
    /// spec it returns (printed so that `render --light` can draw the same frame), and selects
    /// it. A frame holds at most `MAX_LIGHTS`: then nothing is added and the error says so.
    pub fn add_light(&mut self, kind: AddedLight, target: Vec3) -> std::result::Result<String, String> {
        if self.lights.len() >= MAX_LIGHTS {
            return Err(format!("a frame holds at most {MAX_LIGHTS} lights; remove one first (Shift+X)"));
        }
        // Spread successive lights around the target, above it.
        let turn = Mat4::from_rotation_y(self.lights.len() as f32 * 2.4);
        let at = target + turn.transform_vector3(Vec3::new(1.5, 3.0, 1.5));
        let p = |v: Vec3| format!("{},{},{}", v.x, v.y, v.z);
        let spec = match kind {
            AddedLight::Point => format!("point:at={}", p(at)),
            AddedLight::Spot => format!("spot:at={}:aim={}:outer=35:inner=25", p(at), p(target)),
        };
        let mut light = parse_light_spec(&spec).map_err(|e| e.to_string())?;
        let taken: Vec<SceneLight> = self.lights.iter().map(|l| l.light.clone()).collect();
        light.name = unique_name(&taken, &light.name);
        let spec = light_spec(&light);
        self.lights.push(LiveLight::of(&light));
        self.selected_light = self.lights.len() - 1;
        Ok(spec)
    }

    /// Removes the selected light (its name, for a message); the previous one is selected.
    pub fn remove_selected_light(&mut self) -> Option<String> {
        if self.selected_light >= self.lights.len() {
            return None;
        }
        let removed = self.lights.remove(self.selected_light);
        self.selected_light = self.selected_light.saturating_sub(1).min(self.lights.len().saturating_sub(1));
        Some(removed.light.name)
    }

    /// "light 2/3 'lamp'" for the title (and "off" when it is switched off).
    pub fn describe_light(&self) -> String {
        match self.lights.get(self.selected_light) {
            Some(live) => format!(
                "light {}/{} '{}'{}",
                self.selected_light + 1,
                self.lights.len(),
                live.light.name,
                if live.off { " off" } else { "" }
            ),
            None => "no light".into(),
        }
    }

    /// Back to the loaded camera, lights and animation time (the pause stays as it is).
    pub fn reset(&mut self, base: &Scene) {
        self.orbit = Orbit::of(base);
        self.lights = base.lights.iter().map(LiveLight::of).collect();
        self.selected_light = base.primary_light_index().unwrap_or(0);
        self.time = 0.0;
    }

    /// Whether `scene`'s lights are the live ones in number and in what casts shadows: what a
    /// technique's passes are planned for.
    pub fn lights_shaped_as(&self, scene: &Scene) -> bool {
        scene.lights.len() == self.lights.len()
            && scene.lights.iter().zip(&self.lights).all(|(a, b)| a.casts_shadow == b.light.casts_shadow)
    }

    /// `base` with the live lights (unturned, on): the scene a technique is built from.
    pub fn lit(&self, base: &Scene) -> Scene {
        let mut scene = base.clone();
        scene.lights = self.lights.iter().map(|l| l.light.clone()).collect();
        scene
    }

    pub fn apply(&self, base: &Scene, scene: &mut Scene) -> Result<()> {
        scene.camera.eye = self.orbit.eye_for(&base.camera);
        scene.lights.clear();
        scene.lights.extend(self.lights.iter().map(LiveLight::current));
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
            let tilted = if side == Vec3::ZERO {
                yawed
            } else {
                Mat4::from_axis_angle(side, turn.tilt).transform_vector3(yawed)
            };
            // Keep the light above the horizon.
            Light::Directional { direction: Vec3::new(tilted.x, tilted.y.min(-0.05), tilted.z).normalize() }
        }
        Light::Point { position } => Light::Point {
            position: Mat4::from_rotation_y(turn.yaw).transform_point3(position) + Vec3::Y * turn.tilt * 2.0,
        },
    }
}
