//! Shared by the integration tests: a GPU with the validation layer on, and the check that it
//! reported nothing.

#![allow(dead_code)]

use std::sync::Arc;

use nostencil::gpu::{Gpu, GpuOptions};

pub mod raw_vulkan;
pub mod ray_world;
pub mod work_program;
pub mod x_server;

/// A GPU with the Khronos validation layer recording every message (every check), on the
/// device `NOSTENCIL_DEVICE` names or the one chosen automatically.
pub fn gpu() -> Arc<Gpu> {
    let options = GpuOptions { validation: Some(nostencil::ValidationChecks::ALL), ..GpuOptions::default() };
    match Gpu::new(&options) {
        Ok(gpu) => gpu,
        Err(e) => panic!("tests need a Vulkan device with the validation layer (run tools/setup-debian.sh): {e}"),
    }
}

/// Fails the test on any validation message.
pub fn assert_no_validation_messages(gpu: &Gpu) {
    assert!(gpu.validation_enabled(), "validation layer is not on");
    let messages = gpu.validation_messages();
    assert!(messages.is_empty(), "{} validation message(s):\n{}", messages.len(), messages.join("\n"));
}

/// Whether a test that checks lavapipe's own figures (its fragment-count rule, its measured
/// counts) applies to `gpu`. On lavapipe, the device `cargo test` uses, it does. On a device a
/// user chose with `NOSTENCIL_DEVICE` it cannot, and says so on stderr (`--nocapture` shows
/// it). Any other device fails the test, naming it: such a test never passes without checking.
pub fn lavapipe_figures_apply(gpu: &Gpu, figures: &str) -> bool {
    let name = &gpu.device.info.name;
    if name.contains("llvmpipe") {
        return true;
    }
    match std::env::var("NOSTENCIL_DEVICE") {
        Ok(chosen) => {
            eprintln!("SKIPPED: {figures} are lavapipe's; NOSTENCIL_DEVICE={chosen} chose '{name}'");
            false
        }
        Err(_) => {
            panic!("{figures} are lavapipe's, but the test device is '{name}' (set NOSTENCIL_DEVICE to choose it)")
        }
    }
}

/// Runs `body` in a child process of this test binary that runs the one test `path` (its
/// `module::name`), so that `body` may set the process environment (the fill-rate layer tests
/// load the layer into every instance their process creates) without reaching the tests that
/// run beside it in this binary. In that child, runs `body`. The child must report the test
/// passed, so a `path` that names no test fails instead of passing empty.
pub fn in_own_process(path: &str, body: impl FnOnce()) {
    const CHILD: &str = "NOSTENCIL_TEST_IN_OWN_PROCESS";
    if std::env::var(CHILD).is_ok_and(|running| running == path) {
        body();
        return;
    }
    let me = std::env::current_exe().expect("this test binary");
    let output = std::process::Command::new(me)
        .args(["--exact", path, "--nocapture", "--test-threads=1"])
        .env(CHILD, path)
        .output()
        .expect("run the test in a process of its own");
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    print!("{stdout}");
    eprint!("{stderr}");
    assert!(
        output.status.success() && stdout.contains("test result: ok. 1 passed"),
        "{path} in a process of its own did not pass ({})",
        output.status
    );
}

/// Folder for files a test writes (under the target dir, removed and recreated per test name).
pub fn scratch_dir(test: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// The real glTF files in the repository (`tests/assets`, origins and licences in its
/// `SOURCES.md`). A missing folder fails the tests by name instead of skipping them.
pub fn test_assets() -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/assets");
    assert!(dir.is_dir(), "{} not found: the tests need the glTF test assets", dir.display());
    dir
}

/// One file of the test assets; fails the test when it is missing.
pub fn test_asset(name: &str) -> std::path::PathBuf {
    let path = test_assets().join(name);
    assert!(path.is_file(), "{} not found", path.display());
    path
}

/// `nostencil ARGS` as a command, for a test that sets its environment before running it.
pub fn nostencil_command(args: &[&str]) -> std::process::Command {
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_nostencil"));
    command.args(args);
    command
}

/// Runs `nostencil ARGS` and returns its output, whatever its exit status.
pub fn nostencil(args: &[&str]) -> std::process::Output {
    nostencil_command(args).output().expect("run nostencil")
}

/// A run that had to succeed: fails the test, showing stderr, on a non-zero exit or a panic.
/// Returns (stdout, stderr).
pub fn assert_success(what: &str, output: &std::process::Output) -> (String, String) {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "`{what}` failed ({}):\n{stderr}", output.status);
    assert!(!stderr.contains("panicked"), "`{what}` panicked:\n{stderr}");
    (stdout, stderr)
}

/// A run that had to fail: a non-zero exit status (not a signal) and no panic. Returns stderr,
/// for the caller to check the message.
pub fn assert_failure(what: &str, output: &std::process::Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "`{what}` succeeded but had to fail:\n{stderr}");
    assert!(output.status.code().is_some(), "`{what}` was killed ({}):\n{stderr}", output.status);
    assert!(!stderr.contains("panicked"), "`{what}` panicked:\n{stderr}");
    stderr
}

/// Runs `nostencil ARGS`, which must succeed; returns (stdout, stderr).
pub fn run_ok(args: &[&str]) -> (String, String) {
    assert_success(&format!("nostencil {}", args.join(" ")), &nostencil(args))
}

/// Runs `nostencil ARGS`, which must fail cleanly; returns stderr.
pub fn run_err(args: &[&str]) -> String {
    assert_failure(&format!("nostencil {}", args.join(" ")), &nostencil(args))
}

/// A PNG the binary wrote, as RGB.
pub fn read_png(path: &std::path::Path) -> image::RgbImage {
    match image::open(path) {
        Ok(image) => image.to_rgb8(),
        Err(e) => panic!("{}: {e}", path.display()),
    }
}

/// A linear colour in [0, 1] as the frame stores it: sRGB-encoded, 8 bits (the frame is
/// R8G8B8A8_SRGB).
pub fn srgb8(colour: glam::Vec3) -> [u8; 3] {
    colour.to_array().map(srgb_encode)
}

#[allow(unused_imports)] // each test crate uses its own part of `common`
pub use nostencil::frame::srgb::{decode as srgb_decode, encode as srgb_encode};

/// What lit.frag gives an unshadowed upward-facing surface of `colour` under the scene's
/// directional light: colour x (ambient + (1 - ambient) x max(N.L, 0)), in 8 bits. None under
/// a point light, where it varies over the surface.
pub fn lit_facing_up(scene: &nostencil::scene::Scene, colour: glam::Vec3) -> Option<[u8; 3]> {
    let nostencil::scene::Light::Directional { direction } = scene.light() else { return None };
    let lambert = (-direction.normalize()).dot(glam::Vec3::Y).max(0.0);
    Some(srgb8(colour * (scene.ambient + (1.0 - scene.ambient) * lambert)))
}

/// The lit colour of the scene's ground plane (object "ground"), under a directional light.
pub fn lit_ground(scene: &nostencil::scene::Scene) -> [u8; 3] {
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
    camera: &nostencil::scene::Camera,
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
pub fn pixel_y(scene: &nostencil::scene::Scene, point: glam::Vec3, size: (u32, u32)) -> f32 {
    let clip = scene.camera.view_projection(size.0 as f32 / size.1 as f32) * point.extend(1.0);
    (clip.y / clip.w + 1.0) * 0.5 * size.1 as f32
}

/// Every shadow caster's triangles projected along the scene's directional light onto the
/// ground plane y = 0, as (x, z): the analytic outline of its shadow.
///
/// # Panics
/// If the scene's light is not directional.
pub fn caster_triangles_on_ground(scene: &nostencil::scene::Scene) -> Vec<[glam::Vec2; 3]> {
    let nostencil::scene::Light::Directional { direction } = scene.light() else { panic!("directional light") };
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
    camera: &nostencil::scene::Camera,
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
    camera: &nostencil::scene::Camera,
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
