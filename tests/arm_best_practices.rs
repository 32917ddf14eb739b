//! nostencil's own frames under the Khronos validation layer's best-practice checks with Arm's
//! vendor checks on (`VALIDATION_CHECK_ENABLE_VENDOR_SPECIFIC_ARM`, from a vk_layer_settings.txt):
//! the witness for load/store ops a tile-based GPU pays for. Every technique's frame raises no
//! render-pass or attachment finding (clear-then-load, redundant clear, readback, multisampled
//! memory), and every other message is one of [`STAYS`], each named in
//! docs/fillrate-layer.md ("nostencil's own frames") with why it stays.

use crate::common;

/// The Arm and best-practice messages nostencil's frames still raise, and why.
const STAYS: [(&str, &str); 4] = [
    (
        "vkCreateCommandPool-command-buffer-reset",
        "frames in flight re-record one buffer while the other is pending: buffers are reset one at a time",
    ),
    (
        "vkCreateSampler-border-clamp-color",
        "the shadow maps' compare sampler reads lit (white, depth 1) outside the map; transparent black would read shadowed",
    ),
    (
        "vkCmdDrawIndexed-sparse-index-buffer",
        "meshes share one index buffer (fewer binds); Mali before G71 has no index-driven vertex shading",
    ),
    ("vkCreateInstance-specialuse-extension-debugging", "VK_EXT_debug_utils is enabled only with validation on"),
];

#[test]
fn every_technique_is_clean_under_arms_best_practice_checks_but_for_the_named_few() {
    let dir = common::scratch_dir("arm_best_practices");
    let settings = dir.join("vk_layer_settings.txt");
    std::fs::write(
        &settings,
        "khronos_validation.enables = VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT,VALIDATION_CHECK_ENABLE_VENDOR_SPECIFIC_ARM\n\
         khronos_validation.report_flags = info,warn,perf,error\n\
         khronos_validation.debug_action = VK_DBG_LAYER_ACTION_LOG_MSG\n",
    )
    .expect("settings");
    let mut arm_seen = false;
    for technique in nostencil::TECHNIQUES.iter().map(|t| t.name()) {
        let png = dir.join(format!("{technique}.png"));
        let png = png.to_string_lossy().into_owned();
        let output = common::nostencil_command(&["render", "--technique", technique, "--size", "64x48", "--out", &png])
            .env("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation")
            .env("VK_LAYER_SETTINGS_PATH", &settings)
            .output()
            .expect("render");
        let (stdout, _) = common::assert_success(&format!("render --technique {technique}"), &output);
        assert!(stdout.contains("khronos-validation-createinstance-status-message"), "validation loaded: {stdout}");
        arm_seen |= stdout.contains("[Arm]");
        let found: std::collections::BTreeSet<&str> =
            stdout.lines().filter_map(|l| l.split("[ UNASSIGNED-BestPractices-").nth(1)?.split(' ').next()).collect();
        let unexpected: Vec<&&str> = found.iter().filter(|id| !STAYS.iter().any(|(s, _)| s == *id)).collect();
        assert!(unexpected.is_empty(), "{technique}: {unexpected:?}\n{stdout}");
        assert!(!stdout.contains("Validation Error"), "{technique}: {stdout}");
    }
    assert!(arm_seen, "no [Arm] message at all: the vendor checks were not on");
}
