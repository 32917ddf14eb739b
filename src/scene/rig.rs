//! Animated models kept beside the scene built from them, so that the scene can be re-posed at
//! any time without rebuilding it (see `posing`): node-animated objects get their node's new
//! placement, skinned ones their new joint palette (what GPU skinning reads). The viewer
//! re-poses every frame; `render --time` builds the scene at one time instead.

use std::fmt::Debug;
use std::sync::Arc;

use glam::Mat4;

use super::animation::{pose_at, TimeMode};
use super::model::{Model, Transform};
use super::skinning::world_matrices;
use crate::error::Result;

/// A pose computed in code rather than read from the file (the built-in character's walk).
/// Whoever builds the rig supplies it, so the rig needs to know nothing about who moves.
pub trait PoseSource: Debug + Send + Sync {
    /// Local transforms of every node of `model` at `time` seconds.
    fn local_pose(&self, model: &Model, time: f32) -> Vec<Transform>;
}

/// How a model is posed at a time.
#[derive(Debug, Clone)]
pub enum RigPose {
    /// The model's first glTF animation, looping.
    FirstAnimation,
    /// A pose source supplied by the rig's builder.
    Procedural(Arc<dyn PoseSource>),
}

/// A model and how it moves; shared by every object placed from it.
#[derive(Debug)]
pub struct Rig {
    pub model: Model,
    pub pose: RigPose,
}

impl Rig {
    /// World matrix of every node at `time` seconds.
    pub fn world_at(&self, time: f32) -> Result<Vec<Mat4>> {
        let local = match &self.pose {
            RigPose::FirstAnimation => pose_at(&self.model, 0, time, TimeMode::Loop)?,
            RigPose::Procedural(source) => source.local_pose(&self.model, time),
        };
        Ok(world_matrices(&self.model, &local))
    }

    /// Whether the pose changes with time: a procedural pose, or a file with an animation.
    pub fn moves(&self) -> bool {
        !self.model.animations.is_empty() || matches!(self.pose, RigPose::Procedural(_))
    }
}

/// The part of a rig a scene object was placed from.
#[derive(Debug, Clone)]
pub struct ObjectRig {
    pub rig: Arc<Rig>,
    /// The node whose mesh the object draws.
    pub node: usize,
    /// The node's skin, when the object is skinned.
    pub skin: Option<usize>,
}
