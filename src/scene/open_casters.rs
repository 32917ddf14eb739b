//! Built-in scenes whose casters are not closed manifolds (docs/design/any-mesh-volumes.md): a one-sided
//! quad, a box without its top, a non-manifold fan and touching boxes. Shadow volumes cast them
//! two-sided; their shadows on the ground are projections computable by hand.

use glam::{Mat4, Vec2, Vec3};

use super::camera::{Camera, Light};
use super::layout::with_ground;
use super::objects::Scene;
use crate::mesh::{shapes, MeshData};

/// The light of these scenes: the `box` scene's, from above, slightly to the side.
const LIGHT: Vec3 = Vec3::new(0.4, -1.0, -0.2);

fn scene(name: &str, eye: Vec3, target: Vec3) -> Scene {
    with_ground(name, Camera::look_at(eye, target), Light::Directional { direction: LIGHT.normalize() })
}

/// The camera of the scenes that need no particular one.
const EYE: Vec3 = Vec3::new(0.0, 7.0, 6.0);

/// The parts one after the other in one mesh (indices shifted), each moved by its matrix.
fn merged(parts: &[(MeshData, Mat4)]) -> MeshData {
    let mut mesh = MeshData::default();
    for (part, transform) in parts {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(part.positions.iter().map(|p| transform.transform_point3(*p)));
        mesh.normals.extend(part.normals.iter().map(|n| transform.transform_vector3(*n).normalize_or_zero()));
        mesh.uvs.extend_from_slice(&part.uvs);
        mesh.indices.extend(part.indices.iter().map(|i| base + i));
    }
    mesh
}

/// The quad of `open-quad`, in world space: tilted so that the camera sees its front while the
/// light sees its back (the case a one-sided caster used to drop).
pub fn open_quad_mesh() -> MeshData {
    shapes::quad(Vec3::new(-0.4, 1.6, 0.2), Vec3::new(0.0, -1.0, 0.6), Vec2::new(2.2, 1.8))
}

/// One one-sided quad over the ground, its back to the light.
pub fn open_quad_scene() -> Scene {
    // Low enough to see the quad's underside, its front.
    let mut scene = scene("open-quad", Vec3::new(0.0, 3.5, 7.0), Vec3::new(0.0, 0.5, 0.0));
    let mesh = scene.add_mesh("one-sided quad", open_quad_mesh());
    scene.add_object("quad", mesh, Mat4::IDENTITY, Vec3::new(0.86, 0.36, 0.24), true);
    scene
}

/// Where `open-box` puts its box (edge 1.4).
pub const OPEN_BOX_CENTRE: Vec3 = Vec3::new(-0.4, 1.3, 0.0);

/// A cube of edge `size` without its top face (+Y), centred on the origin.
pub fn open_box_mesh(size: f32) -> MeshData {
    let mut mesh = shapes::cube(size);
    let is_top = |t: &[u32]| t.iter().all(|&i| mesh.normals[i as usize] == Vec3::Y);
    let kept: Vec<u32> = mesh.indices.chunks_exact(3).filter(|t| !is_top(t)).flatten().copied().collect();
    mesh.indices = kept;
    mesh
}

/// A box without its top over the ground; the camera, above, looks in through the hole.
pub fn open_box_scene() -> Scene {
    // Nearly overhead: through the hole the camera sees the box's floor from inside (its
    // back face, which the scene pass culls, so the ground under it shows).
    let mut scene = scene("open-box", Vec3::new(0.0, 9.0, 2.5), Vec3::new(-0.2, 0.6, 0.0));
    let mesh = scene.add_mesh("box without a top", open_box_mesh(1.4));
    scene.add_object("open box", mesh, Mat4::from_translation(OPEN_BOX_CENTRE), Vec3::new(0.30, 0.55, 0.85), true);
    scene
}

/// Three quads sharing their top edge (a fan of pages, non-manifold along the spine).
pub fn fan_mesh() -> MeshData {
    let spine = Vec3::new(0.0, 2.2, 0.0);
    let pages = [-0.9f32, 0.0, 0.9].map(|angle| {
        // Each page hangs from the spine (along X), turned by `angle` about it.
        let down = Vec3::new(0.0, -angle.cos(), angle.sin());
        let normal = down.cross(Vec3::X);
        (shapes::quad(spine + down * 0.6, normal, Vec2::new(1.8, 1.2)), Mat4::IDENTITY)
    });
    merged(&pages)
}

/// A unit box whose first triangle is wound the wrong way: closed, but inconsistently wound.
pub fn box_with_a_flipped_triangle() -> MeshData {
    let mut mesh = shapes::cube(1.0);
    mesh.indices.swap(1, 2);
    mesh
}

/// A non-manifold fan and a box with a flipped triangle over the ground.
pub fn non_manifold_scene() -> Scene {
    let mut scene = scene("non-manifold", EYE, Vec3::ZERO);
    let mesh = scene.add_mesh("fan of three quads", fan_mesh());
    scene.add_object("fan", mesh, Mat4::from_translation(Vec3::new(-1.2, 0.0, 0.0)), Vec3::new(0.42, 0.75, 0.36), true);
    let flipped = scene.add_mesh("box with a flipped triangle", box_with_a_flipped_triangle());
    let place = Mat4::from_translation(Vec3::new(1.6, 1.2, -0.3)) * Mat4::from_rotation_y(0.5);
    scene.add_object("flipped box", flipped, place, Vec3::new(0.75, 0.45, 0.80), true);
    scene
}

/// Two unit boxes in one mesh, the second moved by `offset` (sharing an edge for (1, 1, 0), a
/// corner for (1, 1, 1)).
pub fn touching_boxes(offset: Vec3) -> MeshData {
    let cube = shapes::cube(1.0);
    merged(&[(cube.clone(), Mat4::IDENTITY), (cube, Mat4::from_translation(offset))])
}

/// Boxes touching along an edge (non-manifold: four faces on it) and at a corner (still a
/// closed manifold, as adjacency sees it), one mesh each.
pub fn touching_scene() -> Scene {
    let mut scene = scene("touching", EYE, Vec3::ZERO);
    let edge = scene.add_mesh("boxes sharing an edge", touching_boxes(Vec3::new(1.0, 1.0, 0.0)));
    scene.add_object(
        "edge pair",
        edge,
        Mat4::from_translation(Vec3::new(-2.2, 0.9, -0.6)),
        Vec3::new(0.30, 0.55, 0.85),
        true,
    );
    let corner = scene.add_mesh("boxes sharing a corner", touching_boxes(Vec3::new(1.0, 1.0, 1.0)));
    let place = Mat4::from_translation(Vec3::new(0.9, 0.9, -0.4)) * Mat4::from_scale(Vec3::splat(0.8));
    scene.add_object("corner pair", corner, place, Vec3::new(0.86, 0.36, 0.24), true);
    scene
}
