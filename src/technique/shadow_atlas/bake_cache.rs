//! The cache of the passes before the frame (shadow maps, bake, mips): what they were last
//! rendered for, and from the key of this frame, which objects' shadow textures are stale
//! (`rebake` decides which models a move can have shadowed).

use glam::{Mat4, Vec4};

use super::maps::Coverage;
use super::rebake::{stale_after_moves, Sphere};
use crate::scene::{Light, Scene};

/// What the cached passes were last rendered for.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CacheKey {
    /// Every light's geometry and direction (the primary light as it turns).
    pub(super) lights: Vec<[Vec4; 2]>,
    pub(super) transforms: Vec<Mat4>,
    /// Skinned objects' palettes: a new pose is a moved model.
    pub(super) palettes: Vec<Vec<Mat4>>,
    /// The lights' uniforms as fitted to the scene: a model moving the fit re-bakes everything.
    pub(super) fitted: Vec<u8>,
}

impl CacheKey {
    /// The key of `scene` with its lights at `geometries` (the primary light where this frame
    /// puts it), the fit not yet filled in.
    pub(super) fn of(scene: &Scene, geometries: &[Light]) -> Self {
        CacheKey {
            lights: scene.lights.iter().zip(geometries).map(|(l, g)| [g.as_vec4(), l.direction.extend(0.0)]).collect(),
            transforms: scene.objects.iter().map(|o| o.transform).collect(),
            palettes: scene.objects.iter().filter_map(|o| o.skin.as_ref().map(|s| s.joint_matrices.clone())).collect(),
            fitted: Vec::new(),
        }
    }

    /// Nothing moved since `before`: no light, transform or pose (the fit is then the same).
    pub(super) fn unmoved_since(&self, before: &CacheKey) -> bool {
        (&self.lights, &self.transforms, &self.palettes) == (&before.lights, &before.transforms, &before.palettes)
    }
}

/// What a frame's stale tiles depend on beside the keys: the mesh spheres, which lights have a
/// map layer, and the map's size.
pub(super) struct Shadowing<'a> {
    pub(super) bounds: &'a [Sphere],
    pub(super) coverage: &'a [Coverage],
    pub(super) map_size: u32,
}

/// Which objects' shadow textures this frame re-bakes, its cache key `key` against the last
/// frame's `before`: all of them unless only models moved and the maps' fit held.
pub(super) fn stale_tiles(
    scene: &Scene,
    before: Option<&CacheKey>,
    key: &CacheKey,
    lights: &[Light],
    shadowing: Shadowing,
) -> Vec<usize> {
    let all = || (0..scene.objects.len()).collect();
    let Some(before) = before else { return all() };
    if before.lights != key.lights || before.palettes != key.palettes || before.fitted != key.fitted {
        return all();
    }
    let moved: Vec<usize> =
        (0..scene.objects.len()).filter(|&i| before.transforms.get(i) != key.transforms.get(i)).collect();
    if moved.is_empty() {
        return all();
    }
    let shadowing_lights: Vec<Light> =
        lights.iter().zip(shadowing.coverage).filter(|(_, c)| c.layer().is_some()).map(|(l, _)| *l).collect();
    stale_after_moves(scene, &before.transforms, &moved, shadowing.bounds, &shadowing_lights, shadowing.map_size)
}
