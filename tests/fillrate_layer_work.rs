//! Work outside render passes under the fill-rate layer: a headless program of our own
//! (tests/common/work_program.rs) that fills, dispatches, copies, clears, blits and updates,
//! never presents, and waits for a fence after each submission. With frames cut per
//! submission (`NOSTENCIL_FILLRATE_FRAME_ON=submit`) each submission is one frame whose rows
//! must equal the program's own figures exactly: compute-shader invocations, workgroups, bytes.
//! The program checks what it computed itself; validation with synchronisation checks runs
//! below the layer and must stay silent. This binary holds this one test (it sets the loader's
//! environment).

use crate::common;

use common::work_program::{expected_rows, ExpectedRow, WorkOptions};

#[test]
fn dispatches_and_transfers_are_rows_with_exact_counts_one_frame_per_submission() {
    // It sets the process environment for the layer: in a process of its own.
    common::in_own_process(
        "fillrate_layer_work::dispatches_and_transfers_are_rows_with_exact_counts_one_frame_per_submission",
        || {
            let out = common::raw_vulkan::under_the_layer("fillrate_layer_work");
            let dir = out.parent().expect("scratch folder").to_owned();
            std::env::set_var("VK_LAYER_SETTINGS_PATH", common::raw_vulkan::synchronisation_settings(&dir));
            std::env::set_var("NOSTENCIL_FILLRATE_FRAME_ON", "submit");
            let options = WorkOptions { groups: 3, submissions: 3, boundary_every: 0 };
            // SAFETY: the program's own plain Vulkan use.
            unsafe { common::work_program::run(c"work", options) };

            common::raw_vulkan::assert_no_messages();
            let report = common::raw_vulkan::layer_report(&out);
            // The fill in a secondary command buffer is measured where the primary executes it.
            assert!(report.not_measured.is_empty(), "{:?}", report.not_measured);
            assert_eq!(report.frames_measured, options.submissions as u64, "one frame per submission");
            let expected = expected_rows(options);
            for frame in &report.frames {
                assert!(frame.render_passes.is_empty());
                let rows: Vec<ExpectedRow> = frame
                    .work
                    .iter()
                    .map(|w| {
                        let c = w.counters.expect("measured");
                        assert!(c.gpu_ms.is_some(), "GPU time of {w:?}");
                        let kind: &'static str = if w.kind == "compute" { "compute" } else { "transfer" };
                        let api = expected.iter().find(|e| e.1 == w.api).map_or("?", |e| e.1);
                        let label = w.label.as_deref().map(|_| "add");
                        (
                            kind,
                            api,
                            label,
                            c.commands,
                            c.workgroups,
                            c.compute_invocations,
                            c.bytes_read,
                            c.bytes_written,
                        )
                    })
                    .collect();
                assert_eq!(rows, expected, "frame {}", frame.index);
            }
            assert_eq!(report.work_aggregate.len(), expected.len());
            assert!(report.work_aggregate.iter().all(|w| w.frames == options.submissions as u64));
        },
    );
}
