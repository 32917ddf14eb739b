//! CPU-side mesh processing: welding, edge adjacency, silhouettes, shadow volumes.
//!
//! The usual path: [`weld_by_position`] once at load, then [`EdgeAdjacency::build`] on the
//! welded mesh once; per frame [`face_normals`] from the (skinned) positions.

pub mod adjacency;
mod fast_hash;
pub mod shapes;
pub mod weld;

pub use adjacency::{face_normals, Edge, EdgeAdjacency, NO_FACE};
pub use shapes::MeshData;
pub use weld::{weld_by_position, Welded};
