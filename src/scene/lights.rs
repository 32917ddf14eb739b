//! The scene's lights: what each one is (KHR_lights_punctual's model: kind, colour, intensity,
//! range, spot cones), where it is this frame, and whether it casts shadows. The shading of
//! every pass sums them (`shaders/lights.glsl`); shadowing techniques run their per-light
//! loop over those that cast.

use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::camera::Light;
use super::model::LightKind;
use super::rig::Rig;
use crate::error::{Error, Result};

/// Lights a frame holds (the frame uniforms' array; `shaders/frame_uniforms.glsl`).
pub const MAX_LIGHTS: usize = 8;

/// The built-in scenes' one white light: 1 - the ambient term, so that ambient plus a fully lit
/// face is exactly white, as the seed's Lambert + ambient made it.
pub const DEFAULT_INTENSITY: f32 = 0.75;

/// A light of the scene.
#[derive(Debug, Clone)]
pub struct SceneLight {
    /// Unique in its scene: passes and reports name the light by it ("sun: volumes").
    pub name: String,
    pub kind: LightKind,
    /// Point and spot lights.
    pub position: Vec3,
    /// Directional and spot lights: the way the light travels (unit).
    pub direction: Vec3,
    /// Linear RGB.
    pub colour: Vec3,
    /// Multiplies `colour` (glTF: candela for point and spot, lux for directional).
    pub intensity: f32,
    /// Point and spot: where the light ends (glTF `range`); `None`: it never ends.
    pub range: Option<f32>,
    pub casts_shadow: bool,
    /// The glTF node the light hangs on, followed when the scene is re-posed.
    pub(crate) node: Option<LightNode>,
}

/// A file light's node.
#[derive(Debug, Clone)]
pub struct LightNode {
    pub rig: Arc<Rig>,
    pub node: usize,
}

/// Radians added to a spot's outer cone angle before anything is left out for lying outside
/// it: far more than the rounding of the shader's cone factor, so nothing it lights is lost.
pub const CONE_MARGIN: f32 = 0.01;

/// A spot light's cone: the points whose direction from `apex` is within `half_angle` of
/// `axis` (unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    pub apex: Vec3,
    pub axis: Vec3,
    pub half_angle: f32,
}

impl Cone {
    /// Whether the cone meets the box `low..high`, conservatively: it does where it meets the
    /// box's bounding sphere (the angle to the sphere's centre, less the angle the sphere
    /// subtends, is within the cone's).
    pub fn meets_box(&self, low: Vec3, high: Vec3) -> bool {
        let (centre, radius) = ((low + high) * 0.5, (high - low).length() * 0.5);
        let to_centre = centre - self.apex;
        let distance = to_centre.length();
        if distance <= radius {
            return true;
        }
        let off_axis = (to_centre.dot(self.axis) / distance).clamp(-1.0, 1.0).acos();
        off_axis - (radius / distance).asin() <= self.half_angle
    }

    /// The corners of a pyramid that holds the cone's part within `height` of its apex along
    /// the axis: the apex, and a square around the cone's circle at that height.
    pub fn pyramid(&self, height: f32) -> [Vec3; 5] {
        let side = self.axis.any_orthonormal_vector();
        let up = self.axis.cross(side);
        let centre = self.apex + self.axis * height;
        let half = height * self.half_angle.tan();
        let corner = |a: f32, b: f32| centre + (side * a + up * b) * half;
        [self.apex, corner(1.0, 1.0), corner(1.0, -1.0), corner(-1.0, -1.0), corner(-1.0, 1.0)]
    }
}

/// Where a light can reach: what casters and receivers it can touch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reach {
    Everywhere,
    Sphere { centre: Vec3, radius: f32 },
}

impl SceneLight {
    /// A white light with the built-in intensity, named after its kind.
    pub fn from_geometry(light: Light) -> Self {
        let (name, kind, position, direction) = match light {
            // Kept as given (callers pass a unit vector): a renormalised direction would move
            // shadow edges by a pixel against frames made before lights were a list.
            Light::Directional { direction } => ("sun", LightKind::Directional, Vec3::ZERO, direction),
            Light::Point { position } => ("lamp", LightKind::Point, position, Vec3::NEG_Y),
        };
        SceneLight {
            name: name.into(),
            kind,
            position,
            direction,
            colour: Vec3::ONE,
            intensity: DEFAULT_INTENSITY,
            range: None,
            casts_shadow: true,
            node: None,
        }
    }

    /// The light's geometry as the shadow techniques project along it: a spot light casts
    /// from its position as a point light does.
    pub fn geometry(&self) -> Light {
        match self.kind {
            LightKind::Directional => Light::Directional { direction: self.direction },
            LightKind::Point | LightKind::Spot { .. } => Light::Point { position: self.position },
        }
    }

    /// Moves the light to `light`'s geometry (a directional light takes its direction, unit as
    /// given; a point or spot light its position); a change of kind changes the light's kind.
    pub fn set_geometry(&mut self, light: Light) {
        match light {
            Light::Directional { direction } => {
                self.kind = LightKind::Directional;
                self.direction = direction;
            }
            Light::Point { position } => {
                if self.kind == LightKind::Directional {
                    self.kind = LightKind::Point;
                }
                self.position = position;
            }
        }
    }

    /// Where the light can reach: a point or spot light with a range, the range's sphere (a
    /// spot's cone lies inside it).
    pub(crate) fn reach(&self) -> Reach {
        match (self.kind, self.range) {
            (LightKind::Directional, _) | (_, None) => Reach::Everywhere,
            (_, Some(radius)) => Reach::Sphere { centre: self.position, radius },
        }
    }

    /// Whether the light can reach anything of the box `low..high`: its range's sphere, and a
    /// spot's cone.
    pub fn reaches_box(&self, low: Vec3, high: Vec3) -> bool {
        let in_range = match self.reach() {
            Reach::Everywhere => true,
            Reach::Sphere { centre, radius } => centre.clamp(low, high).distance_squared(centre) <= radius * radius,
        };
        in_range && self.cone().map_or(true, |cone| cone.meets_box(low, high))
    }

    /// A spot light's cone, widened by `CONE_MARGIN` (0.01 rad): everything the spot lights lies in it
    /// (`shaders/lights.glsl` clamps its cone factor to 0 at `dot(direction, towards the
    /// point)` of cos(outer) and below). `None` for other lights, and for a spot whose cone
    /// is a half-space or more.
    pub fn cone(&self) -> Option<Cone> {
        let LightKind::Spot { outer_cone_angle, .. } = self.kind else { return None };
        // The shader takes `direction` as given: with |direction| != 1 the edge is where the
        // unit axis meets the way to the point at cos(outer) / |direction|.
        let length = self.direction.length();
        let cos_edge = outer_cone_angle.cos() / length;
        let half_angle = cos_edge.clamp(-1.0, 1.0).acos() + CONE_MARGIN;
        (length > 0.0 && half_angle < std::f32::consts::FRAC_PI_2).then(|| Cone {
            apex: self.position,
            axis: self.direction / length,
            half_angle,
        })
    }

    /// KHR_lights_punctual's spot attenuation as `clamp(cos * scale + offset, 0, 1)`: (scale,
    /// offset) from the cone angles; (0, 1) for lights without a cone.
    pub fn cone_scale_offset(&self) -> (f32, f32) {
        match self.kind {
            LightKind::Spot { inner_cone_angle, outer_cone_angle } => {
                let cos_outer = outer_cone_angle.cos();
                let scale = 1.0 / (inner_cone_angle.cos() - cos_outer).max(1e-4);
                (scale, -cos_outer * scale)
            }
            _ => (0.0, 1.0),
        }
    }

    /// Follows the light's node to `world` (its node's world matrix): position is its origin,
    /// direction its -Z.
    pub fn place(&mut self, world: Mat4) {
        self.position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z);
        if direction.length_squared() > 0.0 {
            self.direction = direction.normalize();
        }
    }

    /// The radiance the shaders multiply: colour x intensity.
    pub fn radiance(&self) -> Vec3 {
        self.colour * self.intensity
    }

    /// A short description for reports: "sun (directional, shadows)".
    pub fn describe(&self) -> String {
        let kind = match self.kind {
            LightKind::Directional => "directional",
            LightKind::Point => "point",
            LightKind::Spot { .. } => "spot",
        };
        let shadows = if self.casts_shadow { "shadows" } else { "no shadows" };
        format!("{} ({kind}, {shadows})", self.name)
    }
}

/// A command-line light's default intensity for point and spot lights: 10 lights a surface 4 m
/// away at 10 / 16, near the built-in sun's 0.75.
pub const DEFAULT_POSITIONAL_INTENSITY: f32 = 10.0;

/// The light a `--light` spec describes: `KIND[:key=value]...`, KIND one of `directional`,
/// `point`, `spot`; keys `name`, `at=x,y,z` (position), `dir=x,y,z` (the way it shines),
/// `aim=x,y,z` (a point it shines at), `colour=r,g,b` (linear), `intensity`, `range`,
/// `inner`/`outer` (spot cone angles in degrees) and `shadows=on|off`.
pub fn parse_light_spec(spec: &str) -> Result<SceneLight> {
    let bad = |problem: String| Error::InvalidInput(format!("--light '{spec}': {problem}"));
    let mut parts = spec.split(':');
    let kind_name = parts.next().unwrap_or_default().trim();
    let (mut light, mut inner, mut outer) = match kind_name {
        "directional" | "sun" => (SceneLight::from_geometry(Light::Directional { direction: Vec3::NEG_Y }), 0.0, 0.0),
        "point" | "spot" => {
            let mut light = SceneLight::from_geometry(Light::Point { position: Vec3::new(0.0, 4.0, 0.0) });
            light.intensity = DEFAULT_POSITIONAL_INTENSITY;
            if kind_name == "spot" {
                light.name = "spot".into();
            }
            (light, 20f32, 30f32)
        }
        "moving" | "fixed" => {
            return Err(bad(format!("the light's motion is now --light-motion {kind_name}; --light adds a light")))
        }
        other => return Err(bad(format!("unknown light kind '{other}' (directional, point or spot)"))),
    };
    let mut aim = None;
    for part in parts {
        let (key, value) = part.split_once('=').ok_or_else(|| bad(format!("'{part}' is not key=value")))?;
        let number = |value: &str| -> Result<f32> {
            value
                .trim()
                .parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(format!("{key}: '{value}' is not a number")))
        };
        let vector = |value: &str| -> Result<Vec3> {
            let numbers = value.split(',').map(number).collect::<Result<Vec<f32>>>()?;
            match numbers[..] {
                [x, y, z] => Ok(Vec3::new(x, y, z)),
                _ => Err(bad(format!("{key}: '{value}' is not x,y,z"))),
            }
        };
        match key.trim() {
            "name" if !value.trim().is_empty() => light.name = value.trim().to_owned(),
            "at" => light.position = vector(value)?,
            "dir" => {
                let direction = vector(value)?;
                if direction.length_squared() == 0.0 {
                    return Err(bad("dir: the direction is zero".into()));
                }
                light.direction = direction.normalize();
            }
            "aim" => aim = Some(vector(value)?),
            "colour" | "color" => {
                let colour = vector(value)?;
                if colour.min_element() < 0.0 {
                    return Err(bad(format!("colour: '{value}' is negative")));
                }
                light.colour = colour;
            }
            "intensity" => {
                light.intensity = number(value)?;
                if light.intensity < 0.0 {
                    return Err(bad(format!("intensity: '{value}' is negative")));
                }
            }
            "range" => {
                let range = number(value)?;
                if range <= 0.0 {
                    return Err(bad(format!("range: '{value}' is not positive")));
                }
                light.range = Some(range);
            }
            "inner" => inner = number(value)?,
            "outer" => outer = number(value)?,
            "shadows" => {
                light.casts_shadow = match value.trim() {
                    "on" | "yes" | "true" => true,
                    "off" | "no" | "false" => false,
                    other => return Err(bad(format!("shadows: '{other}' is not on or off"))),
                }
            }
            other => {
                return Err(bad(format!(
                    "unknown key '{other}' (name, at, dir, aim, colour, intensity, range, inner, outer, shadows)"
                )))
            }
        }
    }
    if let Some(target) = aim {
        let direction =
            target - if kind_name == "directional" || kind_name == "sun" { Vec3::ZERO } else { light.position };
        if direction.length_squared() == 0.0 {
            return Err(bad("aim: the light sits on the point it aims at".into()));
        }
        light.direction = direction.normalize();
    }
    if kind_name == "spot" {
        if !(0.0..=90.0).contains(&outer) || !(0.0..outer).contains(&inner) {
            return Err(bad(format!(
                "spot cone: need 0 <= inner < outer <= 90 degrees (inner {inner}, outer {outer})"
            )));
        }
        light.kind = LightKind::Spot { inner_cone_angle: inner.to_radians(), outer_cone_angle: outer.to_radians() };
    }
    Ok(light)
}

/// The `--light` spec of `light` (what `parse_light_spec` reads back).
pub fn light_spec(light: &SceneLight) -> String {
    let v = |v: Vec3| format!("{},{},{}", v.x, v.y, v.z);
    let mut spec = match light.kind {
        LightKind::Directional => format!("directional:dir={}", v(light.direction)),
        LightKind::Point => format!("point:at={}", v(light.position)),
        LightKind::Spot { inner_cone_angle, outer_cone_angle } => format!(
            "spot:at={}:dir={}:inner={}:outer={}",
            v(light.position),
            v(light.direction),
            inner_cone_angle.to_degrees(),
            outer_cone_angle.to_degrees()
        ),
    };
    spec.push_str(&format!(":name={}:colour={}:intensity={}", light.name, v(light.colour), light.intensity));
    if let Some(range) = light.range {
        spec.push_str(&format!(":range={range}"));
    }
    if !light.casts_shadow {
        spec.push_str(":shadows=off");
    }
    spec
}

/// Puts the command line's lights in `scene`: added to its lights, or in place of them with
/// `replace`; names made unique.
pub fn apply_light_specs(lights: &mut Vec<SceneLight>, specs: &[SceneLight], replace: bool) -> Result<()> {
    if replace {
        if specs.is_empty() {
            return Err(Error::InvalidInput("--replace-lights needs at least one --light".into()));
        }
        lights.clear();
    }
    for spec in specs {
        let mut light = spec.clone();
        light.name = unique_name(lights, &light.name);
        lights.push(light);
    }
    check_count(lights)
}

/// `base`, or `base 2`, `base 3`... : the first name no light in `lights` has.
pub fn unique_name(lights: &[SceneLight], base: &str) -> String {
    let taken = |name: &str| lights.iter().any(|l| l.name == name);
    if !taken(base) {
        return base.to_owned();
    }
    (2..).map(|i| format!("{base} {i}")).find(|n| !taken(n)).unwrap_or_else(|| base.to_owned())
}

/// Refuses more lights than a frame holds.
pub fn check_count(lights: &[SceneLight]) -> Result<()> {
    if lights.len() > MAX_LIGHTS {
        let names: Vec<&str> = lights[MAX_LIGHTS..].iter().map(|l| l.name.as_str()).collect();
        return Err(Error::InvalidInput(format!(
            "the scene has {} lights; a frame holds at most {MAX_LIGHTS} (beyond them: {})",
            lights.len(),
            names.join(", ")
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn spot(inner: f32, outer: f32) -> SceneLight {
        SceneLight {
            kind: LightKind::Spot { inner_cone_angle: inner, outer_cone_angle: outer },
            range: Some(5.0),
            ..SceneLight::from_geometry(Light::Point { position: Vec3::new(0.0, 4.0, 0.0) })
        }
    }

    #[test]
    fn the_spot_cone_is_one_inside_and_zero_outside_as_khr_writes_it() {
        let light = spot(0.0, std::f32::consts::FRAC_PI_4);
        let (scale, offset) = light.cone_scale_offset();
        let attenuation = |angle: f32| (angle.cos() * scale + offset).clamp(0.0, 1.0);
        assert_eq!(attenuation(0.0), 1.0);
        assert!(attenuation(std::f32::consts::FRAC_PI_4 + 0.01) == 0.0);
        assert!((attenuation(std::f32::consts::FRAC_PI_4 * 0.5) - 0.7).abs() < 0.1);
        let point = SceneLight::from_geometry(Light::Point { position: Vec3::ZERO });
        assert_eq!(point.cone_scale_offset(), (0.0, 1.0));
    }

    #[test]
    fn a_spots_cone_holds_every_box_it_lights_and_leaves_out_the_rest() {
        // Pointing down from (0, 4, 0), 0.5 rad: on the floor (4 below) it lights a disc of
        // radius 4 tan 0.5 = 2.19.
        let light = SceneLight { range: None, ..spot(0.1, 0.5) };
        let cone = light.cone().expect("a spot has a cone");
        assert_eq!(cone.half_angle, 0.5 + CONE_MARGIN);
        let floor_tile = |x: f32| (Vec3::new(x - 0.1, -0.1, -0.1), Vec3::new(x + 0.1, 0.0, 0.1));
        for (x, lit) in [(0.0, true), (2.0, true), (2.25, true), (2.6, false), (-3.0, false)] {
            let (lo, hi) = floor_tile(x);
            assert_eq!(light.reaches_box(lo, hi), lit, "a tile at x = {x}");
        }
        // Above the light, behind the cone; around the apex.
        assert!(!light.reaches_box(Vec3::new(-0.5, 6.0, -0.5), Vec3::new(0.5, 7.0, 0.5)));
        assert!(light.reaches_box(Vec3::new(-0.1, 3.9, -0.1), Vec3::new(0.1, 4.1, 0.1)));
        // Every corner of the pyramid's base lies outside the cone's circle at that height.
        let [apex, base @ ..] = cone.pyramid(4.0);
        assert_eq!(apex, light.position);
        for corner in base {
            assert!(
                (corner.y - 0.0).abs() < 1e-5 && Vec2::new(corner.x, corner.z).length() >= 4.0 * cone.half_angle.tan()
            );
        }
        // No cone for a point light, nor for a spot as wide as a half-space.
        assert!(SceneLight::from_geometry(Light::Point { position: Vec3::ZERO }).cone().is_none());
        assert!(spot(0.1, std::f32::consts::FRAC_PI_2).cone().is_none());
    }

    #[test]
    fn reach_is_the_range_sphere() {
        let light = spot(0.1, 0.5);
        assert!(light.reaches_box(Vec3::new(-1.0, -0.5, -1.0), Vec3::new(1.0, 0.0, 1.0)));
        assert!(!light.reaches_box(Vec3::new(10.0, 0.0, 0.0), Vec3::new(11.0, 1.0, 1.0)));
        let sun = SceneLight::from_geometry(Light::Directional { direction: Vec3::NEG_Y });
        assert_eq!(sun.reach(), Reach::Everywhere);
        assert!(sun.reaches_box(Vec3::splat(100.0), Vec3::splat(101.0)));
    }

    #[test]
    fn a_spec_reads_every_key_and_writes_itself_back() {
        let light = parse_light_spec(
            "spot:name=key:at=1,5,2:aim=1,0,2:colour=1,0.5,0.25:intensity=30:range=9:inner=10:outer=25:shadows=off",
        )
        .expect("spec");
        assert_eq!(light.name, "key");
        assert_eq!(light.position, Vec3::new(1.0, 5.0, 2.0));
        assert!(light.direction.distance(Vec3::NEG_Y) < 1e-6);
        assert_eq!((light.colour, light.intensity, light.range), (Vec3::new(1.0, 0.5, 0.25), 30.0, Some(9.0)));
        assert!(!light.casts_shadow);
        let LightKind::Spot { inner_cone_angle, outer_cone_angle } = light.kind else { panic!("a spot") };
        assert!((inner_cone_angle - 10f32.to_radians()).abs() < 1e-6);
        assert!((outer_cone_angle - 25f32.to_radians()).abs() < 1e-6);
        let again = parse_light_spec(&light_spec(&light)).expect("its own spec");
        assert_eq!(
            (again.name, again.kind, again.range, again.casts_shadow),
            (light.name, light.kind, light.range, false)
        );
        assert!(again.position.distance(light.position) < 1e-6 && again.direction.distance(light.direction) < 1e-6);
    }

    #[test]
    fn bad_specs_are_named() {
        for (spec, says) in [
            ("lamp", "unknown light kind 'lamp'"),
            ("moving", "--light-motion moving"),
            ("point:at=1,2", "'1,2' is not x,y,z"),
            ("point:range=-1", "range: '-1' is not positive"),
            ("point:colour=1,x,1", "'x' is not a number"),
            ("point:size=3", "unknown key 'size'"),
            ("point:at", "'at' is not key=value"),
            ("spot:inner=40:outer=30", "need 0 <= inner < outer"),
            ("directional:dir=0,0,0", "the direction is zero"),
            ("point:shadows=maybe", "not on or off"),
        ] {
            let error = parse_light_spec(spec).expect_err(spec).to_string();
            assert!(error.contains(says) && error.contains(spec), "{spec}: {error}");
        }
    }

    #[test]
    fn specs_add_to_or_replace_the_scenes_lights() {
        let sun = SceneLight::from_geometry(Light::Directional { direction: Vec3::NEG_Y });
        let lamp = parse_light_spec("point").expect("spec");
        let mut lights = vec![sun.clone()];
        apply_light_specs(&mut lights, &[lamp.clone(), lamp.clone()], false).expect("added");
        let names: Vec<&str> = lights.iter().map(|l| l.name.as_str()).collect();
        assert_eq!(names, ["sun", "lamp", "lamp 2"]);
        apply_light_specs(&mut lights, std::slice::from_ref(&lamp), true).expect("replaced");
        assert_eq!(lights.len(), 1);
        assert!(apply_light_specs(&mut lights, &[], true).is_err());
        assert!(apply_light_specs(&mut lights, &vec![lamp; MAX_LIGHTS], false).is_err());
    }

    #[test]
    fn names_are_made_unique() {
        let lights = vec![SceneLight::from_geometry(Light::Directional { direction: Vec3::NEG_Y })];
        assert_eq!(unique_name(&lights, "lamp"), "lamp");
        assert_eq!(unique_name(&lights, "sun"), "sun 2");
    }

    #[test]
    fn a_placed_light_takes_its_nodes_origin_and_minus_z() {
        let mut light = spot(0.1, 0.5);
        light.place(Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)) * Mat4::from_rotation_x(-1.0));
        assert!(light.position.distance(Vec3::new(1.0, 2.0, 3.0)) < 1e-6);
        assert!(light.direction.y < -0.8, "{}", light.direction);
    }
}
