//! A conservative occluder map from a light: for each texel of the light's view, a depth by
//! which *every* ray through the texel is already blocked by some triangle, or none.
//!
//! It answers one question exactly: does a box lie wholly behind other geometry, as the light
//! sees it? Lloyd, Wendt, Govindaraju and Manocha's CC Shadow Volumes (EGSR 2004) cull such
//! casters with a GPU shadow map; a sampled map is only right at its samples, so this one is
//! built the other way round: a triangle counts for a texel only where it covers the whole
//! texel (its four corners inside it), at the deepest its plane reaches over the texel (at a
//! corner: the plane is affine in the map's coordinates). A texel no single triangle covers
//! holds no depth, and nothing behind it is called hidden.
//!
//! Depth grows away from the light along every ray: distance along the light for a
//! directional light (an orthographic view), view-space z for a point light (a perspective
//! view, where 1/z is the affine quantity).

use glam::{Vec2, Vec3};

use crate::mesh::fast_hash::{u64_map_with_capacity, U64Map};

/// How the light sees the world.
#[derive(Debug, Clone, Copy)]
enum Projection {
    /// A directional light: map coordinates are world coordinates across the light.
    Orthographic,
    /// A point light at `eye`: map coordinates are (x/z, y/z) in its view.
    Perspective { eye: Vec3 },
}

/// Points closer to a point light than this (in its view's z, relative to the scene's size)
/// are not projected: they may lie beside or behind it.
const NEAR_FRACTION: f32 = 1e-3;

/// A perspective view wider than this (in x/z or y/z) is not worth a map: the light sits among
/// the casters.
const MAX_SLOPE: f32 = 4.0;

/// The light's view: a basis, the projection, and the map's placement in it.
#[derive(Debug, Clone, Copy)]
pub struct LightView {
    projection: Projection,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    /// Smallest z a point light projects (NEAR_FRACTION of the scene's extent).
    near: f32,
}

/// A projected point: map coordinates (before placement) and its depth.
#[derive(Debug, Clone, Copy)]
struct Projected {
    at: Vec2,
    depth: f32,
}

impl LightView {
    /// A directional light travelling along `direction`.
    pub fn directional(direction: Vec3) -> Option<LightView> {
        let forward = direction.try_normalize()?;
        let (right, up) = forward.any_orthonormal_pair();
        Some(LightView { projection: Projection::Orthographic, right, up, forward, near: 0.0 })
    }

    /// A point light at `eye`, looking at `centre` (of a scene `extent` across).
    pub fn point(eye: Vec3, centre: Vec3, extent: f32) -> Option<LightView> {
        let forward = (centre - eye).try_normalize()?;
        let (right, up) = forward.any_orthonormal_pair();
        let near = (extent * NEAR_FRACTION).max(f32::MIN_POSITIVE);
        Some(LightView { projection: Projection::Perspective { eye }, right, up, forward, near })
    }

    /// `p` in the view, `None` for a point a point light cannot project.
    fn project(&self, p: Vec3) -> Option<Projected> {
        match self.projection {
            Projection::Orthographic => {
                Some(Projected { at: Vec2::new(p.dot(self.right), p.dot(self.up)), depth: p.dot(self.forward) })
            }
            Projection::Perspective { eye } => {
                let d = p - eye;
                let z = d.dot(self.forward);
                if z.is_nan() || z <= self.near {
                    return None;
                }
                let at = Vec2::new(d.dot(self.right), d.dot(self.up)) / z;
                (at.abs().max_element() <= MAX_SLOPE).then_some(Projected { at, depth: z })
            }
        }
    }

    /// The quantity affine in map coordinates over a triangle's plane: depth itself
    /// (orthographic), or 1/z (perspective).
    fn affine(&self, depth: f32) -> f32 {
        match self.projection {
            Projection::Orthographic => depth,
            Projection::Perspective { .. } => 1.0 / depth,
        }
    }

    /// The deepest point of a plane over a texel, from its affine quantity at the corners.
    fn deepest(&self, affine_at_corners: [f32; 4]) -> f32 {
        match self.projection {
            Projection::Orthographic => affine_at_corners.into_iter().fold(f32::MIN, f32::max),
            Projection::Perspective { .. } => {
                let smallest = affine_at_corners.into_iter().fold(f32::MAX, f32::min);
                if smallest > 0.0 {
                    1.0 / smallest
                } else {
                    f32::INFINITY
                }
            }
        }
    }
}

/// The map: `side x side` texels over a rectangle of the light's view.
pub struct OccluderMap {
    view: LightView,
    origin: Vec2,
    texel: f32,
    width: usize,
    height: usize,
    /// Per texel: every ray through it is blocked at this depth or nearer (`INFINITY`: unknown).
    blocked_by: Vec<f32>,
    /// Depths closer than this apart are not told apart (f32 rounding of the projection).
    epsilon: f32,
}

impl OccluderMap {
    /// An empty map over the rectangle that holds every point of `extent_points` (the casters'
    /// box corners), at most `resolution` texels along its longer side. `None` when the light
    /// cannot project one of them (it sits among them).
    pub fn new(view: LightView, extent_points: &[Vec3], resolution: usize) -> Option<OccluderMap> {
        let mut lo = Vec2::splat(f32::MAX);
        let mut hi = Vec2::splat(f32::MIN);
        let (mut near, mut far) = (f32::MAX, f32::MIN);
        for &p in extent_points {
            let q = view.project(p)?;
            (lo, hi) = (lo.min(q.at), hi.max(q.at));
            (near, far) = (near.min(q.depth), far.max(q.depth));
        }
        let size = hi - lo;
        if size.max_element().is_nan() || size.max_element() <= 0.0 || resolution == 0 {
            return None;
        }
        let texel = size.max_element() / resolution as f32;
        let width = ((size.x / texel).ceil() as usize).clamp(1, resolution);
        let height = ((size.y / texel).ceil() as usize).clamp(1, resolution);
        let depth_scale = far.abs().max(near.abs()).max(far - near);
        Some(OccluderMap {
            view,
            origin: lo,
            texel,
            width,
            height,
            blocked_by: vec![f32::INFINITY; width * height],
            epsilon: depth_scale * 1e-4,
        })
    }

    /// A point in texel units.
    fn to_map(&self, at: Vec2) -> Vec2 {
        (at - self.origin) / self.texel
    }

    /// Adds a mesh (world-space `positions`, a triangle list `indices`). Its triangles are
    /// taken in two sets, those the light sees wound one way and those wound the other; each
    /// set is a surface whose projection changes cover only across its *outline*: the edges not
    /// shared by exactly two of its triangles lying on either side of them. So a texel that no
    /// outline edge touches and whose corners are all covered is covered whole, every ray
    /// through it meets the set, and no deeper than the deepest of the set's triangles that
    /// overlap the texel. Triangles the light cannot project belong to neither set.
    pub fn add_mesh(&mut self, positions: &[Vec3], indices: &[u32]) {
        let projected: Vec<Option<(Vec2, f32)>> = positions
            .iter()
            .map(|&p| self.view.project(p).map(|q| (self.to_map(q.at), self.view.affine(q.depth))))
            .collect();
        let mut triangles: [Vec<MapTriangle>; 2] = [Vec::new(), Vec::new()];
        for t in indices.chunks_exact(3) {
            let corner = |i: u32| projected.get(i as usize).copied().flatten();
            let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
                continue;
            };
            let area = (b.0 - a.0).perp_dot(c.0 - a.0);
            if area.abs() < 1e-9 {
                continue;
            }
            let set = usize::from(area < 0.0);
            triangles[set].push(MapTriangle {
                vertices: [t[0], t[1], t[2]],
                at: [a.0, b.0, c.0],
                affine: [a.1, b.1, c.1],
            });
        }
        for set in &triangles {
            self.add_surface(set);
        }
    }

    /// One set of [`add_mesh`]: triangles of one projected winding.
    fn add_surface(&mut self, triangles: &[MapTriangle]) {
        let Some(rect) = TexelRect::around(triangles.iter().flat_map(|t| t.at), self.width, self.height) else {
            return;
        };
        let mut corners_covered = vec![false; (rect.width + 1) * (rect.height + 1)];
        let mut deepest = vec![f32::MIN; rect.width * rect.height];
        let mut outlined = vec![false; rect.width * rect.height];
        for t in triangles {
            t.cover_corners(&rect, &mut corners_covered);
            t.deepen(&rect, &self.view, &mut deepest);
        }
        for (p, q) in outline(triangles) {
            mark_segment(p, q, &rect, &mut outlined);
        }
        for y in 0..rect.height {
            for x in 0..rect.width {
                let corner = |dx: usize, dy: usize| corners_covered[(y + dy) * (rect.width + 1) + x + dx];
                let whole = corner(0, 0) && corner(1, 0) && corner(0, 1) && corner(1, 1);
                if !whole || outlined[y * rect.width + x] {
                    continue;
                }
                let slot = &mut self.blocked_by[(rect.y0 + y) * self.width + rect.x0 + x];
                *slot = slot.min(deepest[y * rect.width + x]);
            }
        }
    }

    /// Whether every light ray through the box with corners `corners` is blocked strictly
    /// before the box begins: then everything in the box, and behind it, is in the shadow of
    /// what blocks those rays (none of which lies in the box).
    pub fn hides_box(&self, corners: &[Vec3; 8]) -> bool {
        let mut lo = Vec2::splat(f32::MAX);
        let mut hi = Vec2::splat(f32::MIN);
        let mut nearest = f32::MAX;
        for &p in corners {
            let Some(q) = self.view.project(p) else {
                return false;
            };
            let at = self.to_map(q.at);
            (lo, hi) = (lo.min(at), hi.max(at));
            nearest = nearest.min(q.depth);
        }
        // Every texel the box's footprint touches (the hull of its corners lies in this rect).
        // At least one texel, even for a flat footprint on a texel's edge, and checked against
        // the map as such: one past a row's end is the next row's first texel.
        let (x0, y0) = (lo.x.floor(), lo.y.floor());
        let (x1, y1) = (hi.x.ceil().max(x0 + 1.0), hi.y.ceil().max(y0 + 1.0));
        if x0 < 0.0 || y0 < 0.0 || x1 > self.width as f32 || y1 > self.height as f32 {
            return false;
        }
        let before = nearest - self.epsilon;
        (y0 as usize..y1 as usize).all(|y| {
            (x0 as usize..x1 as usize).all(|x| self.blocked_by.get(y * self.width + x).is_some_and(|&d| d < before))
        })
    }

    /// Texels whose rays some triangle blocks (a diagnostic, and the tests' view of coverage).
    #[cfg(test)]
    pub fn blocked_texels(&self) -> usize {
        self.blocked_by.iter().filter(|d| d.is_finite()).count()
    }
}

/// A triangle in map coordinates (texel units), with its affine depth quantity per corner.
struct MapTriangle {
    vertices: [u32; 3],
    at: [Vec2; 3],
    affine: [f32; 3],
}

impl MapTriangle {
    /// Edge functions oriented so that the inside is positive.
    fn edges(&self) -> [(Vec2, Vec2); 3] {
        let [a, b, c] = self.at;
        let sign = (b - a).perp_dot(c - a).signum();
        [(a, (b - a) * sign), (b, (c - b) * sign), (c, (a - c) * sign)]
    }

    /// The plane of the affine depth quantity at `p`.
    fn plane(&self, p: Vec2) -> f32 {
        let [a, b, c] = self.at;
        let area = (b - a).perp_dot(c - a);
        let l0 = (c - b).perp_dot(p - b) / area;
        let l1 = (a - c).perp_dot(p - c) / area;
        self.affine[0] * l0 + self.affine[1] * l1 + self.affine[2] * (1.0 - l0 - l1)
    }

    /// Marks the texel corners (lattice points) inside the closed triangle.
    fn cover_corners(&self, rect: &TexelRect, covered: &mut [bool]) {
        let edges = self.edges();
        let (lo, hi) = self.bounds();
        let [x0, y0, x1, y1] = rect.clamp(lo.ceil(), hi.floor());
        for y in y0..=y1 {
            for x in x0..=x1 {
                let p = Vec2::new(x as f32, y as f32);
                if edges.iter().all(|&(o, e)| e.perp_dot(p - o) >= 0.0) {
                    let (cx, cy) = (x as usize - rect.x0, y as usize - rect.y0);
                    covered[cy * (rect.width + 1) + cx] = true;
                }
            }
        }
    }

    /// Raises each texel the triangle may overlap to the deepest its plane reaches there.
    fn deepen(&self, rect: &TexelRect, view: &LightView, deepest: &mut [f32]) {
        let edges = self.edges();
        let (lo, hi) = self.bounds();
        let [x0, y0, x1, y1] = rect.clamp(lo.floor(), hi.ceil());
        for y in y0..y1 {
            for x in x0..x1 {
                let (fx, fy) = (x as f32, y as f32);
                let corners =
                    [(fx, fy), (fx + 1.0, fy), (fx, fy + 1.0), (fx + 1.0, fy + 1.0)].map(|(u, v)| Vec2::new(u, v));
                // Apart only when all four corners lie outside one edge (a margin keeps
                // rounding on the overlapping side).
                let apart = edges.iter().any(|&(o, e)| corners.iter().all(|&c| e.perp_dot(c - o) < -1e-3 * e.length()));
                if apart {
                    continue;
                }
                let d = view.deepest(corners.map(|c| self.plane(c)));
                let slot = &mut deepest[(y as usize - rect.y0) * rect.width + x as usize - rect.x0];
                *slot = slot.max(d);
            }
        }
    }

    fn bounds(&self) -> (Vec2, Vec2) {
        let [a, b, c] = self.at;
        (a.min(b).min(c), a.max(b).max(c))
    }
}

/// The texels a set of points spans, clamped to the map.
struct TexelRect {
    x0: usize,
    y0: usize,
    width: usize,
    height: usize,
}

impl TexelRect {
    fn around(points: impl Iterator<Item = Vec2>, map_width: usize, map_height: usize) -> Option<TexelRect> {
        let (lo, hi) =
            points.fold((Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)), |(lo, hi), p| (lo.min(p), hi.max(p)));
        let x0 = lo.x.floor().max(0.0) as usize;
        let y0 = lo.y.floor().max(0.0) as usize;
        let x1 = (hi.x.ceil().max(0.0) as usize).min(map_width);
        let y1 = (hi.y.ceil().max(0.0) as usize).min(map_height);
        (x1 > x0 && y1 > y0).then(|| TexelRect { x0, y0, width: x1 - x0, height: y1 - y0 })
    }

    /// Whole map coordinates from `lo` to `hi` (already rounded outwards or inwards), limited to
    /// the lattice of this rectangle's texel corners: `[x0, y0, x1, y1]`.
    fn clamp(&self, lo: Vec2, hi: Vec2) -> [isize; 4] {
        [
            (lo.x as isize).max(self.x0 as isize),
            (lo.y as isize).max(self.y0 as isize),
            (hi.x as isize).min((self.x0 + self.width) as isize),
            (hi.y as isize).min((self.y0 + self.height) as isize),
        ]
    }
}

/// The outline of one set of triangles: every edge not shared by exactly two of them on
/// either side of it, as map-space segments.
fn outline(triangles: &[MapTriangle]) -> Vec<(Vec2, Vec2)> {
    /// One undirected edge: its end points, the opposite corners of the first two triangles on
    /// it, and how many triangles run it (a third makes it outline whatever the first two say).
    struct EdgeUse {
        ends: (Vec2, Vec2),
        opposite: [Vec2; 2],
        count: u32,
    }
    let mut edges: U64Map<EdgeUse> = u64_map_with_capacity(triangles.len() * 2);
    for t in triangles {
        for k in 0..3 {
            let (i, j, o) = (k, (k + 1) % 3, (k + 2) % 3);
            let (vi, vj) = (t.vertices[i], t.vertices[j]);
            let key = (u64::from(vi.min(vj)) << 32) | u64::from(vi.max(vj));
            let ends = if vi < vj { (t.at[i], t.at[j]) } else { (t.at[j], t.at[i]) };
            let edge = edges.entry(key).or_insert(EdgeUse { ends, opposite: [Vec2::ZERO; 2], count: 0 });
            if let Some(slot) = edge.opposite.get_mut(edge.count as usize) {
                *slot = t.at[o];
            }
            edge.count += 1;
        }
    }
    edges
        .into_values()
        .filter(|edge| {
            if edge.count != 2 {
                return true;
            }
            let ((p, q), [a, b]) = (edge.ends, edge.opposite);
            let e = q - p;
            let (sa, sb) = (e.perp_dot(a - p), e.perp_dot(b - p));
            // Interior only when the two lie strictly on either side (NaN: outline).
            let apart = sa * sb;
            apart.is_nan() || apart >= 0.0
        })
        .map(|edge| edge.ends)
        .collect()
}

/// Marks every texel of `rect` that the segment from `p` to `q` touches, with a margin.
fn mark_segment(p: Vec2, q: Vec2, rect: &TexelRect, outlined: &mut [bool]) {
    const MARGIN: f32 = 1e-2;
    let (lo, hi) = (p.min(q) - MARGIN, p.max(q) + MARGIN);
    let [x0, y0, x1, y1] = rect.clamp(lo.floor(), hi.ceil());
    let direction = q - p;
    let normal = direction.perp().try_normalize();
    for y in y0..y1 {
        for x in x0..x1 {
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            // The square meets the segment's line where the line's distance to its centre is
            // at most the square's half-extent along the normal (the box test bounds the rest).
            let touches = match normal {
                Some(n) => n.dot(centre - p).abs() <= 0.5 * (n.x.abs() + n.y.abs()) + MARGIN,
                None => true,
            };
            if touches {
                outlined[(y as usize - rect.y0) * rect.width + x as usize - rect.x0] = true;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square of side `2 * half` at height `y`, as two triangles sharing a diagonal.
    fn square_at(y: f32, half: f32) -> (Vec<Vec3>, Vec<u32>) {
        let p = |x: f32, z: f32| Vec3::new(x, y, z);
        (vec![p(-half, -half), p(half, -half), p(half, half), p(-half, half)], vec![0, 1, 2, 0, 2, 3])
    }

    fn box_corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
        [0, 1, 2, 3, 4, 5, 6, 7].map(|i| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        })
    }

    fn map_over(view: LightView, extent: f32, resolution: usize) -> OccluderMap {
        let corners = box_corners(Vec3::splat(-extent), Vec3::splat(extent));
        OccluderMap::new(view, &corners, resolution).unwrap()
    }

    #[test]
    fn a_box_under_a_roof_is_hidden_from_a_sun_overhead_and_one_beside_it_is_not() {
        let mut map = map_over(LightView::directional(Vec3::NEG_Y).unwrap(), 4.0, 64);
        let (positions, indices) = square_at(2.0, 2.0);
        map.add_mesh(&positions, &indices);
        assert!(map.hides_box(&box_corners(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0))));
        // Reaching past the roof's edge, or above it: not hidden.
        assert!(!map.hides_box(&box_corners(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(2.5, 1.0, 1.0))));
        assert!(!map.hides_box(&box_corners(Vec3::new(-1.0, 1.0, -1.0), Vec3::new(1.0, 2.5, 1.0))));
        // Touching the roof's plane: not strictly behind it.
        assert!(!map.hides_box(&box_corners(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0))));
    }

    #[test]
    fn texels_an_outline_touches_are_not_covered_and_shared_edges_are_no_outline() {
        // 8 texels over 8 world units. Half of a square a little over 4x4 texels, its
        // hypotenuse through texel corners: the texels it touches, even at a corner, stay
        // unknown, so of the 4x4 texels inside, 2 + 1 lie wholly on one side.
        let mut map = map_over(LightView::directional(Vec3::NEG_Y).unwrap(), 4.0, 8);
        let (positions, indices) = square_at(2.0, 2.05);
        map.add_mesh(&positions, &indices[..3]);
        assert_eq!(map.blocked_texels(), 3);
        // Both halves: the diagonal is shared, so all 4x4 texels are covered.
        let mut map = map_over(LightView::directional(Vec3::NEG_Y).unwrap(), 4.0, 8);
        map.add_mesh(&positions, &indices);
        assert_eq!(map.blocked_texels(), 16);
    }

    #[test]
    fn a_closed_box_blocks_at_its_top_face_not_its_bottom() {
        // A unit cube seen from straight above: its top face covers, at the top's depth.
        let cube = crate::mesh::shapes::cube(2.0);
        let lifted: Vec<Vec3> = cube.positions.iter().map(|p| *p + Vec3::Y * 2.0).collect();
        let mut map = map_over(LightView::directional(Vec3::NEG_Y).unwrap(), 4.0, 64);
        map.add_mesh(&lifted, &cube.indices);
        // Just under the top face (y = 3): inside the cube, still behind the top.
        assert!(map.hides_box(&box_corners(Vec3::new(-0.5, 2.0, -0.5), Vec3::new(0.5, 2.9, 0.5))));
        assert!(!map.hides_box(&box_corners(Vec3::new(-0.5, 2.0, -0.5), Vec3::new(0.5, 3.1, 0.5))));
    }

    #[test]
    fn a_point_light_sees_through_the_gap_between_two_tiles() {
        let light = Vec3::new(0.0, 10.0, 0.0);
        let view = LightView::point(light, Vec3::ZERO, 8.0).unwrap();
        let mut map = map_over(view, 4.0, 128);
        // Two tiles with a gap along x = 0.
        let p = |x: f32, z: f32| Vec3::new(x, 2.0, z);
        let tiles = [p(0.1, -3.0), p(3.0, -3.0), p(3.0, 3.0), p(0.1, 3.0)];
        map.add_mesh(&tiles, &[0, 1, 2, 0, 2, 3]);
        let tiles = [p(-3.0, -3.0), p(-0.1, -3.0), p(-0.1, 3.0), p(-3.0, 3.0)];
        map.add_mesh(&tiles, &[0, 1, 2, 0, 2, 3]);
        // Under one tile: hidden. Under the gap: not.
        assert!(map.hides_box(&box_corners(Vec3::new(0.5, 0.0, -0.5), Vec3::new(1.0, 0.5, 0.5))));
        assert!(!map.hides_box(&box_corners(Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 0.5, 0.5))));
    }

    #[test]
    fn a_flat_box_on_the_maps_far_edge_is_not_judged_by_the_next_rows_texel() {
        // Only the texel at (0, 1) blocks. A box flat across the light at map x = 8, the
        // right edge of an 8-texel row 0, lies beside no blocked texel; one texel past row 0's
        // end is, in memory, row 1's first texel.
        let mut map = map_over(LightView::directional(Vec3::NEG_Y).unwrap(), 4.0, 8);
        map.blocked_by[map.width] = f32::MIN;
        let view = map.view;
        let world = |x: f32, y: f32, depth: f32| {
            let at = map.origin + Vec2::new(x, y) * map.texel;
            view.right * at.x + view.up * at.y + view.forward * depth
        };
        let flat = |x: f32| {
            let (lo, hi) = (world(x, 0.2, 1.0), world(x, 0.8, 2.0));
            box_corners(lo.min(hi), lo.max(hi))
        };
        assert!(!map.hides_box(&flat(8.0)));
        // The same box at the row's start is judged by texel (0, 0): not blocked either, and
        // the one blocked texel does hide what lies within it.
        assert!(!map.hides_box(&flat(0.0)));
        let (lo, hi) = (world(0.2, 1.2, 1.0), world(0.8, 1.8, 2.0));
        assert!(map.hides_box(&box_corners(lo.min(hi), lo.max(hi))));
    }

    #[test]
    fn a_light_among_the_points_gives_no_map() {
        let view = LightView::point(Vec3::ZERO, Vec3::X, 1.0).unwrap();
        assert!(OccluderMap::new(view, &box_corners(Vec3::splat(-1.0), Vec3::splat(1.0)), 16).is_none());
    }
}
