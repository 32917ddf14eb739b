//! `nostencil view` in a real window: an Xvfb server started by the test, lavapipe, the
//! validation layer on. The viewer renders frames, resizes its window, and its screenshot (read
//! back from the presented swapchain image, BGRA on X11) must equal `nostencil render` of the
//! same scene, technique and size, pixel for pixel. Keys switch techniques live, and closing the
//! window (destroying it under the swapchain: a lost surface) ends the viewer cleanly.
//! The X server itself dying ends the viewer with an error and no panic or hang.
//!
//! Needs Xvfb and xdotool (tools/setup-debian.sh installs them): without them the tests fail
//! saying so rather than skip.

use crate::common;

use common::x_server::{start_x_server, XServer};

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Starts `nostencil ARGS` on the X server.
fn spawn_on(x: &XServer, args: &[&str]) -> Child {
    Command::new(common::program())
        .args(args)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run nostencil")
}

/// Runs `nostencil` on the X server and waits for it, at most two minutes.
fn run(x: &XServer, args: &[&str]) -> Output {
    wait_with_timeout(spawn_on(x, args), Duration::from_secs(120))
}

fn wait_with_timeout(mut child: Child, limit: Duration) -> Output {
    let start = Instant::now();
    loop {
        if child.try_wait().expect("poll nostencil").is_some() {
            return child.wait_with_output().expect("collect output");
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let output = child.wait_with_output().expect("collect output");
            panic!("nostencil did not finish in {limit:?}; stderr:\n{}", stderr(&output));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn assert_clean(output: &Output, what: &str) {
    let err = stderr(output);
    assert!(output.status.success(), "{what} failed:\n{err}");
    assert!(!err.contains("vulkan validation"), "{what}: validation messages:\n{err}");
    assert!(!err.contains("panicked"), "{what}: panic:\n{err}");
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8()
}

#[test]
fn screenshot_after_a_resize_equals_the_offscreen_render() {
    let x = start_x_server();
    let dir = common::scratch_dir("viewer-screenshot");
    // (scene, extra options): every technique; for shadow volumes both stencil paths and the
    // normalisation through an input attachment, whose render pass has the feedback loop.
    let cases: [(&str, &[&str]); 14] = [
        ("default", &["--technique", "shadow-volume"]),
        // One sample: drawn into the swapchain image itself; and the subpass normalisation,
        // which reads its own colour, drawn offscreen and copied in (the fallback, said).
        ("default", &["--technique", "shadow-volume", "--samples", "1"]),
        (
            "overlap",
            &["--technique", "shadow-volume", "--normalize", "subpass", "--shadow-mode", "modulate", "--samples", "1"],
        ),
        ("point-light", &["--technique", "shadow-volume", "--stencil", "reference"]),
        ("overlap", &["--technique", "shadow-volume", "--normalize", "subpass", "--increment", "2"]),
        ("default", &["--technique", "lit"]),
        ("outline", &["--technique", "outline"]),
        ("duck", &["--technique", "silhouette", "--stencil", "reference"]),
        ("default", &["--technique", "toon", "--silhouette", "hull"]),
        ("character", &["--technique", "planar", "--stencil", "reference", "--time", "0.4"]),
        ("default", &["--technique", "blob"]),
        ("character-point", &["--technique", "shadow-texture"]),
        ("default", &["--technique", "shadow-map"]),
        ("atlas-one", &["--technique", "shadow-texture-atlas"]),
    ];
    for (index, (scene, technique)) in cases.iter().enumerate() {
        let shot = dir.join(format!("view-{index}.png"));
        let reference = dir.join(format!("render-{index}.png"));
        let mut args = vec!["view", "--validation", "--device", "lavapipe", "--paused", "--scene", scene];
        args.extend_from_slice(technique);
        // Opens at 160x120, renders 2 frames, asks for 128x96, then 4 more frames once the
        // swapchain has the new size; the screenshot is the last presented image.
        args.extend_from_slice(&["--size", "160x120", "--resize-after", "2", "128x96", "--frames", "6"]);
        args.extend_from_slice(&["--screenshot", shot.to_str().unwrap()]);
        let output = run(&x, &args);
        assert_clean(&output, &format!("view {scene} {technique:?}"));
        let err = stderr(&output);
        assert!(err.contains("swapchain 160x120"), "no first swapchain at 160x120:\n{err}");
        assert!(err.contains("swapchain 128x96"), "the swapchain was not recreated at 128x96:\n{err}");
        assert!(err.contains("frames drawn into its images"), "not drawn into the swapchain images:\n{err}");
        let fallback = technique.contains(&"subpass") && technique.contains(&"1");
        assert_eq!(
            err.contains("(the fallback)"),
            fallback,
            "{scene} {technique:?}: the fallback is named when used:\n{err}"
        );

        let mut args = vec!["render", "--validation", "--device", "lavapipe", "--scene", scene, "--size", "128x96"];
        args.extend_from_slice(technique);
        args.extend_from_slice(&["--out", reference.to_str().unwrap()]);
        assert_clean(&common::nostencil(&args), "render");

        let (viewed, rendered) = (rgb(&shot), rgb(&reference));
        assert_eq!(viewed.dimensions(), (128, 96), "screenshot size");
        let differing = viewed.pixels().zip(rendered.pixels()).filter(|(a, b)| a != b).count();
        assert_eq!(differing, 0, "{scene} {technique:?}: {differing} pixels differ from `nostencil render`");
        // Not a blank frame (flat Lambert shading of the lit scene alone gives a dozen colours).
        let distinct: std::collections::HashSet<_> = viewed.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 8, "{scene} {technique:?}: only {} distinct colours", distinct.len());
    }
}

/// Waits for the viewer's window; if the viewer exits or never shows one, fails with its stderr.
fn wait_for_window(x: &XServer, mut child: Child) -> (Child, String) {
    let start = Instant::now();
    loop {
        if let Some(id) = xdotool(x, &["search", "--name", "^nostencil view"]).lines().next() {
            return (child, id.to_owned());
        }
        let exited = child.try_wait().expect("poll nostencil").is_some();
        if exited || start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let output = child.wait_with_output().expect("collect output");
            panic!("the viewer's window never appeared ({}); stderr:\n{}", output.status, stderr(&output));
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Waits until the window titled "nostencil view..." shows `wanted` in its title.
fn wait_for_title(x: &XServer, window: &str, wanted: &str) -> String {
    let start = Instant::now();
    let mut title = String::new();
    while start.elapsed() < Duration::from_secs(60) {
        title = xdotool(x, &["getwindowname", window]);
        if title.contains(wanted) {
            return title;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    panic!("the title never showed '{wanted}'; last: {title}");
}

/// The number the title shows before `unit` ("1.69 fragments/px" -> 1.69).
fn per_pixel(title: &str, unit: &str) -> f64 {
    let before = title.split(unit).next().filter(|b| b.len() < title.len());
    before
        .and_then(|b| b.trim_end().rsplit(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("no {unit} in the title: {title}"))
}

fn xdotool(x: &XServer, args: &[&str]) -> String {
    let output =
        Command::new("xdotool").args(args).env("DISPLAY", &x.display).output().unwrap_or_else(|e| {
            panic!("xdotool is needed to drive the window (tools/setup-debian.sh installs it): {e}")
        });
    String::from_utf8_lossy(&output.stdout).trim().to_owned()
}

#[test]
fn keys_switch_the_technique_live_and_closing_the_window_ends_cleanly() {
    let x = start_x_server();
    let child =
        spawn_on(&x, &["view", "--validation", "--device", "lavapipe", "--size", "160x120", "--technique", "lit"]);

    let (child, window) = wait_for_window(&x, child);
    let lit_title = wait_for_title(&x, &window, "lit (emulated)");
    // No window manager: keys go to the focused window.
    xdotool(&x, &["windowfocus", &window]);
    assert!(lit_title.contains("ms GPU"), "title without GPU time: {lit_title}");

    // T: shadow volumes; S: the real-stencil reference; N (after S back): max normalisation.
    xdotool(&x, &["key", "t"]);
    wait_for_title(&x, &window, "shadow-volume (emulated, seed");
    xdotool(&x, &["key", "s"]);
    wait_for_title(&x, &window, "shadow-volume (reference");
    xdotool(&x, &["key", "s", "n"]);
    let title = wait_for_title(&x, &window, "shadow-volume (emulated, max");
    // The emulated frame's passes (volumes, normalisation, apply) cost several times the
    // fragments of the lit frame the viewer opened with.
    let (lit, emulated) = (per_pixel(&lit_title, "fragments/px"), per_pixel(&title, "fragments/px"));
    assert!(emulated > 2.0 * lit, "lit: {lit_title}\nshadow-volume: {title}");

    // Every other technique, live while the casters turn (each frame a moved pose of the scene);
    // O and B the outline's copy and blur, E and L the cartoon silhouette method and the atlas
    // light; Shift+T goes back.
    for technique in ["outline", "silhouette", "toon", "planar", "blob", "shadow-texture", "shadow-map"] {
        xdotool(&x, &["key", "t"]);
        let title = wait_for_title(&x, &window, &format!("| {technique} (emulated"));
        assert!(per_pixel(&title, "fragments/px") > 0.5, "{title}");
        if technique == "outline" {
            // O: the document's scaled copy; B: blurred (offscreen mask and blur passes, live).
            xdotool(&x, &["key", "o"]);
            wait_for_title(&x, &window, "outline (emulated, scale)");
            xdotool(&x, &["key", "b"]);
            wait_for_title(&x, &window, "outline (emulated, scale, blur 4)");
        }
        if technique == "silhouette" {
            xdotool(&x, &["key", "e"]);
            wait_for_title(&x, &window, "silhouette (emulated, shader)");
        }
    }
    xdotool(&x, &["key", "t", "l"]);
    wait_for_title(&x, &window, "shadow-texture-atlas (emulated, moving light)");
    xdotool(&x, &["key", "T"]);
    // The light mode is a setting of its own: the shadow map now turns its light too.
    wait_for_title(&x, &window, "shadow-map (emulated, moving light)");

    xdotool(&x, &["key", "space"]);
    wait_for_title(&x, &window, "paused");

    // Another client destroys the window: the swapchain's surface is lost mid-run.
    xdotool(&x, &["windowclose", &window]);
    let output = wait_with_timeout(child, Duration::from_secs(60));
    assert_clean(&output, "view after its window was destroyed");
}

#[test]
fn without_a_display_the_viewer_fails_in_one_line_and_offscreen_commands_still_work() {
    let dir = common::scratch_dir("viewer-no-display");
    let nostencil = || {
        let mut command = Command::new(common::program());
        command.env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY");
        command
    };
    let output = nostencil().args(["view", "--frames", "1"]).output().expect("run nostencil view");
    let err = common::assert_failure("view without a display", &output);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("DISPLAY"), "{err}");

    let out = dir.join("frame.png");
    let output = nostencil()
        .args(["render", "--validation", "--size", "64x48", "--out", out.to_str().unwrap()])
        .output()
        .expect("run nostencil render");
    assert_clean(&output, "render with no display");
    // The default scene, lit: sky along the top row, lit.frag's ground colour at the bottom.
    let image = rgb(&out);
    assert_eq!(image.dimensions(), (64, 48));
    let scene = nostencil::builtin_scene("default").expect("scene");
    let sky = common::srgb8(scene.background);
    assert!((0..64).all(|x| image.get_pixel(x, 0).0 == sky), "top row is not the sky {sky:?}");
    let (bottom, ground) = (image.get_pixel(32, 47).0, common::lit_ground(&scene));
    assert!(common::near(&bottom, &ground, 1), "bottom centre {bottom:?}, lit ground {ground:?}");

    let output = nostencil().args(["view", "--screenshot", "x.png"]).output().expect("run nostencil view");
    let err = common::assert_failure("view --screenshot without --frames", &output);
    assert!(err.contains("--frames"), "{err}");
}

#[test]
fn escape_with_frames_in_flight_ends_cleanly() {
    let x = start_x_server();
    let child = spawn_on(
        &x,
        &["view", "--validation", "--device", "lavapipe", "--size", "160x120", "--technique", "shadow-volume"],
    );
    let (child, window) = wait_for_window(&x, child);
    wait_for_title(&x, &window, "fragments/px");
    xdotool(&x, &["windowfocus", &window]);
    // Rebuilds (k, n), light moves, then quit while a frame's copy may still be running: the
    // targets it reads must outlive it.
    xdotool(&x, &["key", "k", "n", "Left", "Up", "Escape"]);
    let output = wait_with_timeout(child, Duration::from_secs(60));
    assert_clean(&output, "view closed with Escape");
}

#[test]
fn the_x_server_going_away_ends_the_viewer_without_a_panic_or_a_hang() {
    let mut x = start_x_server();
    let child = spawn_on(&x, &["view", "--validation", "--device", "lavapipe", "--size", "96x96"]);
    let (child, window) = wait_for_window(&x, child);
    wait_for_title(&x, &window, "fragments/px");
    // The display dies under the swapchain: the surface is lost and the connection broken.
    let _ = Command::new("kill").arg(x.child.id().to_string()).status();
    let _ = x.child.wait();
    let output = wait_with_timeout(child, Duration::from_secs(30));
    let err = stderr(&output);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    // It ends by itself, with any exit status, but not killed by a signal (a crash).
    assert!(output.status.code().is_some(), "the viewer died by a signal ({}):\n{err}", output.status);
    assert!(!err.contains("vulkan validation"), "validation messages:\n{err}");
    // Whoever notices first says so: Vulkan (surface lost: the viewer closes as when its
    // window is destroyed), winit (an error naming the display), or Xlib, whose handler ends
    // the process with status 1 and its own one-line message.
    assert!(
        ["surface was lost", "connection to the display was lost", "broken (explicit kill or server shutdown)"]
            .iter()
            .any(|w| err.contains(w)),
        "the error names the lost display:\n{err}"
    );
}

/// Waits until the title differs from `before` (a new frame was drawn).
fn wait_for_new_frame(x: &XServer, window: &str, before: &str) -> String {
    let start = Instant::now();
    loop {
        let title = xdotool(x, &["getwindowname", window]);
        if title != before {
            return title;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "no new frame after: {before}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn a_hidden_window_draws_nothing_and_resumes_when_shown() {
    let x = start_x_server();
    let base = ["--validation", "--device", "lavapipe", "--technique", "planar"];
    let child = spawn_on(&x, &[&["view"], &base[..], &["--size", "160x120"]].concat());
    let (child, window) = wait_for_window(&x, child);
    let shown = wait_for_title(&x, &window, "fragments/px");

    // A second, larger window opens on top of it (no window manager: both at the origin).
    let cover = spawn_on(&x, &["view", "--device", "lavapipe", "--size", "320x240"]);
    let start = Instant::now();
    while xdotool(&x, &["search", "--name", "^nostencil view"]).lines().count() < 2 {
        assert!(start.elapsed() < Duration::from_secs(60), "the covering window never appeared");
        std::thread::sleep(Duration::from_millis(100));
    }
    // Drawing stops: the casters turn every frame, so a drawn frame changes the counters.
    std::thread::sleep(Duration::from_secs(2));
    let hidden = xdotool(&x, &["getwindowname", &window]);
    std::thread::sleep(Duration::from_secs(1));
    assert_eq!(xdotool(&x, &["getwindowname", &window]), hidden, "frames were drawn while the window was hidden");
    let mut cover = cover;
    let _ = cover.kill();
    let _ = cover.wait();
    let shown_again = wait_for_new_frame(&x, &window, &hidden);

    // Unmapped and mapped again, as a window manager iconifies and restores a window.
    xdotool(&x, &["windowunmap", &window]);
    std::thread::sleep(Duration::from_millis(500));
    xdotool(&x, &["windowmap", &window]);
    let restored = xdotool(&x, &["getwindowname", &window]);
    wait_for_new_frame(&x, &window, &restored);

    xdotool(&x, &["windowfocus", &window]);
    xdotool(&x, &["key", "Escape"]);
    let output = wait_with_timeout(child, Duration::from_secs(60));
    assert_clean(&output, "view hidden, shown, unmapped and mapped");
    let err = stderr(&output);
    assert!(err.contains("hidden: drawing paused") && err.contains("visible again"), "{shown}\n{shown_again}\n{err}");
}

/// Pixels of `image` whose 3x3 neighbourhood is not one colour: edges of objects and shadows.
fn on_an_edge(image: &image::RgbImage, x: u32, y: u32) -> bool {
    let centre = image.get_pixel(x, y);
    let (x0, y0) = (x.saturating_sub(1), y.saturating_sub(1));
    let (x1, y1) = ((x + 1).min(image.width() - 1), (y + 1).min(image.height() - 1));
    (y0..=y1).any(|ny| (x0..=x1).any(|nx| image.get_pixel(nx, ny) != centre))
}

/// M switches the sample count live: a frame switched from 1x to 4x after its second frame
/// (`--press-after 2 m`) equals `render --samples 4` (same camera, light and time), differs
/// from the 1x frame only along edges; in a live window M goes 1x -> 4x -> 1x, the title says
/// which, and a count the device lacks (lavapipe has no 2x) is named and skipped.
#[test]
fn m_switches_between_one_and_four_samples_live() {
    let x = start_x_server();
    let dir = common::scratch_dir("viewer-samples");
    let base = ["--validation", "--device", "lavapipe", "--paused", "--technique", "shadow-volume", "--size", "128x96"];
    let shot = |name: &str, extra: &[&str]| {
        let path = dir.join(name);
        let args = [&["view"], &base[..], extra, &["--samples", "1", "--screenshot", path.to_str().unwrap()]].concat();
        let output = run(&x, &args);
        assert_clean(&output, &format!("view {extra:?}"));
        (rgb(&path), stderr(&output))
    };
    let (one, _) = shot("one.png", &["--frames", "4"]);
    let (switched, err) = shot("switched.png", &["--press-after", "2", "m", "--frames", "5"]);
    let reference = dir.join("render4.png");
    let args = [&["render"], &base[..], &["--samples", "4", "--out", reference.to_str().unwrap()]].concat();
    let args: Vec<&str> = args.into_iter().filter(|a| *a != "--paused").collect();
    assert_clean(&common::nostencil(&args), "render --samples 4");
    let four = rgb(&reference);
    let differing = switched.pixels().zip(four.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "the frame switched to 4x differs from `render --samples 4` in {differing} pixels\n{err}");

    let changed: Vec<(u32, u32)> = (0..96)
        .flat_map(|y| (0..128).map(move |x| (x, y)))
        .filter(|&(x, y)| one.get_pixel(x, y) != switched.get_pixel(x, y))
        .collect();
    assert!(changed.len() > 40, "only {} pixels changed from 1x to 4x", changed.len());
    let off_edge: Vec<_> = changed.iter().filter(|&&(x, y)| !on_an_edge(&one, x, y)).collect();
    assert!(off_edge.is_empty(), "pixels away from any edge changed at 4x: {off_edge:?}");

    // Live, by key, in a window.
    let args = [&["view"], &base[..], &["--samples", "1"]].concat();
    let child = spawn_on(&x, &args);
    let (child, window) = wait_for_window(&x, child);
    wait_for_title(&x, &window, "| 1x MSAA |");
    xdotool(&x, &["windowfocus", &window]);
    xdotool(&x, &["key", "Left", "m"]);
    let title = wait_for_title(&x, &window, "| 4x MSAA |");
    assert!(title.contains("shadow-volume (emulated"), "{title}");
    xdotool(&x, &["key", "m"]);
    wait_for_title(&x, &window, "| 1x MSAA |");
    xdotool(&x, &["key", "Escape"]);
    let output = wait_with_timeout(child, Duration::from_secs(60));
    assert_clean(&output, "view switching its sample count");
    let offers_two = nostencil::frame::targets::frame_sample_counts(&common::gpu(), nostencil::StencilMode::Emulated)
        .contains(ash::vk::SampleCountFlags::TYPE_2);
    if !offers_two {
        let err = stderr(&output);
        assert!(err.contains("2x skipped") && err.contains("offers 1, 4"), "the missing 2x was not named:\n{err}");
    }
}

/// `render` with the arguments a `view` was given (`--paused` aside) and `extra`, into `out`: the
/// offscreen frame a live one must equal.
fn render_as_viewed(out: &Path, view_args: &[&str], extra: &[&str]) -> image::RgbImage {
    let args = [&["render"], view_args, extra, &["--out", out.to_str().unwrap()]].concat();
    let args: Vec<&str> = args.into_iter().filter(|a| *a != "--paused").collect();
    assert_clean(&common::nostencil(&args), "render");
    rgb(out)
}

/// V switches the shadow mode live: the lights scene switched to modulate after its second frame
/// equals `render --shadow-mode modulate`; in a window I selects the next light and X switches
/// it off, and the title says which light and whether it is off.
#[test]
fn v_switches_the_shadow_mode_and_i_x_select_and_switch_off_lights_live() {
    let x = start_x_server();
    let dir = common::scratch_dir("viewer-lights");
    let base = [
        "--validation",
        "--device",
        "lavapipe",
        "--paused",
        "--technique",
        "shadow-volume",
        "--scene",
        "lights",
        "--size",
        "128x96",
        "--samples",
        "1",
    ];
    let path = dir.join("switched.png");
    let args =
        [&["view"], &base[..], &["--press-after", "2", "v", "--frames", "5", "--screenshot", path.to_str().unwrap()]]
            .concat();
    let output = run(&x, &args);
    assert_clean(&output, "view --press-after 2 v");
    let switched = rgb(&path);
    let render = |name: &str, extra: &[&str]| render_as_viewed(&dir.join(name), &base, extra);
    let modulate = render("modulate.png", &["--shadow-mode", "modulate"]);
    let additive = render("additive.png", &[]);
    let differing = switched.pixels().zip(modulate.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "the frame switched to modulate differs from `render --shadow-mode modulate`");
    assert!(switched.pixels().zip(additive.pixels()).filter(|(a, b)| a != b).count() > 100, "V changed nothing");

    // Live, by key, in a window: the sun is selected first (the primary light).
    let args = [&["view"], &base[..]].concat();
    let child = spawn_on(&x, &args);
    let (child, window) = wait_for_window(&x, child);
    wait_for_title(&x, &window, "| light 1/3 'sun' |");
    xdotool(&x, &["windowfocus", &window]);
    xdotool(&x, &["key", "i"]);
    wait_for_title(&x, &window, "| light 2/3 'lamp' |");
    xdotool(&x, &["key", "x"]);
    wait_for_title(&x, &window, "| light 2/3 'lamp' off |");
    xdotool(&x, &["key", "Escape"]);
    let output = wait_with_timeout(child, Duration::from_secs(60));
    assert_clean(&output, "view selecting and switching off lights");
}

/// One `--tour` report line: (tours done, frames, resident KiB, live objects).
fn tour_reports(err: &str) -> Vec<(u32, u32, u64, String)> {
    err.lines()
        .filter_map(|line| {
            let rest = line.strip_prefix("nostencil view: tour ")?;
            let (tours, rest) = rest.split_once(" done after ")?;
            let (frames, rest) = rest.split_once(" frames: resident ")?;
            let (resident, objects) = rest.split_once(" KiB; live objects: ")?;
            Some((tours.parse().ok()?, frames.parse().ok()?, resident.parse().ok()?, objects.to_owned()))
        })
        .collect()
}

/// One soak run: the viewer runs `tours` tours of every technique in both stencil modes at 1x
/// and 4x (the casters and the walking character animated), the window resized at every stop,
/// validation on with `checks`. Checks that it ends cleanly (no validation message), that each
/// tour reported and that the live Vulkan objects after every tour are exactly those after the
/// first; returns the reports (tours, frames, resident KiB, objects).
fn soak(checks: &str, tours: u32) -> Vec<(u32, u32, u64, String)> {
    const FRAMES_PER_STOP: u32 = 8;
    let stops = 4 * nostencil::TECHNIQUES.len() as u32;
    let frames = FRAMES_PER_STOP * stops * tours;
    let x = start_x_server();
    let tour = FRAMES_PER_STOP.to_string();
    let frames_arg = frames.to_string();
    let validation = format!("--validation={checks}");
    let args = ["view", &validation, "--device", "lavapipe", "--size", "96x72"];
    let start = Instant::now();
    let output = wait_with_timeout(
        spawn_on(&x, &[&args[..], &["--tour", &tour, "--frames", &frames_arg]].concat()),
        Duration::from_secs(300),
    );
    let seconds = start.elapsed().as_secs_f64();
    assert_clean(&output, "the soak");
    let err = stderr(&output);
    let reports = tour_reports(&err);
    let done: Vec<u32> = reports.iter().map(|r| r.0).collect();
    assert_eq!(done, (1..=tours).collect::<Vec<_>>(), "one report per tour:\n{err}");
    for size in ["swapchain 96x72", "swapchain 80x60"] {
        assert!(err.matches(size).count() >= (stops * tours / 2) as usize, "too few '{size}':\n{err}");
    }
    let (first, last) = (&reports[0], &reports[reports.len() - 1]);
    eprintln!(
        "soak ({checks}): {} frames in {seconds:.1} s; resident {} KiB after tour 1, {} KiB after tour {}; objects: {}",
        last.1, first.2, last.2, last.0, last.3
    );
    assert_eq!(last.1, frames);
    for report in &reports[1..] {
        assert_eq!(report.3, first.3, "live objects after tour {} differ from tour 1", report.0);
    }
    reports
}

/// The soak: thousands of frames through every technique, both stencil modes, 1x and 4x, with
/// resizes and skinned animation. Resident memory after the last tour is within
/// `RSS_TOLERANCE_KIB` of that after the first, live objects are exactly equal, and no
/// validation message appears, first with every check the layer has, then (for the memory)
/// without the synchronisation checks: this layer version's (1.3.239) synchronisation state
/// grows by ~50 KiB per submitted frame whatever the application does (measured: the same
/// growth in `bench --technique lit`, none with those checks off), which is the layer's memory,
/// not ours.
#[test]
fn soak_thousands_of_frames_through_every_technique_leaks_nothing() {
    // 8 MiB over the 768 frames between the first and last of three reports (12 techniques,
    // 4 stops each, 8 frames a stop): a leak of 11 KiB a frame fails. Resident memory moves by
    // up to 3.5 MiB between tours with no trend over 8 tours (measured, with and without
    // validation): the allocator's fragmentation as each stop builds and drops its renderer.
    // The leak this test found was 600 KiB a frame.
    const RSS_TOLERANCE_KIB: u64 = 8192;
    // Every check for one tour (its validation messages), then the memory and objects over three.
    soak("all", 1);
    let reports = soak("core,best-practices", 3);
    let (first, last) = (&reports[0], &reports[reports.len() - 1]);
    assert!(
        last.2 <= first.2 + RSS_TOLERANCE_KIB,
        "resident memory grew from {} KiB to {} KiB (tolerance {RSS_TOLERANCE_KIB} KiB):\n{reports:?}",
        first.2,
        last.2
    );
}

/// A lost device or exhausted device memory at a submit ends the viewer with a one-line error
/// naming the work (the frame's passes, or the copy to the window): no panic, no hang.
/// Simulated by the fault hooks of src/gpu/faults.rs (`NOSTENCIL_FAULT_SUBMIT`).
#[test]
fn a_failing_submit_ends_the_viewer_with_an_error_naming_the_work() {
    let x = start_x_server();
    // The frame drawn into the swapchain image is one submission; `--present copy` adds the copy's.
    let cases = [
        ("frame:device-lost", "ERROR_DEVICE_LOST", "the frame's passes: ", "direct"),
        ("frame:out-of-device-memory", "ERROR_OUT_OF_DEVICE_MEMORY", "the frame's passes: ", "direct"),
        ("frame:device-lost", "ERROR_DEVICE_LOST", "the frame's passes: ", "copy"),
        ("present:device-lost", "ERROR_DEVICE_LOST", "the copy of the frame to the window", "copy"),
        ("present:out-of-device-memory", "ERROR_OUT_OF_DEVICE_MEMORY", "the copy of the frame to the window", "copy"),
    ];
    for (fault, says, work, present) in cases {
        let args = ["view", "--validation", "--device", "lavapipe", "--technique", "planar", "--size", "96x72"];
        let child = Command::new(common::program())
            .args([&args[..], &["--frames", "3", "--present", present]].concat())
            .env("DISPLAY", &x.display)
            .env_remove("WAYLAND_DISPLAY")
            .env("NOSTENCIL_FAULT_SUBMIT", fault)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run nostencil");
        let output = wait_with_timeout(child, Duration::from_secs(60));
        let err = common::assert_failure(fault, &output);
        assert!(!err.contains("vulkan validation"), "{fault}: validation messages:\n{err}");
        let error: Vec<&str> = err.lines().filter(|l| !l.starts_with("nostencil view: ")).collect();
        assert_eq!(error.len(), 1, "{fault}: one error line:\n{err}");
        assert!(error[0].contains("vkQueueSubmit failed") && error[0].contains(says), "{fault}:\n{err}");
        assert!(error[0].contains(work), "{fault}: the work is not named:\n{err}");
        if let Some((_, passes)) = error[0].split_once("the frame's passes: ") {
            assert!(passes.split(", ").count() >= 2, "{fault}: the passes are not listed:\n{err}");
        }
    }
}

/// A adds a point light live and selects it; the frame equals `render --light` with the spec
/// the viewer printed. Shift+X removes the selected light, rebuilding the technique for the
/// lights left: on the lights scene, removing the sun gives the frame that switching it off
/// (X) gives, to the pixel.
#[test]
fn a_adds_a_light_and_shift_x_removes_one_live() {
    let x = start_x_server();
    let dir = common::scratch_dir("viewer-add-light");
    let base = [
        "--validation",
        "--device",
        "lavapipe",
        "--paused",
        "--technique",
        "shadow-volume",
        "--size",
        "128x96",
        "--samples",
        "1",
    ];
    let shot = |name: &str, extra: &[&str], key: &str| {
        let path = dir.join(name);
        let args = [
            &["view"],
            &base[..],
            extra,
            &["--press-after", "2", key, "--frames", "5", "--screenshot", path.to_str().unwrap()],
        ]
        .concat();
        let output = run(&x, &args);
        assert_clean(&output, &format!("view --press-after 2 {key}"));
        (rgb(&path), stderr(&output))
    };
    let (added, err) = shot("added.png", &[], "a");
    let spec = err
        .lines()
        .find_map(|line| line.split("added a light: --light '").nth(1))
        .and_then(|rest| rest.strip_suffix('\''))
        .unwrap_or_else(|| panic!("no spec printed:\n{err}"));
    let render = |name: &str, extra: &[&str]| render_as_viewed(&dir.join(name), &base, extra);
    let with_it = render("with.png", &["--light", spec]);
    let without = render("without.png", &[]);
    let differing = added.pixels().zip(with_it.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "the frame with the added light differs from `render --light '{spec}'`");
    assert!(added.pixels().zip(without.pixels()).filter(|(a, b)| a != b).count() > 100, "A added no light");

    let (removed, err) = shot("removed.png", &["--scene", "lights"], "X");
    assert!(err.contains("removed the light 'sun'"), "{err}");
    let (off, _) = shot("off.png", &["--scene", "lights"], "x");
    let loaded = render("lights.png", &["--scene", "lights"]);
    let differing = removed.pixels().zip(off.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "the sun removed differs from the sun switched off");
    assert!(removed.pixels().zip(loaded.pixels()).filter(|(a, b)| a != b).count() > 100, "Shift+X removed nothing");
}
