//! The surface point of every texel of a geometry image's shadow texture: what the rasterised
//! bake interpolates at each texel centre, computed once on the CPU so that the texel bake reads
//! it instead of rasterising eight sub-texel triangles per texel (seed 004: in a geometry image
//! each texel *is* a surface point).

use glam::{DVec2, Vec3, Vec4};

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

    #[test]
    fn a_mesh_that_leaves_texels_uncovered_keeps_the_rasterised_bake() {
        let cube = crate::mesh::shapes::cube(1.0);
        let atlas = mesh_atlas("cube", &cube, None, 64).expect("atlas");
        assert!(texel_surface(&atlas).is_none(), "generated charts leave gutters");
    }
}
