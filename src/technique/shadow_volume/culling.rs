//! Casters that cast nothing new for a light (CC Shadow Volumes' culling, Lloyd et al. 2004):
//! a caster whose box lies wholly behind other casters, as the light sees it, is in their
//! shadow, and so is everything behind it. Its volume only adds to counts that are already at
//! least 1, so leaving it out changes no shadow (docs/shadow-volumes.md, "Casters culled").
//!
//! Decided on the CPU from a conservative occluder map ([`OccluderMap`]): a texel counts as
//! blocked only where one triangle covers it whole, so a caster is called hidden only when it
//! is. Its cost, with a moving light, is one map per light and frame; `profile` reports it.

use std::time::Instant;

use glam::{Mat4, Vec3};

use super::bounds::Aabb;
use super::casters::{posed_welded_positions, Caster};
use super::occluder_map::{LightView, OccluderMap};
use crate::scene::model::LightKind;
use crate::scene::{Light, Scene, SceneLight};

/// Texels along the occluder map's longer side: fine enough that a part's faces cover whole
/// texels, small enough to build in a few milliseconds.
pub const MAP_RESOLUTION: usize = 256;

/// Which casters a light's volumes can leave out, and what deciding it cost.
#[derive(Debug, Clone, Default)]
pub struct Culling {
    /// Per caster (in the order of the casters given): wholly in the shadow of others.
    pub hidden: Vec<bool>,
    /// CPU time spent building the map and testing the casters, in milliseconds.
    pub cpu_ms: f64,
}

impl Culling {
    /// Nothing culled (culling off, or no map for this light).
    pub fn none(casters: usize) -> Culling {
        Culling { hidden: vec![false; casters], cpu_ms: 0.0 }
    }

    pub fn count(&self) -> usize {
        self.hidden.iter().filter(|&&h| h).count()
    }

    pub fn is_hidden(&self, caster: usize) -> bool {
        self.hidden.get(caster).copied().unwrap_or(false)
    }
}

/// The culling last decided for one light, with what it was decided from. Where neither the light
/// nor any caster moved, and no caster is skinned, the same inputs decide the same casters: the
/// next frame takes it as it is (as the volumes' buffers are kept, Doom 3's static shadows).
pub struct KeptCulling {
    key: CullingKey,
    culling: Culling,
}

/// What a culling depends on: the light's kind, geometry and range, and every caster's
/// transform (its mesh is fixed; a skinned caster moves without one, so none is kept then).
#[derive(Debug, Clone, PartialEq)]
struct CullingKey {
    kind: LightKind,
    light: Light,
    range: Option<f32>,
    transforms: Vec<Mat4>,
}

impl CullingKey {
    fn of(scene: &Scene, casters: &[Caster], light: &SceneLight) -> Option<CullingKey> {
        let objects = || casters.iter().map(|c| &scene.objects[c.object]);
        if objects().any(|o| o.skin.is_some()) {
            return None;
        }
        let transforms = objects().map(|o| o.transform).collect();
        Some(CullingKey { kind: light.kind, light: light.geometry(), range: light.range, transforms })
    }
}

/// [`hidden_casters`], or the culling in `kept` where nothing it depends on moved; whether it
/// was kept. A culling decided again replaces the one kept. Its `cpu_ms` is this frame's.
pub fn hidden_casters_kept(
    kept: &mut Option<KeptCulling>,
    scene: &Scene,
    casters: &[Caster],
    light: &SceneLight,
    boxes: &[Option<Aabb>],
) -> (Culling, bool) {
    let start = Instant::now();
    let key = CullingKey::of(scene, casters, light);
    if let (Some(key), Some(kept)) = (&key, kept.as_ref()) {
        if *key == kept.key {
            let culling = Culling { cpu_ms: start.elapsed().as_secs_f64() * 1e3, ..kept.culling.clone() };
            return (culling, true);
        }
    }
    let culling = hidden_casters(scene, casters, light, boxes);
    *kept = key.map(|key| KeptCulling { key, culling: culling.clone() });
    (culling, false)
}

/// The casters `light` reaches that lie wholly in the shadow of the others it reaches.
/// `boxes` are the objects' posed world boxes ([`super::bounds::object_boxes`]).
pub fn hidden_casters(scene: &Scene, casters: &[Caster], light: &SceneLight, boxes: &[Option<Aabb>]) -> Culling {
    let start = Instant::now();
    let mut culling = Culling::none(casters.len());
    // Only casters that cast for this light can shadow one another.
    let reached: Vec<Option<Aabb>> = casters
        .iter()
        .map(|c| boxes.get(c.object).copied().flatten().filter(|b| light.reaches_box(b.lo, b.hi)))
        .collect();
    if let Some(map) = occluder_map(scene, casters, light, &reached) {
        for (hidden, caster_box) in culling.hidden.iter_mut().zip(&reached) {
            *hidden = caster_box.is_some_and(|b| map.hides_box(&b.corners()));
        }
    }
    culling.cpu_ms = start.elapsed().as_secs_f64() * 1e3;
    culling
}

/// Every reached caster's triangles drawn into a map from the light over their boxes; `None`
/// when fewer than two casters are reached or the light sits among them.
fn occluder_map(
    scene: &Scene,
    casters: &[Caster],
    light: &SceneLight,
    reached: &[Option<Aabb>],
) -> Option<OccluderMap> {
    if reached.iter().flatten().count() < 2 {
        return None;
    }
    let all = reached.iter().flatten().copied().reduce(Aabb::union)?;
    let view = match light.geometry() {
        Light::Directional { direction } => LightView::directional(direction)?,
        Light::Point { position } => LightView::point(position, (all.lo + all.hi) * 0.5, (all.hi - all.lo).length())?,
    };
    let corners: Vec<Vec3> = reached.iter().flatten().flat_map(|b| b.corners()).collect();
    let mut map = OccluderMap::new(view, &corners, MAP_RESOLUTION)?;
    let mut world = Vec::new();
    for (caster, _) in casters.iter().zip(reached).filter(|(_, b)| b.is_some()) {
        let model = scene.objects[caster.object].transform;
        let posed = posed_welded_positions(scene, caster);
        let positions = posed.as_deref().unwrap_or(&caster.mesh.welded.positions);
        world.clear();
        world.extend(positions.iter().map(|&p| model.transform_point3(p)));
        map.add_mesh(&world, &caster.mesh.welded.indices);
    }
    Some(map)
}
