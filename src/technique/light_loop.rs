//! The per-light loop of the additive shadow mode, as Doom 3 BFG (`RB_DrawInteractions`) and
//! Ogre (`renderAdditiveStencilShadowedQueueGroupObjects`) run it: ambient first, then for each
//! light its shadows and its contribution where they do not fall. Here: which lights a plan
//! loops over, and what its passes are called.

use crate::scene::Scene;

/// A light as a plan sees it: its name (the prefix of its passes) and whether it casts shadows.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct PlannedLight {
    pub name: String,
    pub shadows: bool,
}

impl PlannedLight {
    /// The scene's lights, in its order.
    pub fn of_scene(scene: &Scene) -> Vec<PlannedLight> {
        scene.lights.iter().map(|l| PlannedLight { name: l.name.clone(), shadows: l.casts_shadow }).collect()
    }

    /// The lights of a plan made without a scene: the built-in scenes' one shadowing sun.
    #[cfg(test)]
    pub fn default_lights() -> Vec<PlannedLight> {
        vec![PlannedLight { name: "sun".into(), shadows: true }]
    }
}

/// The primary light among `lights`: the first that casts shadows, else the first (as
/// `Scene::primary_light`).
pub fn primary(lights: &[PlannedLight]) -> Option<usize> {
    lights.iter().position(|l| l.shadows).or((!lights.is_empty()).then_some(0))
}

/// `light: pass`, the name of a pass of the loop ("sun: volumes (alpha, z-pass)").
pub fn pass_name(light: &PlannedLight, pass: &str) -> String {
    format!("{}: {pass}", light.name)
}

/// Which lights a technique shadows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowedLights {
    /// Every light that casts shadows (the additive loop).
    Every,
    /// The primary light only (the first that casts shadows).
    Primary,
    /// None: the technique draws no shadows (lit, outlines, ink).
    None,
    /// The lights whose bit is set (bit i: the scene's light i), the others not: shadow maps
    /// cover what one frustum can (no cube map for a point light inside the scene).
    Listed(u8),
}

impl ShadowedLights {
    /// Whether light `index` of `scene`, which casts shadows, is shadowed.
    pub fn covers(self, scene: &Scene, index: usize) -> bool {
        match self {
            ShadowedLights::Every => true,
            ShadowedLights::Primary => scene.primary_light_index() == Some(index),
            ShadowedLights::None => false,
            ShadowedLights::Listed(mask) => index < 8 && mask & (1 << index) != 0,
        }
    }
}
