//! The command line as a user meets it: the README's commands work, and bad input gets a
//! one-line error and a non-zero exit, never a panic or a partial file.

use crate::common;

use std::path::Path;

use nostencil::{builtin_scene, scene_from_gltf};

/// A failure a user caused: non-zero exit, one line on stderr naming the problem, no panic.
fn assert_clean_failure(what: &str, output: &std::process::Output, mentions: &str) {
    let err = common::assert_failure(what, output);
    assert_eq!(err.trim_end().lines().count(), 1, "expected one line, got:\n{err}");
    assert!(err.contains(mentions), "'{mentions}' not in: {err}");
}

fn refused(args: &[&str], mentions: &str) {
    assert_clean_failure(&args.join(" "), &common::nostencil(args), mentions);
}

#[test]
fn render_writes_a_png_of_the_requested_size() {
    let dir = common::scratch_dir("cli-render");
    let out = dir.join("frame.png");
    let (_, err) = common::run_ok(&["render", "--size", "192x128", "--out", out.to_str().unwrap(), "--validation"]);
    assert!(!err.contains("vulkan validation"), "{err}");
    let image = common::read_png(&out);
    assert_eq!(image.dimensions(), (192, 128));
    // With no options, the project's point: stencil-free shadow volumes, in the additive loop.
    // The frame is the lit one with shadows: darker than it (by more than 8 levels summed over
    // RGB) in many pixels and lighter in none (ambient and the light are added in two passes,
    // each rounded to 8 bits: a level or two either way, not more).
    assert!(err.contains("shadow-volume"), "{err}");
    let lit_out = dir.join("lit.png");
    common::run_ok(&["render", "--size", "192x128", "--technique", "lit", "--out", lit_out.to_str().unwrap()]);
    let lit = common::read_png(&lit_out);
    let darker = image.pixels().zip(lit.pixels()).filter(|(p, q)| p != q).filter(|(p, q)| {
        assert!(
            (0..3).all(|c| p.0[c] <= q.0[c].saturating_add(2)),
            "a shadow made a pixel lighter: {p:?} vs lit {q:?}"
        );
        (0..3).map(|c| i32::from(q.0[c]) - i32::from(p.0[c])).sum::<i32>() > 8
    });
    assert!(darker.count() > 300, "the default render shows no shadows");
    // The default scene: the sky keeps the clear colour along the whole top row, and the
    // ground at the bottom centre has lit.frag's colour for an upward face under the light.
    let scene = builtin_scene("default").expect("scene");
    let sky = common::srgb8(scene.background);
    assert!((0..192).all(|x| image.get_pixel(x, 0).0 == sky), "top row is not the sky {sky:?}");
    let ground = common::lit_ground(&scene);
    let bottom = image.get_pixel(96, 127).0;
    assert!(common::near(&bottom, &ground, 1), "bottom centre {bottom:?}, lit ground {ground:?}");
}

#[test]
fn profile_json_is_readable_by_a_program() {
    let (stdout, _) = common::run_ok(&["profile", "--size", "128x96", "--format", "json"]);
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(report["schema"], "nostencil-profile/2");
    assert_eq!(report["width"], 128);
    let passes = report["passes"].as_array().expect("passes");
    // The additive loop's first pass (the seed's frame calls it "scene").
    let scene = passes.iter().find(|p| p["name"] == "scene (ambient)").expect("scene pass");
    assert!(scene["samples_passed"].as_u64().unwrap() > 0);
    assert!(scene["fragment_invocations"].as_u64().unwrap() >= scene["samples_passed"].as_u64().unwrap());
    assert!(scene["gpu_ms"].as_f64().unwrap() > 0.0);
}

#[test]
fn profile_csv_and_table_list_the_passes() {
    let (csv, _) = common::run_ok(&["profile", "--size", "64x64", "--format", "csv"]);
    assert!(csv.starts_with("pass,draws,"), "{csv}");
    let header = csv.lines().next().unwrap_or_default();
    assert!(header.ends_with(",share,render_pass_instances,tiler_bytes,immediate_bytes"), "{header}");
    assert!(csv.lines().any(|l| l.starts_with("scene (ambient),")), "{csv}");
    let (table, _) = common::run_ok(&["profile", "--size", "64x64"]);
    assert!(table.contains("samples/px"), "{table}");
    assert!(table.lines().any(|l| l.starts_with("scene")), "{table}");
}

#[test]
fn info_prints_device_profile_and_limits() {
    let (stdout, _) = common::run_ok(&["info", "--json"]);
    let info: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    let limits = info["limits"].as_array().expect("limits");
    assert!(limits.iter().any(|l| l["name"] == "maxPushConstantsSize" && l["profile"] == "128"));
    assert!(limits.iter().all(|l| l["ok"] == true));
    assert_eq!(info["forbidden_features"].as_array().unwrap().len(), 6);
    assert_eq!(info["frame_colour_format"], "R8G8B8A8_SRGB");
    assert!(info["frame_depth_format_reference"].as_str().is_some_and(|f| f.ends_with("S8_UINT")));
    // What the unshadowed-lights warning sends a user to: asked of each technique, in text too.
    let every: Vec<&str> = info["shadowing_every_light"]
        .as_array()
        .expect("shadowing_every_light")
        .iter()
        .filter_map(|t| t.as_str())
        .collect();
    assert_eq!(every, ["shadow-volume", "planar"]);
    let (text, _) = common::run_ok(&["info"]);
    assert!(
        text.lines().any(|l| l == "shadowing every light (--shadow-mode additive): shadow-volume, planar"),
        "{text}"
    );
}

#[test]
fn info_validation_names_the_active_checks_in_text_and_json() {
    let (json, stderr) = common::run_ok(&["info", "--validation", "--json"]);
    assert!(!stderr.contains("vulkan validation"), "info itself raised validation messages:\n{stderr}");
    let info: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    let validation = &info["validation"];
    assert!(validation["layer"].as_str().is_some_and(|l| l.starts_with("VK_LAYER_KHRONOS_validation")), "{validation}");
    assert_eq!(validation["core"], true);
    assert_eq!(validation["synchronization"], true, "synchronisation validation must be on: {validation}");
    assert_eq!(validation["best_practices"], true);
    assert_eq!(validation["gpu_assisted"], false);
    let silenced = validation["silenced"].as_array().expect("silenced list");
    assert_eq!(silenced.len(), nostencil::gpu::validation::SILENCED.len());
    assert!(silenced.iter().all(|s| s["id"].as_str().is_some() && s["why"].as_str().is_some_and(|w| !w.is_empty())));

    let (text, _) = common::run_ok(&["info", "--validation"]);
    assert!(text.contains("synchronization on"), "{text}");
    assert!(text.contains("core on"), "{text}");
    assert_eq!(text.lines().filter(|l| l.trim_start().starts_with("silenced:")).count(), silenced.len(), "{text}");

    // A chosen list: core is always on, the others only when named.
    let (chosen, _) = common::run_ok(&["info", "--validation=core,best-practices", "--json"]);
    let chosen: serde_json::Value = serde_json::from_str(&chosen).expect("JSON");
    assert_eq!(chosen["validation"]["synchronization"], false, "{}", chosen["validation"]);
    assert_eq!(chosen["validation"]["best_practices"], true, "{}", chosen["validation"]);
    let error = common::run_err(&["info", "--validation=core,gpu"]);
    assert!(error.contains("unknown validation check 'gpu'"), "{error}");

    let (off, _) = common::run_ok(&["info", "--json"]);
    let off: serde_json::Value = serde_json::from_str(&off).expect("JSON");
    assert!(off["validation"].is_null(), "validation was not asked for: {}", off["validation"]);
    let (off_text, _) = common::run_ok(&["info"]);
    assert!(off_text.contains("validation: off"), "{off_text}");
}

#[test]
fn unknown_option_is_a_one_line_error() {
    refused(&["render", "--out", "x.png", "--frobnicate"], "--frobnicate");
}

#[test]
fn an_option_that_needs_another_names_the_one_missing() {
    // clap lists the missing arguments on the lines after its first: the one line keeps them.
    refused(&["bench", "--each-skinning"], "--loop <N>");
    refused(&["render", "--out", "x.png", "--skinning", "sideways"], "[possible values: gpu, cpu]");
}

#[test]
fn zero_and_oversized_sizes_are_refused() {
    refused(&["render", "--size", "0x256", "--out", "x.png"], "at least 1");
    refused(&["profile", "--size", "5000x256"], "4096");
    refused(&["profile", "--size", "big"], "WIDTHxHEIGHT");
}

#[test]
fn unwritable_output_leaves_no_file() {
    let dir = common::scratch_dir("cli-unwritable");
    let out = dir.join("missing-folder").join("frame.png");
    refused(&["render", "--size", "32x32", "--out", out.to_str().unwrap()], "frame.png");
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "nothing may be left behind");
}

#[test]
fn unknown_device_is_named_with_the_devices_available() {
    refused(&["info", "--device", "no-such-gpu"], "no-such-gpu");
    refused(&["info", "--device", "99"], "available: 0: ");
}

#[test]
fn unknown_scene_and_technique_are_named() {
    refused(&["profile", "--scene", "nowhere"], "nowhere");
    refused(&["profile", "--technique", "magic"], "magic");
}

/// `nostencil info | head -1`: the reader leaves first; the process ends by SIGPIPE like any
/// Unix filter, with no panic on stderr.
#[test]
fn a_closed_stdout_ends_the_command_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let mut child =
        common::nostencil_command(&["info"]).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("run");
    // Closing our end before the command prints anything makes its first print fail.
    drop(child.stdout.take());
    let output = child.wait_with_output().expect("wait");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(output.status.signal(), Some(libc::SIGPIPE), "{:?}: {stderr}", output.status);
}

#[test]
fn missing_vulkan_driver_is_a_clear_error() {
    let dir = common::scratch_dir("cli-no-device");
    let out = dir.join("frame.png");
    let output = common::nostencil_command(&["render", "--size", "32x32", "--out", out.to_str().unwrap()])
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .output()
        .expect("run");
    assert_clean_failure("render without a Vulkan driver", &output, "Vulkan");
    assert!(!Path::new(&out).exists());
}

#[test]
fn cornell_box_renders_its_walls_and_warns_of_nothing() {
    let dir = common::scratch_dir("cli-gltf-warning");
    let out = dir.join("cornell.png");
    let path = common::test_asset("CornellBox.glb");
    let (_, err) = common::run_ok(&[
        "render",
        "--scene",
        path.to_str().unwrap(),
        "--size",
        "48x48",
        // One sample: the walls' pure colours are counted, and 4x blends their borders.
        "--samples",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    // Everything CornellBox uses is read (its emissive strength too): no warning.
    assert!(!err.contains("nostencil: warning"), "{err}");
    // What was not ignored is drawn: the sky in the top corners, the ground (lit.frag's colour
    // for it) at the bottom centre, and the box's red and green walls (pure red, pure green).
    let image = common::read_png(&out);
    assert_eq!(image.dimensions(), (48, 48));
    let scene = scene_from_gltf(&path, 0.0).expect("scene");
    let sky = common::srgb8(scene.background);
    assert_eq!((image.get_pixel(0, 0).0, image.get_pixel(47, 0).0), (sky, sky), "top corners are not the sky");
    let (bottom, ground) = (image.get_pixel(24, 47).0, common::lit_ground(&scene));
    assert!(common::near(&bottom, &ground, 1), "bottom centre {bottom:?}, lit ground {ground:?}");
    let red = image.pixels().filter(|p| p[0] > 30 && p[1] == 0 && p[2] == 0).count();
    let green = image.pixels().filter(|p| p[1] > 10 && p[0] == 0 && p[2] == 0).count();
    assert!(red > 20 && green > 20, "{red} red and {green} green wall pixels");
}

/// An extension the loader does not read is named in one warning line, once, however often the
/// file lists it.
#[test]
fn an_ignored_extension_is_named_once_in_a_warning() {
    let dir = common::scratch_dir("cli-gltf-ignored-extension");
    let text = std::fs::read_to_string(common::test_asset("SimpleSkin.gltf")).expect("SimpleSkin.gltf");
    let mut json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    json["extensionsUsed"] = serde_json::json!(["KHR_materials_sheen", "KHR_materials_sheen"]);
    let file = dir.join("sheen.gltf");
    std::fs::write(&file, json.to_string()).expect("write");
    let out = dir.join("sheen.png");
    let (_, err) = common::run_ok(&[
        "render",
        "--scene",
        file.to_str().unwrap(),
        "--size",
        "32x32",
        "--out",
        out.to_str().unwrap(),
    ]);
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("nostencil: warning:")).collect();
    let naming: Vec<&&str> = warnings.iter().filter(|l| l.contains("KHR_materials_sheen")).collect();
    assert_eq!(naming.len(), 1, "{err}");
    assert_eq!(naming[0].matches("KHR_materials_sheen").count(), 1, "{err}");
    assert!(naming[0].contains("sheen.gltf"), "{err}");
}

#[test]
fn bench_json_reports_round_robin_ratios_with_intervals() {
    let args = "bench --technique planar --size 64x64 --warmup 1 --runs 5 --json --validation";
    let (out, err) = common::run_ok(&args.split(' ').collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("bench --json is JSON");
    assert_eq!(report["schema"], "nostencil-bench/2");
    assert_eq!(report["order"], "round-robin");
    assert_eq!(report["bootstrap"]["resamples"], 2000);
    assert_eq!(report["runs"], 5);
    let variants = report["variants"].as_array().expect("variants");
    assert!(variants.len() >= 2, "{report}");
    for v in variants {
        let rounds: Vec<f64> =
            v["frame_ms_rounds"].as_array().expect("rounds").iter().filter_map(|x| x.as_f64()).collect();
        assert_eq!(rounds.len(), 5, "{v}");
        let ratio = &v["frame_ratio"];
        let (median, low, high) =
            (ratio["median"].as_f64(), ratio["ci95"]["low"].as_f64(), ratio["ci95"]["high"].as_f64());
        let (median, low, high) = (median.expect("median"), low.expect("low"), high.expect("high"));
        assert!(low <= median && median <= high, "{ratio}");
    }
    // The reference is its own ratio in every round.
    assert_eq!(variants[0]["frame_ratio"]["ci95"]["low"], 1.0);
    assert_eq!(variants[0]["frame_ratio"]["ci95"]["high"], 1.0);
}

/// `bench --samples 4`: every variant at 4x and at 1x, one after the other in every round, and
/// per variant the 4x/1x ratios (recomputable from the rounds); the lit default scene's draws
/// pass about 4 times the samples at 4x (every covered sample counts; edges make it inexact).
/// `--samples 1` benches the variants alone, with no ratios.
#[test]
fn bench_loop_plays_animated_frames_of_each_technique_and_counts_what_each_makes() {
    let number = |r: &serde_json::Value, key: &str| r[key].as_f64().unwrap_or_else(|| panic!("{key} in {r}"));
    // One frame in flight, a frame a turn; two (the default) and three, turns of 8 frames, for
    // every technique.
    for (in_flight, turn) in [("1", 1), ("2", 8), ("3", 8)] {
        let args = format!(
            "bench --loop 4 --warmup 2 --technique shadow-volume,lit,shadow-map,shadow-texture-atlas --size 64x48 --samples 1 --json \
             --validation --frames-in-flight {in_flight}"
        );
        let (out, err) = common::run_ok(&args.split_whitespace().collect::<Vec<_>>());
        assert!(!err.contains("vulkan validation"), "{err}");
        let report: serde_json::Value = serde_json::from_str(&out).expect("bench --loop --json is JSON");
        assert_eq!(report["turn"], turn, "{report}");
        let results = report["results"].as_array().expect("results");
        let names: Vec<&str> = results.iter().filter_map(|r| r["technique"].as_str()).collect();
        assert_eq!(names, ["shadow-volume", "lit", "shadow-map", "shadow-texture-atlas"], "{report}");
        for result in results {
            assert_eq!(result["frames_in_flight"].to_string(), in_flight, "{result}");
            assert_eq!(result["frames"], 4 * turn, "{result}");
            let frame_ms = number(result, "frame_ms");
            assert!((number(result, "frames_per_second") * frame_ms / 1e3 - 1.0).abs() < 1e-9, "{result}");
            assert!(number(result, "cpu_ms") <= frame_ms && number(result, "wait_ms") <= frame_ms, "{result}");
            // A steady-state frame waits once (for the frame that last used its slot; a turn's
            // first frames find theirs finished, and its end waits for the last ones instead),
            // and allocates nothing: posed vertices and volumes are rewritten into its slot's
            // buffers.
            assert_eq!(number(result, "waits_per_frame"), 1.0, "{result}");
            assert_eq!(number(result, "allocations_per_frame"), 0.0, "{result}");
            assert_eq!(number(result, "buffers_per_frame"), 0.0, "{result}");
            // Every frame records its passes' binds, pushes and draws, counted exactly.
            assert!(number(result, "commands_per_frame") >= 1.0, "{result}");
            // Every frame slot's command pool is reset on a worker once its frame is done, and
            // shadow volumes are built (and the objects' boxes taken) as jobs on other threads:
            // their CPU time is counted apart from the render thread's. No other technique
            // runs a job but the reset.
            let (jobs_ms, reset_ms) = (number(result, "jobs_cpu_ms"), number(result, "pool_reset_cpu_ms"));
            assert!(reset_ms > 0.0 && reset_ms <= jobs_ms, "{result}");
            if result["technique"] == "shadow-volume" {
                assert!(jobs_ms > reset_ms, "the casters turn: their volumes are built every frame: {result}");
            } else {
                assert_eq!(jobs_ms, reset_ms, "{result}");
            }
        }
        assert!(results[0]["throughput_ratio"].is_null(), "the first is the reference: {report}");
        let ratio = &results[1]["throughput_ratio"];
        let (low, high) = (number(&ratio["ci95"], "low"), number(&ratio["ci95"], "high"));
        assert!(low <= number(ratio, "median") && number(ratio, "median") <= high, "{ratio}");
    }

    // `--each-extrusion`: shadow-volume once per volume extrusion, in turn with the others, each
    // with no allocation and one wait a frame; the shader form builds nothing on the CPU.
    let args = "bench --loop 2 --warmup 1 --technique lit,shadow-volume --each-extrusion --size 64x48 --samples 1 \
                --json --validation";
    let (out, err) = common::run_ok(&args.split_whitespace().collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("bench --loop --json is JSON");
    let results = report["results"].as_array().expect("results");
    let names: Vec<&str> = results.iter().filter_map(|r| r["technique"].as_str()).collect();
    assert_eq!(names, ["lit", "shadow-volume (indices)", "shadow-volume (shader)"], "{report}");
    for result in results {
        assert_eq!(number(result, "allocations_per_frame"), 0.0, "{result}");
        assert_eq!(number(result, "waits_per_frame"), 1.0, "{result}");
    }
    let err = common::run_err(&["bench", "--each-extrusion", "--size", "64x48"]);
    assert!(err.contains("--loop"), "{err}");

    let err = common::run_err(&["bench", "--loop", "0", "--size", "64x48"]);
    assert!(err.contains("--loop") && err.contains("at least 1"), "{err}");
    let err = common::run_err(&["bench", "--loop", "3", "--runs", "5", "--size", "64x48"]);
    assert!(err.contains("drop --table1-out, --runs and --trace"), "{err}");
    let err = common::run_err(&["bench", "--loop", "3", "--frames-in-flight", "4", "--size", "64x48"]);
    assert!(err.contains("--frames-in-flight"), "{err}");
}

#[test]
fn bench_samples_4_pairs_every_variant_with_itself_at_1x() {
    let args = "bench --technique lit --size 64x64 --warmup 1 --runs 5 --json --validation --samples 4";
    let (out, err) = common::run_ok(&args.split(' ').collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("bench --json is JSON");
    assert_eq!(report["samples"], 4);
    let variants = report["variants"].as_array().expect("variants");
    let msaa = report["msaa"].as_array().expect("msaa");
    assert_eq!(variants.len(), 2 * msaa.len(), "{report}");
    assert_eq!(msaa.len(), 2, "lit's variants are reference and emulated: {report}");
    let rounds = |v: &serde_json::Value, key: &str| -> Vec<f64> {
        v[key].as_array().expect("rounds").iter().filter_map(|x| x.as_f64()).collect()
    };
    for (pair, ratio) in variants.chunks(2).zip(msaa) {
        let label = ratio["variant"].as_str().expect("label");
        assert_eq!(pair[0]["name"], format!("{label} @4x"));
        assert_eq!(pair[1]["name"], format!("{label} @1x"));
        assert_eq!(ratio["samples"], 4);
        let samples = |v: &serde_json::Value| v["samples_passed"].as_f64().expect("samples passed");
        let passed = ratio["samples_passed_ratio"].as_f64().expect("samples ratio");
        assert!((passed / (samples(&pair[0]) / samples(&pair[1])) - 1.0).abs() < 1e-12, "{ratio}");
        assert!((passed - 4.0).abs() < 0.1, "{label}: 4x passed {passed} times the 1x samples");
        let fragments = |v: &serde_json::Value| v["fragment_invocations"].as_f64().expect("fragments");
        let fragment_ratio = ratio["fragment_ratio"].as_f64().expect("fragment ratio");
        assert!((fragment_ratio / (fragments(&pair[0]) / fragments(&pair[1])) - 1.0).abs() < 1e-12, "{ratio}");
        // The frame ratio is the median of the per-round ratios (5 rounds: the middle one).
        let mut per_round: Vec<f64> = rounds(&pair[0], "frame_ms_rounds")
            .iter()
            .zip(rounds(&pair[1], "frame_ms_rounds"))
            .map(|(multi, single)| multi / single)
            .collect();
        assert_eq!(per_round.len(), 5);
        per_round.sort_by(f64::total_cmp);
        let frame = &ratio["frame_ratio"];
        // (JSON round-trips the times to within a last bit.)
        let median = frame["median"].as_f64().expect("median");
        assert!((median / per_round[2] - 1.0).abs() < 1e-12, "{ratio}: rounds give {}", per_round[2]);
        let (low, high) = (frame["ci95"]["low"].as_f64().expect("low"), frame["ci95"]["high"].as_f64().expect("high"));
        assert!(low <= per_round[2] && per_round[2] <= high, "{ratio}");
    }

    let (table, _) =
        common::run_ok(&["bench", "--technique", "lit", "--size", "64x64", "--warmup", "1", "--runs", "3"]);
    assert!(table.contains("lit (emulated) @4x") && table.contains("lit (emulated) @1x"), "{table}");
    let section = table.split("4x / 1x, the same variant in the same rounds:").nth(1).expect("the 4x/1x section");
    assert!(section.lines().any(|l| l.starts_with("lit (emulated) ")), "{table}");

    let single = "bench --technique lit --size 64x64 --warmup 1 --runs 3 --json --samples 1";
    let (out, _) = common::run_ok(&single.split(' ').collect::<Vec<_>>());
    let report: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(report["samples"], 1);
    assert_eq!(report["msaa"].as_array().map(Vec::len), Some(0), "{report}");
    let names: Vec<&str> =
        report["variants"].as_array().expect("variants").iter().filter_map(|v| v["name"].as_str()).collect();
    assert_eq!(names, ["lit (reference)", "lit (emulated)"]);
}

/// `bench --technique A,B` interleaves whole techniques, each as the command line renders it,
/// and gives each one's ratios to A: in the table and in JSON, with exact counters per
/// technique equal to that technique's own `profile` frame.
#[test]
fn bench_compares_listed_techniques_in_one_run() {
    let args =
        "bench --technique shadow-volume,shadow-map --size 48x32 --samples 1 --warmup 1 --runs 3 --validation --json";
    let (out, err) = common::run_ok(&args.split(' ').collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(report["technique"], "shadow-volume,shadow-map");
    let variants = report["variants"].as_array().expect("variants");
    let names: Vec<&str> = variants.iter().filter_map(|v| v["name"].as_str()).collect();
    assert_eq!(names, ["shadow-volume", "shadow-map"]);
    assert_eq!(variants[0]["frame_ratio"]["median"].as_f64(), Some(1.0), "the first listed is the reference");
    assert!(variants[1]["frame_ratio"]["median"].as_f64().is_some_and(|r| r > 0.0), "{report}");
    // Each technique's counters are its own frame's: the shadow-volume frame as profile draws it.
    let profiled = "profile --technique shadow-volume --size 48x32 --samples 1 --format json";
    let (profile, _) = common::run_ok(&profiled.split(' ').collect::<Vec<_>>());
    let profile: serde_json::Value = serde_json::from_str(&profile).expect("profile JSON");
    let passes = profile["passes"].as_array().expect("passes");
    assert_eq!(variants[0]["passes"].as_u64(), Some(passes.len() as u64), "{report}");

    let (table, _) = common::run_ok(&args.trim_end_matches(" --json").split(' ').collect::<Vec<_>>());
    assert!(table.contains("the first row's (shadow-volume)"), "{table}");
    refused(&["bench", "--technique", "shadow-volume,shadow-volume"], "each technique once");
    refused(&["bench", "--technique", "shadow-volume,all"], "each technique once");
    refused(&["bench", "--technique", "shadow-volume,nope"], "nope");
}

#[test]
fn bench_refuses_zero_runs() {
    refused(&["bench", "--technique", "planar", "--size", "64x64", "--runs", "0"], "--runs");
}

/// `--samples` takes what the device offers (`info` lists it) and names the offer otherwise,
/// in one line, before any file is written.
#[test]
fn sample_counts_outside_the_offer_are_refused_by_name() {
    let (info, _) = common::run_ok(&["info", "--json"]);
    let info: serde_json::Value = serde_json::from_str(&info).expect("info JSON");
    let offered: Vec<u64> =
        info["frame_samples_emulated"].as_array().expect("offered samples").iter().filter_map(|v| v.as_u64()).collect();
    assert!(offered.contains(&1) && offered.contains(&4), "the mobile profile guarantees 1 and 4: {offered:?}");
    let dir = common::scratch_dir("cli-samples");
    for samples in ["0", "2", "3", "8", "x"] {
        let out = dir.join(format!("{samples}.png"));
        let args = ["render", "--size", "16x16", "--samples", samples, "--out", out.to_str().expect("utf-8")];
        if samples == "2" && offered.contains(&2) {
            common::run_ok(&args);
            continue;
        }
        let err = common::run_err(&args);
        assert!(err.contains("--samples"), "{samples}: {err}");
        assert!(!out.exists(), "{samples}: a file was written");
    }
}
