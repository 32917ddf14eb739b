//! Geometry images: closed surfaces sampled on an n x n grid (Gu, Gortler and Hoppe 2002). The
//! grid is the octahedral parameterisation of the sphere, pushed out to `radius(direction)`:
//! the square's border folds onto itself (each border edge meets its mirror half), so the mesh
//! is closed, and the grid coordinate is a unique atlas UV by construction.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::MeshData;
use crate::error::{Error, Result};

/// The unit direction of grid point (u, v) in [-1, 1]^2 (octahedral map, y up).
pub fn octahedral_direction(u: f32, v: f32) -> Vec3 {
    let (mut x, mut z) = (u, v);
    let y = 1.0 - u.abs() - v.abs();
    if y < 0.0 {
        (x, z) = ((1.0 - v.abs()) * u.signum(), (1.0 - u.abs()) * v.signum());
    }
    Vec3::new(x, y, z).normalize()
}

/// An n x n geometry image: n^2 vertices, 2 (n - 1)^2 triangles, wound counter-clockwise seen
/// from outside, vertex normals averaged across the folded border. `uvs` are the grid
/// coordinates i / (n - 1), j / (n - 1).
pub fn geometry_image(n: u32, radius: impl Fn(Vec3) -> f32) -> Result<MeshData> {
    if !(3..=1025).contains(&n) {
        return Err(Error::InvalidInput(format!("geometry image of {n}x{n}: use 3..=1025 vertices a side")));
    }
    let last = (n - 1) as f32;
    let mut positions = Vec::with_capacity((n * n) as usize);
    let mut uvs = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let uv = Vec2::new(i as f32 / last, j as f32 / last);
            let d = octahedral_direction(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0);
            positions.push(d * radius(d));
            uvs.push(uv);
        }
    }
    let mut indices = Vec::with_capacity(((n - 1) * (n - 1) * 6) as usize);
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = j * n + i;
            let (b, c, d) = (a + 1, a + n + 1, a + n);
            // Split each quad along the diagonal that does not cross the octahedron's folds.
            let (u, v) = (i as f32 / last * 2.0 - 1.0, j as f32 / last * 2.0 - 1.0);
            // In the quadrants where u and v have one sign the folds run along b-d.
            if (u + 0.5 / last).signum() == (v + 0.5 / last).signum() {
                indices.extend_from_slice(&[a, b, d, b, c, d]);
            } else {
                indices.extend_from_slice(&[a, b, c, a, c, d]);
            }
        }
    }
    // Outward winding: the enclosed volume is positive.
    let volume: f32 = indices
        .chunks_exact(3)
        .map(|t| positions[t[0] as usize].dot(positions[t[1] as usize].cross(positions[t[2] as usize])))
        .sum();
    if volume < 0.0 {
        for t in indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
    let normals = welded_normals(&positions, &indices);
    Ok(MeshData { positions, normals, uvs, indices })
}

/// Area-weighted vertex normals, shared by vertices at the same position (the folded border).
fn welded_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let key = |p: Vec3| ((p.x * 1e5).round() as i64, (p.y * 1e5).round() as i64, (p.z * 1e5).round() as i64);
    let mut sums: HashMap<(i64, i64, i64), Vec3> = HashMap::new();
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let n = (b - a).cross(c - a);
        for p in [a, b, c] {
            *sums.entry(key(p)).or_insert(Vec3::ZERO) += n;
        }
    }
    positions.iter().map(|p| sums.get(&key(*p)).copied().unwrap_or(Vec3::Y).normalize_or(Vec3::Y)).collect()
}

/// The grid size n when `mesh` is an n x n geometry image (its UVs are the grid coordinates).
pub fn grid_size(mesh: &MeshData) -> Option<u32> {
    let count = mesh.positions.len();
    let n = (count as f64).sqrt().round() as usize;
    if n < 3 || n * n != count || mesh.uvs.len() != count || mesh.indices.len() != (n - 1) * (n - 1) * 6 {
        return None;
    }
    let last = (n - 1) as f32;
    let on_grid = mesh.uvs.iter().enumerate().all(|(k, uv)| {
        let expected = Vec2::new((k % n) as f32 / last, (k / n) as f32 / last);
        (*uv - expected).abs().max_element() < 1e-6
    });
    on_grid.then_some(n as u32)
}

/// A sphere with horns: `horns` (unit direction, height) raise smooth spikes whose flanks and
/// bases shadow the body between them (a concave, self-shadowing surface).
pub fn horned_radius(horns: &[(Vec3, f32)]) -> impl Fn(Vec3) -> f32 + '_ {
    move |d| {
        1.0 + horns
            .iter()
            .map(|(axis, height)| {
                let t = ((d.dot(axis.normalize()) - 0.88) / 0.12).max(0.0);
                height * t * t
            })
            .sum::<f32>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{weld_by_position, EdgeAdjacency};

    #[test]
    fn paper_sizes_and_closed() {
        let big = geometry_image(257, |_| 1.0).expect("257");
        assert_eq!((big.positions.len(), big.face_count()), (66_049, 131_072));
        let small = geometry_image(64, horned_radius(&[(Vec3::Y, 0.8)])).expect("64");
        assert_eq!((small.positions.len(), small.face_count()), (4_096, 7_938));
        assert_eq!(grid_size(&small), Some(64));
        let welded = weld_by_position("gi", &small.positions, &small.indices, 1e-5).expect("weld");
        let adjacency = EdgeAdjacency::build("gi", &welded.positions, &welded.indices).expect("adjacency");
        adjacency.require_closed_manifold().expect("a geometry image is closed");
    }
}
