//! Scenes: built-in scenes, glTF loading, animation and skinning on the CPU side.

pub mod builtin;
pub mod camera;
pub mod objects;

pub use builtin::{builtin_scene, BUILTIN_SCENES};
pub use camera::{Camera, Light};
pub use objects::{Scene, SceneObject};
