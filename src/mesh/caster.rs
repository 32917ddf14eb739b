//! A mesh prepared to cast shadow volumes: welded by position, its edge adjacency built, and
//! checked to be a closed manifold (the volume of an open mesh leaks).

use glam::Vec3;

use super::{weld_by_position, EdgeAdjacency, Welded};
use crate::error::{Error, Result};

/// Positions closer than this weld into one vertex (UV seams, split normals).
pub const WELD_EPSILON: f32 = 1e-5;

/// A closed, manifold caster's topology, built once.
pub struct ClosedCaster {
    pub welded: Welded,
    pub adjacency: EdgeAdjacency,
}

impl ClosedCaster {
    /// Welds `positions`/`indices` and checks the result; an open or non-manifold mesh is
    /// refused with `name`.
    pub fn prepare(name: &str, positions: &[Vec3], indices: &[u32]) -> Result<ClosedCaster> {
        let welded = weld_by_position(name, positions, indices, WELD_EPSILON)?;
        let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
        adjacency.require_closed_manifold().map_err(|e| match e {
            Error::Mesh { mesh, problem } => Error::Mesh {
                mesh,
                problem: format!("{problem}; shadow volumes need closed meshes (mark it as not casting shadows)"),
            },
            other => other,
        })?;
        Ok(ClosedCaster { welded, adjacency })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn a_cube_is_welded_closed_and_an_open_box_is_refused_by_name() {
        let cube = shapes::cube(1.0);
        let caster = ClosedCaster::prepare("cube", &cube.positions, &cube.indices).expect("closed");
        assert_eq!((caster.welded.positions.len(), caster.adjacency.face_count()), (8, 12));
        let open = &cube.indices[..cube.indices.len() - 6];
        let error = ClosedCaster::prepare("open box", &cube.positions, open).err().expect("open").to_string();
        assert!(error.contains("open box") && error.contains("shadow volumes need closed meshes"), "{error}");
    }
}
