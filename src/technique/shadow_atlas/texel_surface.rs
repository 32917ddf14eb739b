//! The surface point of every texel of a shadow texture whose atlas covers every texel centre (a
//! geometry image, a quad mapped whole onto its square): what the rasterised
//! bake interpolates at each texel centre, computed once on the CPU so that the texel bake reads
//! it instead of rasterising eight sub-texel triangles per texel (seed 004: in a geometry image
//! each texel *is* a surface point).

use glam::{DVec2, Vec2, Vec3, Vec4};

use super::atlas::MeshAtlas;

/// Per texel of a `size` x `size` tile, row by row from the top (texel y = 0 is atlas v = 0):
/// the object-space position (w = 1) and normal (w = 0) the triangle covering the texel centre
/// interpolates there, as the rasteriser's barycentrics would. `None` when some texel centre
/// lies in no triangle: the mesh then keeps the rasterised bake (and its dilation).
pub fn texel_surface(atlas: &MeshAtlas) -> Option<Vec<[Vec4; 2]>> {
    let size = atlas.size as usize;
    let mut texels: Vec<Option<[Vec4; 2]>> = vec![None; size * size];
    let at = |k: u32| DVec2::new(f64::from(atlas.uvs[k as usize].x), f64::from(atlas.uvs[k as usize].y)) * size as f64;
    for triangle in atlas.indices.chunks_exact(3) {
        let [a, b, c] = [at(triangle[0]), at(triangle[1]), at(triangle[2])];
        let area = (b - a).perp_dot(c - a);
        if area.abs() < 1e-12 {
            continue;
        }
        let lo = a.min(b).min(c).floor().max(DVec2::ZERO);
        let hi = a.max(b).max(c).ceil().min(DVec2::splat(size as f64));
        for y in lo.y as usize..hi.y as usize {
            for x in lo.x as usize..hi.x as usize {
                if texels[y * size + x].is_some() {
                    continue;
                }
                let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let wa = (c - b).perp_dot(p - b) / area;
                let wb = (a - c).perp_dot(p - c) / area;
                let wc = 1.0 - wa - wb;
                // Centres on a shared edge belong to either triangle: both interpolate the same
                // value there.
                if wa < -1e-9 || wb < -1e-9 || wc < -1e-9 {
                    continue;
                }
                let mix = |list: &[Vec3]| {
                    let v = |k: u32| list.get(k as usize).copied().unwrap_or(Vec3::Y).as_dvec3();
                    (v(triangle[0]) * wa + v(triangle[1]) * wb + v(triangle[2]) * wc).as_vec3()
                };
                texels[y * size + x] = Some([mix(&atlas.positions).extend(1.0), mix(&atlas.normals).extend(0.0)]);
            }
        }
    }
    texels.into_iter().collect()
}

/// One texel's surface point as the page pass reads it (`shaders/atlas_page_tiles.glsl`): the
/// object-space position's bits in x, y, z and the normal's direction in w, octahedral, two
/// 16-bit snorms (`unpackSnorm2x16`). One 16-byte read a texel, where position and normal
/// apart were two: on a software rasteriser each is a gather per lane. The direction is kept
/// to 1/32767 of the octahedron's side, about 0.003 degrees.
pub fn packed([position, normal]: [Vec4; 2]) -> [u32; 4] {
    let p = position.truncate();
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits(), pack_snorm2x16(octahedral(normal.truncate()))]
}

/// `n`'s direction on the octahedron folded into [-1, 1]^2 (+z up: the upper half unfolded,
/// the lower folded over the diagonals). A zero vector maps to +z.
fn octahedral(n: Vec3) -> Vec2 {
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if l1 <= f32::MIN_POSITIVE {
        return Vec2::ZERO;
    }
    let n = n / l1;
    if n.z >= 0.0 {
        return n.truncate();
    }
    let sign = |v: f32| if v >= 0.0 { 1.0 } else { -1.0 };
    Vec2::new((1.0 - n.y.abs()) * sign(n.x), (1.0 - n.x.abs()) * sign(n.y))
}

/// GLSL's `packSnorm2x16`: x in the low half.
fn pack_snorm2x16(v: Vec2) -> u32 {
    let snorm = |c: f32| u32::from((c.clamp(-1.0, 1.0) * 32767.0).round() as i16 as u16);
    snorm(v.x) | (snorm(v.y) << 16)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::geometry_image::{geometry_image, grid_size};
    use crate::technique::shadow_atlas::atlas::mesh_atlas;

    #[test]
    fn every_texel_of_a_geometry_image_lies_on_its_surface() {
        let mesh = geometry_image(17, |_| 1.0).expect("sphere");
        assert_eq!(grid_size(&mesh), Some(17));
        let atlas = mesh_atlas("sphere", &mesh, None, 64).expect("atlas");
        assert_eq!(atlas.size, 16);
        let texels = texel_surface(&atlas).expect("a geometry image covers its square");
        assert_eq!(texels.len(), 16 * 16);
        for [position, normal] in &texels {
            // Inside the unit sphere, no deeper than a flat facet of a 16-segment octahedral grid.
            let r = position.truncate().length();
            assert!((0.9..=1.0 + 1e-6).contains(&r), "radius {r}");
            assert!(normal.truncate().normalize().dot(position.truncate().normalize()) > 0.95);
            assert_eq!((position.w, normal.w), (1.0, 0.0));
        }
        // Texel (3, 5)'s centre is grid point (3.5 * 16 / 16, 5.5): between grid points 3..4 and
        // 5..6; its position lies within that grid cell's corners' bounds.
        let corner = |i: usize, j: usize| atlas.positions[j * 17 + i];
        let p = texels[5 * 16 + 3][0].truncate();
        let (lo, hi) = [corner(3, 5), corner(4, 5), corner(3, 6), corner(4, 6)]
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), c| (lo.min(*c), hi.max(*c)));
        assert!(p.cmpge(lo - 1e-6).all() && p.cmple(hi + 1e-6).all(), "{p} outside {lo}..{hi}");
    }

    /// The shader's decoding (`atlas_page_tiles.glsl`), on the CPU.
    fn unpacked(texel: [u32; 4]) -> (Vec3, Vec3) {
        let position = Vec3::new(f32::from_bits(texel[0]), f32::from_bits(texel[1]), f32::from_bits(texel[2]));
        let snorm = |bits: u32| (f32::from(bits as u16 as i16) / 32767.0).max(-1.0);
        let e = Vec2::new(snorm(texel[3]), snorm(texel[3] >> 16));
        let mut n = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
        let t = (-n.z).max(0.0);
        n.x += if n.x >= 0.0 { -t } else { t };
        n.y += if n.y >= 0.0 { -t } else { t };
        (position, n.normalize())
    }

    #[test]
    fn a_packed_texel_keeps_its_position_exactly_and_its_normal_to_a_few_thousandths_of_a_degree() {
        let mut worst: f64 = 0.0;
        for k in 0..2000 {
            // Directions all over the sphere (a Fibonacci spiral), unnormalised as interpolated
            // normals are, and the six axes (fold edges and corners).
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / 2000.0;
            let a = k as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            let n = Vec3::new(r * a.cos(), r * a.sin(), z) * (0.5 + (k % 7) as f32 * 0.3);
            let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
            for normal in [n, axes[k % 6]] {
                let position = Vec4::new(k as f32 * 0.37 - 3.0, -1.0e-7, 12345.678, 1.0);
                let (p, m) = unpacked(packed([position, normal.extend(0.0)]));
                assert_eq!(p, position.truncate());
                // In f64 (atan2 of sine and cosine): an f32 acos alone errs by 0.02 degrees.
                let (a, b) = (m.as_dvec3(), normal.as_dvec3().normalize());
                worst = worst.max(a.cross(b).length().atan2(a.dot(b)).to_degrees());
            }
        }
        assert!(worst < 0.005, "worst normal error {worst} degrees");
    }

    #[test]
    fn a_quad_mapped_whole_has_a_surface_point_at_every_texel() {
        let quad = crate::mesh::shapes::quad(Vec3::ZERO, Vec3::Y, glam::Vec2::splat(4.0));
        let atlas = mesh_atlas("ground", &quad, None, 32).expect("atlas");
        assert!(matches!(atlas.source, crate::technique::shadow_atlas::atlas::AtlasSource::TexCoord0));
        let texels = texel_surface(&atlas).expect("the quad's UVs cover its square");
        assert_eq!(texels.len(), 32 * 32);
        // Texel centres are 4/32 apart on a 4 x 4 quad in the y = 0 plane, all facing up.
        let xs: Vec<f32> = texels.iter().map(|[p, _]| p.x).collect();
        let (lo, hi) = xs.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        assert!((lo + 2.0 - 0.0625).abs() < 1e-5 && (hi - 2.0 + 0.0625).abs() < 1e-5, "{lo}..{hi}");
        assert!(texels.iter().all(|[p, n]| p.y.abs() < 1e-6 && (n.truncate() - Vec3::Y).length() < 1e-6));
    }

    #[test]
    fn a_mesh_that_leaves_texels_uncovered_keeps_the_rasterised_bake() {
        let cube = crate::mesh::shapes::cube(1.0);
        let atlas = mesh_atlas("cube", &cube, None, 64).expect("atlas");
        assert!(texel_surface(&atlas).is_none(), "generated charts leave gutters");
    }
}
