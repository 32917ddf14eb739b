//! Timings of the mesh pipeline on a 131,072-face torus, printed rather than asserted (a timed
//! assertion fails on a busy machine): run by hand with
//! `cargo test --lib mesh::timing -- --ignored --nocapture`.

use std::time::{Duration, Instant};

use glam::Vec3;

use super::adjacency::EdgeAdjacency;
use super::edges::{classify_into, EdgeClasses, View};
use super::shadow_volume::{build_shadow_volume_into, Light, VolumeGeometry};
use super::{shapes, weld::weld_by_position};
use crate::Result;

/// Fastest of `runs` runs, and the last result.
fn best_of<T>(runs: usize, mut work: impl FnMut() -> T) -> (Duration, T) {
    let mut best = Duration::MAX;
    let mut last = None;
    for _ in 0..runs {
        let start = Instant::now();
        last = Some(work());
        best = best.min(start.elapsed());
    }
    (best, last.expect("at least one run"))
}

#[test]
#[ignore = "prints timings; run by hand"]
fn edge_extraction_131072_faces() -> Result<()> {
    let torus = shapes::torus(1.0, 0.3, 256, 256)?;
    let (weld_time, welded) = best_of(5, || weld_by_position("torus", &torus.positions, &torus.indices, 1e-6));
    let welded = welded?;
    assert_eq!(welded.face_count(), 131_072);
    let (build_time, adjacency) = best_of(5, || EdgeAdjacency::build("torus", &welded.positions, &welded.indices));
    let adjacency = adjacency?;

    let view = View::Perspective { eye: Vec3::new(3.0, 2.0, 4.0) };
    let mut normals = Vec::new();
    let mut classes = EdgeClasses::default();
    let (normals_time, _) = best_of(20, || adjacency.recompute_face_normals(&welded.positions, &mut normals));
    let (classify_time, _) =
        best_of(20, || classify_into(&adjacency, &welded.positions, &normals, view, 40.0, &[], &mut classes));
    let mut volume = VolumeGeometry::default();
    let light = Light::Point(Vec3::new(0.0, 5.0, 1.0));
    let (volume_time, _) =
        best_of(20, || build_shadow_volume_into(&adjacency, &welded.positions, &normals, light, true, &mut volume));
    println!(
        "131072 faces, {} edges: weld {weld_time:?}, adjacency build {build_time:?}; per frame: \
         face normals {normals_time:?}, classify {classify_time:?} ({} silhouette edges), \
         capped point-light volume {volume_time:?} ({} triangles)",
        adjacency.edges.len(),
        classes.silhouette.len(),
        volume.triangle_count()
    );
    Ok(())
}
