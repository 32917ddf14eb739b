//! Shadow-volume geometry on the CPU (seed 000, docs/design/shadow-volumes.md): silhouette sides
//! extruded to infinity, and for z-fail the two caps (Everitt and Kilgard's construction).
//!
//! Points at infinity are homogeneous, w = 0, and need an infinite-far projection. The volume is
//! the sweep of the light-facing ("lit") surface away from the light:
//! - near cap: the lit triangles as they are, so it faces the light, i.e. out of the volume;
//! - sides: one quad per silhouette edge (lit face on one side, unlit on the other), wound so
//!   that it shares the edge with its lit face in the opposite direction;
//! - far cap: the lit triangles projected to infinity with reversed winding.
//!
//! Every directed edge is then matched by its reverse ([`VolumeGeometry::is_closed`] checks
//! it): the near cap's inner edges pair among themselves, its rim pairs with the sides, the
//! sides pair with each other along the silhouette loops and with the far cap at infinity. With
//! the mesh wound counter-clockwise seen from outside, every volume triangle is wound
//! counter-clockwise seen from outside the volume (front faces point out), as docs/design/shadow-volumes.md's
//! increment/decrement table assumes.
//!
//! For a directional light every point at infinity is the same point, `(direction, 0)`: each
//! side quad is the triangle (b, a, infinity) and the far cap collapses to that single point, so
//! it is left out. The volume is still closed: the sides meet at the apex.

#[cfg(test)]
use std::collections::HashMap;

use glam::{Vec3, Vec4};

use super::adjacency::{EdgeAdjacency, NO_FACE};
#[cfg(test)]
use super::fast_hash::{u64_map_with_capacity, U64Map};

/// A light as the volume sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// The direction the light travels (from the light towards the scene); need not be unit.
    Directional(Vec3),
    /// The light's position. It must lie outside the occluder and off its vertices.
    Point(Vec3),
}

/// Shadow-volume triangle lists over one vertex buffer.
///
/// `vertices` holds the mesh positions with w = 1 at their own indices, then the points at
/// infinity: one `(direction, 0)` for a directional light, or `(p - light, 0)` for each vertex
/// `p` at index `vertex_count + i` for a point light.
#[derive(Debug, Clone, Default)]
pub struct VolumeGeometry {
    pub vertices: Vec<Vec4>,
    /// Extruded silhouette edges (both z-pass and z-fail draw these).
    pub sides: Vec<u32>,
    /// Light-facing triangles: the near cap, drawn in z-fail, and in z-pass for open casters
    /// (docs/shadow-volumes.md); the renderer always builds it (empty only when built without caps).
    pub near_cap: Vec<u32>,
    /// Light-facing triangles at infinity, reversed: the far cap, drawn with the volume in both
    /// methods (empty when built without caps, and for a directional light, where it
    /// degenerates to a point).
    pub far_cap: Vec<u32>,
    /// Per mesh face, whether it faces the light.
    pub lit_faces: Vec<bool>,
    /// Two-sided walls of edges that casting faces run |m| >= 2 times on balance (with their far
    /// cap's fan triangles), each wall once, grouped by |m|: `(m, indices)`, m ascending. A
    /// stencil draws each list m times ([`VolumeGeometry::repeated_copies`]); the alpha counter
    /// draws it once adding m k, the same count for a fraction of the fill.
    pub repeated_walls: Vec<(u32, Vec<u32>)>,
    /// Set by the caller: leave `vertices` empty, the indices naming the doubled layout all
    /// the same (a vertex buffer of the mesh's positions at w = 1, then at w = 0, then the
    /// centroid at w = 0: `doubled_vertices`), whose far points the vertex shader places.
    pub indices_only: bool,
    /// `repeated_walls`' lists from the last build, emptied, for the next to reuse: a volume
    /// rebuilt every frame then allocates nothing once its lists have grown.
    spare_lists: Vec<Vec<u32>>,
}

/// Builds the shadow volume of a mesh, with caps for z-fail (`caps = true`) or sides only for
/// z-pass.
///
/// A face is lit when `N . L < 0`, `L` being the direction the light travels to it; a face seen
/// exactly edge-on is unlit. `face_normals` are this frame's (`adjacency::face_normals`).
///
/// For meshes that pass `EdgeAdjacency::require_closed_manifold` only (the silhouette path): on
/// an open mesh the boundary edges of lit faces are extruded too, so the volume stays closed,
/// but faces seen from behind cast no shadow; on non-manifold or inconsistently wound meshes the
/// volume is not closed. Those cast with `two_sided_volume` instead (`caster::CasterMesh` picks).
///
/// # Panics
/// If `positions` or `face_normals` are shorter than the mesh.
#[cfg(test)]
pub fn build_shadow_volume(
    adjacency: &EdgeAdjacency,
    positions: &[Vec3],
    face_normals: &[Vec3],
    light: Light,
    caps: bool,
) -> VolumeGeometry {
    let mut volume = VolumeGeometry::default();
    build_shadow_volume_into(adjacency, positions, face_normals, light, Reach::Infinite, caps, &mut volume);
    volume
}

/// [`build_shadow_volume`] into buffers that are cleared and reused frame to frame, reaching
/// as far as `reach` says.
pub fn build_shadow_volume_into(
    adjacency: &EdgeAdjacency,
    positions: &[Vec3],
    face_normals: &[Vec3],
    light: Light,
    reach: Reach,
    caps: bool,
    out: &mut VolumeGeometry,
) {
    let vertex_count = adjacency.vertex_count;
    assert!(
        positions.len() >= vertex_count && face_normals.len() >= adjacency.face_count(),
        "mesh '{}': shadow volume needs {} positions and {} face normals (got {}, {})",
        adjacency.mesh_name,
        vertex_count,
        adjacency.face_count(),
        positions.len(),
        face_normals.len()
    );
    let extrusion = start_volume(adjacency, positions, face_normals, light, reach, out);
    let lit = &out.lit_faces;
    for edge in &adjacency.edges {
        let [f0, f1] = edge.faces;
        let lit0 = lit[f0 as usize];
        let lit1 = f1 != NO_FACE && lit[f1 as usize];
        if lit0 == lit1 {
            continue;
        }
        // (a, b) as the lit face runs it; the side runs it b -> a.
        let [a, b] = edge.directed_by(if lit0 { 0 } else { 1 });
        extrusion.push_wall(a, b, &mut out.sides, &mut out.far_cap);
    }
    if !caps {
        out.far_cap.clear();
    }

    if caps {
        for (face, corners) in adjacency.indices.chunks_exact(3).enumerate() {
            if !lit[face] {
                continue;
            }
            let corners = [corners[0], corners[1], corners[2]];
            out.near_cap.extend_from_slice(&corners);
            extrusion.push_far_cap(corners, &mut out.far_cap);
        }
    }
}

/// How far a volume reaches away from the light.
///
/// A volume only darkens what it contains, and what a frame shows lies inside the receivers'
/// bounds: a volume cut off beyond them (closed there by a finite far cap) counts every visible
/// pixel as the infinite one does, and rasterises less (`technique::shadow_volume::bounds`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reach {
    /// To infinity: the far points have w = 0 (needs an infinite-far projection).
    Infinite,
    /// For a directional light: each vertex `p` goes to `p + t L` (`t > 0`, the same for all:
    /// the far cap is the near cap moved along the light).
    Along(f32),
    /// For a point light: each vertex `p` goes to `light + scale (p - light)` (`scale > 1`).
    Scaled(f32),
}

/// How a volume reaches its far end: the layout of the far vertices that [`start_volume`]
/// wrote after the mesh's own (one point at infinity for a directional light reaching
/// infinity, else one far point per vertex, and for a bounded reach one more: the apex of the
/// far cap's fan).
#[derive(Debug, Clone, Copy)]
pub(super) struct Extrusion {
    shape: FarEnd,
    vertex_count: u32,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum FarEnd {
    /// A directional light at infinity: every wall meets at one point, no far cap.
    Apex,
    /// A point light at infinity: the far cap is the lit faces at infinity.
    Infinite,
    /// A bounded reach: the far cap is a fan from one far point (this index) over the walls'
    /// far edges.
    Fan(u32),
}

impl Extrusion {
    /// The index of vertex `v` pushed to the far end, away from the light.
    pub(super) fn far(&self, v: u32) -> u32 {
        match self.shape {
            FarEnd::Apex => self.vertex_count,
            FarEnd::Infinite | FarEnd::Fan(_) => self.vertex_count + v,
        }
    }

    /// The wall extruded from edge `a -> b` (as a face that casts runs it): it runs `b -> a`.
    /// Where every vertex meets at one apex (a directional light at infinity) the wall is one
    /// triangle; otherwise it is a quad. A bounded volume also gets its far cap here: one
    /// triangle from the wall's far edge to the fan's apex. Over the closed silhouette loops
    /// the fan's inner edges cancel, so the cap closes the volume with a triangle per wall
    /// instead of one per lit face (counting only needs a surface bounded by the loops).
    pub(super) fn push_wall(&self, a: u32, b: u32, sides: &mut Vec<u32>, far_cap: &mut Vec<u32>) {
        let (a_far, b_far) = (self.far(a), self.far(b));
        match self.shape {
            FarEnd::Apex => sides.extend_from_slice(&[b, a, a_far]),
            FarEnd::Infinite => sides.extend_from_slice(&[b, a, a_far, b, a_far, b_far]),
            FarEnd::Fan(apex) => {
                sides.extend_from_slice(&[b, a, a_far, b, a_far, b_far]);
                far_cap.extend_from_slice(&[b_far, a_far, apex]);
            }
        }
    }

    /// [`Extrusion::push_wall`] with the wall and its far cap's triangle in one list.
    pub(super) fn push_wall_and_fan(&self, a: u32, b: u32, list: &mut Vec<u32>) {
        let (a_far, b_far) = (self.far(a), self.far(b));
        match self.shape {
            FarEnd::Apex => list.extend_from_slice(&[b, a, a_far]),
            FarEnd::Infinite => list.extend_from_slice(&[b, a, a_far, b, a_far, b_far]),
            FarEnd::Fan(apex) => list.extend_from_slice(&[b, a, a_far, b, a_far, b_far, b_far, a_far, apex]),
        }
    }

    /// Whether each casting face has its own far cap ([`Extrusion::push_far_cap`] writes one).
    pub(super) fn caps_each_face(&self) -> bool {
        self.shape == FarEnd::Infinite
    }

    /// The far cap of a casting face `[a, b, c]` for a point light at infinity: the face at
    /// infinity, reversed. None where the walls meet at one apex or bring their own fan.
    pub(super) fn push_far_cap(&self, [a, b, c]: [u32; 3], far_cap: &mut Vec<u32>) {
        if self.shape == FarEnd::Infinite {
            far_cap.extend_from_slice(&[self.far(a), self.far(c), self.far(b)]);
        }
    }
}

/// Whether `reach` bounds a volume from `light`: a positive finite distance along a
/// directional light, a finite scale above 1 from a point light. Any other reach (or a reach
/// that does not fit the light) leaves the volume reaching infinity. The one rule for the CPU's
/// far points and for the vertex shader's (`technique::shadow_volume::gpu_extrusion::VolumePush`).
pub fn bounds_volume(light: Light, reach: Reach) -> bool {
    match (light, reach) {
        (Light::Directional(_), Reach::Along(t)) => t > 0.0 && t.is_finite(),
        (Light::Point(_), Reach::Scaled(scale)) => scale > 1.0 && scale.is_finite(),
        _ => false,
    }
}

/// Where vertex `p` goes at the far end of the volume, homogeneous; `None` where `reach` does
/// not fit `light` (the volume then reaches infinity).
fn far_point(light: Light, reach: Reach, p: Vec3) -> Option<Vec4> {
    match (light, reach) {
        (Light::Directional(direction), Reach::Along(t)) => {
            (t > 0.0 && t.is_finite()).then(|| (p + t * direction).extend(1.0))
        }
        (Light::Point(at), Reach::Scaled(scale)) => {
            (scale > 1.0 && scale.is_finite()).then(|| (at + scale * (p - at)).extend(1.0))
        }
        _ => None,
    }
}

/// Starts a volume of `adjacency`'s mesh in `out`, shared by the silhouette and the two-sided
/// builders: clears it, marks which faces face the light (`N . L < 0`, `L` the direction the
/// light travels to the face), and writes the mesh's vertices (w = 1) followed by the far ones
/// (at infinity, w = 0, or where `reach` says, w = 1).
pub(super) fn start_volume(
    adjacency: &EdgeAdjacency,
    positions: &[Vec3],
    face_normals: &[Vec3],
    light: Light,
    reach: Reach,
    out: &mut VolumeGeometry,
) -> Extrusion {
    let vertex_count = adjacency.vertex_count;
    out.vertices.clear();
    out.sides.clear();
    out.near_cap.clear();
    out.far_cap.clear();
    out.lit_faces.clear();
    for (_, mut list) in out.repeated_walls.drain(..) {
        list.clear();
        out.spare_lists.push(list);
    }
    let normals = &face_normals[..adjacency.face_count()];
    match light {
        Light::Directional(direction) => out.lit_faces.extend(normals.iter().map(|n| n.dot(direction) < 0.0)),
        // N.(p - light) is the same for every point p of the face's plane.
        Light::Point(at) => out.lit_faces.extend(
            normals
                .iter()
                .zip(adjacency.indices.chunks_exact(3))
                .map(|(n, t)| n.dot(positions[t[0] as usize] - at) < 0.0),
        ),
    }
    let mesh = &positions[..vertex_count];
    if out.indices_only {
        // The far end's shape only: the far points are the vertex shader's.
        let bounded = vertex_count > 0 && bounds_volume(light, reach);
        let shape = match (bounded, light) {
            (true, _) => FarEnd::Fan(2 * vertex_count as u32),
            (false, Light::Directional(_)) => FarEnd::Apex,
            (false, Light::Point(_)) => FarEnd::Infinite,
        };
        return Extrusion { shape, vertex_count: vertex_count as u32 };
    }
    out.vertices.extend(mesh.iter().map(|p| p.extend(1.0)));
    // Bounded only if every vertex can be (a bad reach is not half applied). The fan's apex is
    // the far image of the mesh's centroid: inside the far image of its hull, so beyond the
    // receivers as every far point is.
    let centroid = mesh.iter().copied().sum::<Vec3>() / vertex_count.max(1) as f32;
    let bounded: Option<Vec<Vec4>> = mesh.iter().chain([&centroid]).map(|&p| far_point(light, reach, p)).collect();
    let shape = match (bounded, light) {
        (Some(far), _) if reach != Reach::Infinite && vertex_count > 0 => {
            out.vertices.extend(far);
            FarEnd::Fan(2 * vertex_count as u32)
        }
        (_, Light::Directional(direction)) => {
            out.vertices.push(direction.extend(0.0));
            FarEnd::Apex
        }
        (_, Light::Point(at)) => {
            out.vertices.extend(mesh.iter().map(|&p| (p - at).extend(0.0)));
            FarEnd::Infinite
        }
    };
    Extrusion { shape, vertex_count: vertex_count as u32 }
}

/// The vertex buffer an `indices_only` volume of a mesh at `positions` indexes: the positions
/// at w = 1, again at w = 0 (pushed from the light by the vertex shader), and their centroid
/// at w = 0 (the bounded far cap's apex), into `out`. Built once for a rigid mesh.
pub fn doubled_vertices(positions: &[Vec3], out: &mut Vec<Vec4>) {
    out.clear();
    out.extend(positions.iter().map(|p| p.extend(1.0)));
    out.extend(positions.iter().map(|p| p.extend(0.0)));
    let centroid = positions.iter().copied().sum::<Vec3>() / positions.len().max(1) as f32;
    out.push(centroid.extend(0.0));
}

/// Volumes are equal by what they draw: the spare lists a build left are not part of it.
impl PartialEq for VolumeGeometry {
    fn eq(&self, other: &Self) -> bool {
        (&self.vertices, &self.sides, &self.near_cap, &self.far_cap, &self.lit_faces, &self.repeated_walls)
            == (&other.vertices, &other.sides, &other.near_cap, &other.far_cap, &other.lit_faces, &other.repeated_walls)
            && self.indices_only == other.indices_only
    }
}

impl VolumeGeometry {
    /// The list of repeated walls for multiplicity `times` (>= 2), made (from a spare list) in
    /// its place by ascending `times` if the volume has none yet.
    pub(super) fn repeated_list(&mut self, times: u32) -> &mut Vec<u32> {
        let at = match self.repeated_walls.binary_search_by_key(&times, |(m, _)| *m) {
            Ok(at) => at,
            Err(at) => {
                let list = self.spare_lists.pop().unwrap_or_default();
                self.repeated_walls.insert(at, (times, list));
                at
            }
        };
        &mut self.repeated_walls[at].1
    }

    /// Number of triangles drawn with a stencil: the three lists and every repeated wall's copies.
    #[cfg(test)]
    pub fn triangle_count(&self) -> usize {
        (self.sides.len() + self.near_cap.len() + self.far_cap.len() + self.repeated_copies().count()) / 3
    }

    /// The repeated walls as a stencil draws them: each list `m` times over.
    #[cfg(test)]
    pub fn repeated_copies(&self) -> impl Iterator<Item = u32> + '_ {
        self.repeated_walls.iter().flat_map(|(m, list)| (0..*m).flat_map(move |_| list.iter().copied()))
    }

    /// Every directed edge of sides + caps is matched by its reverse (as a multiset), with
    /// vertices compared by where they are: finite points by position, points at infinity by
    /// direction. This is what makes z-fail counts return to zero outside the volume.
    #[cfg(test)]
    pub fn is_closed(&self) -> bool {
        self.unmatched_edges() == 0
    }

    /// Directed edges of sides + caps without a reverse partner: 0 for a closed volume.
    #[cfg(test)]
    pub fn unmatched_edges(&self) -> usize {
        // Identify vertices by the point they stand for, so that duplicates of one point (or
        // different scalings of one direction at infinity) count as one.
        let mut id_of_point: HashMap<[u32; 4], u32> = HashMap::with_capacity(self.vertices.len());
        let point_ids: Vec<u32> = self
            .vertices
            .iter()
            .map(|&v| {
                let next_id = id_of_point.len() as u32;
                *id_of_point.entry(point_key(v)).or_insert(next_id)
            })
            .collect();

        // +1 for u -> v with u < v, -1 for the reverse: matched edges cancel.
        let mut balance: U64Map<i32> = u64_map_with_capacity(3 * self.triangle_count());
        let copies: Vec<u32> = self.repeated_copies().collect();
        for list in [&self.sides, &self.near_cap, &self.far_cap, &copies] {
            for triangle in list.chunks_exact(3) {
                for k in 0..3 {
                    let from = point_ids[triangle[k] as usize];
                    let to = point_ids[triangle[(k + 1) % 3] as usize];
                    if from == to {
                        continue; // degenerate edge: its own reverse
                    }
                    let (low, high, step) = if from < to { (from, to, 1) } else { (to, from, -1) };
                    *balance.entry((u64::from(low) << 32) | u64::from(high)).or_insert(0) += step;
                }
            }
        }
        balance.values().map(|b| b.unsigned_abs() as usize).sum()
    }
}

/// Bits identifying the point a homogeneous vertex stands for: position for w != 0,
/// unit direction for w = 0 (the last word tells them apart).
#[cfg(test)]
fn point_key(v: Vec4) -> [u32; 4] {
    let (point, finite) = if v.w == 0.0 { (v.truncate().normalize_or_zero(), 0) } else { (v.truncate() / v.w, 1) };
    // + 0.0 turns -0.0 into 0.0, so that they compare equal.
    let [x, y, z] = (point + Vec3::ZERO).to_array().map(f32::to_bits);
    [x, y, z, finite]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Result;
    use crate::mesh::shapes::{self, MeshData};
    use crate::mesh::weld::weld_by_position;

    struct Occluder {
        positions: Vec<Vec3>,
        adjacency: EdgeAdjacency,
    }

    fn occluder(name: &str, mesh: &MeshData) -> Result<Occluder> {
        let welded = weld_by_position(name, &mesh.positions, &mesh.indices, 1e-6)?;
        let adjacency = EdgeAdjacency::build(name, &welded.positions, &welded.indices)?;
        adjacency.require_closed_manifold()?;
        Ok(Occluder { positions: welded.positions, adjacency })
    }

    fn volume(occluder: &Occluder, light: Light, caps: bool) -> VolumeGeometry {
        build_shadow_volume(&occluder.adjacency, &occluder.positions, &occluder.adjacency.face_normals, light, caps)
    }

    /// Replaces points at infinity by far finite stand-ins (`reach` times as far from a point
    /// light, or one apex `reach` along a directional light), giving a closed polyhedron whose
    /// signed volume is positive iff the triangles face out.
    fn finite_signed_volume(volume: &VolumeGeometry, light: Light, reach: f32) -> f32 {
        let finite = |v: Vec4| {
            if v.w != 0.0 {
                return v.truncate() / v.w;
            }
            match light {
                Light::Directional(direction) => direction.normalize() * reach,
                Light::Point(at) => at + v.truncate() * reach,
            }
        };
        [&volume.sides, &volume.near_cap, &volume.far_cap]
            .into_iter()
            .flat_map(|list| list.chunks_exact(3))
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| finite(volume.vertices[t[k] as usize]));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn lights() -> [Light; 4] {
        [
            Light::Directional(Vec3::new(0.0, -1.0, 0.0)),
            Light::Directional(Vec3::new(0.3, -1.0, 0.5)),
            Light::Point(Vec3::new(0.0, 6.0, 0.0)),
            Light::Point(Vec3::new(4.0, 3.0, -5.0)),
        ]
    }

    #[test]
    fn cube_under_an_axis_light_extrudes_its_top_square() -> Result<()> {
        let cube = occluder("cube", &shapes::cube(1.0))?;
        let directional = volume(&cube, Light::Directional(Vec3::NEG_Y), true);
        assert_eq!(directional.near_cap.len() / 3, 2, "the top face");
        assert_eq!(directional.sides.len() / 3, 4, "one triangle per top edge");
        assert!(directional.far_cap.is_empty(), "collapses to the point at infinity");
        assert_eq!(directional.vertices.len(), 8 + 1);
        assert!(directional.is_closed());

        let point = volume(&cube, Light::Point(Vec3::new(0.0, 5.0, 0.0)), true);
        assert_eq!(point.near_cap.len() / 3, 2);
        assert_eq!(point.sides.len() / 3, 8, "one quad per top edge");
        assert_eq!(point.far_cap.len() / 3, 2);
        assert_eq!(point.vertices.len(), 16);
        assert!(point.vertices[8..].iter().all(|v| v.w == 0.0));
        assert!(point.is_closed());
        Ok(())
    }

    #[test]
    fn cube_lit_from_a_corner_has_a_hexagonal_silhouette() -> Result<()> {
        let cube = occluder("cube", &shapes::cube(1.0))?;
        let point = volume(&cube, Light::Point(Vec3::splat(10.0)), true);
        assert_eq!(point.near_cap.len() / 3, 6, "three faces");
        assert_eq!(point.sides.len() / 6, 6, "six silhouette edges");
        assert!(point.is_closed());
        Ok(())
    }

    #[test]
    fn volumes_are_closed_for_every_shape_and_light() -> Result<()> {
        let shapes = [
            ("cube", shapes::cube(1.0)),
            ("sphere", shapes::uv_sphere(12, 24)?),
            ("torus", shapes::torus(1.0, 0.3, 32, 16)?),
            ("knot", shapes::torus_knot(2, 3, 1.0, 0.1, 128, 8)?),
        ];
        for (name, mesh) in &shapes {
            let occluder = occluder(name, mesh)?;
            for light in lights() {
                let capped = volume(&occluder, light, true);
                assert!(!capped.sides.is_empty(), "{name} {light:?}");
                assert_eq!(capped.unmatched_edges(), 0, "{name} {light:?}");
                let signed = finite_signed_volume(&capped, light, 50.0);
                assert!(signed > 0.0, "{name} {light:?}: faces point in ({signed})");
                // Sides alone (z-pass) are open exactly where the caps were.
                let sides_only = volume(&occluder, light, false);
                assert!(sides_only.near_cap.is_empty() && sides_only.far_cap.is_empty());
                assert_eq!(sides_only.sides, capped.sides);
                assert!(!sides_only.is_closed(), "{name} {light:?}");
            }
        }
        Ok(())
    }

    #[test]
    fn bounded_volumes_are_closed_finite_and_face_out() -> Result<()> {
        for (name, mesh) in [("cube", shapes::cube(1.0)), ("torus", shapes::torus(1.0, 0.3, 32, 16)?)] {
            let occluder = occluder(name, &mesh)?;
            for light in lights() {
                let reach = match light {
                    Light::Directional(_) => Reach::Along(7.5),
                    Light::Point(_) => Reach::Scaled(4.0),
                };
                let mut bounded = VolumeGeometry::default();
                let normals = &occluder.adjacency.face_normals;
                build_shadow_volume_into(
                    &occluder.adjacency,
                    &occluder.positions,
                    normals,
                    light,
                    reach,
                    true,
                    &mut bounded,
                );
                assert!(bounded.vertices.iter().all(|v| v.w == 1.0), "{name} {light:?}: a point at infinity");
                assert_eq!(bounded.unmatched_edges(), 0, "{name} {light:?}");
                assert!(!bounded.far_cap.is_empty(), "{name} {light:?}: closed by a far cap");
                let signed = finite_signed_volume(&bounded, light, 1.0);
                assert!(signed > 0.0, "{name} {light:?}: faces point in ({signed})");
                // Each far point is its vertex moved along the light, or scaled from it.
                let n = occluder.adjacency.vertex_count;
                for (p, far) in occluder.positions.iter().zip(&bounded.vertices[n..]) {
                    let expected = match light {
                        Light::Directional(direction) => *p + 7.5 * direction,
                        Light::Point(at) => at + 4.0 * (*p - at),
                    };
                    assert!(far.truncate().abs_diff_eq(expected, 1e-4), "{name} {light:?}");
                }
                // The same lit faces and silhouette as the infinite volume.
                let infinite = volume(&occluder, light, true);
                assert_eq!(bounded.lit_faces, infinite.lit_faces);
                assert_eq!(bounded.near_cap, infinite.near_cap);
            }
        }
        Ok(())
    }

    #[test]
    fn a_reach_that_does_not_fit_the_light_reaches_infinity() -> Result<()> {
        let cube = occluder("cube", &shapes::cube(1.0))?;
        let normals = &cube.adjacency.face_normals;
        for (light, reach) in [
            (Light::Directional(Vec3::NEG_Y), Reach::Scaled(3.0)),
            (Light::Point(Vec3::new(0.0, 5.0, 0.0)), Reach::Along(3.0)),
            (Light::Directional(Vec3::NEG_Y), Reach::Along(-1.0)),
            (Light::Point(Vec3::new(0.0, 5.0, 0.0)), Reach::Scaled(0.5)),
        ] {
            let mut out = VolumeGeometry::default();
            build_shadow_volume_into(&cube.adjacency, &cube.positions, normals, light, reach, true, &mut out);
            assert_eq!(out, volume(&cube, light, true), "{light:?} {reach:?}");
        }
        Ok(())
    }

    #[test]
    fn side_faces_point_away_from_a_convex_occluder() -> Result<()> {
        // A convex occluder's centre is inside its volume, behind every side plane.
        for (name, mesh) in [("cube", shapes::cube(1.0)), ("sphere", shapes::uv_sphere(8, 16)?)] {
            let occluder = occluder(name, &mesh)?;
            for light in lights() {
                let v = volume(&occluder, light, false);
                for t in v.sides.chunks_exact(3) {
                    // Finite stand-ins in the side's plane for its points at infinity; the
                    // first corner is always a mesh vertex.
                    let anchor = v.vertices[t[0] as usize].truncate();
                    let [p0, p1, p2] = [0, 1, 2].map(|k| {
                        let p = v.vertices[t[k] as usize];
                        match (p.w != 0.0, light) {
                            (true, _) => p.truncate(),
                            (false, Light::Directional(direction)) => anchor + direction,
                            (false, Light::Point(at)) => at + p.truncate() * 2.0,
                        }
                    });
                    let outward = (p1 - p0).cross(p2 - p0);
                    assert!(outward.dot(Vec3::ZERO - p0) < 0.0, "{name} {light:?}: side faces in");
                }
            }
        }
        Ok(())
    }

    #[test]
    fn torus_along_its_axis_has_two_silhouette_loops() -> Result<()> {
        let (major, minor) = (32, 16);
        let torus = occluder("torus", &shapes::torus(1.0, 0.3, major, minor)?)?;
        let v = volume(&torus, Light::Directional(Vec3::NEG_Y), true);
        // The outer and inner equators, one edge per major segment each.
        assert_eq!(v.sides.len() / 3, 2 * major as usize);
        assert!(v.is_closed());
        Ok(())
    }

    #[test]
    fn skinned_positions_move_the_volume() -> Result<()> {
        let cube = occluder("cube", &shapes::cube(1.0))?;
        let moved: Vec<Vec3> = cube.positions.iter().map(|p| *p + Vec3::X * 3.0).collect();
        let mut normals = Vec::new();
        cube.adjacency.recompute_face_normals(&moved, &mut normals);
        let mut reused = VolumeGeometry::default();
        let light = Light::Point(Vec3::new(0.0, 5.0, 0.0));
        build_shadow_volume_into(&cube.adjacency, &moved, &normals, light, Reach::Infinite, true, &mut reused);
        assert!(reused.is_closed());
        assert_eq!(reused.vertices[0].truncate(), moved[0]);
        // Seen from (0, 5, 0) the moved cube shows its top and its -X face.
        assert_eq!(reused.near_cap.len() / 3, 4);
        Ok(())
    }

    #[test]
    fn open_mesh_volume_sweeps_its_lit_faces() -> Result<()> {
        // Documented behaviour for callers that skip require_closed_manifold: a lit quad
        // sweeps a closed prism; the same quad seen from behind casts nothing.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, -1.0), Vec3::NEG_Z];
        let indices = [0, 1, 2, 0, 2, 3]; // faces +Y
        let adjacency = EdgeAdjacency::build("floor tile", &positions, &indices)?;
        assert!(adjacency.require_closed_manifold().is_err());
        let from_above = Light::Point(Vec3::new(0.5, 4.0, -0.5));
        let lit = build_shadow_volume(&adjacency, &positions, &adjacency.face_normals, from_above, true);
        assert_eq!(lit.sides.len() / 6, 4);
        assert!(lit.is_closed());
        let from_below = Light::Point(Vec3::new(0.5, -4.0, -0.5));
        let unlit = build_shadow_volume(&adjacency, &positions, &adjacency.face_normals, from_below, true);
        assert_eq!(unlit.triangle_count(), 0);
        Ok(())
    }

    #[test]
    fn closure_check_catches_a_missing_triangle() -> Result<()> {
        let sphere = occluder("sphere", &shapes::uv_sphere(8, 16)?)?;
        let mut v = volume(&sphere, Light::Point(Vec3::new(1.0, 5.0, 2.0)), true);
        v.far_cap.truncate(v.far_cap.len() - 3);
        assert_eq!(v.unmatched_edges(), 3);
        Ok(())
    }
}
