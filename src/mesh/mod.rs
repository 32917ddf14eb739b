//! CPU-side mesh processing: welding, edge adjacency, silhouettes, shadow volumes.

pub mod shapes;

pub use shapes::MeshData;
