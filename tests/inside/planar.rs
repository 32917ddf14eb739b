//! Planar projected shadows (seed 001): the one-pass alpha trick equals the real-stencil
//! reference pixel for pixel; every shadowed pixel is darkened exactly once by the same factor;
//! the GPU projection lands where the CPU formula says; GPU skinning matches the CPU oracle; and
//! real glTF files render with animated shadows. With several lights (the additive loop), each
//! light's projected shadow removes only that light, as the CPU's projection says, and the
//! emulated loop equals Ogre's stencil loop on every built-in scene.

use crate::common::{self, technique};

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use image::RgbaImage;
use nostencil::technique::planar::{self, project_onto_plane, GivenPlane, PlanarOptions, Plane, TextureShadowOn};
use nostencil::Gpu;
use nostencil::Light;
use nostencil::StencilMode;
use nostencil::{builtin_scene_at, scene_from_gltf, Scene};
use nostencil::{render_scene, RenderOptions, ShadowMode, Technique, TechniqueFrame};

const SIZE: (u32, u32) = (160, 120);
/// The default shadow tone, grey: shadowed colour x 102/255.
const FACTOR: u8 = nostencil::technique::ShadowTone::DEFAULT_FACTOR;

fn render(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, shadows: bool) -> TechniqueFrame {
    let options = PlanarOptions { shadows, ..Default::default() };
    render_with(gpu, scene, technique("planar"), SIZE, stencil, options).expect("planar frame")
}

/// Renders `scene` with one of the seed 001 techniques, as the seed draws it (`--shadow-mode
/// modulate`: the lit frame darkened by one factor; the additive loop's tests are in `planar/additive.rs`).
fn render_with(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    technique: Technique,
    (width, height): (u32, u32),
    stencil: StencilMode,
    planar: PlanarOptions,
) -> nostencil::error::Result<TechniqueFrame> {
    let shadow_mode = ShadowMode::Modulate;
    render_scene(
        gpu,
        scene,
        &RenderOptions { width, height, stencil, technique, planar, shadow_mode, ..Default::default() },
    )
}

fn rgb_differences(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p[..3] != q[..3]).count()
}

/// What the blend unit computes for `x * f/255` on the sRGB frame: the stored value decoded to
/// linear light, multiplied by the destination alpha f/255 (linear UNORM8), encoded again.
/// Vulkan lets the encode be approximate (lavapipe's is a polynomial): compare with
/// [`darkened_once`], which allows that 1/255.
fn darken(x: u8, f: u8) -> u8 {
    common::srgb_encode(common::srgb_decode(x) * (f as f32 / 255.0))
}

/// `p` is `q` darkened once by `f`, up to the sRGB encoder's rounding. Twice would be at least
/// 2/255 further for every channel value above 6 (checked in the tests that use it).
fn darkened_once(p: &[u8], q: &[u8], f: u8) -> bool {
    (0..3).all(|c| p[c].abs_diff(darken(q[c], f)) <= 1)
}

/// The pixels the projected shadow darkened (RGB differs from the frame without shadows).
fn changed(shadowed: &RgbaImage, unshadowed: &RgbaImage) -> Vec<bool> {
    shadowed.chunks_exact(4).zip(unshadowed.chunks_exact(4)).map(|(p, q)| p[..3] != q[..3]).collect()
}

/// Receiver pixels: the scene pass alone writes alpha F/255 there and 1 everywhere else.
fn receiver_mask(unshadowed: &RgbaImage) -> Vec<bool> {
    unshadowed.chunks_exact(4).map(|p| p[3] == FACTOR).collect()
}

/// Rasterises triangles given in world space after projection onto the plane, with the frame's
/// camera, at pixel centres: the CPU's idea of where the shadow is.
fn cpu_shadow_mask(scene: &Scene, triangles: &[[Vec3; 3]]) -> Vec<bool> {
    let (w, h) = SIZE;
    let view_proj = scene.camera.view_projection(w as f32 / h as f32);
    let to_pixel = |p: Vec3| {
        let c = view_proj * p.extend(1.0);
        let ndc = c.truncate() / c.w;
        glam::Vec2::new((ndc.x * 0.5 + 0.5) * w as f32, (ndc.y * 0.5 + 0.5) * h as f32)
    };
    let mut mask = vec![false; (w * h) as usize];
    for tri in triangles {
        let [a, b, c] = tri.map(to_pixel);
        let edge = |p: glam::Vec2, q: glam::Vec2, r: glam::Vec2| (q - p).perp_dot(r - p);
        let area = edge(a, b, c);
        if area.abs() < 1e-9 {
            continue;
        }
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        for y in (lo.y.floor().max(0.0) as u32)..(hi.y.ceil().min(h as f32) as u32) {
            for x in (lo.x.floor().max(0.0) as u32)..(hi.x.ceil().min(w as f32) as u32) {
                let p = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let (e0, e1, e2) = (edge(b, c, p) / area, edge(c, a, p) / area, edge(a, b, p) / area);
                if e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0 {
                    mask[(y * w + x) as usize] = true;
                }
            }
        }
    }
    mask
}

/// Every caster triangle (CPU-skinned positions) projected onto the receiving plane.
fn projected_triangles(scene: &Scene, objects: impl Fn(usize) -> bool, h: f32) -> Vec<[Vec3; 3]> {
    let mut out = Vec::new();
    for (_, o) in scene.objects.iter().enumerate().filter(|(i, _)| objects(*i)) {
        let data = &scene.meshes[o.mesh].data;
        let world =
            |v: u32| project_onto_plane(o.transform.transform_point3(data.positions[v as usize]), &scene.light(), h);
        for t in data.indices.chunks_exact(3) {
            out.push([world(t[0]), world(t[1]), world(t[2])]);
        }
    }
    out
}

/// Pixels whose 3x3 neighbourhood agrees in `mask`: away from the shadow's edge, where the
/// GPU's and the CPU's rasterisations cannot disagree by rounding.
fn interior(mask: &[bool], x: u32, y: u32) -> bool {
    let (w, h) = SIZE;
    let centre = mask[(y * w + x) as usize];
    (y.saturating_sub(1)..(y + 2).min(h))
        .all(|yy| (x.saturating_sub(1)..(x + 2).min(w)).all(|xx| mask[(yy * w + xx) as usize] == centre))
}

/// Character vertex ranges, in the order `character.rs` builds its boxes (24 vertices each).
const TORSO: std::ops::Range<usize> = 0..24;
const RIGHT_ARM: std::ops::Range<usize> = 72..96;
const LEFT_ARM: std::ops::Range<usize> = 48..72;

fn character_part_triangles(scene: &Scene, part: std::ops::Range<usize>, h: f32) -> Vec<[Vec3; 3]> {
    let o = scene.object("character").expect("character");
    let data = &scene.meshes[o.mesh].data;
    let world =
        |v: u32| project_onto_plane(o.transform.transform_point3(data.positions[v as usize]), &scene.light(), h);
    data.indices
        .chunks_exact(3)
        .filter(|t| part.contains(&(t[0] as usize)))
        .map(|t| [world(t[0]), world(t[1]), world(t[2])])
        .collect()
}

#[test]
fn emulated_equals_reference_where_arms_and_torso_overlap_in_the_shadow() {
    let gpu = common::gpu();
    let mut overlap_checked = 0;
    for name in ["character", "character-point", "default", "point-light"] {
        for time in [0.0, 0.2, 0.45, 0.7] {
            let scene = builtin_scene_at(name, time).expect("scene");
            let reference = render(&gpu, &scene, StencilMode::Reference, true);
            let emulated = render(&gpu, &scene, StencilMode::Emulated, true);
            let unshadowed = render(&gpu, &scene, StencilMode::Emulated, false);
            let shadowed: usize =
                changed(&emulated.output.image, &unshadowed.output.image).iter().filter(|c| **c).count();
            assert!(shadowed > 30, "{name} at {time}s: no shadow ({shadowed} pixels)");
            let differing = rgb_differences(&emulated.output.image, &reference.output.image);
            assert_eq!(differing, 0, "{name} at {time}s: {differing} pixels differ from the reference");

            // The shadow pass wrote more samples than there are shadowed pixels: overlaps happened
            // (front and back faces, limbs over the torso), and the reference's stencil let one
            // sample per receiver pixel through.
            let samples = |f: &TechniqueFrame| {
                f.output
                    .counters
                    .passes
                    .iter()
                    .filter(|p| p.name.starts_with("planar shadow"))
                    .map(|p| p.samples_passed)
                    .sum::<u64>()
            };
            assert!(samples(&emulated) as usize > shadowed * 3 / 2, "{name} at {time}s: no overlap to stop");
            assert!(samples(&reference) < samples(&emulated), "{name} at {time}s: the stencil stopped nothing");

            // Where an arm's shadow lies on the torso's, on visible ground, the pixel is darkened
            // once, like its neighbours.
            if name.starts_with("character") {
                let h = planar::receiver_plane(&scene, None).expect("plane").height;
                let torso = cpu_shadow_mask(&scene, &character_part_triangles(&scene, TORSO, h));
                let receivers = receiver_mask(&unshadowed.output.image);
                for arm in [LEFT_ARM, RIGHT_ARM] {
                    let arm = cpu_shadow_mask(&scene, &character_part_triangles(&scene, arm, h));
                    for (i, ((a, t), r)) in arm.iter().zip(&torso).zip(&receivers).enumerate() {
                        let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
                        if *a && *t && *r && interior(&arm, x, y) && interior(&torso, x, y) {
                            let (p, q) =
                                (&emulated.output.image.as_raw()[i * 4..], &unshadowed.output.image.as_raw()[i * 4..]);
                            assert!(
                                darkened_once(p, q, FACTOR),
                                "{name} {time}s pixel ({x},{y}): {:?} from {:?}",
                                &p[..3],
                                &q[..3]
                            );
                            overlap_checked += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(overlap_checked > 60, "arm-over-torso shadow pixels checked: {overlap_checked}");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn every_shadowed_pixel_is_darkened_by_exactly_the_same_factor_and_only_on_receivers() {
    let gpu = common::gpu();
    for (name, time) in [("character", 0.2), ("default", 0.45), ("point-light", 0.7)] {
        let scene = builtin_scene_at(name, time).expect("scene");
        let unshadowed = render(&gpu, &scene, StencilMode::Emulated, false);
        let shadowed = render(&gpu, &scene, StencilMode::Emulated, true);
        let receivers = receiver_mask(&unshadowed.output.image);
        let mut darkened = 0;
        for (i, (p, q)) in
            shadowed.output.image.chunks_exact(4).zip(unshadowed.output.image.chunks_exact(4)).enumerate()
        {
            if p[..3] == q[..3] {
                continue;
            }
            assert!(receivers[i], "{name}: pixel {i} changed but no receiver is visible there");
            assert!(darkened_once(p, q, FACTOR), "{name}: pixel {i} ({q:?} to {p:?}) is not darkened exactly once");
            darkened += 1;
        }
        assert!(darkened > 100, "{name}: only {darkened} shadowed pixels");
        // The same check would catch double darkening: it changes every non-black pixel.
        assert!((7u8..=255).all(|x| darken(darken(x, FACTOR), FACTOR).abs_diff(darken(x, FACTOR)) > 1));
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn the_gpu_projection_lands_where_the_cpu_formula_says() {
    let gpu = common::gpu();
    for (name, time) in [("character", 0.3), ("character-point", 0.3), ("character-point", 0.8)] {
        let scene = builtin_scene_at(name, time).expect("scene");
        let plane = planar::receiver_plane(&scene, None).expect("plane");
        let unshadowed = render(&gpu, &scene, StencilMode::Emulated, false);
        let shadowed = render(&gpu, &scene, StencilMode::Emulated, true);
        let gpu_mask = changed(&shadowed.output.image, &unshadowed.output.image);
        let receivers = receiver_mask(&unshadowed.output.image);
        let cpu_mask = cpu_shadow_mask(&scene, &projected_triangles(&scene, |i| !plane.receivers[i], plane.height));
        let (mut inside, mut mismatches, mut occluded) = (0, Vec::new(), 0);
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let i = (y * SIZE.0 + x) as usize;
                if !receivers[i] && cpu_mask[i] && interior(&cpu_mask, x, y) {
                    // The character stands in front of its own shadow here: the pixel must stay.
                    assert!(!gpu_mask[i], "{name}: the shadow was drawn over an occluder at ({x},{y})");
                    occluded += 1;
                }
                if !receivers[i] || !interior(&cpu_mask, x, y) {
                    continue;
                }
                inside += cpu_mask[i] as usize;
                if cpu_mask[i] != gpu_mask[i] {
                    mismatches.push((x, y, cpu_mask[i]));
                }
            }
        }
        assert!(inside > 100, "{name}: only {inside} shadow pixels compared");
        assert!(occluded > 10, "{name}: no occluder in front of the shadow to test ({occluded} pixels)");
        assert!(mismatches.is_empty(), "{name} at {time}s: GPU and CPU shadows disagree at {mismatches:?}");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn gpu_skinning_matches_the_cpu_skinned_mesh() {
    let gpu = common::gpu();
    let lit = |scene: &Scene| {
        let options =
            RenderOptions { width: SIZE.0, height: SIZE.1, technique: technique("lit"), ..Default::default() };
        render_scene(&gpu, scene, &options).expect("lit").output.image
    };
    let large_differences = |a: &RgbaImage, b: &RgbaImage| {
        a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 3)).count()
    };
    for (name, time) in [("character", 0.0), ("character", 0.3), ("character-point", 0.65)] {
        let scene = builtin_scene_at(name, time).expect("scene");
        let gpu_skinned = render(&gpu, &scene, StencilMode::Emulated, false).output.image;
        let cpu_skinned = lit(&scene);
        let mut empty = scene.clone();
        empty.objects.retain(|o| o.skin.is_none());
        let silhouette = rgb_differences(&cpu_skinned, &lit(&empty));
        assert!(silhouette > 500, "{name}: the character covers only {silhouette} pixels");
        let off = large_differences(&gpu_skinned, &cpu_skinned);
        assert!(off * 100 <= silhouette, "{name} at {time}s: {off} of {silhouette} character pixels differ");
        // The check can fail: the CPU mesh of another time is far off.
        let other = builtin_scene_at(name, time + 0.25).expect("scene");
        assert!(large_differences(&gpu_skinned, &lit(&other)) * 10 > silhouette);
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn every_test_asset_renders_with_planar_shadows_animated_ones_moving() {
    let gpu = common::gpu();
    let dir = common::test_assets();
    let entries = std::fs::read_dir(&dir).expect("read the test assets");
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "glb" || e == "gltf"))
        .collect();
    files.sort();
    assert!(files.len() >= 7, "{files:?}");
    for path in &files {
        let file = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
        let mut shadows = Vec::new();
        for time in [0.25, 0.9] {
            let scene = scene_from_gltf(path, time).unwrap_or_else(|e| panic!("{file}: {e}"));
            let emulated = render(&gpu, &scene, StencilMode::Emulated, true);
            let reference = render(&gpu, &scene, StencilMode::Reference, true);
            let unshadowed = render(&gpu, &scene, StencilMode::Emulated, false);
            assert_eq!(rgb_differences(&emulated.output.image, &reference.output.image), 0, "{file} at {time}s");
            // The additive loop on the same content (skins, cut-outs, blended materials).
            let loop_emulated = additive(&gpu, &scene, SIZE, StencilMode::Emulated, 1);
            let loop_reference = additive(&gpu, &scene, SIZE, StencilMode::Reference, 1);
            let differing = rgb_differences(&loop_emulated.output.image, &loop_reference.output.image);
            assert_eq!(differing, 0, "{file} at {time}s, additive: {differing} pixels differ from the reference");
            let mask = changed(&emulated.output.image, &unshadowed.output.image);
            assert!(mask.iter().filter(|m| **m).count() > 20, "{file} at {time}s: no visible planar shadow");
            let skinned = scene.objects.iter().filter(|o| o.skin.is_some()).count();
            assert_eq!(skinned > 0, file == "RiggedSimple.glb" || file == "SimpleSkin.gltf", "{file}: skinned objects");
            shadows.push(mask);
        }
        let moved = shadows[0].iter().zip(&shadows[1]).filter(|(a, b)| a != b).count();
        let animated = matches!(file.as_str(), "RiggedSimple.glb" | "SimpleSkin.gltf" | "BoxAnimated.glb");
        if animated {
            assert!(moved > 10, "{file}: the shadow does not follow the animation ({moved} pixels)");
        } else {
            assert_eq!(moved, 0, "{file}: not animated, yet the shadow moved");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// Every caster triangle (CPU-skinned positions) projected by `project`.
fn triangles_projected_by(
    scene: &Scene,
    objects: impl Fn(usize) -> bool,
    project: impl Fn(Vec3) -> Vec3,
) -> Vec<[Vec3; 3]> {
    let mut out = Vec::new();
    for (_, o) in scene.objects.iter().enumerate().filter(|(i, _)| objects(*i)) {
        let data = &scene.meshes[o.mesh].data;
        let world = |v: u32| project(o.transform.transform_point3(data.positions[v as usize]));
        for t in data.indices.chunks_exact(3) {
            out.push([world(t[0]), world(t[1]), world(t[2])]);
        }
    }
    out
}

/// Intersection over union of two masks, counted where `inside` holds.
fn iou(a: &[bool], b: &[bool], inside: &[bool]) -> f64 {
    let (mut both, mut either) = (0usize, 0usize);
    for ((a, b), i) in a.iter().zip(b).zip(inside) {
        if *i {
            both += (*a && *b) as usize;
            either += (*a || *b) as usize;
        }
    }
    both as f64 / either.max(1) as f64
}

/// Renders `scene` with planar shadows in the additive loop (the default mode).
fn additive(gpu: &Arc<Gpu>, scene: &Scene, size: (u32, u32), stencil: StencilMode, samples: u32) -> TechniqueFrame {
    let (width, height) = size;
    let options =
        RenderOptions { width, height, stencil, samples, technique: technique("planar"), ..Default::default() };
    render_scene(gpu, scene, &options).expect("additive planar frame")
}

// The tests by topic, beside those above.
#[path = "planar/additive.rs"]
mod additive;
#[path = "planar/textures_blobs_and_cli.rs"]
mod textures_blobs_and_cli;
#[path = "planar/tilted_and_simplified.rs"]
mod tilted_and_simplified;
