//! VK_EXT_frame_boundary under the fill-rate layer: lavapipe (Mesa 22.3) lacks the extension,
//! so the layer offers it and keeps it from the validation layer and driver below it. The
//! program of tests/common/work_program.rs enables it and marks every second submission as a
//! frame's end (`VkFrameBoundaryEXT`, FRAME_END): its boundaries, not its submissions or waits,
//! cut the frames. Validation with synchronisation checks below the layer stays silent (it
//! would name the extension's structs had they reached it). This binary holds this one test.

use crate::common;

use ash::vk;
use common::work_program::{expected_rows, WorkOptions};

#[test]
fn frame_boundaries_cut_frames_and_the_layer_offers_the_extension() {
    // It sets the process environment for the layer: in a process of its own.
    common::in_own_process(
        "fillrate_layer_boundary::frame_boundaries_cut_frames_and_the_layer_offers_the_extension",
        || {
            let out = common::raw_vulkan::under_the_layer("fillrate_layer_boundary");
            let dir = out.parent().expect("scratch folder").to_owned();
            std::env::set_var("VK_LAYER_SETTINGS_PATH", common::raw_vulkan::synchronisation_settings(&dir));
            // A wait after every submission: boundaries must win over --frame-on wait.
            std::env::set_var("NOSTENCIL_FILLRATE_FRAME_ON", "wait");

            // SAFETY: plain Vulkan queries on an instance made and destroyed here.
            let offered = unsafe {
                let raw = common::raw_vulkan::raw_instance(c"offered");
                let listed = raw.instance.enumerate_device_extension_properties(raw.physical).expect("extensions");
                let mut boundary = vk::PhysicalDeviceFrameBoundaryFeaturesEXT::default();
                let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut boundary);
                raw.instance.get_physical_device_features2(raw.physical, &mut features);
                let feature = boundary.frame_boundary;
                raw.destroy();
                (listed.iter().any(|e| e.extension_name_as_c_str() == Ok(c"VK_EXT_frame_boundary")), feature)
            };
            assert_eq!(offered, (true, vk::TRUE), "the extension and its feature are offered");

            let options = WorkOptions { groups: 2, submissions: 4, boundary_every: 2 };
            // SAFETY: the program's own plain Vulkan use.
            unsafe { common::work_program::run(c"boundary", options) };

            common::raw_vulkan::assert_no_messages();
            let report = common::raw_vulkan::layer_report(&out);
            assert_eq!(report.frames_measured, 2, "two frames of two submissions each");
            let per_submission = expected_rows(options).len();
            for frame in &report.frames {
                assert_eq!(frame.work.len(), 2 * per_submission, "frame {}", frame.index);
                let invocations: u64 = frame.work.iter().filter_map(|w| w.counters?.compute_invocations).sum();
                let expected: u64 = expected_rows(options).iter().filter_map(|r| r.5).sum();
                assert_eq!(invocations, 2 * expected);
            }
        },
    );
}
