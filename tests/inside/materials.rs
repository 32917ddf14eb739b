//! Materials that show: base colour textures sampled where their UVs say (checked on the CPU by
//! casting each pixel's ray into the mesh), KHR_texture_transform, MASK cut-outs in the scene
//! and in every kind of cast shadow, double-sided faces, BLEND drawn back to front, and every
//! technique binding exactly the material variants its plan declares.

use crate::common;

use nostencil::render::plan::Only;

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use image::RgbaImage;
use nostencil::mesh::MeshData;
use nostencil::render::plan::MaterialVariant;
use nostencil::scene::model::{AlphaMode, Filter, Material, Sampler, TextureRef, TextureRgba8, TextureTransform, Wrap};
use nostencil::StencilMode;
use nostencil::{render_scene, technique as by_name, RenderOptions, TECHNIQUES};
use nostencil::{Camera, Light, Scene};

// ---------------------------------------------------------------------------------------------
// Colour arithmetic of the frame.

fn srgb_decode(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn srgb_encode(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.0031308 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// What the frame stores for a linear colour: sRGB-encoded when the frame's colour format is
/// an _SRGB one, else the linear value.
fn stored(linear: Vec3) -> [u8; 3] {
    let srgb = nostencil::frame::render_pass::COLOUR_FORMAT == ash::vk::Format::R8G8B8A8_SRGB;
    let encode = |c: f32| (if srgb { srgb_encode(c) } else { c.clamp(0.0, 1.0) } * 255.0).round() as u8;
    [encode(linear.x), encode(linear.y), encode(linear.z)]
}

fn rgb(image: &RgbaImage, x: u32, y: u32) -> [u8; 3] {
    let p = image.get_pixel(x, y).0;
    [p[0], p[1], p[2]]
}

fn close(a: [u8; 3], b: [u8; 3], tolerance: u8) -> bool {
    a.iter().zip(b).all(|(p, q)| p.abs_diff(q) <= tolerance)
}

// ---------------------------------------------------------------------------------------------
// Pixel rays on the CPU.

/// The world ray through the centre of pixel (x, y).
fn pixel_ray(camera: &Camera, (x, y): (u32, u32), (width, height): (u32, u32)) -> (Vec3, Vec3) {
    let inverse = camera.view_projection(width as f32 / height as f32).inverse();
    let ndc = |p: u32, size: u32| (p as f32 + 0.5) / size as f32 * 2.0 - 1.0;
    let near = inverse.project_point3(Vec3::new(ndc(x, width), ndc(y, height), 0.0));
    let far = inverse.project_point3(Vec3::new(ndc(x, width), ndc(y, height), 0.5));
    (near, (far - near).normalize())
}

/// The nearest hit of the ray with object `index`'s triangles: (distance, interpolated UV0,
/// face normal).
fn hit(scene: &Scene, index: usize, (origin, dir): (Vec3, Vec3)) -> Option<(f32, Vec2, Vec3)> {
    let object = &scene.objects[index];
    let data = &scene.meshes[object.mesh].data;
    let world: Vec<Vec3> = data.positions.iter().map(|p| object.transform.transform_point3(*p)).collect();
    let mut best: Option<(f32, Vec2, Vec3)> = None;
    for t in data.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let (e1, e2) = (world[b] - world[a], world[c] - world[a]);
        let p = dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-9 {
            continue;
        }
        let s = origin - world[a];
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = dir.dot(q) / det;
        let distance = e2.dot(q) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 || distance <= 0.0 || best.is_some_and(|b| b.0 <= distance) {
            continue;
        }
        let uv = data.uvs[a] * (1.0 - u - v) + data.uvs[b] * u + data.uvs[c] * v;
        best = Some((distance, uv, e1.cross(e2).normalize()));
    }
    best
}

/// The texel containing `uv` (repeat wrap), and whether every texel within `radius` of it has
/// the same colour (so that any filtering the sampler does returns that colour).
fn uniform_texel(texture: &TextureRgba8, uv: Vec2, radius: i32) -> Option<[u8; 4]> {
    let (w, h) = (texture.width as i32, texture.height as i32);
    let (cx, cy) = ((uv.x * w as f32).floor() as i32, (uv.y * h as f32).floor() as i32);
    let at = |x: i32, y: i32| {
        let (x, y) = (x.rem_euclid(w) as usize, y.rem_euclid(h) as usize);
        let i = (y * w as usize + x) * 4;
        [texture.pixels[i], texture.pixels[i + 1], texture.pixels[i + 2], texture.pixels[i + 3]]
    };
    let centre = at(cx, cy);
    for dy in -radius..=radius {
        for dx in -radius..=radius {
            if at(cx + dx, cy + dy) != centre {
                return None;
            }
        }
    }
    Some(centre)
}

// ---------------------------------------------------------------------------------------------
// Scenes built here.

fn scene_looking_at(name: &str, eye: Vec3, target: Vec3, light: Light) -> Scene {
    Scene { background: Vec3::new(0.1, 0.2, 0.3), ..Scene::empty(name, Camera::look_at(eye, target), light) }
}

/// A square of side 2 in the z = 0 plane facing +Z, UV (0, 0) at its top left (-1, 1).
fn square_z() -> MeshData {
    MeshData {
        positions: vec![
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ],
        normals: vec![Vec3::Z; 4],
        uvs: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// A square of side `size` in the y = 0 plane facing +Y, UV (0, 0) at (-x, -z).
fn square_y(size: f32) -> MeshData {
    let h = size * 0.5;
    MeshData {
        positions: vec![Vec3::new(-h, 0.0, -h), Vec3::new(-h, 0.0, h), Vec3::new(h, 0.0, h), Vec3::new(h, 0.0, -h)],
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

fn nearest() -> Sampler {
    Sampler {
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        mag_filter: Filter::Nearest,
        min_filter: Filter::Nearest,
        mipmap_filter: None,
    }
}

/// An n x n texture whose texel (x, y) is `texel(x, y)`.
fn texture(n: u32, texel: impl Fn(u32, u32) -> [u8; 4]) -> TextureRgba8 {
    let pixels = (0..n * n).flat_map(|i| texel(i % n, i / n)).collect();
    TextureRgba8 { name: Some("test".into()), width: n, height: n, pixels, srgb: true, sampler: nearest() }
}

fn options(technique: &str, width: u32, height: u32) -> RenderOptions {
    RenderOptions { width, height, technique: by_name(technique).expect("technique"), ..Default::default() }
}

// ---------------------------------------------------------------------------------------------
// Textures.

#[test]
fn box_textured_pixels_show_the_texels_their_uvs_name() {
    let gpu = common::gpu();
    let path = common::test_assets().join("BoxTextured.glb");
    let mut scene = nostencil::scene_from_gltf(&path, 0.0).expect("BoxTextured");
    // Unlit: the stored colour is the texel's, so the comparison needs no lighting model.
    for material in &mut scene.materials {
        material.unlit = true;
    }
    let (width, height) = (160, 160);
    let image = render_scene(&gpu, &scene, &options("lit", width, height)).expect("frame").output.image;
    let material = scene.material_of(&scene.objects[0]);
    let reference = material.base_color_texture.expect("BoxTextured has a base colour texture");
    let texture = Arc::clone(&scene.textures[reference.texture]);
    let (mut checked, mut colours) = (0, std::collections::HashSet::new());
    for y in 0..height {
        for x in 0..width {
            let ray = pixel_ray(&scene.camera, (x, y), (width, height));
            let Some((_, uv, _)) = hit(&scene, 0, ray) else { continue };
            // The texels one pixel covers (the neighbours' UVs): trilinear filtering reads the
            // mip above that footprint, whose texels span 2^level texels of the base.
            let step = |dx: u32, dy: u32| {
                let ray = pixel_ray(&scene.camera, (x + dx, y + dy), (width, height));
                hit(&scene, 0, ray)
                    .map(|(_, n, _)| ((n - uv) * Vec2::new(texture.width as f32, texture.height as f32)).length())
            };
            let (Some(along), Some(down)) = (step(1, 0), step(0, 1)) else { continue };
            let level = along.max(down).max(1.0).log2().ceil() as u32;
            let radius = 2 * (1i32 << level) + 1;
            // Far from any colour edge at that scale: the sampler's filters and mips all give
            // this texel.
            let Some(texel) = uniform_texel(&texture, uv, radius) else { continue };
            let factor = material.base_color.truncate();
            let linear = Vec3::new(srgb_decode(texel[0]), srgb_decode(texel[1]), srgb_decode(texel[2])) * factor;
            let expected = stored(linear);
            let got = rgb(&image, x, y);
            assert!(close(got, expected, 2), "pixel ({x}, {y}) at UV {uv}: {got:?}, the texel says {expected:?}");
            checked += 1;
            colours.insert(expected);
        }
    }
    assert!(checked > 300, "only {checked} pixels fell on uniform texture regions");
    assert!(colours.len() >= 2, "the checked pixels show one colour only: {colours:?}");
    common::assert_no_validation_messages(&gpu);
}

/// A quad seen face on, unlit, textured by a 4x4 texture of 16 distinct colours.
fn quad_scene(transform: Option<TextureTransform>) -> Scene {
    let mut scene =
        scene_looking_at("quad", Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Light::Directional { direction: -Vec3::Z });
    let t = scene.add_texture(texture(4, |x, y| [(x * 60 + 20) as u8, (y * 60 + 20) as u8, 128, 255]));
    let material = scene.add_material(Material {
        base_color_texture: Some(TextureRef { texture: t, tex_coord: 0, transform }),
        unlit: true,
        ..Material::default()
    });
    let mesh = scene.add_mesh("quad", square_z());
    scene.add_object_with_material("quad", mesh, Mat4::IDENTITY, material, false);
    scene
}

/// Every pixel of the quad has the texel (nearest, repeat) at its UV moved by `transform`.
fn check_quad(image: &RgbaImage, scene: &Scene, transform: Mat4) -> usize {
    let (width, height) = image.dimensions();
    let texture = &scene.textures[0];
    let mut checked = 0;
    for y in 0..height {
        for x in 0..width {
            let Some((_, uv, _)) = hit(scene, 0, pixel_ray(&scene.camera, (x, y), (width, height))) else { continue };
            let moved = transform.transform_point3(uv.extend(0.0)).truncate();
            // Texel edges are left out: there the GPU's and the CPU's rounding may differ.
            let f = (moved * 4.0).fract().abs();
            if f.min_element() < 0.05 || f.max_element() > 0.95 {
                continue;
            }
            let Some(texel) = uniform_texel(texture, moved, 0) else { continue };
            let expected = stored(Vec3::new(srgb_decode(texel[0]), srgb_decode(texel[1]), srgb_decode(texel[2])));
            let got = rgb(image, x, y);
            assert!(close(got, expected, 2), "pixel ({x}, {y}) UV {uv} -> {moved}: {got:?}, expected {expected:?}");
            checked += 1;
        }
    }
    checked
}

#[test]
fn a_texture_transform_offset_moves_the_texels() {
    let gpu = common::gpu();
    let plain = quad_scene(None);
    let offset = TextureTransform { offset: Vec2::new(0.5, 0.25), rotation: 0.0, scale: Vec2::ONE };
    let moved = quad_scene(Some(offset));
    let a = render_scene(&gpu, &plain, &options("lit", 96, 96)).expect("plain").output.image;
    let b = render_scene(&gpu, &moved, &options("lit", 96, 96)).expect("moved").output.image;
    assert!(check_quad(&a, &plain, Mat4::IDENTITY) > 1000);
    let translate = Mat4::from_translation(Vec3::new(0.5, 0.25, 0.0));
    assert!(check_quad(&b, &moved, translate) > 1000);
    let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert!(differing > 1000, "the offset changed only {differing} pixels");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn a_material_on_texcoord_1_reads_the_second_uv_set() {
    let gpu = common::gpu();
    let mut scene = quad_scene(None);
    // UV1 is UV0 moved by half the texture across: the texels move with it when the material
    // names TEXCOORD_1, and stay when it names TEXCOORD_0.
    let uv1 = scene.meshes[0].data.uvs.iter().map(|uv| *uv + Vec2::new(0.5, 0.0)).collect();
    scene.meshes[0].uv1 = Some(uv1);
    let on_uv0 = render_scene(&gpu, &scene, &options("lit", 96, 96)).expect("uv0").output.image;
    assert!(check_quad(&on_uv0, &scene, Mat4::IDENTITY) > 1000);
    if let Some(t) = scene.materials[0].base_color_texture.as_mut() {
        t.tex_coord = 1;
    }
    let on_uv1 = render_scene(&gpu, &scene, &options("lit", 96, 96)).expect("uv1").output.image;
    assert!(check_quad(&on_uv1, &scene, Mat4::from_translation(Vec3::new(0.5, 0.0, 0.0))) > 1000);
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn vertex_colours_and_emissive_reach_the_pixels() {
    let gpu = common::gpu();
    let mut scene =
        scene_looking_at("colours", Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Light::Directional { direction: -Vec3::Z });
    let mesh = scene.add_mesh("quad", square_z());
    scene.meshes[mesh].colors = Some(vec![Vec4::new(0.5, 0.25, 1.0, 1.0); 4]);
    let material = scene.add_material(Material {
        base_color: Vec4::new(0.5, 1.0, 0.5, 1.0),
        emissive: Vec3::new(0.0, 0.0, 0.25),
        unlit: true,
        ..Material::default()
    });
    scene.add_object_with_material("quad", mesh, Mat4::IDENTITY, material, false);
    let image = render_scene(&gpu, &scene, &options("lit", 64, 64)).expect("frame").output.image;
    // factor x COLOR_0 + emissive.
    let expected = stored(Vec3::new(0.25, 0.25, 0.5 + 0.25));
    assert!(close(rgb(&image, 32, 32), expected, 2), "{:?} vs {expected:?}", rgb(&image, 32, 32));
    common::assert_no_validation_messages(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Alpha mask: the cut-out and its shadow.

/// Cells of the checkerboard per side.
const CELLS: u32 = 4;
/// The masked square's side, its height, and how far its shadow is thrown along +X.
const SIDE: f32 = 1.6;
const HEIGHT: f32 = 1.0;
const THROW: f32 = 2.0;

/// A 4 x 4 checkerboard-masked square (cells with x + y even are cut out) held up over a
/// ground, a light throwing its shadow beside it, a camera looking down at both.
fn checkerboard_scene() -> Scene {
    let light = Light::Directional { direction: Vec3::new(THROW, -HEIGHT, 0.0).normalize() };
    let mut scene = scene_looking_at("checkerboard", Vec3::new(1.0, 7.0, 3.5), Vec3::new(1.0, 0.0, 0.0), light);
    let ground = scene.add_mesh("ground", square_y(14.0));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::new(0.8, 0.8, 0.7), false);
    let n = 8;
    let t = scene.add_texture(texture(n, |x, y| {
        let cut = (x * CELLS / n + y * CELLS / n) % 2 == 0;
        [200, 60, 40, if cut { 0 } else { 255 }]
    }));
    let material = scene.add_material(Material {
        base_color_texture: Some(TextureRef { texture: t, tex_coord: 0, transform: None }),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    });
    let square = scene.add_mesh("checkerboard", square_y(SIDE));
    let place = Mat4::from_translation(Vec3::new(-THROW * 0.5, HEIGHT, 0.0));
    // Casts (the shadow map draws casters only): a flat square, so no shadow volume.
    scene.add_object_with_material("checkerboard", square, place, material, true);
    scene
}

/// Centre of checkerboard cell (i, j) on the ground, where the light throws it.
fn shadow_cell_centre(i: u32, j: u32) -> Vec3 {
    let cell = SIDE / CELLS as f32;
    let u = (i as f32 + 0.5) * cell - SIDE * 0.5;
    let v = (j as f32 + 0.5) * cell - SIDE * 0.5;
    Vec3::new(-THROW * 0.5 + u + THROW, 0.0, v)
}

/// The pixel of the frame where world point `p` lands.
fn pixel_of(scene: &Scene, p: Vec3, (width, height): (u32, u32)) -> (u32, u32) {
    let ndc = scene.camera.view_projection(width as f32 / height as f32).project_point3(p);
    (((ndc.x + 1.0) * 0.5 * width as f32) as u32, ((ndc.y + 1.0) * 0.5 * height as f32) as u32)
}

#[test]
fn a_checkerboard_mask_casts_a_checkerboard_shadow() {
    let gpu = common::gpu();
    let scene = checkerboard_scene();
    let size = (160, 160);
    let dir = common::scratch_dir("checkerboard_shadow");
    for technique in ["shadow-map", "shadow-texture-atlas", "planar", "shadow-texture"] {
        let image = render_scene(&gpu, &scene, &options(technique, size.0, size.1)).expect(technique).output.image;
        image.save(dir.join(format!("{technique}.png"))).expect("save, to look at");
        // The lit ground, far from the shadow, is the reference for "lit".
        let (lx, ly) = pixel_of(&scene, Vec3::new(1.0, 0.0, 2.5), size);
        let lit = rgb(&image, lx, ly);
        let mut lit_cells = Vec::new();
        for j in 0..CELLS {
            for i in 0..CELLS {
                let (x, y) = pixel_of(&scene, shadow_cell_centre(i, j), size);
                let here = rgb(&image, x, y);
                let is_lit = close(here, lit, 3);
                let dark = here.iter().zip(lit).all(|(p, q)| (*p as i32) < q as i32 - 20);
                assert!(is_lit || dark, "{technique}: cell ({i}, {j}) is neither lit {lit:?} nor shadowed: {here:?}");
                if is_lit {
                    lit_cells.push((i, j));
                }
            }
        }
        // Cells with i + j even are cut out: their light reaches the ground.
        let expected: Vec<(u32, u32)> =
            (0..CELLS).flat_map(|j| (0..CELLS).map(move |i| (i, j))).filter(|(i, j)| (i + j) % 2 == 0).collect();
        assert_eq!(lit_cells, expected, "{technique}: the lit squares inside the shadow");
    }
    common::assert_no_validation_messages(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Double-sided and blended.

#[test]
fn a_double_sided_square_shows_from_behind() {
    let gpu = common::gpu();
    for double_sided in [false, true] {
        // The camera looks at the square's back.
        let mut scene = scene_looking_at(
            "behind",
            Vec3::new(0.0, 0.0, -3.0),
            Vec3::ZERO,
            Light::Directional { direction: Vec3::Z },
        );
        let material = scene.add_material(Material {
            base_color: Vec4::new(0.9, 0.5, 0.1, 1.0),
            double_sided,
            ..Material::default()
        });
        let mesh = scene.add_mesh("square", square_z());
        scene.add_object_with_material("square", mesh, Mat4::IDENTITY, material, false);
        let image = render_scene(&gpu, &scene, &options("lit", 64, 64)).expect("frame").output.image;
        let background = stored(scene.background);
        let centre = rgb(&image, 32, 32);
        if double_sided {
            // The light shines on the back face, along -normal: lit with the normal flipped.
            let expected = stored(Vec3::new(0.9, 0.5, 0.1));
            assert!(close(centre, expected, 2), "double-sided from behind: {centre:?}, expected {expected:?}");
        } else {
            assert!(close(centre, background, 1), "single-sided from behind is culled: {centre:?}");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn blended_squares_are_drawn_back_to_front() {
    let gpu = common::gpu();
    let mut scene =
        scene_looking_at("blend", Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Light::Directional { direction: -Vec3::Z });
    let mesh = scene.add_mesh("square", square_z());
    let (near, far) = (Vec4::new(1.0, 0.0, 0.0, 0.5), Vec4::new(0.0, 0.0, 1.0, 0.5));
    // The near square first in scene order: drawn in that order, it would hide the far one's
    // blend behind its depth... it writes no depth, but the order would still give the wrong mix.
    for (name, colour, z) in [("near", near, 1.0), ("far", far, 0.0)] {
        let material = scene.add_material(Material {
            base_color: colour,
            alpha_mode: AlphaMode::Blend,
            unlit: true,
            ..Material::default()
        });
        scene.add_object_with_material(name, mesh, Mat4::from_translation(Vec3::new(0.0, 0.0, z)), material, false);
    }
    let image = render_scene(&gpu, &scene, &options("lit", 64, 64)).expect("frame").output.image;
    let over = |dst: Vec3, src: Vec4| src.truncate() * src.w + dst * (1.0 - src.w);
    let back_to_front = over(over(scene.background, far), near);
    let front_to_back = over(over(scene.background, near), far);
    let centre = rgb(&image, 32, 32);
    assert!(close(centre, stored(back_to_front), 3), "{centre:?}, expected {:?}", stored(back_to_front));
    assert!(!close(stored(back_to_front), stored(front_to_back), 10), "the test cannot tell the orders apart");
    common::assert_no_validation_messages(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Every technique, every variant.

/// The default scene with one object of each material kind added (masked, double-sided,
/// blended) and its character double-sided and masked.
fn material_scene() -> Scene {
    let mut scene = nostencil::builtin_scene("default").expect("default scene");
    let t = scene.add_texture(texture(8, |x, y| [220, 200, 90, if (x + y) % 2 == 0 { 0 } else { 255 }]));
    let textured = Some(TextureRef { texture: t, tex_coord: 0, transform: None });
    let kinds = [
        (
            "masked",
            Material {
                base_color_texture: textured,
                alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
                ..Material::default()
            },
        ),
        (
            "double-sided",
            Material { base_color: Vec4::new(0.3, 0.8, 0.4, 1.0), double_sided: true, ..Material::default() },
        ),
        (
            "blended",
            Material { base_color: Vec4::new(0.9, 0.2, 0.6, 0.5), alpha_mode: AlphaMode::Blend, ..Material::default() },
        ),
    ];
    // The skinned character double-sided and masked (untextured: nothing is cut): the planar
    // techniques' GPU-skinned scene and caster variants too.
    let character = scene.object("character").expect("the default scene's character").material;
    scene.materials[character].double_sided = true;
    scene.materials[character].alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
    let square = scene.add_mesh("square", square_z());
    for (i, (name, material)) in kinds.into_iter().enumerate() {
        let material = scene.add_material(material);
        let place =
            Mat4::from_translation(Vec3::new(-2.0 + 2.0 * i as f32, 1.2, 2.2)) * Mat4::from_scale(Vec3::splat(0.5));
        scene.add_object_with_material(name, square, place, material, false);
    }
    scene
}

#[test]
fn every_technique_binds_the_variants_its_materials_need_and_matches_its_reference() {
    let gpu = common::gpu();
    let scene = material_scene();
    let surfaces: Vec<MaterialVariant> =
        scene.objects.iter().filter_map(|o| MaterialVariant::for_surface(scene.material_of(o))).collect();
    for technique in TECHNIQUES {
        let emulated = RenderOptions { width: 96, height: 72, technique: *technique, ..Default::default() };
        let mut renderer = technique.build(&gpu, &scene, &emulated).expect("renderer");
        let plan = renderer.plan().clone();
        let frame = renderer.frame_with(&scene).expect("frame");
        drop(renderer);
        for (name, bound) in &frame.output.trace {
            let pass = plan.passes.iter().find(|p| p.name == *name).expect("a planned pass");
            // Every pipeline bound is planned; every one that is not a material variant is bound,
            // or else a variant of it (all the objects it draws need one: the character).
            for label in bound {
                assert!(pass.pipelines.iter().any(|d| d.name == *label), "{name}: '{label}' is not planned");
            }
            for (desc, variant) in pass.pipelines.iter().zip(&pass.variants) {
                let stand_in = |i: usize| pass.bases[i] == desc.name && bound.contains(&pass.pipelines[i].name);
                // A pass of blended objects only draws none of the opaque ones (the character).
                if variant.is_none() && pass.only != Only::Blended {
                    assert!(
                        bound.contains(&desc.name)
                            || (0..pass.pipelines.len()).any(|i| pass.variants[i].is_some() && stand_in(i)),
                        "{}: {name} bound neither '{}' nor a variant of it",
                        technique.name(),
                        desc.name
                    );
                }
            }
            // A pass drawing objects binds the variants their materials need, and no other (a
            // variant may exist for several pipelines: static and skinned objects). The additive
            // loop's passes draw the opaque and cut-out objects, its last the blended ones.
            if pass.draws.describe() == "objects" {
                use MaterialVariant::*;
                for v in [Masked, DoubleSided, Blend, BlendDoubleSided] {
                    let blended = matches!(v, Blend | BlendDoubleSided);
                    let drawn = match pass.only {
                        Only::All => true,
                        Only::Opaque => !blended,
                        Only::Blended => blended,
                    };
                    let used = pass
                        .pipelines
                        .iter()
                        .zip(&pass.variants)
                        .any(|(d, w)| *w == Some(v) && bound.contains(&d.name));
                    assert_eq!(used, drawn && surfaces.contains(&v), "{}: {name}, variant {v:?}", technique.name());
                }
            }
        }
        let reference = RenderOptions { stencil: StencilMode::Reference, ..emulated.clone() };
        let a = render_scene(&gpu, &scene, &emulated).expect("emulated").output.image;
        let b = render_scene(&gpu, &scene, &reference).expect("reference").output.image;
        let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
        assert_eq!(differing, 0, "{}: {differing} pixels differ from the stencil reference", technique.name());
    }
    common::assert_no_validation_messages(&gpu);
}
