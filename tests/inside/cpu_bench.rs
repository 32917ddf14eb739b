//! CPU-side hot paths: welding and edge extraction for a 131,072-face mesh (the paper's 257x257
//! geometry image size), shadow-volume building (silhouette and two-sided), animation sampling and CPU skinning.
//! Criterion, run from an ignored test because the functions it times are private to the crate:
//! `cargo test --release --lib --features cpu-bench cpu_bench -- --ignored --nocapture`.

use std::path::Path;

use criterion::Criterion;
use glam::Vec3;
use nostencil::mesh::adjacency::face_normals;
use nostencil::mesh::edges::classify_into;
use nostencil::mesh::shadow_volume::build_shadow_volume_into;
use nostencil::mesh::two_sided_volume::{build_two_sided_volume_into, CornerEdges};
use nostencil::mesh::{self, shapes, EdgeAdjacency, View};
use nostencil::scene;
use nostencil::scene::animation::{pose_at, TimeMode};
use nostencil::scene::skinning::{joint_matrices, skin_positions_normals, world_matrices};

fn big_torus() -> shapes::MeshData {
    // 256 x 256 quads = 131,072 triangles.
    shapes::torus(1.0, 0.3, 256, 256).expect("torus")
}

fn edges(c: &mut Criterion) {
    let mesh = big_torus();
    c.bench_function("weld by position, 131072 faces", |b| {
        b.iter(|| mesh::weld_by_position("torus", &mesh.positions, &mesh.indices, 1e-6).expect("weld"))
    });
    let welded = mesh::weld_by_position("torus", &mesh.positions, &mesh.indices, 1e-6).expect("weld");
    c.bench_function("edge adjacency build, 131072 faces", |b| {
        b.iter(|| EdgeAdjacency::build("torus", &welded.positions, &welded.indices).expect("adjacency"))
    });
    let adjacency = EdgeAdjacency::build("torus", &welded.positions, &welded.indices).expect("adjacency");
    let mut normals = Vec::new();
    let mut classes = mesh::EdgeClasses::default();
    c.bench_function("per-frame face normals + silhouette/crease classify, 131072 faces", |b| {
        b.iter(|| {
            face_normals(&welded.positions, &welded.indices, &mut normals);
            let view = View::Perspective { eye: Vec3::new(0.0, 2.0, 4.0) };
            classify_into(&adjacency, &welded.positions, &normals, view, 40.0, &[], &mut classes);
        })
    });
    let mut volume = mesh::VolumeGeometry::default();
    c.bench_function("capped shadow volume, point light, 131072 faces", |b| {
        b.iter(|| {
            let light = mesh::Light::Point(Vec3::new(2.0, 5.0, 1.0));
            build_shadow_volume_into(
                &adjacency,
                &welded.positions,
                &adjacency.face_normals,
                light,
                mesh::Reach::Infinite,
                true,
                &mut volume,
            )
        })
    });
    // The same mesh cast two-sided (what an open or non-manifold mesh of that size costs).
    let corners = CornerEdges::build(&adjacency).expect("corner edges");
    let mut multiplicities = Vec::new();
    c.bench_function("two-sided shadow volume, point light, 131072 faces", |b| {
        b.iter(|| {
            let light = mesh::Light::Point(Vec3::new(2.0, 5.0, 1.0));
            build_two_sided_volume_into(
                &adjacency,
                &corners,
                &welded.positions,
                &adjacency.face_normals,
                light,
                mesh::Reach::Infinite,
                &mut multiplicities,
                &mut volume,
            )
        })
    });
}

fn animation(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/assets/RiggedSimple.glb");
    let Ok(model) = scene::load_gltf(&path) else {
        eprintln!("skipped animation benches: {} not found", path.display());
        return;
    };
    c.bench_function("pose_at (RiggedSimple)", |b| b.iter(|| pose_at(&model, 0, 0.7, TimeMode::Loop).expect("pose")));
    let pose = pose_at(&model, 0, 0.7, TimeMode::Loop).expect("pose");
    let world = world_matrices(&model, &pose);
    let (node, skin) =
        model.nodes.iter().enumerate().find_map(|(i, n)| n.skin.map(|s| (i, s))).expect("a skinned node");
    let joints = joint_matrices(&model, skin, &world, world[node]).expect("joints");
    let primitive = &model.meshes[model.nodes[node].mesh.expect("mesh")].primitives[0];
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    c.bench_function("CPU skinning (RiggedSimple)", |b| {
        b.iter(|| skin_positions_normals(primitive, &joints, &mut positions, &mut normals).expect("skin"))
    });
}

#[test]
#[ignore = "a benchmark: cargo test --release --lib --features cpu-bench cpu_bench -- --ignored --nocapture"]
fn cpu_bench() {
    let mut criterion = Criterion::default();
    edges(&mut criterion);
    animation(&mut criterion);
    criterion.final_summary();
}
