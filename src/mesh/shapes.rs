//! Closed test meshes, counter-clockwise seen from outside, with smooth normals.
//! (Provisional: replaced by the mesh module's generators.)

use glam::{Vec2, Vec3};
use std::f32::consts::TAU;

#[derive(Debug, Clone, Default)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub indices: Vec<u32>,
}

/// An axis-aligned cube centred on the origin, with flat normals (24 vertices).
pub fn cube(size: f32) -> MeshData {
    let h = size * 0.5;
    let mut mesh = MeshData::default();
    let faces = [
        (Vec3::X, Vec3::Y, Vec3::Z),
        (Vec3::NEG_X, Vec3::Y, Vec3::NEG_Z),
        (Vec3::Y, Vec3::Z, Vec3::X),
        (Vec3::NEG_Y, Vec3::NEG_Z, Vec3::X),
        (Vec3::Z, Vec3::Y, Vec3::NEG_X),
        (Vec3::NEG_Z, Vec3::Y, Vec3::X),
    ];
    for (n, up, _) in faces {
        let base = mesh.positions.len() as u32;
        // r x up = n keeps the quad counter-clockwise seen from outside.
        let r = up.cross(n);
        for (u, v) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            mesh.positions.push((n + r * u + up * v) * h);
            mesh.normals.push(n);
            mesh.uvs.push(Vec2::new((u + 1.0) * 0.5, (v + 1.0) * 0.5));
        }
        mesh.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    mesh
}

/// A torus around the Y axis.
pub fn torus(major: f32, minor: f32, major_segments: u32, minor_segments: u32) -> MeshData {
    sweep(major_segments, minor_segments, |u| {
        let a = u * TAU;
        let centre = Vec3::new(a.cos(), 0.0, a.sin()) * major;
        let tangent = Vec3::new(-a.sin(), 0.0, a.cos());
        (centre, tangent, Vec3::Y, minor)
    })
}

/// A (p, q) torus knot tube.
pub fn torus_knot(p: u32, q: u32, radius: f32, tube: f32, segments: u32, sides: u32) -> MeshData {
    let curve = |t: f32| {
        let phi = t * TAU;
        let r = radius * (2.0 + (q as f32 * phi).cos()) / 3.0;
        Vec3::new(r * (p as f32 * phi).cos(), radius * (q as f32 * phi).sin() / 3.0, r * (p as f32 * phi).sin())
    };
    sweep(segments, sides, |u| {
        let c = curve(u);
        let tangent = (curve(u + 1e-4) - curve(u - 1e-4)).normalize();
        let up = c.normalize();
        (c, tangent, up, tube)
    })
}

/// A closed tube around a closed curve: `frame(u)` gives centre, tangent, a reference up and
/// the tube radius. Seam vertices are shared, so the result is closed without welding.
fn sweep(segments: u32, sides: u32, frame: impl Fn(f32) -> (Vec3, Vec3, Vec3, f32)) -> MeshData {
    let mut mesh = MeshData::default();
    for i in 0..segments {
        let u = i as f32 / segments as f32;
        let (centre, tangent, up, radius) = frame(u);
        let side = tangent.cross(up).normalize();
        let normal_axis = side.cross(tangent).normalize();
        for j in 0..sides {
            let v = j as f32 / sides as f32;
            let b = v * TAU;
            let n = normal_axis * b.cos() + side * b.sin();
            mesh.positions.push(centre + n * radius);
            mesh.normals.push(n);
            mesh.uvs.push(Vec2::new(u, v));
        }
    }
    for i in 0..segments {
        for j in 0..sides {
            let a = i * sides + j;
            let b = ((i + 1) % segments) * sides + j;
            let c = ((i + 1) % segments) * sides + (j + 1) % sides;
            let d = i * sides + (j + 1) % sides;
            mesh.indices.extend([a, d, c, a, c, b]);
        }
    }
    mesh
}

/// A flat square in the XZ plane facing +Y (open: a receiver, not a caster).
pub fn ground_plane(size: f32) -> MeshData {
    let h = size * 0.5;
    MeshData {
        positions: vec![Vec3::new(-h, 0.0, -h), Vec3::new(-h, 0.0, h), Vec3::new(h, 0.0, h), Vec3::new(h, 0.0, -h)],
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}
