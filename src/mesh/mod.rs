//! CPU-side mesh processing: welding, edge adjacency, silhouettes, shadow volumes.
