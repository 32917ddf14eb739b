//! Scenes: built-in scenes, glTF loading, animation and skinning on the CPU side.

pub mod animation;
mod gltf_data;
pub mod gltf_loader;
pub mod model;
pub mod normals;
pub mod skinning;

#[cfg(test)]
mod gltf_tests;

pub use animation::{pose_at, rest_pose, sample_channel, Animation, TimeMode};
pub use gltf_loader::{load_gltf, load_gltf_slice};
pub use model::{Model, Transform, MAX_JOINTS};
pub use skinning::{joint_matrices, skin_positions_normals, world_matrices};
