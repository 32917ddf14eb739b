//! Where a shadow volume can matter: every pixel a frame shows lies on a receiver, so a volume
//! only needs to exist inside the receivers' bounds. From those bounds each caster gets:
//! - a [`Reach`]: its volume ends just beyond the bounds, closed by a finite far cap, instead of
//!   running to infinity;
//! - a scissor: the screen rectangle of its volume inside the bounds. Outside it the caster's
//!   walls add up to nothing on every pixel (the pixel's surface is outside the volume), so
//!   leaving them unrasterised changes no count.
//!
//! Both paths (the alpha counter and the real stencil) draw the same clipped volumes, inside
//! the same scissors, and the apply is scissored to their union: what is saved is saved in both.

use ash::vk;
use glam::{Vec3, Vec4};

use super::convex_region::ConvexSolid;
use crate::gpu::Gpu;
use crate::mesh::Reach;
use crate::render::jobs;
use crate::render::plan::Scissor;
use crate::scene::lights::Reach as LightReach;
use crate::scene::{Camera, Light, Scene, SceneLight};

/// An axis-aligned box in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub lo: Vec3,
    pub hi: Vec3,
}

impl Aabb {
    pub fn of_points(points: impl IntoIterator<Item = Vec3>) -> Option<Aabb> {
        crate::scene::objects::bounds_of(points).map(|(lo, hi)| Aabb { lo, hi })
    }

    pub fn corners(&self) -> [Vec3; 8] {
        let (lo, hi) = (self.lo, self.hi);
        [0, 1, 2, 3, 4, 5, 6, 7].map(|i| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        })
    }

    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { lo: self.lo.min(other.lo), hi: self.hi.max(other.hi) }
    }

    /// The overlap, `None` where the boxes do not meet.
    pub fn intersection(self, other: Aabb) -> Option<Aabb> {
        let (lo, hi) = (self.lo.max(other.lo), self.hi.min(other.hi));
        (lo.cmple(hi).all()).then_some(Aabb { lo, hi })
    }

    fn diagonal(&self) -> f32 {
        (self.hi - self.lo).length()
    }

    /// Distance from `p` to the box (0 inside).
    fn distance_to(&self, p: Vec3) -> f32 {
        (p - p.clamp(self.lo, self.hi)).length()
    }
}

/// Every object's world bounds in its current pose (`None` for one without vertices): computed
/// once a frame, for the receivers' box and each caster's own.
#[cfg(test)]
pub fn object_boxes(scene: &Scene) -> Vec<Option<Aabb>> {
    (0..scene.objects.len()).map(|i| object_box(scene, i)).collect()
}

/// [`object_boxes`] as jobs on other cores than the caller's (`render::jobs`): they walk every
/// posed vertex of the scene, every frame.
pub fn object_boxes_in_jobs(gpu: &Gpu, scene: &Scene) -> Vec<Option<Aabb>> {
    jobs::run(gpu, (0..scene.objects.len()).collect(), |i| object_box(scene, i))
}

fn object_box(scene: &Scene, index: usize) -> Option<Aabb> {
    scene.posed_bounds(index).map(|(lo, hi)| Aabb { lo, hi })
}

/// The receivers' bounds: every object of the scene (any object a pixel shows can be in
/// shadow), from [`object_boxes`]. `None` for a scene with no vertices.
pub fn receivers_box(objects: &[Option<Aabb>]) -> Option<Aabb> {
    objects.iter().flatten().copied().reduce(Aabb::union)
}

/// One caster's clipped volume: how far it reaches (the same number in the caster's own
/// space, as its volume is built: moving along a light and scaling about it both commute with
/// an affine transform), and where it can darken.
#[derive(Debug, Clone, PartialEq)]
pub struct CasterBounds {
    pub reach: Reach,
    /// The part of the receivers' box the volume can cover; `None`: it covers none of it
    /// (the caster darkens nothing this frame).
    pub region: Option<Aabb>,
    /// Point sets whose convex hulls each hold that part too: the caster's box with its
    /// image on the plane of a receivers' face the light leaves by. Tighter than `region`
    /// where the light slants (the shadow footprint on a floor rather than a box around it).
    pub hulls: Vec<Vec<Vec3>>,
}

/// Margin beyond the receivers' box, as a fraction of its diagonal: keeps far caps strictly
/// outside it, so that rounding cannot bring one back onto a receiver.
const MARGIN: f32 = 1.0 / 64.0;

/// Scales beyond this (a caster almost touching a point light) would put far points where
/// f32 loses the volume's shape: such a volume reaches infinity instead.
const MAX_SCALE: f32 = 1.0e4;

/// The reach and shading bounds of the caster whose posed world bounds are `caster`, under
/// `light`, inside `receivers`.
pub fn caster_bounds(light: &Light, caster: Aabb, receivers: Aabb) -> CasterBounds {
    let margin = MARGIN * receivers.diagonal().max(f32::MIN_POSITIVE);
    let corners = caster.corners();
    // The caster's box with its image on each receivers' face plane the light leaves by.
    let with_image = |image: [Vec3; 8]| corners.iter().chain(&image).copied().collect::<Vec<Vec3>>();
    let (far, reach, hulls): ([Vec3; 8], Reach, Vec<Vec<Vec3>>) = match *light {
        Light::Directional { direction } => {
            // Along the light, a point x of the caster leaves slab i of the receivers at an
            // affine t_i(x), and the receivers at min_i t_i(x): the volume's part inside them
            // lies between the caster and its image at t_i, for every i (so in the hull of
            // the box's corners and theirs), and ends by t = min_i max_corners t_i.
            let axes: Vec<usize> = (0..3).filter(|&i| direction[i].abs() > f32::EPSILON).collect();
            let exit_t = |i: usize, c: Vec3| {
                let exit = if direction[i] > 0.0 { receivers.hi[i] } else { receivers.lo[i] };
                (exit - c[i]) / direction[i]
            };
            let reach = axes
                .iter()
                .map(|&i| corners.iter().map(|&c| exit_t(i, c)).fold(f32::MIN, f32::max))
                .fold(f32::MAX, f32::min);
            let t = reach.max(0.0) + margin / direction.length();
            if axes.is_empty() || !t.is_finite() {
                return CasterBounds::unbounded(receivers);
            }
            let hulls = axes.iter().map(|&i| with_image(corners.map(|c| c + exit_t(i, c).max(0.0) * direction)));
            (corners.map(|c| c + t * direction), Reach::Along(t), hulls.collect())
        }
        Light::Point { position } => {
            // The axes along which the whole caster lies on one side of the light, each with
            // the receivers' face its rays leave by, and the scale from the light at which a
            // ray through `c` meets that face's plane (depends on `c` along that axis only).
            let sides: Vec<(usize, f32)> = (0..3)
                .filter_map(|i| {
                    let ahead = corners.iter().all(|c| c[i] > position[i]);
                    let behind = corners.iter().all(|c| c[i] < position[i]);
                    (ahead || behind).then_some((i, if ahead { receivers.hi[i] } else { receivers.lo[i] }))
                })
                .collect();
            let exit_scale = |i: usize, exit: f32, c: Vec3| (exit - position[i]) / (c[i] - position[i]);
            // Every point of the caster is at least `nearest` from the light, and every
            // receiver at most `farthest`: scaled from the light by farthest / nearest, the
            // caster lies beyond every receiver. Tighter along a side axis: every ray through
            // the caster has left that slab (grown by the margin) by the greatest of its
            // corners' exit scales, so the receivers by the least such over the side axes (a
            // lamp over a floor: just past the floor under the caster).
            let nearest = caster.distance_to(position);
            let farthest = receivers.corners().iter().map(|c| c.distance(position)).fold(0.0, f32::max) + margin;
            let slab_exit = sides
                .iter()
                .map(|&(i, exit)| {
                    let grown = exit + margin * (exit - position[i]).signum();
                    corners.iter().map(|&c| exit_scale(i, grown, c)).fold(0.0, f32::max)
                })
                .fold(f32::MAX, f32::min);
            let scale = (farthest / nearest).min(slab_exit);
            if !(nearest > 0.0 && scale.is_finite() && scale <= MAX_SCALE) {
                return CasterBounds::unbounded(receivers);
            }
            let scale = scale.max(1.0 + MARGIN);
            // Along a side axis the caster's rays leave the receivers' slab where the caster's
            // central image on that face plane is: the volume's part inside lies between the
            // caster and that image.
            let hulls = sides
                .iter()
                .map(|&(i, exit)| {
                    with_image(corners.map(|c| position + exit_scale(i, exit, c).max(1.0) * (c - position)))
                })
                .collect();
            (corners.map(|c| position + scale * (c - position)), Reach::Scaled(scale), hulls)
        }
    };
    // The volume lies in the hull of the caster's box and its far image (both ends are affine
    // in the point), so in the box of those 16 corners.
    let swept = Aabb::of_points(corners.into_iter().chain(far));
    CasterBounds { reach, region: swept.and_then(|s| s.intersection(receivers)), hulls }
}

impl CasterBounds {
    /// A volume to infinity, which may shade anything among the receivers.
    fn unbounded(receivers: Aabb) -> Self {
        CasterBounds { reach: Reach::Infinite, region: Some(receivers), hulls: Vec::new() }
    }

    /// The frame's scissor rectangle around where the volume can shade, seen by `camera` on an
    /// `extent` frame; `None` where that is nowhere on screen. Every bound holds the volume's
    /// part inside the receivers, so their rectangles' overlap does.
    pub fn screen_rect(&self, camera: &Camera, extent: vk::Extent2D) -> Option<vk::Rect2D> {
        let region = self.region?;
        let mut rect = screen_rect(&region.corners(), camera, extent)?;
        for hull in &self.hulls {
            rect = rect_intersection(rect, screen_rect(hull, camera, extent)?)?;
        }
        Some(rect)
    }
}

/// The frame's scissor rectangle around the convex hull of `points` seen by `camera` on an
/// `extent` frame, padded by a pixel against rounding; `None` where nothing of it is on screen.
/// The part behind the near plane is cut off first (it is clipped anyway), so a hull around
/// the camera still gets a rectangle, the whole frame at worst.
pub fn screen_rect(points: &[Vec3], camera: &Camera, extent: vk::Extent2D) -> Option<vk::Rect2D> {
    const PAD: f32 = 1.0;
    let (width, height) = (extent.width as f32, extent.height as f32);
    let view_projection = camera.view_projection(width / height);
    let clip: Vec<Vec4> = points.iter().map(|c| view_projection * c.extend(1.0)).collect();
    let near = camera.near;
    // The hull's part in front of the near plane is the hull of the points there and of
    // where the segments between points cross the plane.
    let mut front: Vec<Vec4> = clip.iter().copied().filter(|c| c.w >= near).collect();
    for (a, &ca) in clip.iter().enumerate() {
        for &cb in &clip[a + 1..] {
            if (ca.w < near) != (cb.w < near) {
                let t = (near - ca.w) / (cb.w - ca.w);
                front.push(ca + t * (cb - ca));
            }
        }
    }
    if front.is_empty() {
        return None;
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for c in front {
        let ndc = c.truncate() / c.w;
        lo = lo.min(ndc);
        hi = hi.max(ndc);
    }
    let x0 = (((lo.x * 0.5 + 0.5) * width - PAD).floor()).clamp(0.0, width);
    let x1 = (((hi.x * 0.5 + 0.5) * width + PAD).ceil()).clamp(0.0, width);
    let y0 = (((lo.y * 0.5 + 0.5) * height - PAD).floor()).clamp(0.0, height);
    let y1 = (((hi.y * 0.5 + 0.5) * height + PAD).ceil()).clamp(0.0, height);
    (x1 > x0 && y1 > y0).then_some(vk::Rect2D {
        offset: vk::Offset2D { x: x0 as i32, y: y0 as i32 },
        extent: vk::Extent2D { width: (x1 - x0) as u32, height: (y1 - y0) as u32 },
    })
}

/// The overlap of two rectangles; `None` where they do not overlap.
pub fn rect_intersection(a: vk::Rect2D, b: vk::Rect2D) -> Option<vk::Rect2D> {
    let x0 = a.offset.x.max(b.offset.x);
    let y0 = a.offset.y.max(b.offset.y);
    let x1 = (a.offset.x + a.extent.width as i32).min(b.offset.x + b.extent.width as i32);
    let y1 = (a.offset.y + a.extent.height as i32).min(b.offset.y + b.extent.height as i32);
    (x1 > x0 && y1 > y0).then_some(vk::Rect2D {
        offset: vk::Offset2D { x: x0, y: y0 },
        extent: vk::Extent2D { width: (x1 - x0) as u32, height: (y1 - y0) as u32 },
    })
}

/// Doom 3's light scissor: the screen rectangle around what light `light` can reach of the
/// receivers, where its passes draw: for a point or spot light with a range, the part of the
/// receivers' box in its sphere's box; for a spot, that part's overlap with its cone (a
/// pyramid around the cone, as deep as the range or the farthest receiver). The whole frame
/// for a light that reaches everywhere, and no rectangle for one that reaches nothing on
/// screen.
pub fn light_scissor(light: &SceneLight, receivers: Option<Aabb>, camera: &Camera, extent: vk::Extent2D) -> Scissor {
    let sphere = match light.reach() {
        LightReach::Sphere { centre, radius } => Some((centre, radius)),
        LightReach::Everywhere => None,
    };
    let cone = light.cone();
    if sphere.is_none() && cone.is_none() {
        return Scissor::Frame;
    }
    let rect = receivers.and_then(|receivers| {
        let region = match sphere {
            Some((centre, radius)) => {
                Aabb { lo: centre - Vec3::splat(radius), hi: centre + Vec3::splat(radius) }.intersection(receivers)?
            }
            None => receivers,
        };
        let Some(cone) = cone else { return screen_rect(&region.corners(), camera, extent) };
        // Every receiver lies within `farthest` of the apex, so its part in the cone within
        // that height along the axis, inside the pyramid.
        let farthest = region.corners().iter().map(|c| c.distance(cone.apex)).fold(0.0, f32::max);
        let height = sphere.map_or(farthest, |(_, radius)| radius.min(farthest));
        let pyramid = ConvexSolid::pyramid(&cone.pyramid(height));
        screen_rect(&pyramid.overlap_corners(&ConvexSolid::of_box(region.lo, region.hi)), camera, extent)
    });
    Scissor::Rects(rect.into_iter().collect())
}

/// `rect` less `pixels` on every side; `None` when nothing is left.
pub fn shrunk(rect: vk::Rect2D, pixels: u32) -> Option<vk::Rect2D> {
    let (width, height) = (rect.extent.width.checked_sub(2 * pixels)?, rect.extent.height.checked_sub(2 * pixels)?);
    (width > 0 && height > 0).then_some(vk::Rect2D {
        offset: vk::Offset2D { x: rect.offset.x + pixels as i32, y: rect.offset.y + pixels as i32 },
        extent: vk::Extent2D { width, height },
    })
}

/// `rect` and `pixels` more on every side, inside an `extent` frame.
pub fn grown(rect: vk::Rect2D, pixels: u32, extent: vk::Extent2D) -> vk::Rect2D {
    let x0 = (rect.offset.x - pixels as i32).max(0);
    let y0 = (rect.offset.y - pixels as i32).max(0);
    let x1 = (rect.offset.x + (rect.extent.width + pixels) as i32).min(extent.width as i32);
    let y1 = (rect.offset.y + (rect.extent.height + pixels) as i32).min(extent.height as i32);
    vk::Rect2D {
        offset: vk::Offset2D { x: x0, y: y0 },
        extent: vk::Extent2D { width: (x1 - x0).max(0) as u32, height: (y1 - y0).max(0) as u32 },
    }
}

/// Rectangles that cover exactly the pixels of `rects`, none twice: an apply drawn once per
/// rectangle shades each pixel once (a multiply must not happen twice) and nothing between
/// the casters. Columns between consecutive x edges, each cut where its covering intervals
/// merge, and neighbouring columns with the same cuts joined.
pub fn disjoint_cover(rects: &[vk::Rect2D]) -> Vec<vk::Rect2D> {
    let span = |r: &vk::Rect2D| {
        let (x, y) = (i64::from(r.offset.x), i64::from(r.offset.y));
        (x, x + i64::from(r.extent.width), y, y + i64::from(r.extent.height))
    };
    let mut xs: Vec<i64> = rects.iter().flat_map(|r| [span(r).0, span(r).1]).collect();
    xs.sort_unstable();
    xs.dedup();
    // Sorted by their y intervals once, so that each column meets its intervals in order. A
    // frame has a rectangle per caster, and the render thread works this out every frame: the
    // columns reuse two lists instead of allocating their own.
    let mut spans: Vec<(i64, i64, i64, i64)> = rects.iter().map(span).filter(|s| s.2 < s.3).collect();
    spans.sort_unstable_by_key(|&(_, _, y0, y1)| (y0, y1));
    let mut cover = Vec::new();
    // The column being grown and the next column's intervals.
    let (mut open, mut next): (Column, Vec<(i64, i64)>) = ((0, 0, Vec::new()), Vec::new());
    for pair in xs.windows(2) {
        let (x0, x1) = (pair[0], pair[1]);
        next.clear();
        for &(_, _, y0, y1) in spans.iter().filter(|&&(rx0, rx1, _, _)| rx0 <= x0 && x1 <= rx1) {
            match next.last_mut() {
                Some(last) if y0 <= last.1 => last.1 = last.1.max(y1),
                _ => next.push((y0, y1)),
            }
        }
        if !next.is_empty() && open.1 == x0 && open.2 == next {
            open.1 = x1;
            continue;
        }
        push_column(&open, &mut cover);
        std::mem::swap(&mut open.2, &mut next);
        (open.0, open.1) = (x0, x1);
    }
    push_column(&open, &mut cover);
    cover
}

/// A column of `disjoint_cover`: its x0 and x1, and its merged y intervals.
type Column = (i64, i64, Vec<(i64, i64)>);

/// A column's rectangles, one per merged interval.
fn push_column((x0, x1, ys): &Column, cover: &mut Vec<vk::Rect2D>) {
    cover.extend(ys.iter().map(|&(y0, y1)| vk::Rect2D {
        offset: vk::Offset2D { x: *x0 as i32, y: y0 as i32 },
        extent: vk::Extent2D { width: (x1 - x0) as u32, height: (y1 - y0) as u32 },
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(centre: Vec3, half: f32) -> Aabb {
        Aabb { lo: centre - Vec3::splat(half), hi: centre + Vec3::splat(half) }
    }

    #[test]
    fn directional_reach_ends_where_the_light_leaves_the_receivers() {
        let receivers = Aabb { lo: Vec3::new(-10.0, -1.0, -10.0), hi: Vec3::new(10.0, 5.0, 10.0) };
        let caster = unit_box(Vec3::new(0.0, 2.0, 0.0), 0.5);
        let light = Light::Directional { direction: Vec3::new(0.0, -2.0, 0.0) };
        let bounds = caster_bounds(&light, caster, receivers);
        // From the caster's top (y = 2.5) down to the floor (y = -1), at 2 units per t.
        let Reach::Along(t) = bounds.reach else { panic!("{:?}", bounds.reach) };
        assert!(t > 1.75 && t < 1.75 + 0.5, "{t}");
        // The region: the column under the caster, down to the floor of the receivers.
        let region = bounds.region.expect("the caster shades the floor");
        assert!(region.lo.abs_diff_eq(Vec3::new(-0.5, -1.0, -0.5), 1e-5), "{region:?}");
        assert!(region.hi.abs_diff_eq(Vec3::new(0.5, 2.5, 0.5), 1e-5), "{region:?}");
    }

    #[test]
    fn a_slanted_light_reaches_only_as_far_as_the_floor() {
        // A wide, flat floor: the light leaves it through the bottom long before the far side.
        let receivers = Aabb { lo: Vec3::new(-50.0, 0.0, -50.0), hi: Vec3::new(50.0, 3.0, 50.0) };
        let caster = unit_box(Vec3::new(0.0, 2.0, 0.0), 0.5);
        let light = Light::Directional { direction: Vec3::new(1.0, -1.0, 0.0) };
        let region = caster_bounds(&light, caster, receivers).region.expect("shades");
        // The shadow of the box's top falls at most 2.5 to the right of it.
        assert!(region.hi.x <= 0.5 + 2.5 + 2.0, "{region:?}");
        assert!(region.lo.x >= -0.5 - 1e-5, "{region:?}");
    }

    #[test]
    fn point_reach_scales_the_caster_past_every_receiver() {
        let receivers = unit_box(Vec3::ZERO, 4.0);
        let light = Light::Point { position: Vec3::new(0.0, 3.0, 0.0) };
        let caster = unit_box(Vec3::new(0.0, 1.0, 0.0), 0.5);
        let bounds = caster_bounds(&light, caster, receivers);
        let Reach::Scaled(scale) = bounds.reach else { panic!("{:?}", bounds.reach) };
        for c in caster.corners() {
            let far = Vec3::new(0.0, 3.0, 0.0) + scale * (c - Vec3::new(0.0, 3.0, 0.0));
            assert!(receivers.distance_to(far) > 0.0, "{far} is still inside the receivers");
        }
    }

    #[test]
    fn a_lamp_over_a_wide_floor_reaches_just_past_the_floor() {
        // The floor's far corners are 70 away, the caster 2.5 from the lamp: scaled to reach
        // them the volume would run 29 times the caster's distance, where its rays leave the
        // floor's slab at under 3 times it.
        let receivers = Aabb { lo: Vec3::new(-50.0, 0.0, -50.0), hi: Vec3::new(50.0, 3.0, 50.0) };
        let lamp = Vec3::new(0.0, 5.0, 0.0);
        let caster = unit_box(Vec3::new(0.5, 2.0, 0.0), 0.5);
        let bounds = caster_bounds(&Light::Point { position: lamp }, caster, receivers);
        let Reach::Scaled(scale) = bounds.reach else { panic!("{:?}", bounds.reach) };
        let margin = MARGIN * receivers.diagonal();
        assert!(scale < (5.0 + margin) / 2.5 + 1e-4, "{scale}");
        for c in caster.corners() {
            let far = lamp + scale * (c - lamp);
            assert!(far.y <= -margin + 1e-4, "{far} is not past the floor by the margin");
        }
    }

    #[test]
    fn a_caster_touching_a_point_light_reaches_infinity() {
        let receivers = unit_box(Vec3::ZERO, 4.0);
        let light = Light::Point { position: Vec3::ZERO };
        let bounds = caster_bounds(&light, unit_box(Vec3::ZERO, 0.5), receivers);
        assert_eq!(bounds, CasterBounds::unbounded(receivers));
    }

    #[test]
    fn a_volume_leaving_the_receivers_has_no_region() {
        // Lit from below: the volume goes up, away from every receiver.
        let receivers = Aabb { lo: Vec3::new(-5.0, -1.0, -5.0), hi: Vec3::new(5.0, 1.0, 5.0) };
        let caster = unit_box(Vec3::new(0.0, 3.0, 0.0), 0.5);
        let light = Light::Directional { direction: Vec3::Y };
        assert_eq!(caster_bounds(&light, caster, receivers).region, None);
    }

    #[test]
    fn screen_rect_of_a_box_in_front_is_its_projection_padded() {
        let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
        let extent = vk::Extent2D { width: 200, height: 100 };
        let rect = screen_rect(&unit_box(Vec3::ZERO, 0.5).corners(), &camera, extent).expect("in view");
        // Centred, as wide as the box's nearest face projects (half-width 0.5 at distance 4.5).
        let f = 1.0 / (25f32.to_radians()).tan();
        let half_width_px = 0.5 / 4.5 * f / 2.0 * 100.0;
        let centre = rect.offset.x as f32 + rect.extent.width as f32 / 2.0;
        assert!((centre - 100.0).abs() <= 1.0, "{rect:?}");
        let half = rect.extent.width as f32 / 2.0;
        assert!(half >= half_width_px && half <= half_width_px + 2.0, "{half} vs {half_width_px}");
    }

    #[test]
    fn disjoint_cover_covers_every_pixel_once() {
        let rect =
            |x, y, width, height| vk::Rect2D { offset: vk::Offset2D { x, y }, extent: vk::Extent2D { width, height } };
        let cases = [
            vec![],
            vec![rect(3, 4, 5, 6)],
            vec![rect(0, 0, 10, 10), rect(5, 5, 10, 10)],
            vec![rect(0, 0, 10, 10), rect(2, 2, 3, 3)],
            vec![rect(0, 0, 4, 20), rect(10, 0, 4, 20), rect(0, 8, 14, 2)],
            vec![rect(1, 1, 7, 3), rect(4, 2, 9, 9), rect(0, 6, 3, 8), rect(11, 0, 2, 2), rect(5, 5, 0, 4)],
        ];
        for rects in cases {
            let inside = |r: &vk::Rect2D, x: i32, y: i32| {
                x >= r.offset.x
                    && y >= r.offset.y
                    && x < r.offset.x + r.extent.width as i32
                    && y < r.offset.y + r.extent.height as i32
            };
            let cover = disjoint_cover(&rects);
            for y in -1..25 {
                for x in -1..25 {
                    let wanted = usize::from(rects.iter().any(|r| inside(r, x, y)));
                    let got = cover.iter().filter(|r| inside(r, x, y)).count();
                    assert_eq!(got, wanted, "pixel ({x}, {y}) of {rects:?}: covered by {cover:?}");
                }
            }
        }
    }

    #[test]
    fn screen_rect_of_a_box_around_the_camera_is_the_frame() {
        let camera = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z);
        let extent = vk::Extent2D { width: 64, height: 48 };
        let rect = screen_rect(&unit_box(Vec3::ZERO, 10.0).corners(), &camera, extent).expect("around the camera");
        assert_eq!(rect, vk::Rect2D { offset: vk::Offset2D { x: 0, y: 0 }, extent });
        // Wholly behind: nothing.
        assert_eq!(screen_rect(&unit_box(Vec3::new(0.0, 0.0, 5.0), 1.0).corners(), &camera, extent), None);
    }
}
