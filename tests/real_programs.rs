//! `nostencil profile-app` on programs nobody here wrote, from Debian, on Xvfb and lavapipe:
//! vkd3d-gears (Direct3D 12 through vkd3d; it crashed in lavapipe under the layer until the
//! layer's queries began only at draws), vkd3d-triangle (never exits, draws only on expose),
//! and vkcube ended from outside (Ctrl-C to profile-app, a crash, a kill) after some frames;
//! and the layer installed in a fresh HOME, then turned on by VK_INSTANCE_LAYERS alone; a video
//! player (mpv) and a headless video filter (ffmpeg's libplacebo filter) on Vulkan, with their
//! dispatches and transfers; and two OpenGL programs (glxgears, es2gears) on zink.
//!
//! Needs vkd3d-demos, vulkan-tools, mpv, ffmpeg, mesa-utils, Xvfb and xdotool
//! (tools/setup-debian.sh installs them):
//! without them the tests fail saying so rather than skip.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::x_server::{start_x_server, XServer};
use nostencil_fillrate_report::report::FillrateReport;

/// Every child gets at most this long; then it is killed and the test fails.
const LIMIT: Duration = Duration::from_secs(120);

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn read_report(path: &Path) -> FillrateReport {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    FillrateReport::from_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `nostencil profile-app --format json --out DIR/NAME.json EXTRA -- PROGRAM` started on `x`,
/// stdout and stderr into files (a full pipe could stall it), no layers from the caller's shell.
fn start_profile_app(
    dir: &Path,
    name: &str,
    extra: &[&str],
    program: &[&str],
    env: &[(&str, &str)],
    x: &XServer,
) -> Child {
    let result = dir.join(format!("{name}.json"));
    let result = result.to_string_lossy().into_owned();
    let args = [&["profile-app", "--format", "json", "--out", result.as_str()], extra, &["--"], program].concat();
    let file = |suffix: &str| {
        let path = dir.join(format!("{name}.{suffix}"));
        std::fs::File::create(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    };
    let mut command = common::nostencil_command(&args);
    command.stdin(Stdio::null()).stdout(file("stdout")).stderr(file("stderr"));
    command.env_remove("VK_INSTANCE_LAYERS").env_remove("VK_LAYER_PATH").env_remove("VK_ADD_LAYER_PATH");
    command.env("DISPLAY", &x.display).env_remove("WAYLAND_DISPLAY");
    for (key, value) in env {
        command.env(key, value);
    }
    command.spawn().expect("run nostencil profile-app")
}

/// Waits for `child` at most [`LIMIT`], calling `tick` every 100 ms meanwhile; kills it and
/// fails on time-out. Returns its output as the files hold it.
fn finish(mut child: Child, dir: &Path, name: &str, mut tick: impl FnMut()) -> Output {
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("poll profile-app") {
            break status;
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("profile-app ({name}) did not finish in {LIMIT:?}");
        }
        tick();
        std::thread::sleep(Duration::from_millis(100));
    };
    let read = |suffix: &str| std::fs::read(dir.join(format!("{name}.{suffix}"))).unwrap_or_default();
    Output { status, stdout: read("stdout"), stderr: read("stderr") }
}

/// Validation below the fill-rate layer: errors and warnings logged to stdout, and a status
/// line that proves it loaded.
fn validation_env(dir: &Path) -> (String, PathBuf) {
    let path = dir.join("vk_layer_settings.txt");
    let settings = "khronos_validation.report_flags = info,warn,error\n\
                    khronos_validation.debug_action = VK_DBG_LAYER_ACTION_LOG_MSG\n\
                    khronos_validation.enables = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT\n";
    std::fs::write(&path, settings).expect("write settings");
    ("VK_LAYER_NOSTENCIL_fillrate:VK_LAYER_KHRONOS_validation".to_owned(), path)
}

fn validation_problems(output: &Output) -> Vec<String> {
    let all = format!("{}\n{}", text(&output.stdout), text(&output.stderr));
    let kinds = ["Validation Error", "Validation Warning", "Validation Performance Warning"];
    all.lines().filter(|l| kinds.iter().any(|k| l.contains(k))).map(str::to_owned).collect()
}

#[test]
fn vkd3d_gears_runs_under_the_layer_and_is_ended_after_its_frames() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_gears");
    let (layers, settings) = validation_env(&dir);
    let settings = settings.to_string_lossy().into_owned();
    let env = [("VK_INSTANCE_LAYERS", layers.as_str()), ("VK_LAYER_SETTINGS_PATH", settings.as_str())];
    let child = start_profile_app(&dir, "gears", &["--frames", "10"], &["vkd3d-gears"], &env, &x);
    let output = finish(child, &dir, "gears", || {});
    common::assert_success("profile-app --frames 10 -- vkd3d-gears", &output);
    let stdout = text(&output.stdout);
    assert!(
        stdout.contains("Current Enables: VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION"),
        "no validation:\n{stdout}"
    );
    let problems = validation_problems(&output);
    assert!(problems.is_empty(), "{} validation message(s):\n{}", problems.len(), problems.join("\n"));
    let report = read_report(&dir.join("gears.json"));
    assert_eq!(report.frames_measured, 10, "{report:#?}");
    let run = report.run.as_ref().expect("run recorded");
    assert_eq!((run.how.as_str(), run.partial), ("ended", false), "{run:?}");
    for frame in &report.frames {
        // A colour clear, a depth clear (render passes of vkd3d's own) and the gears: six draws.
        let draws: Vec<u64> =
            frame.render_passes.iter().map(|p| p.counters.as_ref().map_or(u64::MAX, |c| c.draws)).collect();
        assert_eq!(draws, [0, 0, 6], "frame {}: {:#?}", frame.index, frame.render_passes);
        let gears = frame.render_passes[2].counters.as_ref().expect("measured");
        assert!(gears.samples_passed > 1000 && gears.fragment_invocations.is_some_and(|f| f >= gears.samples_passed));
    }
}

/// Two OpenGL programs from Debian's mesa-utils under `profile-app --gl --frames 20`: glxgears
/// (desktop GL through GLX) and es2gears (GLES 2 through EGL), on zink over lavapipe. Every
/// frame is one buffer swap's: its pass holds exactly the draws one frame of the program makes
/// (two swaps in one frame would double them), with vertices, fragments and samples above
/// zero, and no flag, hidden work or unmeasured pass.
#[test]
fn opengl_and_gles_programs_are_measured_a_frame_per_swap() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_gl");
    // Draws one frame makes: glxgears's three gears as four draws each (faces, teeth, the
    // outside and the inside of the rim), es2gears's three gears as one draw each.
    for (program, draws) in [("glxgears", 12), ("es2gears_x11", 3)] {
        let child = start_profile_app(&dir, program, &["--gl", "--frames", "20"], &[program], &[], &x);
        let output = finish(child, &dir, program, || {});
        common::assert_success(&format!("profile-app --gl --frames 20 -- {program}"), &output);
        let report = read_report(&dir.join(format!("{program}.json")));
        assert_eq!(report.frames_measured, 20, "{program}: {report:#?}");
        assert!(report.device.contains("llvmpipe"), "{program} on zink over lavapipe: {}", report.device);
        assert!(report.not_measured.is_empty(), "{program}: {:?}", report.not_measured);
        for frame in &report.frames {
            let drawn: Vec<_> = frame.render_passes.iter().filter_map(|p| p.counters.filter(|c| c.draws > 0)).collect();
            assert!(frame.render_passes.iter().all(|p| p.flag.is_none()), "{program}: {:#?}", frame.render_passes);
            assert_eq!(drawn.len(), 1, "{program} frame {}: {:#?}", frame.index, frame.render_passes);
            let c = drawn[0];
            assert_eq!(c.draws, draws, "{program} frame {}", frame.index);
            let (vertices, fragments) = (c.vertex_invocations.unwrap_or(0), c.fragment_invocations.unwrap_or(0));
            assert!(vertices > 0 && fragments > 0 && c.samples_passed > 0, "{program} frame {}: {c:?}", frame.index);
        }
    }
}

/// The compute and transfer rows of every kept frame: (dispatch groups, compute-shader
/// invocations, transfer rows, bytes they moved).
fn work_totals(report: &FillrateReport) -> (usize, u64, usize, u64) {
    let work = report.frames.iter().flat_map(|f| &f.work);
    let (compute, transfer): (Vec<_>, Vec<_>) = work.partition(|w| w.kind == "compute");
    let invocations = compute.iter().filter_map(|w| w.counters?.compute_invocations).sum();
    let bytes = transfer.iter().filter_map(|w| w.counters).map(|c| c.bytes_read + c.bytes_written).sum();
    (compute.len(), invocations, transfer.len(), bytes)
}

/// A headless video filter on Vulkan: ffmpeg's libplacebo filter (Debian's ffmpeg 5.1 with
/// libplacebo 4.208) scales 10 test frames 320x240 to 640x480 with EWA (polar) scalers, which
/// libplacebo runs as compute shaders, uploading and downloading with copies. It never
/// presents: with `--frame-on submit` its submissions are the frames.
#[test]
fn ffmpeg_libplacebo_filter_is_measured_per_submission_with_its_dispatches_and_copies() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_ffmpeg");
    let filter = "format=yuv420p,hwupload,libplacebo=w=640:h=480:upscaler=ewa_lanczos:downscaler=ewa_lanczos,\
                  hwdownload,format=yuv420p";
    let program = [
        "ffmpeg",
        "-hide_banner",
        "-loglevel",
        "error",
        "-init_hw_device",
        "vulkan=vk",
        "-filter_hw_device",
        "vk",
        "-f",
        "lavfi",
        "-i",
        "testsrc=size=320x240:rate=10",
        "-frames:v",
        "10",
        "-vf",
        filter,
        "-f",
        "null",
        "-",
    ];
    let child = start_profile_app(&dir, "ffmpeg", &["--frame-on", "submit"], &program, &[], &x);
    let output = finish(child, &dir, "ffmpeg", || {});
    common::assert_success("profile-app --frame-on submit -- ffmpeg ... libplacebo", &output);
    let report = read_report(&dir.join("ffmpeg.json"));
    assert!(report.frames_measured > 1, "one frame per submission: {}", report.frames_measured);
    assert!(report.not_measured.is_empty(), "{:?}", report.not_measured);
    let (groups, invocations, transfers, bytes) = work_totals(&report);
    assert!(groups > 0 && invocations > 0, "dispatches: {groups} groups, {invocations} invocations");
    assert!(transfers > 0 && bytes > 0, "transfers: {transfers} rows, {bytes} bytes");
}

/// A video player with Vulkan output: mpv 0.35 (`--vo=gpu-next`, libplacebo 4.208) on Xvfb,
/// told to use lavapipe (it skips software devices otherwise) and to scale 320x240 video into a
/// 640x480 window with EWA, a compute shader of one invocation per output pixel.
#[test]
fn mpv_gpu_next_is_measured_with_its_render_passes_dispatches_and_uploads() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_mpv");
    let video = dir.join("test.mp4");
    let video_arg = video.to_string_lossy().into_owned();
    let made = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-y", "-f", "lavfi", "-i", "testsrc=size=320x240:rate=30"])
        .args(["-t", "3", "-c:v", "mpeg4", video_arg.as_str()])
        .output()
        .unwrap_or_else(|e| panic!("cannot run ffmpeg ({e}); tools/setup-debian.sh installs it"));
    common::assert_success("ffmpeg makes a test video", &made);
    let program = [
        "mpv",
        "--no-config",
        "--vo=gpu-next",
        "--gpu-api=vulkan",
        "--gpu-sw",
        "--gpu-context=x11vk",
        "--vulkan-device=llvmpipe (LLVM 15.0.6, 256 bits)",
        "--hwdec=no",
        "--no-audio",
        "--scale=ewa_lanczos",
        "--geometry=640x480",
        video_arg.as_str(),
    ];
    let child = start_profile_app(&dir, "mpv", &["--frames", "10"], &program, &[], &x);
    let output = finish(child, &dir, "mpv", || {});
    common::assert_success("profile-app --frames 10 -- mpv --vo=gpu-next", &output);
    let report = read_report(&dir.join("mpv.json"));
    assert_eq!(report.frames_measured, 10);
    assert!(report.frames.iter().all(|f| !f.render_passes.is_empty()), "a render pass per frame at least");
    let (groups, invocations, transfers, bytes) = work_totals(&report);
    assert!(groups >= 10 && invocations >= 10 * 640 * 480, "{groups} groups, {invocations} invocations");
    assert!(transfers > 0 && bytes > 0, "uploads: {transfers} rows, {bytes} bytes");
}

/// The X window whose name contains `name`, once it exists.
fn window(x: &XServer, name: &str) -> Option<String> {
    let output = Command::new("xdotool").args(["search", "--name", name]).env("DISPLAY", &x.display).output();
    let output = output.unwrap_or_else(|e| panic!("cannot run xdotool ({e}); tools/setup-debian.sh installs it"));
    text(&output.stdout).lines().next().map(str::to_owned)
}

#[test]
fn vkd3d_triangle_which_never_exits_reports_its_frames_and_is_ended() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_triangle");
    let child = start_profile_app(&dir, "triangle", &["--frames", "10"], &["vkd3d-triangle"], &[], &x);
    // vkd3d-triangle draws a frame per expose event: unmapping and mapping its window makes one.
    let output = finish(child, &dir, "triangle", || {
        if let Some(id) = window(&x, "Triangle") {
            for action in ["windowunmap", "windowmap"] {
                let _ =
                    Command::new("xdotool").args([action, "--sync", id.as_str()]).env("DISPLAY", &x.display).status();
            }
        }
    });
    common::assert_success("profile-app --frames 10 -- vkd3d-triangle", &output);
    let report = read_report(&dir.join("triangle.json"));
    assert_eq!(report.frames_measured, 10, "{report:#?}");
    assert_eq!(report.run.as_ref().map(|r| r.how.as_str()), Some("ended"));
    let draws: u64 =
        report.frames.iter().flat_map(|f| &f.render_passes).filter_map(|p| p.counters.as_ref()).map(|c| c.draws).sum();
    assert_eq!(draws, 10, "one triangle draw per frame: {report:#?}");
}

/// Frames in profile-app's own result file (its scratch folder is named by its pid).
fn frames_so_far(profile_app: u32) -> u64 {
    let prefix = format!("nostencil-profile-app-{profile_app}-");
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else { return 0 };
    entries
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(&prefix))
        .filter_map(|e| std::fs::read_to_string(e.path().join("result.json")).ok())
        .filter_map(|t| FillrateReport::from_json(&t).ok())
        .map(|r| r.frames_measured)
        .max()
        .unwrap_or(0)
}

/// The pid of `parent`'s child process.
fn child_of(parent: u32) -> Option<i32> {
    let children = std::fs::read_to_string(format!("/proc/{parent}/task/{parent}/children")).ok()?;
    children.split_whitespace().next()?.parse().ok()
}

/// Runs vkcube (which never exits without --c) under profile-app until 3 frames are written,
/// then sends `signal` to profile-app (`to_app` false) or to vkcube; returns the run's output
/// and report.
fn vkcube_ended_by(dir: &Path, name: &str, signal: i32, to_app: bool, x: &XServer) -> (Output, FillrateReport) {
    let child = start_profile_app(dir, name, &[], &["vkcube", "--width", "64", "--height", "64"], &[], x);
    let pid = child.id();
    let mut sent = false;
    let output = finish(child, dir, name, || {
        if !sent && frames_so_far(pid) >= 3 {
            let target = if to_app { Some(pid as i32) } else { child_of(pid) };
            if let Some(target) = target {
                // SAFETY: kill(2) on a process this test started (or its child), still running.
                unsafe { libc::kill(target, signal) };
                sent = true;
            }
        }
    });
    assert!(sent, "{name}: no 3 frames before the end:\n{}", text(&output.stderr));
    (output, read_report(&dir.join(format!("{name}.json"))))
}

#[test]
fn ctrl_c_a_crash_and_a_kill_each_report_the_frames_measured() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_endings");
    let (output, report) = vkcube_ended_by(&dir, "interrupt", libc::SIGINT, true, &x);
    common::assert_success("profile-app -- vkcube, then Ctrl-C", &output);
    let run = report.run.as_ref().expect("run");
    assert_eq!((run.how.as_str(), run.partial), ("interrupted", false), "{run:?}");
    assert!(report.frames_measured >= 3, "{report:#?}");

    for (name, signal, how) in [("crash", libc::SIGSEGV, "crashed"), ("kill", libc::SIGKILL, "killed")] {
        let (output, report) = vkcube_ended_by(&dir, name, signal, false, &x);
        let stderr = common::assert_failure(&format!("profile-app -- vkcube, then {name}"), &output);
        let run = report.run.as_ref().expect("run");
        assert_eq!((run.how.as_str(), run.partial), (how, true), "{run:?}");
        assert!(report.frames_measured >= 3, "{report:#?}");
        let line = format!("after {} measured frames; the report covers those", report.frames_measured);
        assert!(stderr.contains(&line), "{stderr}");
        // Every measured frame is in the report, up to the 64 it keeps without --frames.
        let kept = report.frames_measured.min(nostencil_fillrate_report::report::KEPT_FRAMES as u64);
        assert_eq!(report.frames.len() as u64, kept);
    }
}

/// A program of our own that crashes on purpose: `nostencil view` built with the test-only
/// fault injection aborts right after its 8th present. profile-app reports the frames measured
/// before, marked partial, and exits 1 naming the crash.
#[test]
fn a_program_that_crashes_on_purpose_still_gets_a_report_of_its_frames() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_crash");
    let nostencil = env!("CARGO_BIN_EXE_nostencil");
    let program = [nostencil, "view", "--frames", "1000", "--size", "64x64"];
    let env = [("NOSTENCIL_FAULT_CRASH_AFTER", "8")];
    let child = start_profile_app(&dir, "crash", &[], &program, &env, &x);
    let output = finish(child, &dir, "crash", || {});
    let stderr = common::assert_failure("profile-app -- nostencil view (crashing)", &output);
    let report = read_report(&dir.join("crash.json"));
    let run = report.run.as_ref().expect("run");
    assert_eq!((run.how.as_str(), run.detail.as_str(), run.partial), ("crashed", "crashed with SIGABRT", true));
    // Every frame finished before the abort is in the report: the layer journals each frame as
    // it finishes, whatever the 100 ms between rewrites of the whole report. The viewer draws
    // each frame into the swapchain image with 2 frames in flight: before the 8th, it waited
    // for the 6th (whose slot the 8th reuses); the 7th and 8th may or may not have finished
    // when it aborts. Every finished frame is reported, and no other.
    assert!((6..=8).contains(&report.frames_measured), "{report:#?}");
    let indices: Vec<u64> = report.frames.iter().map(|f| f.index).collect();
    assert_eq!(indices, (0..report.frames_measured).collect::<Vec<_>>());
    assert_eq!(report.frames.len() as u64, report.frames_measured);
    assert!(report.frames.iter().all(|f| f.render_passes.iter().any(|p| p.counters.is_some())), "{report:#?}");
    let line = format!("crashed with SIGABRT after {} measured frame", report.frames_measured);
    assert!(stderr.contains(&line), "{stderr}");
}

/// Every file under `dir`.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files
}

#[test]
fn installed_in_a_fresh_home_the_layer_is_turned_on_by_its_name_alone() {
    let x = start_x_server();
    let dir = common::scratch_dir("real_programs_install");
    let home = dir.join("home");
    std::fs::create_dir_all(&home).expect("home");
    let in_home = |args: &[&str]| {
        let mut command = common::nostencil_command(args);
        command.env("HOME", &home).env_remove("XDG_DATA_HOME");
        command.output().expect("run nostencil")
    };
    let (_, said) = common::assert_success("nostencil layer install", &in_home(&["layer", "install"]));
    let manifest = home.join(".local/share/vulkan/explicit_layer.d/VkLayer_nostencil_fillrate.json");
    let library = home.join(".local/lib/nostencil/libnostencil_fillrate.so");
    assert!(manifest.is_file() && library.is_file(), "{said}");
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&manifest).expect("manifest")).expect("manifest JSON");
    assert_eq!(value["layer"]["library_path"], library.to_string_lossy().as_ref());

    // Only the user's folders tell the loader: no layer path variable at all.
    let out = dir.join("vkcube.json");
    let mut vkcube = Command::new("vkcube");
    vkcube.args(["--c", "5", "--width", "64", "--height", "64"]).stdin(Stdio::null());
    vkcube.env("HOME", &home).env_remove("XDG_DATA_HOME").env_remove("VK_LAYER_PATH").env_remove("VK_ADD_LAYER_PATH");
    vkcube.env("DISPLAY", &x.display).env("VK_INSTANCE_LAYERS", "VK_LAYER_NOSTENCIL_fillrate");
    vkcube.env("NOSTENCIL_FILLRATE_OUT", &out);
    let output = vkcube.output().unwrap_or_else(|e| panic!("cannot run vkcube ({e}); setup-debian.sh installs it"));
    assert!(output.status.success(), "vkcube: {}", text(&output.stderr));
    let report = read_report(&out);
    assert!(report.frames_measured >= 4, "{report:#?}");
    assert!(report.frames.iter().all(|f| f.render_passes.iter().all(|p| p.counters.is_some())), "{report:#?}");

    common::assert_success("nostencil layer uninstall", &in_home(&["layer", "uninstall"]));
    assert_eq!(files_under(&home), Vec::<PathBuf>::new(), "uninstall left files behind");
    for gone in ["vulkan", "../lib"] {
        assert!(!home.join(".local/share").join(gone).exists(), "{gone} left behind");
    }
    // Uninstalling again is not an error; it says there is nothing to remove.
    let (_, said) = common::assert_success("nostencil layer uninstall (again)", &in_home(&["layer", "uninstall"]));
    assert!(said.contains("was not installed"), "{said}");
}
