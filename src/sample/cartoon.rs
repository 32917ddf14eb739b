//! What the ink sample needs from the engine's cartoon techniques and no port writes twice:
//! the scene pass's ramps (set 2 of `cartoon_shade.frag`) and each object's copy for the
//! inverted hull (welded, smooth normals), both exactly as the engine makes them.

use glam::Vec3;

use super::sets::ExtraSet;
use super::SampleBase;
use crate::error::Result;
use crate::technique::cartoon_shading::Ramps;
use crate::technique::extruded::{smooth_normals, weld_object};

/// An object's mesh welded by position (seams closed), with one angle-weighted smooth normal
/// per vertex: what `cartoon_extrude.vert` pushes out (`VertexInput::PositionNormal`).
pub struct SmoothCopy {
    /// Position, normal.
    pub vertices: Vec<[Vec3; 2]>,
    pub indices: Vec<u32>,
}

impl SampleBase {
    /// Set 2 of the cartoon scene pass: the engine's toon ramp (binding 0) and dark-rim ramp
    /// (binding 1). `cartoon_shade.frag` declares both; Lambert shading reads neither.
    pub fn cartoon_ramps(&self) -> Result<ExtraSet> {
        let ramps = Ramps::new(&self.gpu)?;
        let (set_layout, set) = (ramps.set.layout, ramps.set.set);
        self.extra_set_of(set_layout, set, Box::new(ramps))
    }

    /// Object `index`'s copy for the inverted hull, as the engine builds it (`ExtrudedCopies`).
    pub fn smooth_copy(&self, index: usize) -> Result<SmoothCopy> {
        let welded = weld_object(&self.scene, index)?;
        // A mirroring transform winds the mesh clockwise in its own space: normals turned out.
        let out = if self.scene.objects[index].mirrored() { -1.0 } else { 1.0 };
        let normals = smooth_normals(&welded);
        let vertices = welded.positions.iter().zip(&normals).map(|(p, n)| [*p, out * *n]).collect();
        Ok(SmoothCopy { vertices, indices: welded.indices })
    }
}
