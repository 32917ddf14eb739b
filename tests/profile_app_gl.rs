//! An OpenGL program under `profile-app --gl` (tests/common/gl_program.rs): it runs on Vulkan
//! through Mesa's zink over lavapipe, with the layer's library preloaded so that its buffer
//! swaps end frames. Each frame must be one frame of the report, its pass with the program's
//! own draws, vertices and samples exactly (zink draws through VK_EXT_multi_draw, which the
//! layer measures), and the program's last frame must read back the same with the layer and
//! without it. zink's own draw for that read-back (a blit) is measured too, in the last frame.

use crate::common;

use common::gl_program::{samples_per_frame, RECTS};
use common::x_server::start_x_server;
use nostencil_fillrate_report::report::FillrateReport;

const FRAMES: u32 = 6;

/// zink on lavapipe, as `profile-app --gl` runs a GL program.
const ZINK: [(&str, &str); 2] = [("LIBGL_ALWAYS_SOFTWARE", "1"), ("GALLIUM_DRIVER", "zink")];

/// The program: FRAMES frames, its last frame's pixels to `GL_PROGRAM_OUT`.
#[test]
#[ignore = "a program for the test of this file, run by it with and without the layer"]
fn gl_program() {
    let out = std::env::var("GL_PROGRAM_OUT").expect("GL_PROGRAM_OUT names the pixel file");
    // SAFETY: plain GLX use on the test's X server.
    let pixels = unsafe { common::gl_program::run(FRAMES) };
    std::fs::write(out, pixels).expect("write the pixels");
}

fn program_args(me: &str) -> [&str; 5] {
    [me, "--exact", "profile_app_gl::gl_program", "--ignored", "--test-threads=1"]
}

#[test]
fn a_gl_program_through_zink_is_measured_frame_by_frame_at_its_swaps() {
    let x = start_x_server();
    let dir = common::scratch_dir("profile_app_gl");
    let me = std::env::current_exe().expect("this test binary").to_string_lossy().into_owned();
    let args = program_args(&me);

    let plain = dir.join("plain.rgba");
    let run = std::process::Command::new(args[0])
        .args(&args[1..])
        .envs(ZINK)
        .env("DISPLAY", &x.display)
        .env("GL_PROGRAM_OUT", &plain)
        .output()
        .expect("run the GL program");
    common::assert_success("the GL program on zink without the layer", &run);

    let measured_pixels = dir.join("measured.rgba");
    let out = dir.join("report.json");
    let out_arg = out.to_string_lossy().into_owned();
    let profile = common::nostencil_command(
        &[&["profile-app", "--gl", "--format", "json", "--out", out_arg.as_str(), "--"][..], &args[..]].concat(),
    )
    .env("DISPLAY", &x.display)
    .env("GL_PROGRAM_OUT", &measured_pixels)
    .output()
    .expect("profile-app runs");
    common::assert_success("profile-app --gl", &profile);
    let report = FillrateReport::from_json(&std::fs::read_to_string(&out).expect("report")).expect("a report");

    let (plain, measured) = (std::fs::read(&plain).expect("pixels"), std::fs::read(&measured_pixels).expect("pixels"));
    assert!(plain == measured, "the program's last frame reads back the same with the layer and without it");
    assert!(plain.chunks(4).any(|p| p[0] == 255), "the program drew its rectangles");

    assert!(report.device.contains("llvmpipe"), "zink over lavapipe: {}", report.device);
    assert!(report.not_measured.is_empty(), "{:?}", report.not_measured);
    // A frame per swap: the last swap's frame ends with the program.
    let frames = report.frames_measured;
    assert!(frames == FRAMES as u64 || frames == FRAMES as u64 + 1, "{frames} frames for {FRAMES} swaps");
    let hidden: Vec<&str> = report.hidden_extensions.iter().map(|h| h.name.as_str()).collect();
    assert!(hidden.contains(&"VK_EXT_conditional_rendering"), "{hidden:?}");
    for frame in report.frames.iter().take(FRAMES as usize) {
        let drawn: Vec<_> = frame
            .render_passes
            .iter()
            .filter_map(|p| {
                assert!(p.flag.is_none(), "frame {} pass {}: {:?}", frame.index, p.index, p.flag);
                p.counters.filter(|c| c.draws > 0)
            })
            .collect();
        // The last frame also has zink's read-back: one draw of the whole target.
        let last = frame.index + 1 == FRAMES as u64;
        let expected = if last { 2 } else { 1 };
        assert_eq!(drawn.len(), expected, "frame {}: passes that draw: {:#?}", frame.index, frame.render_passes);
        if last {
            let whole = (common::gl_program::SIZE * common::gl_program::SIZE) as u64;
            assert_eq!((drawn[1].draws, drawn[1].samples_passed), (1, whole), "zink's read-back blit");
        }
        let c = drawn[0];
        assert_eq!(
            (c.draws, c.vertex_invocations, c.samples_passed),
            (RECTS as u64, Some(6 * RECTS as u64), samples_per_frame()),
            "frame {}",
            frame.index
        );
        assert!(c.fragment_invocations.is_some_and(|f| f >= samples_per_frame()), "{c:?}");
    }
}

#[test]
fn capture_is_refused_with_gl_by_a_line_that_says_why() {
    let dir = common::scratch_dir("profile_app_gl_capture");
    let png = dir.join("never.png");
    let png = png.to_string_lossy().into_owned();
    let output = common::nostencil(&["profile-app", "--gl", "--capture", &png, "--", "true"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{stderr}");
    assert!(stderr.contains("--capture") && stderr.contains("presents none"), "{stderr}");
    assert!(!std::path::Path::new(&png).exists(), "no file written");
}
