//! A generated atlas for meshes without usable UVs: charts grown over neighbouring triangles
//! that face nearly the same way, each laid flat on its mean plane, packed on shelves at the
//! largest texel density that fits, with padding between charts.
//!
//! One chart per triangle (the simplest atlas) stops working past a few hundred triangles: the
//! padding alone outgrows the texture. Grown charts keep a smooth 200k-triangle sphere to a
//! few dozen charts.
//!
//! Also whether a UV set can serve as an atlas as it is ([`overlap`]): the same rasterising of
//! triangles onto texel centres.

use glam::{Vec2, Vec3};

use super::fast_hash::u64_map_with_capacity;
use super::weld::weld_by_position;
use super::MeshData;
use crate::error::{Error, Result};

/// A chart takes a triangle whose normal lies within this angle of the chart's first one. Every
/// triangle then faces within 2x this of the chart's mean normal (< 90 degrees), so none flips
/// when the chart is laid flat, and area stretches by at most 1 / cos(2x). A chart that still
/// covers itself (a strip winding around a tube) is grown again with the next, narrower cone,
/// and past the last one split into single triangles.
const CONE_DEGREES: [f32; 3] = [40.0, 20.0, 5.0];

/// Densest packing search: halvings of the texel-density interval.
const DENSITY_STEPS: u32 = 24;

/// Re-packs after splitting self-covering charts; each round narrows the cone of the charts
/// that still cover themselves, so a few rounds reach single triangles.
const MAX_ROUNDS: usize = CONE_DEGREES.len() + 2;

/// A generated atlas: one UV per corner of `indices` (corners are not shared between charts).
pub struct GeneratedAtlas {
    /// Per corner (3 per triangle, in the mesh's triangle order), its atlas UV in [0, 1].
    pub corner_uvs: Vec<Vec2>,
    pub charts: u32,
    pub padding: u32,
}

/// Charts for `mesh` packed into a `size` x `size` texture with `padding` texels around each
/// (fewer when that many charts cannot fit with it). Fails, naming `mesh_name`, only when the
/// charts cannot fit even at one texel each.
pub fn generate(mesh_name: &str, mesh: &MeshData, size: u32, padding: u32) -> Result<GeneratedAtlas> {
    let grower = ChartGrower::new(mesh_name, mesh)?;
    let all: Vec<u32> =
        (0..grower.normals.len() as u32).filter(|&f| grower.normals[f as usize] != Vec3::ZERO).collect();
    // Each chart with the index of the cone it was grown with (past the last: one triangle).
    let mut charts: Vec<(Vec<u32>, usize)> = grower.grow(&all, CONE_DEGREES[0]).into_iter().map(|c| (c, 0)).collect();
    for _ in 0..MAX_ROUNDS {
        let flat: Vec<FlatChart> = charts.iter().map(|(faces, _)| FlatChart::new(mesh, faces)).collect();
        let Some((packing, used_padding)) = pack_with_fewest_losses(&flat, size, padding) else {
            return Err(Error::Mesh {
                mesh: mesh_name.to_owned(),
                problem: format!(
                    "{} atlas charts do not fit a {size}x{size} shadow texture even at one texel each; \
                     raise --shadow-texture-size",
                    flat.len()
                ),
            });
        };
        let mut corner_uvs = vec![Vec2::ZERO; mesh.indices.len()];
        for (((faces, _), chart), origin) in charts.iter().zip(&flat).zip(&packing.origins) {
            for (f, corners) in faces.iter().zip(&chart.corners) {
                for k in 0..3 {
                    let texel = *origin + corners[k] * packing.density;
                    corner_uvs[*f as usize * 3 + k] = texel / size as f32;
                }
            }
        }
        let covering_themselves = self_covering_charts(&charts, &corner_uvs, size);
        if covering_themselves.is_empty() {
            return Ok(GeneratedAtlas { corner_uvs, charts: charts.len() as u32, padding: used_padding });
        }
        let mut next = Vec::with_capacity(charts.len());
        for (i, (faces, cone)) in charts.into_iter().enumerate() {
            if covering_themselves.binary_search(&i).is_err() {
                next.push((faces, cone));
            } else if let Some(&degrees) = CONE_DEGREES.get(cone + 1) {
                next.extend(grower.grow(&faces, degrees).into_iter().map(|c| (c, cone + 1)));
            } else {
                next.extend(faces.into_iter().map(|f| (vec![f], CONE_DEGREES.len())));
            }
        }
        charts = next;
    }
    Err(Error::Mesh {
        mesh: mesh_name.to_owned(),
        problem: format!("no generated atlas without overlapping charts after {MAX_ROUNDS} rounds"),
    })
}

/// Why a UV set cannot be an atlas: texels outside [0, 1], or texel centres covered by more
/// than one triangle (shared edges excluded). `None`: it can.
pub fn overlap(uvs: &[Vec2], indices: &[u32], size: u32) -> Option<String> {
    if uvs.iter().any(|uv| !(uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all() && uv.is_finite())) {
        return Some("UVs outside [0, 1]".into());
    }
    let mut hits = vec![0u8; (size * size) as usize];
    let mut covered = 0usize;
    let mut doubled = 0usize;
    for t in indices.chunks_exact(3) {
        let corners = [0, 1, 2].map(|k| uvs.get(t[k] as usize).copied().unwrap_or_default() * size as f32);
        for_each_covered_texel(corners, size, |texel| {
            let h = &mut hits[texel];
            match *h {
                0 => covered += 1,
                1 => doubled += 1,
                _ => {}
            }
            *h = h.saturating_add(1);
        });
    }
    // A few texels along shared edges may count twice by rounding; a real overlap is larger.
    (doubled > covered / 1000).then(|| format!("{doubled} of {covered} covered texels are covered twice"))
}

/// Indices (ascending) of the charts with texels that two of their own triangles cover. Texel
/// centres on a shared edge count for neither triangle, so a shared edge is no overlap.
fn self_covering_charts(charts: &[(Vec<u32>, usize)], corner_uvs: &[Vec2], size: u32) -> Vec<usize> {
    let mut covered = vec![false; (size * size) as usize];
    let mut found = Vec::new();
    for (i, (faces, _)) in charts.iter().enumerate() {
        let mut doubled = false;
        for &f in faces {
            let t = [0, 1, 2].map(|k| corner_uvs[f as usize * 3 + k] * size as f32);
            for_each_covered_texel(t, size, |texel| {
                doubled |= std::mem::replace(&mut covered[texel], true);
            });
        }
        if doubled {
            found.push(i);
        }
    }
    found
}

/// Calls `visit` with the index of every texel whose centre lies strictly inside triangle `t`
/// (in texels).
pub fn for_each_covered_texel([a, b, c]: [Vec2; 3], size: u32, mut visit: impl FnMut(usize)) {
    let area = (b - a).perp_dot(c - a);
    if area.abs() < 1e-12 {
        return;
    }
    let lo = a.min(b).min(c).floor().max(Vec2::ZERO);
    let hi = a.max(b).max(c).ceil().min(Vec2::splat(size as f32));
    for y in lo.y as u32..hi.y as u32 {
        for x in lo.x as u32..hi.x as u32 {
            let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let w = [(c - b).perp_dot(p - b), (a - c).perp_dot(p - c), (b - a).perp_dot(p - a)].map(|w| w / area);
            if w.iter().all(|w| *w > 1e-4) {
                visit((y * size + x) as usize);
            }
        }
    }
}

/// Face normals and neighbours (sharing an edge once vertices are welded by position), built
/// once and then grown into charts over any subset of the faces.
struct ChartGrower {
    /// Unit normal per face; zero for a face of zero area (in no chart: it covers no texel,
    /// and its corners keep UV (0, 0)).
    normals: Vec<Vec3>,
    neighbours: Vec<Vec<u32>>,
    /// 0 for a face, k for the k-th repeat of the same three (welded) vertices: a doubled
    /// surface laid flat would cover itself, so repeats never share a chart with the original.
    layer: Vec<u32>,
}

impl ChartGrower {
    fn new(mesh_name: &str, mesh: &MeshData) -> Result<ChartGrower> {
        let faces = mesh.indices.len() / 3;
        let welded = weld_by_position(mesh_name, &mesh.positions, &mesh.indices, 0.0)?;
        let normals: Vec<Vec3> = mesh
            .indices
            .chunks_exact(3)
            .map(|t| {
                let p = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
                (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
            })
            .collect();
        let edge_key = |a: u32, b: u32| (a.min(b) as u64) << 32 | a.max(b) as u64;
        let mut edge_faces = u64_map_with_capacity::<Vec<u32>>(welded.indices.len());
        let mut layer = vec![0u32; faces];
        let mut seen = std::collections::HashMap::with_capacity(welded.face_count());
        for (t, &face) in welded.indices.chunks_exact(3).zip(&welded.original_faces) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                edge_faces.entry(edge_key(a, b)).or_default().push(face);
            }
            let mut key = [t[0], t[1], t[2]];
            key.sort_unstable();
            let repeats = seen.entry(key).or_insert(0u32);
            layer[face as usize] = *repeats;
            *repeats += 1;
        }
        let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); faces];
        for users in edge_faces.values() {
            for &f in users {
                neighbours[f as usize].extend(users.iter().filter(|&&g| g != f));
            }
        }
        Ok(ChartGrower { normals, neighbours, layer })
    }

    /// `faces` (none of zero area) grouped into charts: a face joins the chart of a neighbour
    /// in `faces` when its normal is within `cone_degrees` of the chart's first face.
    fn grow(&self, faces: &[u32], cone_degrees: f32) -> Vec<Vec<u32>> {
        const OUTSIDE: u32 = u32::MAX - 1;
        const UNASSIGNED: u32 = u32::MAX;
        let cone_cos = cone_degrees.to_radians().cos();
        let mut chart_of: std::collections::HashMap<u32, u32> = faces.iter().map(|&f| (f, UNASSIGNED)).collect();
        let mut charts = Vec::new();
        let mut stack = Vec::new();
        for &seed in faces {
            if chart_of.get(&seed) != Some(&UNASSIGNED) {
                continue;
            }
            let chart = charts.len() as u32;
            let (axis, layer) = (self.normals[seed as usize], self.layer[seed as usize]);
            let mut members = vec![seed];
            chart_of.insert(seed, chart);
            stack.push(seed);
            while let Some(f) = stack.pop() {
                for &g in &self.neighbours[f as usize] {
                    let state = chart_of.get(&g).copied().unwrap_or(OUTSIDE);
                    let g_index = g as usize;
                    if state == UNASSIGNED
                        && self.layer[g_index] == layer
                        && self.normals[g_index].dot(axis) >= cone_cos
                    {
                        chart_of.insert(g, chart);
                        members.push(g);
                        stack.push(g);
                    }
                }
            }
            charts.push(members);
        }
        charts
    }
}

/// A chart laid flat on its mean plane: per face, its corners in world units from the chart's
/// lower-left, the long side along x.
struct FlatChart {
    corners: Vec<[Vec2; 3]>,
    extent: Vec2,
}

impl FlatChart {
    fn new(mesh: &MeshData, faces: &[u32]) -> FlatChart {
        let triangle = |f: u32| [0, 1, 2].map(|k| mesh.positions[mesh.indices[f as usize * 3 + k] as usize]);
        // Area-weighted mean normal.
        let normal = faces
            .iter()
            .map(|&f| {
                let p = triangle(f);
                (p[1] - p[0]).cross(p[2] - p[0])
            })
            .sum::<Vec3>()
            .normalize_or(Vec3::Z);
        let (u, v) = normal.any_orthonormal_pair();
        let flat: Vec<[Vec2; 3]> = faces.iter().map(|&f| triangle(f).map(|p| Vec2::new(p.dot(u), p.dot(v)))).collect();
        // Principal axis of the corners, so that long thin charts get a tight rectangle.
        let points = || flat.iter().flatten();
        let count = (flat.len() * 3) as f32;
        let mean = points().sum::<Vec2>() / count;
        let (mut xx, mut yy, mut xy) = (0.0, 0.0, 0.0);
        for p in points() {
            let d = *p - mean;
            xx += d.x * d.x;
            yy += d.y * d.y;
            xy += d.x * d.y;
        }
        let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
        let rotate = Vec2::from_angle(-angle);
        let rotated: Vec<[Vec2; 3]> = flat.iter().map(|t| t.map(|p| rotate.rotate(p - mean))).collect();
        let lo = rotated.iter().flatten().fold(Vec2::splat(f32::INFINITY), |a, p| a.min(*p));
        let hi = rotated.iter().flatten().fold(Vec2::splat(f32::NEG_INFINITY), |a, p| a.max(*p));
        let corners = rotated.iter().map(|t| t.map(|p| p - lo)).collect();
        FlatChart { corners, extent: (hi - lo).max(Vec2::ZERO) }
    }
}

/// Where each chart's lower-left lands, in texels, at `density` texels per world unit.
struct Packing {
    origins: Vec<Vec2>,
    density: f32,
}

/// The densest packing with `padding`, else with less padding (down to 1 texel).
fn pack_with_fewest_losses(charts: &[FlatChart], size: u32, padding: u32) -> Option<(Packing, u32)> {
    let mut padding = padding.max(1);
    loop {
        if let Some(packing) = densest_packing(charts, size, padding) {
            return Some((packing, padding));
        }
        if padding == 1 {
            return None;
        }
        padding /= 2;
    }
}

fn densest_packing(charts: &[FlatChart], size: u32, padding: u32) -> Option<Packing> {
    // Cannot be denser than the largest chart across the texture, nor than all chart area
    // covering it.
    let longest = charts.iter().map(|c| c.extent.max_element()).fold(0.0f32, f32::max);
    let area: f32 = charts.iter().map(|c| c.extent.x * c.extent.y).sum();
    let mut high = size as f32 / longest.max(f32::MIN_POSITIVE);
    if area > 0.0 {
        high = high.min(size as f32 / area.sqrt());
    }
    let mut best = shelf_pack(charts, size, padding, 0.0)?;
    let mut low = 0.0;
    for _ in 0..DENSITY_STEPS {
        let mid = 0.5 * (low + high);
        match shelf_pack(charts, size, padding, mid) {
            Some(packing) => {
                low = mid;
                best = packing;
            }
            None => high = mid,
        }
    }
    Some(best)
}

/// Shelf packing, tallest charts first; `None` when the shelves overflow the texture.
fn shelf_pack(charts: &[FlatChart], size: u32, padding: u32, density: f32) -> Option<Packing> {
    // Texels a chart spans, at least one, plus padding on every side.
    let cell = |c: &FlatChart| {
        let texels = (c.extent * density).ceil().max(Vec2::ONE);
        (texels.x as u32 + 2 * padding, texels.y as u32 + 2 * padding)
    };
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(cell(&charts[i]).1));
    let mut origins = vec![Vec2::ZERO; charts.len()];
    let (mut x, mut y, mut shelf) = (0u32, 0u32, 0u32);
    for i in order {
        let (w, h) = cell(&charts[i]);
        if w > size {
            return None;
        }
        if x + w > size {
            (x, y, shelf) = (0, y + shelf, 0);
        }
        if y + h > size {
            return None;
        }
        origins[i] = Vec2::new((x + padding) as f32, (y + padding) as f32);
        x += w;
        shelf = shelf.max(h);
    }
    Some(Packing { origins, density })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    fn sequential(corners: usize) -> Vec<u32> {
        (0..corners as u32).collect()
    }

    #[test]
    fn a_knot_needs_narrower_charts_only_where_a_strip_covers_itself() {
        let mut knot = shapes::torus_knot(2, 3, 0.6, 0.18, 256, 16).expect("knot");
        knot.uvs.clear();
        let atlas = generate("knot", &knot, 256, 4).expect("atlas");
        assert_eq!(atlas.padding, 4);
        assert!(atlas.charts < 400, "{} charts", atlas.charts);
        assert_eq!(overlap(&atlas.corner_uvs, &sequential(atlas.corner_uvs.len()), 256), None);
    }

    #[test]
    fn a_doubled_surface_is_laid_out_twice() {
        // Every triangle of a cube repeated: each copy gets charts of its own.
        let mut cube = shapes::cube(1.0);
        let twins = cube.indices.clone();
        cube.indices.extend(twins);
        let atlas = generate("doubled", &cube, 128, 4).expect("atlas");
        assert_eq!(atlas.charts, 12);
        assert_eq!(overlap(&atlas.corner_uvs, &sequential(atlas.corner_uvs.len()), 128), None);
    }

    #[test]
    fn a_cube_has_one_chart_per_face() {
        let atlas = generate("cube", &shapes::cube(1.0), 128, 4).expect("atlas");
        assert_eq!((atlas.charts, atlas.padding), (6, 4));
    }

    #[test]
    fn a_dense_sphere_has_few_charts_and_no_overlap() {
        // 2 x 160 x 160 triangles: far more than one chart per triangle can fit in 256^2.
        let sphere = shapes::uv_sphere(160, 160).expect("sphere");
        let atlas = generate("sphere", &sphere, 256, 4).expect("atlas");
        assert!(atlas.charts < 100, "{} charts", atlas.charts);
        assert_eq!(atlas.padding, 4);
        assert_eq!(overlap(&atlas.corner_uvs, &sequential(atlas.corner_uvs.len()), 256), None);
        // Texel density: most of the texture is used.
        let covered: f32 =
            atlas.corner_uvs.chunks_exact(3).map(|t| 0.5 * (t[1] - t[0]).perp_dot(t[2] - t[0]).abs()).sum();
        assert!(covered > 0.3, "charts cover {:.0}% of the texture", covered * 100.0);
    }

    #[test]
    fn scattered_triangles_lose_padding_before_failing() {
        // 5,000 separate triangles: 5,000 charts. With 4 texels of padding they cannot fit in
        // 512^2 (each cell >= 9x9 texels: 405,000 texels), with 2 they can (5x5: 125,000).
        let mut mesh = MeshData::default();
        for i in 0..5000u32 {
            let o = Vec3::new((i % 100) as f32 * 3.0, 0.0, (i / 100) as f32 * 3.0);
            let base = mesh.positions.len() as u32;
            mesh.positions.extend([o, o + Vec3::X, o + Vec3::Z]);
            mesh.normals.extend([Vec3::Y; 3]);
            mesh.indices.extend([base, base + 2, base + 1]);
        }
        let atlas = generate("confetti", &mesh, 512, 4).expect("atlas");
        assert_eq!((atlas.charts, atlas.padding), (5000, 2));
        let error = generate("confetti", &mesh, 64, 4).err().expect("cannot fit").to_string();
        assert!(error.contains("confetti") && error.contains("5000 atlas charts"), "{error}");
    }
}
