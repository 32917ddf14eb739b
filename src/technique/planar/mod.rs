//! The ground shadows of seed 001, each a technique of its own: planar projected shadows with
//! double darkening stopped in alpha ([`projected`]; from several lights, [`per_light`]), blobs ([`blob`]) and a render-texture
//! shadow ([`shadow_texture`]). What they share: the receiver plane and the projection onto it
//! ([`receiver`]), the scene's meshes and the lit scene pass ([`scene_meshes`]; skinned objects
//! skinned on the GPU by the passes' skinned pipelines), low-poly shadow casters ([`lod`]) and
//! the quad the seed lays its render texture on ([`texture_quad`]).

pub mod blob;
pub mod flattened;
pub mod lod;
pub mod per_light;
pub mod projected;
pub mod receiver;
pub mod scene_meshes;
pub mod shadow_texture;
pub mod shared;
pub mod texture_quad;

#[cfg(test)]
pub use crate::technique::options::TextureShadowOn;
pub use crate::technique::options::{GivenPlane, PlanarOptions};
#[cfg(test)]
pub use receiver::project_onto_plane;
pub use receiver::receiver_plane;
#[cfg(test)]
pub use receiver::Plane;
pub use shared::{BlobShadows, Planar, PlanarStats, ShadowTexture};
