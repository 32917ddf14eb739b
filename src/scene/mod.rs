//! Scenes: built-in scenes, glTF loading, animation and skinning on the CPU side.

// Dependency order: each file imports only files on lines above its own (tests aside), so
// there are no import cycles. Data first, then the functions over it, then scene building.
//   model (animation data in model/animation_data), camera, normals: import nothing of scene
//   animation, skinning -> model
//   gltf/ (the loader)  -> model, normals
//   rig                 -> animation, model, skinning
//   lights              -> camera, model, rig
//   objects             -> camera, lights, rig, skinning
//   posing              -> objects, rig, skinning
//   joint_palettes      -> objects
//   layout              -> camera, objects
//   place               -> model, objects, rig, skinning
//   character           -> model, objects, place, rig, skinning
//   from_gltf           -> animation, camera, gltf, layout, model, objects, place, rig, skinning
//   open_casters        -> camera, layout, objects
//   builtin             -> camera, character, layout, lights, objects, open_casters

pub mod animation;
pub mod builtin;
pub mod camera;
pub mod character;
pub mod from_gltf;
pub mod gltf;
pub mod joint_palettes;
pub mod layout;
pub mod lights;
pub mod model;
pub mod normals;
pub mod objects;
pub mod open_casters;
pub mod place;
pub mod posing;
pub mod rig;
pub mod skinning;

pub use builtin::{builtin_scene, builtin_scene_at, BUILTIN_SCENES, OTHER_SCENES};
pub use camera::{Camera, Light};
#[cfg(test)]
pub use from_gltf::scene_and_warnings_from_gltf_slice;
pub use from_gltf::{scene_and_warnings_from_gltf, scene_from_gltf};
pub use lights::{SceneLight, MAX_LIGHTS};
// `self::`: `gltf` alone would also name the gltf crate.
#[cfg(test)]
pub use self::gltf::load_gltf;
pub use joint_palettes::JointPalettes;
pub use model::MAX_JOINTS;
pub use objects::{bounds_of, Scene, SceneObject, SceneSkin};
pub use posing::{PoseTracker, SlotPoses};
