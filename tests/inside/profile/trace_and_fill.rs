//! The trace file's slices and counters, and the casters' fill against the volume passes.

use super::*;

/// The trace-event JSON's schema (ui.perfetto.dev and chrome://tracing open it): `traceEvents`,
/// complete events (`ph` "X") with `ts` and `dur` in microseconds, counter events (`ph` "C"),
/// process and thread names; every event has `pid` and `tid`.
fn trace_events(path: &std::path::Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let trace: serde_json::Value = serde_json::from_str(&text).expect("the trace is JSON");
    let events = trace["traceEvents"].as_array().expect("traceEvents").clone();
    for e in &events {
        assert!(e["pid"].is_u64() && e["tid"].is_u64() && e["name"].is_string(), "{e}");
        match e["ph"].as_str() {
            Some("X") => assert!(
                e["ts"].as_f64().is_some_and(|t| t >= 0.0) && e["dur"].as_f64().is_some_and(|d| d >= 0.0),
                "{e}"
            ),
            Some("C") => assert!(e["ts"].is_number() && e["args"].is_object(), "{e}"),
            Some("M") => assert!(["process_name", "thread_name"].contains(&e["name"].as_str().unwrap_or("")), "{e}"),
            other => panic!("unexpected phase {other:?}: {e}"),
        }
    }
    let named = |name: &str, tid: u64| events.iter().any(|e| e["ph"] == "M" && e["name"] == name && e["tid"] == tid);
    assert!(named("process_name", 0) && named("thread_name", 1), "process and GPU track named");
    events
}

/// `profile --trace`: one GPU slice per pass, its duration the report's GPU time in
/// microseconds; the CPU's record, submit and wait on their own track; the frame's counters
/// equal the report's totals. `bench --trace`: every frame it rendered, each with its CPU phases.
#[test]
fn the_trace_has_a_slice_per_pass_with_the_reports_gpu_times_and_its_counters() {
    let dir = common::scratch_dir("profile_trace");
    let path = dir.join("trace.json");
    let path_arg = path.to_string_lossy().into_owned();
    let args = ["profile", "--size", "96x64", "--technique", "shadow-volume", "--format", "json", "--trace", &path_arg];
    let (stdout, _) = common::run_ok(&args);
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    let events = trace_events(&path);
    assert!(events.iter().any(|e| e["ph"] == "M" && e["name"] == "thread_name" && e["tid"] == 2), "CPU track named");
    let gpu: Vec<&serde_json::Value> = events.iter().filter(|e| e["ph"] == "X" && e["tid"] == 1).collect();
    let passes = report["passes"].as_array().expect("passes");
    assert_eq!(gpu.len(), passes.len(), "one slice per pass");
    for (slice, pass) in gpu.iter().zip(passes) {
        assert_eq!(slice["name"], pass["name"]);
        let (dur, ms) = (slice["dur"].as_f64().unwrap_or(-1.0), pass["gpu_ms"].as_f64().unwrap_or(-2.0));
        assert!((dur - ms * 1e3).abs() < 1e-6 * dur.max(1.0), "{slice} against {pass}");
    }
    // Laid out from the timestamps: in order, none before the previous one began.
    assert!(gpu.windows(2).all(|w| w[1]["ts"].as_f64() >= w[0]["ts"].as_f64()));
    let cpu: Vec<&str> =
        events.iter().filter(|e| e["ph"] == "X" && e["tid"] == 2).filter_map(|e| e["name"].as_str()).collect();
    assert_eq!(cpu, ["record", "submit", "wait"]);
    let counter = |name: &str, series: &str| {
        let found = events.iter().find(|e| e["ph"] == "C" && e["name"] == name);
        found.map(|e| e["args"][series].clone()).unwrap_or_else(|| panic!("counter {name}"))
    };
    let totals = &report["totals"];
    assert_eq!(counter("samples", "samples passed"), totals["samples_passed"]);
    assert_eq!(counter("bytes", "tiler"), totals["tiler_bytes"]);
    assert_eq!(counter("bytes", "immediate-mode"), totals["immediate_bytes"]);
    if totals["fragment_invocations"].is_u64() {
        assert_eq!(counter("fragments", "fragments"), totals["fragment_invocations"]);
    }

    let bench_path = dir.join("bench.json");
    let bench_arg = bench_path.to_string_lossy().into_owned();
    let bench = ["bench", "--technique", "lit", "--size", "32x32", "--samples", "1", "--warmup", "1", "--runs", "2"];
    let (stdout, _) = common::run_ok(&[&bench[..], &["--json", "--trace", &bench_arg]].concat());
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("bench JSON");
    let variants = report["variants"].as_array().map_or(0, Vec::len);
    let events = trace_events(&bench_path);
    let waits = events.iter().filter(|e| e["ph"] == "X" && e["name"] == "wait").count();
    assert_eq!(waits, variants * 3, "one frame per variant and round, the warm-up round too");
    let samples = events.iter().filter(|e| e["ph"] == "C" && e["name"] == "samples").count();
    assert_eq!(samples, waits, "counters per frame");
}

/// `profile --caster-fill`: each caster's volumes drawn alone, with the frame's counters. The
/// volumes are independent draws, so the casters' fragments and samples add up to the frame's
/// volume passes exactly; each light's fill and floor in the technique stats are those passes'
/// own counters per pixel; the top list is sorted; another technique is refused by name.
#[test]
fn caster_fill_adds_up_to_the_volume_passes_and_lights_report_their_fill() {
    let args = "profile --technique shadow-volume --scene lights --size 64x48 --samples 1 --format json \
                --caster-fill 99 --validation";
    let (out, err) = common::run_ok(&args.split_whitespace().collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let volume_passes: Vec<&serde_json::Value> = report["passes"]
        .as_array()
        .expect("passes")
        .iter()
        .filter(|p| p["name"].as_str().is_some_and(|n| n.contains("volumes")))
        .collect();
    let sum = |key: &str| volume_passes.iter().map(|p| p[key].as_u64().expect(key)).sum::<u64>();
    let stats = &report["technique_stats"];
    let fills = stats["caster_fill"].as_array().expect("caster_fill");
    assert_eq!(fills.len(), stats["casters"].as_array().map_or(0, Vec::len), "every caster listed with 99");
    let fragments: Vec<u64> = fills.iter().map(|f| f["fragments"].as_u64().expect("fragments")).collect();
    assert!(fragments.windows(2).all(|w| w[0] >= w[1]), "sorted: {fragments:?}");
    assert_eq!(fragments.iter().sum::<u64>(), sum("fragment_invocations"), "{stats}");
    let samples: u64 = fills.iter().map(|f| f["samples_passed"].as_u64().expect("samples")).sum();
    assert_eq!(samples, sum("samples_passed"));
    let pixels = 64.0 * 48.0;
    let lights = stats["lights"].as_array().expect("lights");
    assert_eq!(lights.len(), 3);
    let fill: f64 = lights.iter().map(|l| l["volume_fill"].as_f64().expect("fill")).sum();
    let floor: f64 = lights.iter().map(|l| l["volume_samples_passed"].as_f64().expect("floor")).sum();
    assert!((fill * pixels - sum("fragment_invocations") as f64).abs() < 0.5, "{fill}");
    assert!((floor * pixels - sum("samples_passed") as f64).abs() < 0.5, "{floor}");
    // The volumes' area, from the same frame drawn again with their depth test off: at least
    // the samples that pass, each light beside its own fill and floor.
    let coverage = stats["volume_coverage"].as_array().expect("volume_coverage");
    assert_eq!(coverage.len(), 3, "{stats}");
    for (light, area) in lights.iter().zip(coverage) {
        assert_eq!(area["fill_per_px"], light["volume_fill"], "{area}");
        assert_eq!(area["samples_passed_per_px"], light["volume_samples_passed"], "{area}");
        let (covered, passed) = (
            area["samples_covered_per_px"].as_f64().expect("covered"),
            area["samples_passed_per_px"].as_f64().expect("passed"),
        );
        assert!(covered > passed, "the probe kept the depth test: {area}");
    }

    let table = "profile --technique shadow-volume --scene lights --size 64x48 --samples 1 --caster-fill 2";
    let (out, _) = common::run_ok(&table.split(' ').collect::<Vec<_>>());
    assert!(out.contains("shadow volumes' area") && out.matches("samples covered/px").count() == 3, "{out}");
    // After a move the probe would draw the scene as loaded, not as moved: it says so.
    let moved = "profile --technique shadow-volume --scene lights --size 64x48 --samples 1 --move-model torus";
    let (moved_out, _) = common::run_ok(&moved.split(' ').collect::<Vec<_>>());
    assert!(moved_out.contains("shadow volumes' area: not measured with --move-model"), "{moved_out}");
    assert!(!moved_out.contains("samples covered/px"), "{moved_out}");
    let section = out.split("casters spending most of the volume fill").nth(1).expect("the caster table");
    assert_eq!(section.lines().filter(|l| l.contains("silhouette") || l.contains("two-sided")).count(), 2, "{out}");
    let refused = common::run_err(&["profile", "--technique", "shadow-map", "--size", "32x32", "--caster-fill"]);
    assert!(refused.contains("--caster-fill") && refused.contains("shadow-map"), "{refused}");
    let refused = common::run_err(&["profile", "--size", "32x32", "--caster-fill", "0"]);
    assert!(refused.contains("--caster-fill"), "{refused}");
}
