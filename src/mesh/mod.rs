//! CPU-side mesh processing: welding, edge adjacency, silhouettes, shadow volumes, geometry
//! images, generated atlas charts and CPU ray casts.
//!
//! The usual path: [`weld_by_position`] once at load, [`EdgeAdjacency::build`] on the welded
//! mesh once, [`attribute_seams`] once if ink lines want UV/normal/material boundaries; then per
//! frame [`face_normals`] from the (skinned) positions, and [`classify`] for outlines or
//! [`build_shadow_volume`] per light (or, for a mesh that is not a closed manifold,
//! [`build_two_sided_volume_into`]; [`caster::CasterMesh`] picks).

pub mod adjacency;
pub mod atlas_charts;
pub mod caster;
pub mod edges;
pub(crate) mod fast_hash;
pub mod geometry_image;
pub mod ray;
pub mod shadow_volume;
pub mod shapes;
pub mod two_sided_volume;
pub mod weld;

pub use adjacency::{EdgeAdjacency, NO_FACE};
pub use edges::{attribute_seams, classify_creases_into, classify_view_into, CornerAttributes, EdgeClasses, View};
pub use shadow_volume::{Light, Reach, VolumeGeometry};
pub use shapes::MeshData;
pub use weld::{weld_by_position, Welded};
