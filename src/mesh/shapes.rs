//! Test meshes with known answers: a cube, a UV sphere, a torus, a torus knot (closed), and a
//! one-sided quad (open).
//!
//! All are wound counter-clockwise seen from outside (right-hand normals point out), carry
//! per-vertex normals and UVs, and duplicate vertices the way exporters do: the cube per face,
//! the others along their UV seams and, for the sphere, at the poles. Seam twins have bit-equal
//! positions, so [`weld_by_position`](super::weld::weld_by_position) with any epsilon (even 0)
//! makes each of them a closed manifold.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use crate::error::{Error, Result};

/// An indexed triangle mesh with per-vertex attributes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub indices: Vec<u32>,
}

impl MeshData {
    pub fn face_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// A one-sided quad centred on `centre`, facing `normal` (wound counter-clockwise seen from
/// that side), `size` along its two in-plane axes; the first axis is horizontal.
pub fn quad(centre: Vec3, normal: Vec3, size: Vec2) -> MeshData {
    let normal = normal.normalize();
    let u = Vec3::Y.cross(normal).normalize_or(Vec3::X);
    let v = normal.cross(u);
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    MeshData {
        positions: corners.iter().map(|&(a, b)| centre + u * (a * 0.5 * size.x) + v * (b * 0.5 * size.y)).collect(),
        normals: vec![normal; 4],
        uvs: corners.iter().map(|&(a, b)| Vec2::new(0.5 + 0.5 * a, 0.5 - 0.5 * b)).collect(),
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// An axis-aligned cube of edge `size` centred on the origin: 24 vertices (4 per face, so that
/// each face has its own normal), 12 triangles.
pub fn cube(size: f32) -> MeshData {
    let half = 0.5 * size;
    // (outward normal, first in-face axis); the second axis is normal x first, so that the
    // quad (-u-v, +u-v, +u+v, -u+v) runs counter-clockwise seen from outside.
    let faces = [
        (Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_X, Vec3::Z),
        (Vec3::Y, Vec3::X),
        (Vec3::NEG_Y, Vec3::X),
        (Vec3::Z, Vec3::X),
        (Vec3::NEG_Z, Vec3::NEG_X),
    ];
    let mut mesh = MeshData::default();
    for (normal, u) in faces {
        let v = normal.cross(u);
        let base = mesh.positions.len() as u32;
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            mesh.positions.push((normal + u * su + v * sv) * half);
            mesh.normals.push(normal);
            mesh.uvs.push(Vec2::new(0.5 + 0.5 * su, 0.5 - 0.5 * sv));
        }
        mesh.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    mesh
}

/// A unit sphere with poles on +-Y: `rings` latitude bands (>= 2) of `segments` quads (>= 3).
/// The seam column (u = 1) and each pole are duplicated per segment, as exporters do; after
/// welding it has `(rings - 1) * segments + 2` vertices and `2 * segments * (rings - 1)` faces.
pub fn uv_sphere(rings: u32, segments: u32) -> Result<MeshData> {
    at_least("uv_sphere", "rings", rings, 2)?;
    at_least("uv_sphere", "segments", segments, 3)?;
    Ok(grid_surface(rings, segments, |ring, segment| {
        let position = if ring == 0 {
            Vec3::Y
        } else if ring == rings {
            Vec3::NEG_Y
        } else {
            let theta = PI * ring as f32 / rings as f32;
            let phi = TAU * (segment % segments) as f32 / segments as f32;
            Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin())
        };
        (position, position)
    }))
}

/// A ring torus around the Y axis: tube centre at distance `major_radius` from the axis, tube
/// radius `minor_radius` (0 < minor < major). Genus 1, so V - E + F = 0 once welded.
pub fn torus(major_radius: f32, minor_radius: f32, major_segments: u32, minor_segments: u32) -> Result<MeshData> {
    at_least("torus", "major_segments", major_segments, 3)?;
    at_least("torus", "minor_segments", minor_segments, 3)?;
    if !(minor_radius > 0.0 && minor_radius < major_radius && major_radius.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "torus: need 0 < minor_radius < major_radius (got {minor_radius}, {major_radius})"
        )));
    }
    Ok(grid_surface(major_segments, minor_segments, |major, minor| {
        let u = TAU * (major % major_segments) as f32 / major_segments as f32;
        let v = TAU * (minor % minor_segments) as f32 / minor_segments as f32;
        let radial = Vec3::new(u.cos(), 0.0, u.sin());
        let normal = radial * v.cos() + Vec3::Y * v.sin();
        (radial * major_radius + normal * minor_radius, normal)
    }))
}

/// A tube of radius `tube_radius` around the (p, q) torus knot, which winds `p` times around
/// the Y axis and `q` times through the hole (p, q >= 1, coprime; (2, 3) is the trefoil).
/// `radius` is the knot's outer radius. The tube must be thin enough not to hit itself: for
/// the trefoil, strands come within 0.55 * radius of each other and bend no tighter than
/// 0.47 * radius, so a tube radius below 0.27 * radius stays clear.
pub fn torus_knot(p: u32, q: u32, radius: f32, tube_radius: f32, segments: u32, sides: u32) -> Result<MeshData> {
    at_least("torus_knot", "p", p, 1)?;
    at_least("torus_knot", "q", q, 1)?;
    at_least("torus_knot", "segments", segments, 3)?;
    at_least("torus_knot", "sides", sides, 3)?;
    if greatest_common_divisor(p, q) != 1 {
        return Err(Error::InvalidInput(format!(
            "torus_knot: p and q must be coprime (got {p}, {q}); otherwise the curve retraces itself"
        )));
    }
    if !(tube_radius > 0.0 && tube_radius < radius && radius.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "torus_knot: need 0 < tube_radius < radius (got {tube_radius}, {radius})"
        )));
    }
    let (p, q) = (p as f32, q as f32);
    let a = radius / 3.0;
    Ok(grid_surface(segments, sides, |along, around| {
        let phi = TAU * (along % segments) as f32 / segments as f32;
        let (sin_p, cos_p) = (p * phi).sin_cos();
        let (sin_q, cos_q) = (q * phi).sin_cos();
        // Curve: distance from the Y axis a(2 + cos q.phi), height -a sin q.phi.
        let rho = a * (2.0 + cos_q);
        let centre = Vec3::new(rho * cos_p, -a * sin_q, rho * sin_p);
        let rho_rate = -a * q * sin_q;
        let tangent = Vec3::new(rho_rate * cos_p - rho * p * sin_p, -a * q * cos_q, rho_rate * sin_p + rho * p * cos_p)
            .normalize();
        // A periodic frame that never degenerates: the offset from the torus core circle has no
        // component along the core's direction of travel, which the tangent always has.
        let offset = Vec3::new(cos_q * cos_p, -sin_q, cos_q * sin_p);
        let normal_axis = (offset - tangent * tangent.dot(offset)).normalize();
        let binormal_axis = tangent.cross(normal_axis);
        let theta = TAU * (around % sides) as f32 / sides as f32;
        let normal = normal_axis * theta.cos() + binormal_axis * theta.sin();
        (centre + normal * tube_radius, normal)
    }))
}

/// A (rows + 1) x (cols + 1) vertex grid with uv = (col / cols, row / rows). `sample(row, col)`
/// returns (position, normal); it must be laid out so that d(col) x d(row) points outward,
/// which makes the quad (r, c), (r, c + 1), (r + 1, c + 1), (r + 1, c) counter-clockwise seen
/// from outside. Triangles with two equal positions (at a pole) are left out.
fn grid_surface(rows: u32, cols: u32, sample: impl Fn(u32, u32) -> (Vec3, Vec3)) -> MeshData {
    let vertex_count = ((rows + 1) * (cols + 1)) as usize;
    let mut mesh = MeshData {
        positions: Vec::with_capacity(vertex_count),
        normals: Vec::with_capacity(vertex_count),
        uvs: Vec::with_capacity(vertex_count),
        indices: Vec::with_capacity((rows * cols * 6) as usize),
    };
    for row in 0..=rows {
        for col in 0..=cols {
            let (position, normal) = sample(row, col);
            mesh.positions.push(position);
            mesh.normals.push(normal);
            mesh.uvs.push(Vec2::new(col as f32 / cols as f32, row as f32 / rows as f32));
        }
    }
    let at = |row: u32, col: u32| row * (cols + 1) + col;
    for row in 0..rows {
        for col in 0..cols {
            let quad = [at(row, col), at(row, col + 1), at(row + 1, col + 1), at(row + 1, col)];
            for triangle in [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]] {
                let [a, b, c] = triangle.map(|i| mesh.positions[i as usize]);
                if a != b && b != c && c != a {
                    mesh.indices.extend_from_slice(&triangle);
                }
            }
        }
    }
    mesh
}

fn at_least(shape: &str, name: &str, value: u32, minimum: u32) -> Result<()> {
    if value < minimum {
        return Err(Error::InvalidInput(format!("{shape}: {name} must be at least {minimum} (got {value})")));
    }
    Ok(())
}

fn greatest_common_divisor(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::adjacency::EdgeAdjacency;
    use crate::mesh::weld::weld_by_position;

    /// Signed volume by the divergence theorem: positive iff the winding is CCW-outward.
    fn signed_volume(positions: &[Vec3], indices: &[u32]) -> f32 {
        indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Welds, checks closed manifold, returns the Euler characteristic and the volume.
    fn check_closed(name: &str, mesh: &MeshData) -> Result<(i64, f32)> {
        let welded = weld_by_position(name, &mesh.positions, &mesh.indices, 1e-6)?;
        assert_eq!(welded.dropped_degenerate, 0, "{name}");
        let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
        adjacency.require_closed_manifold()?;
        let (v, e, f) = (welded.positions.len() as i64, adjacency.edges.len() as i64, welded.face_count() as i64);
        assert_eq!(2 * e, 3 * f, "{name}: E = 3F/2 on a closed triangle mesh");
        // Each triangle's winding agrees with its vertices' normals (same hemisphere: the
        // coarsest sphere tilts its faces by 63 degrees from the pole normal).
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
            let face_normal = (b - a).cross(c - a).normalize();
            for &corner in t {
                let dot = face_normal.dot(mesh.normals[corner as usize]);
                assert!(dot > 0.0, "{name}: face normal disagrees ({dot})");
            }
        }
        Ok((v - e + f, signed_volume(&mesh.positions, &mesh.indices)))
    }

    #[test]
    fn cube_is_closed_genus_zero_with_its_volume() -> Result<()> {
        let (euler, volume) = check_closed("cube", &cube(2.0))?;
        assert_eq!(euler, 2);
        assert!((volume - 8.0).abs() < 1e-5, "{volume}");
        Ok(())
    }

    #[test]
    fn uv_sphere_welds_its_seam_and_poles() -> Result<()> {
        for (rings, segments) in [(2, 3), (3, 4), (16, 32)] {
            let sphere = uv_sphere(rings, segments)?;
            let welded = weld_by_position("sphere", &sphere.positions, &sphere.indices, 0.0)?;
            assert!(welded.positions.len() < sphere.positions.len(), "the weld matters");
            assert_eq!(welded.positions.len() as u32, (rings - 1) * segments + 2, "{rings}x{segments}");
            let (euler, volume) = check_closed("sphere", &sphere)?;
            assert_eq!(euler, 2);
            assert!(volume > 0.0 && volume < 4.0 / 3.0 * PI);
        }
        let (_, volume) = check_closed("fine sphere", &uv_sphere(64, 128)?)?;
        assert!((volume - 4.0 / 3.0 * PI).abs() < 0.01 * 4.0, "{volume}");
        Ok(())
    }

    #[test]
    fn torus_is_genus_one() -> Result<()> {
        let (euler, volume) = check_closed("torus", &torus(1.0, 0.25, 64, 32)?)?;
        assert_eq!(euler, 0);
        let exact = 2.0 * PI * PI * 1.0 * 0.25 * 0.25;
        assert!((volume - exact).abs() < 0.01 * exact, "{volume} vs {exact}");
        Ok(())
    }

    #[test]
    fn torus_knot_is_a_closed_tube() -> Result<()> {
        for (p, q) in [(2, 3), (3, 2), (1, 1)] {
            let (euler, volume) = check_closed("knot", &torus_knot(p, q, 1.0, 0.08, 256, 12)?)?;
            assert_eq!(euler, 0, "a tube is a torus topologically");
            assert!(volume > 0.0);
        }
        Ok(())
    }

    #[test]
    fn bad_parameters_are_refused() {
        let errors = [
            uv_sphere(1, 8).map(|_| ()),
            uv_sphere(8, 2).map(|_| ()),
            torus(1.0, 1.5, 8, 8).map(|_| ()),
            torus(1.0, 0.5, 2, 8).map(|_| ()),
            torus_knot(2, 4, 1.0, 0.1, 64, 8).map(|_| ()),
            torus_knot(2, 3, 1.0, f32::NAN, 64, 8).map(|_| ()),
        ];
        for error in errors {
            assert!(matches!(error, Err(Error::InvalidInput(_))), "{error:?}");
        }
    }
}
