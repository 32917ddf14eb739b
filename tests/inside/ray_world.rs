//! CPU ray casts against every triangle of a scene, for tests' ground truth: the triangles in
//! world space in a bounding-volume hierarchy, so that scenes of a million triangles
//! (atlas-125) answer a ray in microseconds instead of milliseconds.

use glam::Vec3;
use nostencil::mesh::ray::ray_hits_triangle;
use nostencil::Scene;

/// Triangles per leaf.
const LEAF: usize = 8;

/// One triangle in world space and where it comes from.
#[derive(Clone, Copy)]
pub struct Placed {
    pub corners: [Vec3; 3],
    pub object: usize,
    /// Its index among its mesh's triangles.
    pub triangle: usize,
}

/// The nearest triangle on a ray.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub object: usize,
    pub triangle: usize,
    pub distance: f32,
}

struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Leaf: its triangles are `start..start + count`; inner node: `count` is 0 and its
    /// children are `start` and `start + 1`.
    start: usize,
    count: usize,
}

/// Every object's triangles (posed as the scene stands), in world space.
pub struct RayWorld {
    triangles: Vec<Placed>,
    nodes: Vec<Node>,
    casts_shadow: Vec<bool>,
}

impl RayWorld {
    pub fn of(scene: &Scene) -> Self {
        let mut triangles: Vec<Placed> = scene
            .objects
            .iter()
            .enumerate()
            .flat_map(|(object, o)| {
                let mesh = &scene.meshes[o.mesh].data;
                mesh.indices.chunks_exact(3).enumerate().map(move |(triangle, t)| Placed {
                    corners: [0, 1, 2].map(|k| o.transform.transform_point3(mesh.positions[t[k] as usize])),
                    object,
                    triangle,
                })
            })
            .collect();
        let mut nodes = vec![Node { lo: Vec3::ZERO, hi: Vec3::ZERO, start: 0, count: 0 }];
        split(&mut triangles, 0, 0, &mut nodes);
        RayWorld { triangles, nodes, casts_shadow: scene.objects.iter().map(|o| o.casts_shadow).collect() }
    }

    /// The nearest triangle the ray from `origin` along the unit `dir` hits.
    pub fn first_hit(&self, origin: Vec3, dir: Vec3) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.walk(origin, dir, &mut |placed, distance| {
            if !best.is_some_and(|b| b.distance <= distance) {
                best = Some(Hit { object: placed.object, triangle: placed.triangle, distance });
            }
            false
        });
        best
    }

    /// An object that casts shadows and blocks the ray from `origin` along `dir` (the first
    /// one found, not the nearest).
    pub fn occluder(&self, origin: Vec3, dir: Vec3) -> Option<usize> {
        let mut found = None;
        self.walk(origin, dir, &mut |placed, distance| {
            let blocks = distance > 1e-4 && self.casts_shadow[placed.object];
            if blocks {
                found = Some(placed.object);
            }
            blocks
        });
        found
    }

    /// Every triangle the ray hits, with its distance, in no particular order.
    #[allow(dead_code)] // Not every test binary that includes this module asks.
    pub fn every_hit(&self, origin: Vec3, dir: Vec3) -> Vec<(Placed, f32)> {
        let mut hits = Vec::new();
        self.walk_all(origin, dir, true, &mut |placed, distance| {
            hits.push((*placed, distance));
            false
        });
        hits
    }

    /// Calls `visit(triangle, distance)` for triangles the ray hits (every one nearer than the
    /// nearest so far: boxes beyond it are skipped) until `visit` returns true.
    fn walk(&self, origin: Vec3, dir: Vec3, visit: &mut dyn FnMut(&Placed, f32) -> bool) {
        self.walk_all(origin, dir, false, visit)
    }

    /// As `walk`; `beyond`: boxes beyond the nearest hit are visited too.
    fn walk_all(&self, origin: Vec3, dir: Vec3, beyond: bool, visit: &mut dyn FnMut(&Placed, f32) -> bool) {
        let inverse = dir.recip();
        let mut nearest = f32::INFINITY;
        let mut stack = if self.triangles.is_empty() { Vec::new() } else { vec![0usize] };
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index];
            if !slab_hit(origin, inverse, node.lo, node.hi).is_some_and(|t| t <= nearest) {
                continue;
            }
            if node.count == 0 {
                stack.extend([node.start, node.start + 1]);
                continue;
            }
            for placed in &self.triangles[node.start..node.start + node.count] {
                if let Some(distance) = ray_hits_triangle(origin, dir, placed.corners) {
                    if visit(placed, distance) {
                        return;
                    }
                    if !beyond {
                        nearest = nearest.min(distance);
                    }
                }
            }
        }
    }
}

/// Fills `nodes[node]` with the box of `triangles` (which start at `start` in the whole list)
/// and splits them at the median of the box's longest axis until a leaf holds `LEAF`.
fn split(triangles: &mut [Placed], start: usize, node: usize, nodes: &mut Vec<Node>) {
    let (lo, hi) =
        triangles.iter().flat_map(|t| t.corners).fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| (lo.min(p), hi.max(p)));
    nodes[node] = Node { lo, hi, start, count: triangles.len() };
    if triangles.len() <= LEAF {
        return;
    }
    let extent = hi - lo;
    let axis = if extent.x >= extent.y.max(extent.z) {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let centre = |t: &Placed| (t.corners[0] + t.corners[1] + t.corners[2])[axis];
    let middle = triangles.len() / 2;
    triangles.select_nth_unstable_by(middle, |a, b| centre(a).total_cmp(&centre(b)));
    let children = nodes.len();
    nodes.extend((0..2).map(|_| Node { lo: Vec3::ZERO, hi: Vec3::ZERO, start: 0, count: 0 }));
    nodes[node] = Node { lo, hi, start: children, count: 0 };
    let (left, right) = triangles.split_at_mut(middle);
    split(left, start, children, nodes);
    split(right, start + middle, children + 1, nodes);
}

/// Where the ray enters the box (0 when it starts inside), if it meets it ahead.
fn slab_hit(origin: Vec3, inverse_dir: Vec3, lo: Vec3, hi: Vec3) -> Option<f32> {
    let (a, b) = ((lo - origin) * inverse_dir, (hi - origin) * inverse_dir);
    let near = a.min(b).max_element().max(0.0);
    let far = a.max(b).min_element();
    // NaN (a ray along a box face) compares false: taken as a hit, which is only slower.
    if near > far {
        None
    } else {
        Some(near)
    }
}
