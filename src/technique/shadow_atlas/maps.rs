//! Which of the scene's lights a technique of the family shadows, and where: a layer of the
//! shadow-map array per shadowing light, and (the atlas) a channel of the baked texel. Decided
//! once, when the renderer is built, from where the lights stand then.

use glam::Vec3;

use crate::scene::model::LightKind;
use crate::scene::Scene;
use crate::technique::light_loop::PlannedLight;
use crate::technique::options::ShadowKind;

/// Lights a baked texel holds: R, G and B. Alpha stays the bake's coverage, which the dilation
/// reads; a fourth light would need a second attachment per model for coverage (another
/// image the size of every shadow texture, and a second write per texel) for a rare scene.
pub const BAKED_CHANNELS: usize = 3;

/// Why a point light inside the scene goes unshadowed.
pub const POINT_INSIDE: &str =
    "a point light inside the scene's bounds: no one frustum covers it, and there are no cube maps";
/// Why a fourth shadowing light goes unshadowed in the atlas.
pub const ATLAS_FULL: &str = "a baked texel holds the shadows of 3 lights";
/// Why the projective texture shadows the primary light alone.
pub const PROJECTIVE_ONE: &str = "the projective texture is laid out in the primary light's view";

/// How a technique of the family treats one scene light.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coverage {
    /// The light casts no shadows.
    NoShadows,
    /// Shadowed through layer `layer` of the map array; the atlas bakes it in channel
    /// `layer` too (its layers stop at `BAKED_CHANNELS`).
    Mapped { layer: u32 },
    /// Casts shadows this technique cannot draw, and why.
    Unshadowed(&'static str),
}

impl Coverage {
    pub fn layer(self) -> Option<u32> {
        match self {
            Coverage::Mapped { layer } => Some(layer),
            _ => None,
        }
    }
}

/// The box around every object as posed (`None` without objects).
pub fn scene_box(scene: &Scene) -> Option<(Vec3, Vec3)> {
    (0..scene.objects.len()).filter_map(|i| scene.posed_bounds(i)).reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

/// What `kind` does with each of `scene`'s lights, in the scene's order.
pub fn coverage(kind: ShadowKind, scene: &Scene) -> Vec<Coverage> {
    let inside = |p: Vec3| scene_box(scene).is_some_and(|(lo, hi)| p.cmpge(lo).all() && p.cmple(hi).all());
    let primary = scene.primary_light_index();
    let mut layers = 0u32;
    scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, light)| {
            let why = match kind {
                _ if !light.casts_shadow => return Coverage::NoShadows,
                // One texture in one light's view: the primary light, wherever it stands.
                ShadowKind::Projective if Some(i) == primary => None,
                ShadowKind::Projective => Some(PROJECTIVE_ONE),
                _ if light.kind == LightKind::Point && inside(light.position) => Some(POINT_INSIDE),
                ShadowKind::Atlas if layers as usize >= BAKED_CHANNELS => Some(ATLAS_FULL),
                _ => None,
            };
            match why {
                Some(why) => Coverage::Unshadowed(why),
                None => {
                    layers += 1;
                    Coverage::Mapped { layer: layers - 1 }
                }
            }
        })
        .collect()
}

/// The scene's lights as the plan sees them: a light "shadows" when it has a map layer.
pub fn planned_lights(coverage: &[Coverage], scene: &Scene) -> Vec<PlannedLight> {
    scene
        .lights
        .iter()
        .zip(coverage)
        .map(|(light, c)| PlannedLight { name: light.name.clone(), shadows: c.layer().is_some() })
        .collect()
}

/// Map layers `coverage` needs (the array has at least one, bound even when no light uses it).
pub fn layer_count(coverage: &[Coverage]) -> u32 {
    coverage.iter().filter_map(|c| c.layer()).count() as u32
}

/// Bit i set: light i is shadowed.
pub fn shadowed_mask(lights: &[PlannedLight]) -> u8 {
    lights.iter().enumerate().filter(|(i, l)| l.shadows && *i < 8).fold(0, |mask, (i, _)| mask | 1 << i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin_scene;
    use crate::scene::lights::parse_light_spec;

    #[test]
    fn the_lights_scene_maps_all_three_and_a_point_light_inside_goes_without() {
        let mut scene = builtin_scene("lights").expect("scene");
        let mapped = |c: &[Coverage]| c.iter().map(|c| c.layer()).collect::<Vec<_>>();
        assert_eq!(mapped(&coverage(ShadowKind::Map, &scene)), [Some(0), Some(1), Some(2)]);
        scene.lights.push(parse_light_spec("point:name=inside:at=0,0.5,0").expect("spec"));
        scene.lights.push(parse_light_spec("directional:name=moon:dir=0,-1,0.2").expect("spec"));
        let map = coverage(ShadowKind::Map, &scene);
        assert_eq!(map[3], Coverage::Unshadowed(POINT_INSIDE));
        assert_eq!(map[4], Coverage::Mapped { layer: 3 });
        let atlas = coverage(ShadowKind::Atlas, &scene);
        assert_eq!(atlas[4], Coverage::Unshadowed(ATLAS_FULL));
        let projective = coverage(ShadowKind::Projective, &scene);
        assert_eq!(mapped(&projective), [Some(0), None, None, None, None]);
        assert_eq!(shadowed_mask(&planned_lights(&map, &scene)), 0b10111);
    }
}
