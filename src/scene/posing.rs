//! Re-posing a built scene at another time from the rigs its objects were placed from, and
//! tracking which CPU-side copies of skinned vertices that made stale.

use std::sync::Arc;

use glam::Mat4;

use super::objects::Scene;
use super::rig::Rig;
use super::skinning::joint_matrices;
use crate::error::Result;

/// Which joint palette each skinned object's CPU-side copies (uploaded vertices, welded
/// positions, atlas vertices) were posed with, so that a renderer re-poses them only when
/// [`Scene::pose_at`] gave the object a new palette.
#[derive(Debug, Clone, Default)]
pub struct PoseTracker {
    /// Per object: the palette its copies hold (`None`: not skinned).
    palettes: Vec<Option<Vec<Mat4>>>,
}

impl PoseTracker {
    /// Starts from `scene`'s meshes: every copy is in the pose the scene was built in (a
    /// scene re-posed before the renderer was built has its copies re-posed at the first frame).
    pub fn new(scene: &Scene) -> Self {
        PoseTracker { palettes: scene.objects.iter().map(|o| o.skin.as_ref().map(|s| s.mesh_pose.clone())).collect() }
    }

    /// The skinned objects of `scene` (indices, ascending) whose palette differs from the one
    /// their copies hold; they count as re-posed from now on.
    pub fn changed(&mut self, scene: &Scene) -> Vec<usize> {
        let mut changed = Vec::new();
        for (index, (object, held)) in scene.objects.iter().zip(&mut self.palettes).enumerate() {
            let Some(skin) = &object.skin else { continue };
            if held.as_ref() != Some(&skin.joint_matrices) {
                *held = Some(skin.joint_matrices.clone());
                changed.push(index);
            }
        }
        changed
    }
}

/// The pose each frame slot's copies of the skinned objects hold (`PoseTracker` per slot): a
/// slot's copies start in the pose they were uploaded in, and are re-posed when that slot's
/// frame needs them to follow the scene.
#[derive(Debug, Clone)]
pub struct SlotPoses {
    uploaded: PoseTracker,
    slots: Vec<PoseTracker>,
}

impl SlotPoses {
    /// Every slot's copies are in `scene`'s current pose (the one they are uploaded in).
    pub fn new(scene: &Scene) -> Self {
        SlotPoses { uploaded: PoseTracker::new(scene), slots: Vec::new() }
    }

    /// The skinned objects of `scene` whose palette differs from the one slot `slot`'s copies
    /// hold (`PoseTracker::changed`); that slot's copies count as re-posed from now on.
    pub fn changed(&mut self, scene: &Scene, slot: usize) -> Vec<usize> {
        if self.slots.len() <= slot {
            self.slots.resize(slot + 1, self.uploaded.clone());
        }
        self.slots[slot].changed(scene)
    }
}

/// Index in `worlds` of `rig`'s node world matrices at `time`, evaluated once per rig.
fn rig_world(worlds: &mut Vec<(*const Rig, Vec<Mat4>)>, rig: &Arc<Rig>, time: f32) -> Result<usize> {
    let key = Arc::as_ptr(rig);
    match worlds.iter().position(|(k, _)| *k == key) {
        Some(index) => Ok(index),
        None => {
            worlds.push((key, rig.world_at(time)?));
            Ok(worlds.len() - 1)
        }
    }
}

impl Scene {
    /// Re-poses every animated object at `time` seconds: its transform becomes its node's
    /// world matrix, its joint palette (skinned objects) that of the new pose. Meshes are not
    /// touched: the CPU-skinned vertices stay in the pose the scene was built in.
    pub fn pose_at(&mut self, time: f32) -> Result<()> {
        // One evaluation per rig, however many objects it placed.
        let mut worlds: Vec<(*const Rig, Vec<Mat4>)> = Vec::new();
        for object in &mut self.objects {
            let Some(placed) = &object.rig else { continue };
            let index = rig_world(&mut worlds, &placed.rig, time)?;
            let world = &worlds[index].1;
            let node_world = world.get(placed.node).copied().unwrap_or(Mat4::IDENTITY);
            object.transform = node_world;
            if let (Some(skin_index), Some(skin)) = (placed.skin, object.skin.as_mut()) {
                skin.joint_matrices = joint_matrices(&placed.rig.model, skin_index, world, node_world)?;
            }
        }
        // File lights ride on their nodes (KHR_lights_punctual).
        for light in &mut self.lights {
            let Some(on) = &light.node else { continue };
            let index = rig_world(&mut worlds, &on.rig, time)?;
            let world = &worlds[index].1;
            let node_world = world.get(on.node).copied().unwrap_or(Mat4::IDENTITY);
            light.place(node_world);
        }
        Ok(())
    }

    /// Whether [`Scene::pose_at`] changes anything.
    pub fn is_animated(&self) -> bool {
        self.objects.iter().any(|o| o.rig.is_some()) || self.lights.iter().any(|l| l.node.is_some())
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::builtin_scene_at;

    #[test]
    fn re_posing_a_built_scene_equals_building_it_at_that_time() {
        for name in ["default", "character"] {
            let mut scene = builtin_scene_at(name, 0.0).expect("scene");
            assert!(scene.is_animated(), "{name}");
            for time in [0.0, 0.3, 0.85] {
                scene.pose_at(time).expect("pose");
                let built = builtin_scene_at(name, time).expect("scene");
                for (a, b) in scene.objects.iter().zip(&built.objects) {
                    assert_eq!(a.transform, b.transform, "{name} at {time}: {}", a.name);
                    let palettes =
                        (a.skin.as_ref().map(|s| &s.joint_matrices), b.skin.as_ref().map(|s| &s.joint_matrices));
                    assert_eq!(palettes.0, palettes.1, "{name} at {time}: {}", a.name);
                }
            }
        }
        assert!(!builtin_scene_at("overlap", 0.0).expect("scene").is_animated());
    }

    #[test]
    fn the_tracker_reports_each_new_pose_once() {
        let mut scene = builtin_scene_at("default", 0.0).expect("scene");
        let skinned: Vec<usize> = (0..scene.objects.len()).filter(|&i| scene.objects[i].skin.is_some()).collect();
        assert!(!skinned.is_empty());
        let mut tracker = super::PoseTracker::new(&scene);
        assert_eq!(tracker.changed(&scene), Vec::<usize>::new(), "as built");
        scene.pose_at(0.3).expect("pose");
        assert_eq!(tracker.changed(&scene), skinned);
        assert_eq!(tracker.changed(&scene), Vec::<usize>::new(), "already re-posed");
        scene.pose_at(0.3).expect("pose");
        assert_eq!(tracker.changed(&scene), Vec::<usize>::new(), "the same time again");
    }

    #[test]
    fn a_tracker_made_for_a_re_posed_scene_re_poses_its_copies_first() {
        // The meshes keep the pose the scene was built in: a renderer built after `pose_at`
        // must still re-pose its copies at its first frame.
        let mut scene = builtin_scene_at("default", 0.0).expect("scene");
        let skinned: Vec<usize> = (0..scene.objects.len()).filter(|&i| scene.objects[i].skin.is_some()).collect();
        scene.pose_at(0.3).expect("pose");
        let mut tracker = super::PoseTracker::new(&scene);
        assert_eq!(tracker.changed(&scene), skinned);
        assert_eq!(tracker.changed(&scene), Vec::<usize>::new());
    }
}
