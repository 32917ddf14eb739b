//! The tests compiled into the library (`tests/inside/`): the helpers both builds share
//! (`tests/common/`), and those that reach inside the crate.

#![allow(dead_code)]

#[path = "ray_world.rs"]
pub mod ray_world;
#[path = "../common/mod.rs"]
mod shared;

pub use crate::frame::srgb::{decode as srgb_decode, encode as srgb_encode};
pub use shared::*;

/// A linear colour in [0, 1] as the frame stores it: sRGB-encoded, 8 bits (the frame is
/// R8G8B8A8_SRGB).
pub fn srgb8(colour: glam::Vec3) -> [u8; 3] {
    colour.to_array().map(srgb_encode)
}

/// What lit.frag gives an unshadowed upward-facing surface of `colour` under the scene's
/// directional light: colour x (ambient + (1 - ambient) x max(N.L, 0)), in 8 bits. None under
/// a point light, where it varies over the surface.
pub fn lit_facing_up(scene: &nostencil::Scene, colour: glam::Vec3) -> Option<[u8; 3]> {
    let nostencil::Light::Directional { direction } = scene.light() else { return None };
    let lambert = (-direction.normalize()).dot(glam::Vec3::Y).max(0.0);
    Some(srgb8(colour * (scene.ambient + (1.0 - scene.ambient) * lambert)))
}

/// The lit colour of the scene's ground plane (object "ground"), under a directional light.
pub fn lit_ground(scene: &nostencil::Scene) -> [u8; 3] {
    let ground = scene.object("ground").expect("the scene has a ground");
    lit_facing_up(scene, scene.base_colour(ground)).expect("a directional light")
}

/// RGB within `tolerance` per channel (the GPU's float shading against the CPU's).
pub fn near(a: &[u8], b: &[u8], tolerance: u8) -> bool {
    a.iter().zip(b).take(3).all(|(p, q)| p.abs_diff(*q) <= tolerance)
}

/// The point of the horizontal plane at `height` seen through the centre of pixel (x, y) of a
/// width x height frame, or None where the pixel looks above the horizon.
pub fn ground_point(
    camera: &nostencil::Camera,
    (x, y): (u32, u32),
    (width, height): (u32, u32),
    plane_height: f32,
) -> Option<glam::Vec3> {
    use glam::Vec3;
    let inverse = camera.view_projection(width as f32 / height as f32).inverse();
    let ndc = |px: u32, size: u32| (px as f32 + 0.5) / size as f32 * 2.0 - 1.0;
    let near = inverse.project_point3(Vec3::new(ndc(x, width), ndc(y, height), 0.0));
    let far = inverse.project_point3(Vec3::new(ndc(x, width), ndc(y, height), 0.5));
    let dir = (far - near).normalize();
    let t = (plane_height - near.y) / dir.y;
    (dir.y < 0.0 && t > 0.0).then(|| near + dir * t)
}

/// The convex hull of points, counter-clockwise (monotone chain).
pub fn convex_hull(points: &[glam::Vec2]) -> Vec<glam::Vec2> {
    let mut p = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let mut hull: Vec<glam::Vec2> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &glam::Vec2>> =
            if pass == 0 { Box::new(p.iter()) } else { Box::new(p.iter().rev()) };
        for &q in iter {
            while hull.len() >= start + 2
                && (hull[hull.len() - 1] - hull[hull.len() - 2]).perp_dot(q - hull[hull.len() - 2]) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// Is `p` inside the counter-clockwise convex polygon `hull` (its border included)?
pub fn inside_hull(hull: &[glam::Vec2], p: glam::Vec2) -> bool {
    (0..hull.len()).all(|i| {
        let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
        (b - a).perp_dot(p - a) >= 0.0
    })
}

/// Pixel rows whose centres fall in [top, bottom) (the rasteriser's top-left rule on a
/// horizontal band).
pub fn rows_between(top: f32, bottom: f32) -> Vec<u32> {
    (0..1000u32).filter(|&j| (j as f32 + 0.5) >= top && (j as f32 + 0.5) < bottom).collect()
}

/// Framebuffer y of a world point.
pub fn pixel_y(scene: &nostencil::Scene, point: glam::Vec3, size: (u32, u32)) -> f32 {
    let clip = scene.camera.view_projection(size.0 as f32 / size.1 as f32) * point.extend(1.0);
    (clip.y / clip.w + 1.0) * 0.5 * size.1 as f32
}

/// Every shadow caster's triangles projected along the scene's directional light onto the
/// ground plane y = 0, as (x, z): the analytic outline of its shadow.
///
/// # Panics
/// If the scene's light is not directional.
pub fn caster_triangles_on_ground(scene: &nostencil::Scene) -> Vec<[glam::Vec2; 3]> {
    let nostencil::Light::Directional { direction } = scene.light() else { panic!("directional light") };
    let to_ground = |c: glam::Vec3| {
        let p = c + direction * (c.y / -direction.y);
        glam::Vec2::new(p.x, p.z)
    };
    scene
        .objects
        .iter()
        .filter(|o| o.casts_shadow)
        .flat_map(|o| {
            let mesh = &scene.meshes[o.mesh].data;
            mesh.indices.chunks_exact(3).map(move |t| {
                [t[0], t[1], t[2]].map(|i| to_ground(o.transform.transform_point3(mesh.positions[i as usize])))
            })
        })
        .collect()
}

/// Is `p` inside triangle `t` (either winding, border included)?
pub fn inside_triangle(t: &[glam::Vec2; 3], p: glam::Vec2) -> bool {
    let side = |a: glam::Vec2, b: glam::Vec2| (b - a).perp_dot(p - a);
    let s = [side(t[0], t[1]), side(t[1], t[2]), side(t[2], t[0])];
    s.iter().all(|&d| d >= 0.0) || s.iter().all(|&d| d <= 0.0)
}

/// Whether pixel `pixel` of a `size` frame from `camera` sees the ground (y = 0, inside the
/// built-in scenes' 14 x 14 ground) at a point inside the projected outline `triangles`
/// (from [`caster_triangles_on_ground`]).
pub fn ground_pixel_in_outline(
    camera: &nostencil::Camera,
    pixel: (u32, u32),
    size: (u32, u32),
    triangles: &[[glam::Vec2; 3]],
) -> bool {
    ground_point(camera, pixel, size, 0.0).is_some_and(|p| {
        let p = glam::Vec2::new(p.x, p.z);
        p.x.abs() < 7.0 && p.y.abs() < 7.0 && triangles.iter().any(|t| inside_triangle(t, p))
    })
}

/// Per pixel of two RGBA8 frames of one size: do they differ?
pub fn differing_pixels(a: &[u8], b: &[u8]) -> Vec<bool> {
    a.chunks_exact(4).zip(b.chunks_exact(4)).map(|(p, q)| p != q).collect()
}

/// (intersection, union) of the ground pixels `dark` says are shadowed and those whose ground
/// point lies inside the projected outline `triangles`, over a `size` frame from `camera`,
/// leaving out the pixels `skip` marks (a caster's own pixels).
pub fn outline_overlap(
    camera: &nostencil::Camera,
    size: (u32, u32),
    triangles: &[[glam::Vec2; 3]],
    skip: &[bool],
    dark: impl Fn(usize) -> bool,
) -> (u32, u32) {
    let (mut both, mut either) = (0, 0);
    for y in 0..size.1 {
        for x in 0..size.0 {
            let i = (y * size.0 + x) as usize;
            if skip[i] {
                continue;
            }
            let (expected, dark) = (ground_pixel_in_outline(camera, (x, y), size, triangles), dark(i));
            both += (expected && dark) as u32;
            either += (expected || dark) as u32;
        }
    }
    (both, either)
}

/// Frame uniforms for draws given in clip space: the identity view-projection, no light.
pub fn clip_space_uniforms() -> nostencil::render::FrameUniforms {
    nostencil::render::FrameUniforms {
        view_proj: glam::Mat4::IDENTITY,
        light: glam::Vec4::ZERO,
        camera_position: glam::Vec4::ZERO,
        shading: glam::Vec4::ZERO,
        lights: Default::default(),
    }
}
