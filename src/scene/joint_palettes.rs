//! Where each skinned object's joint palette lies among the frame's palettes: the GPU skins
//! every object from one storage buffer (`shaders/joint_palettes.glsl`), and each skinned
//! vertex's joint indices are moved up by its object's first joint when it is uploaded.

use super::objects::Scene;

/// The frame's joint palettes: the skinned objects' palettes one after another, in scene order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JointPalettes {
    /// Per object: the index of its first joint (`None`: not skinned).
    pub first_joint: Vec<Option<u32>>,
    /// Joints of all palettes together.
    pub joints: usize,
}

impl JointPalettes {
    pub fn of(scene: &Scene) -> Self {
        let mut joints = 0;
        let first_joint = scene
            .objects
            .iter()
            .map(|object| {
                let skin = object.skin.as_ref()?;
                let first = joints as u32;
                joints += skin.joint_matrices.len();
                Some(first)
            })
            .collect();
        JointPalettes { first_joint, joints }
    }

    /// No object is skinned: nothing to skin, no twin to build.
    pub fn is_empty(&self) -> bool {
        self.first_joint.iter().all(Option::is_none)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin_scene;

    #[test]
    fn palettes_follow_one_another_in_scene_order() {
        let scene = builtin_scene("default").expect("scene");
        let palettes = JointPalettes::of(&scene);
        let mut next = 0;
        for (object, first) in scene.objects.iter().zip(&palettes.first_joint) {
            match (&object.skin, first) {
                (Some(skin), Some(first)) => {
                    assert_eq!(*first as usize, next, "{}", object.name);
                    next += skin.joint_matrices.len();
                }
                (None, None) => {}
                _ => panic!("{}: skinned and first joint disagree", object.name),
            }
        }
        assert!(next > 0, "the default scene has a skinned character");
        assert_eq!(palettes.joints, next);
    }
}
