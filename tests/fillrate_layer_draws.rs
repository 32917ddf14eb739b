//! Draws the layer must see wherever a program records them: VK_EXT_multi_draw's plain and
//! indexed multi-draws, draws in secondary command buffers (continuing a render pass and a
//! dynamic render pass), a multiview pass of two views, and a transfer in a secondary outside
//! any pass (tests/common/draw_program.rs). Every rectangle's edges lie on pixel boundaries,
//! so draws, vertices and samples are known by hand; fragments come from the program's own
//! queries around the same draws recorded inline, in a run without the layer. The layer's
//! figures must equal both exactly, in every one of three submissions (secondaries executed
//! again each time: their queries are reset by the layer ahead of each submission), with
//! validation and synchronisation checks below it silent and the program's images unchanged.

use crate::common;

use common::draw_program::{known_passes, Figures, Outcome, WORK_BYTES};

const SUBMISSIONS: u32 = 3;

/// The program with its own queries and no layer: its figures and images, as JSON to the
/// file `DRAW_PROGRAM_OUT` names (run by the test below in a process of its own).
#[test]
#[ignore = "a program for the test of this file, run by it without the layer"]
fn draw_program_with_its_own_queries() {
    let out = std::env::var("DRAW_PROGRAM_OUT").expect("DRAW_PROGRAM_OUT names the result file");
    // SAFETY: the program's own plain Vulkan use.
    let outcome = unsafe { common::draw_program::run(c"draws-own-queries", SUBMISSIONS, true) };
    common::raw_vulkan::assert_no_messages();
    std::fs::write(out, serde_json::to_string(&outcome).expect("JSON")).expect("write the result");
}

#[test]
fn multi_draws_secondaries_and_multiview_are_measured_exactly() {
    common::in_own_process("fillrate_layer_draws::multi_draws_secondaries_and_multiview_are_measured_exactly", || {
        let out = common::raw_vulkan::under_the_layer("fillrate_layer_draws");
        let dir = out.parent().expect("scratch folder").to_owned();
        let settings = common::raw_vulkan::synchronisation_settings(&dir);

        let own_file = dir.join("own.json");
        let me = std::env::current_exe().expect("this test binary");
        let run = std::process::Command::new(me)
            .args(["--exact", "fillrate_layer_draws::draw_program_with_its_own_queries", "--ignored"])
            .args(["--test-threads=1", "--nocapture"])
            .env("DRAW_PROGRAM_OUT", &own_file)
            .env_remove("VK_INSTANCE_LAYERS")
            .env_remove("NOSTENCIL_FILLRATE_OUT")
            .env("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation")
            .env("VK_LAYER_SETTINGS_PATH", &settings)
            .output()
            .expect("run the program with its own queries");
        assert!(
            run.status.success() && String::from_utf8_lossy(&run.stdout).contains("1 passed"),
            "the program with its own queries: {}\n{}",
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr)
        );
        let own: Outcome =
            serde_json::from_str(&std::fs::read_to_string(&own_file).expect("its result")).expect("JSON");

        std::env::set_var("VK_LAYER_SETTINGS_PATH", &settings);
        std::env::set_var("NOSTENCIL_FILLRATE_FRAME_ON", "submit");
        // SAFETY: the program's own plain Vulkan use.
        let measured = unsafe { common::draw_program::run(c"draws", SUBMISSIONS, false) };
        common::raw_vulkan::assert_no_messages();
        assert!(measured.images == own.images, "the program's images are the same with the layer and without it");

        // The program's own queries agree with the figures known by hand.
        let known = known_passes();
        let by_hand = |f: &Figures| Figures { fragments: None, ..*f };
        assert_eq!(own.own.iter().map(by_hand).collect::<Vec<_>>(), known, "the program's own queries");

        let report = common::raw_vulkan::layer_report(&out);
        assert!(report.not_measured.is_empty(), "{:?}", report.not_measured);
        assert_eq!(report.frames_measured, SUBMISSIONS as u64, "one frame per submission");
        for frame in &report.frames {
            let rows: Vec<Figures> = frame
                .render_passes
                .iter()
                .map(|p| {
                    let c = p.counters.unwrap_or_else(|| panic!("pass {} measured: {:?}", p.index, p.not_measured));
                    assert!(p.flag.is_none(), "{:?}", p.flag);
                    assert!(c.gpu_ms.is_some(), "GPU time of pass {}", p.index);
                    Figures {
                        draws: c.draws,
                        vertices: c.vertex_invocations.expect("statistics"),
                        samples: c.samples_passed,
                        fragments: c.fragment_invocations,
                    }
                })
                .collect();
            assert_eq!(rows, own.own, "frame {}: the layer's figures are the program's own", frame.index);
            let views: Vec<u32> = frame.render_passes.iter().map(|p| p.views).collect();
            assert_eq!(views, [1, 1, 2, 1]);
            // The multiview pass's colour attachment is stored for both views.
            assert_eq!(frame.render_passes[2].attachments[0].bytes_stored, 2 * 32 * 32 * 4);
            // The secondary's fill, then the program's three copies out.
            let work: Vec<(&str, u64)> =
                frame.work.iter().map(|w| (w.api.as_str(), w.counters.expect("measured").bytes_written)).collect();
            assert_eq!(work[0], ("vkCmdFillBuffer", WORK_BYTES));
            assert_eq!(work.len(), 4, "{work:?}");
        }

        // Per draw command too, in the secondaries as in the primary (a multiview pass has none:
        // a timestamp inside it would write one query per view).
        std::env::set_var("NOSTENCIL_FILLRATE_PER_DRAW", "1");
        // SAFETY: as above.
        let per_draw = unsafe { common::draw_program::run(c"draws", 1, false) };
        common::raw_vulkan::assert_no_messages();
        assert!(per_draw.images == own.images);
        let report = common::raw_vulkan::layer_report(&out);
        let passes = &report.frames[0].render_passes;
        let commands: Vec<usize> = passes.iter().map(|p| p.per_draw.len()).collect();
        assert_eq!(commands, [2, 2, 0, 1], "draw commands measured alone");
        for pass in passes.iter().filter(|p| !p.per_draw.is_empty()) {
            let c = pass.counters.expect("measured");
            let samples: u64 = pass.per_draw.iter().map(|d| d.samples_passed).sum();
            let fragments: u64 = pass.per_draw.iter().filter_map(|d| d.fragment_invocations).sum();
            assert_eq!((samples, Some(fragments)), (c.samples_passed, c.fragment_invocations), "pass {}", pass.index);
            assert!(pass.per_draw.iter().all(|d| d.gpu_ms.is_some()));
        }
    });
}
