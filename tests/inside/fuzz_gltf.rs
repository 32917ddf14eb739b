//! A deterministic mutation fuzzer for the glTF loader, bounded by a case count (the same cases
//! on every machine that finishes them: 2,000 in `cargo test`, about 5 s here) and a
//! wall-clock budget (a slow machine stops early, after at least 500), and the replay of every
//! file it found. `cargo test` runs a fixed sample of the fuzzer's cases so that every run proves
//! the same thing quickly; the search for new cases is the longer run by hand
//! (`FUZZ_CASES=20000` took about 19 s, `FUZZ_CASES=100000 FUZZ_SECONDS=600` searches further),
//! and what a search finds is kept in tests/gltf_regressions/, which every run replays.
//!
//! Each case mutates one file of the corpus (every .gltf/.glb under tests/: the real files of
//! tests/assets and the project's own) and loads it the way the CLI does
//! (`scene_and_warnings_from_gltf_slice`, the same
//! loader and scene building as `scene_from_gltf`, on bytes in memory). It must end in a scene
//! or a one-line error that names the file: no panic (caught and reported with the case), no
//! hang (a per-case time limit), and no allocation beyond what the file justifies (a counting
//! allocator bounds the peak heap of each case, see `allocation_limit`). A sample of the
//! cases that load is rendered at 32x32 through the library, so that uploads see them too.
//!
//! FUZZ_SEED, FUZZ_CASES and FUZZ_SECONDS change the run (e.g. a longer one by hand); a
//! failing case is written to the target dir with what was done to it. Cases it found are kept
//! in tests/gltf_regressions/ and replayed by `regression_files_end_in_a_scene_or_an_error`.

use crate::common;
#[path = "fuzz_gltf/mutate.rs"]
mod mutate;

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

use nostencil::scene::scene_and_warnings_from_gltf_slice;
use nostencil::Gpu;
use nostencil::Scene;
use nostencil::StencilMode;
use nostencil::{render_scene, RenderOptions, TECHNIQUES};

use mutate::{mutate, Rng};

/// Heap bytes in use, and the most in use since the last `reset_peak`.
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

struct CountingAllocator;

impl CountingAllocator {
    fn grew(by: usize) {
        let now = CURRENT.fetch_add(by, Ordering::Relaxed) + by;
        PEAK.fetch_max(now, Ordering::Relaxed);
    }
}

// SAFETY: every call is passed on to the system allocator unchanged; only sizes are counted.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            Self::grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if !p.is_null() {
            Self::grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            if new_size >= layout.size() {
                Self::grew(new_size - layout.size());
            } else {
                CURRENT.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// The peak heap one load may reach: 64 times the file (the JSON as a tree, then as gltf-json's
/// document; the BIN chunk copied once, widened to f32 and to the scene's vertices and shadow
/// geometry) plus 32 MiB (fixed costs and decoded textures of the corpus, within its files).
fn allocation_limit(file_len: usize) -> usize {
    64 * file_len + (32 << 20)
}

/// The bytes a case may justify allocations with: the file, plus the external files (buffers,
/// images) it names that exist beside it.
fn justified_len(bytes: &[u8], path: &Path) -> usize {
    let text = if bytes.starts_with(b"glTF") {
        let len = bytes.get(12..16).map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
        bytes.get(20..20 + len).unwrap_or_default()
    } else {
        bytes
    };
    let Ok(doc) = serde_json::from_slice::<serde_json::Value>(text) else { return bytes.len() };
    let dir = path.parent().unwrap_or(Path::new("."));
    let external: u64 = ["buffers", "images"]
        .iter()
        .filter_map(|list| doc.get(list)?.as_array())
        .flatten()
        .filter_map(|item| item.get("uri")?.as_str())
        .filter(|uri| !uri.starts_with("data:") && !uri.contains(".."))
        .filter_map(|uri| std::fs::metadata(dir.join(uri)).ok())
        .map(|m| m.len())
        .sum();
    bytes.len() + external as usize
}

/// Beyond this a case counts as a hang (the slowest unmutated file loads in well under 1 s in
/// the debug profile on the 2-core CI machine).
const CASE_TIME_LIMIT: Duration = Duration::from_secs(10);

/// Scenes with more objects are not rendered: the shadow-texture atlas costs about 160 ms per
/// caster on lavapipe (299 copies of a mesh took 48 s at 32x32, projective texture 17 s), which
/// is that technique's scaling, not the loader's, and would eat the fuzzer's time budget.
const MAX_RENDERED_OBJECTS: usize = 64;

/// One case in a test at a time: the peak heap is process-wide.
static SERIAL: Mutex<()> = Mutex::new(());

/// Where the last panic happened, kept by the hook that `quiet_panics` installs.
static PANIC_AT: Mutex<String> = Mutex::new(String::new());

thread_local! {
    /// Set while a case runs: its panics are caught and reported with the case, not printed.
    static IN_CASE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Panics inside a case only record where they happened; any other panic prints as usual.
fn quiet_panics() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if IN_CASE.with(|c| c.get()) {
            let at = info.location().map(|l| l.to_string()).unwrap_or_default();
            if let Ok(mut slot) = PANIC_AT.lock() {
                *slot = at;
            }
        } else {
            default(info);
        }
    }));
}

/// `f` as one case: a panic in it is caught, with where it happened.
fn in_case<T>(f: impl FnOnce() -> T) -> std::thread::Result<T> {
    IN_CASE.with(|c| c.set(true));
    let result = std::panic::catch_unwind(AssertUnwindSafe(f));
    IN_CASE.with(|c| c.set(false));
    result
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn gltf_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            gltf_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
            out.push(path);
        }
    }
}

/// The seeds: the real test assets and the loader's own test files (all under tests/), in a
/// fixed order.
fn corpus() -> Vec<(PathBuf, Vec<u8>)> {
    let mut paths = Vec::new();
    gltf_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests"), &mut paths);
    assert!(paths.iter().any(|p| p.starts_with(common::test_assets())), "no real asset in the corpus");
    paths.sort();
    paths.into_iter().filter_map(|p| std::fs::read(&p).ok().map(|bytes| (p, bytes))).collect()
}

/// How one case ended.
enum Outcome {
    Scene(Box<Scene>),
    Error(String),
    Panic(String),
}

struct Ended {
    outcome: Outcome,
    peak: usize,
    time: Duration,
}

/// Loads `bytes` as the file `path` (which anchors its relative URIs), measuring the peak heap.
fn load(bytes: &[u8], path: &Path) -> Ended {
    let start = Instant::now();
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let result = in_case(|| scene_and_warnings_from_gltf_slice(bytes, path, 0.5));
    let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
    let outcome = match result {
        Ok(Ok((scene, _warnings))) => Outcome::Scene(Box::new(scene)),
        Ok(Err(e)) => Outcome::Error(e.to_string()),
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            let at = PANIC_AT.lock().map(|s| s.clone()).unwrap_or_default();
            Outcome::Panic(format!("{message} at {at}"))
        }
    };
    Ended { outcome, peak, time: start.elapsed() }
}

/// What is wrong with how a case ended, if anything.
fn judge(ended: &Ended, path: &Path, file_len: usize) -> Option<String> {
    if ended.peak > allocation_limit(file_len) {
        return Some(format!(
            "peak heap {} bytes for a {file_len}-byte file (limit {})",
            ended.peak,
            allocation_limit(file_len)
        ));
    }
    match &ended.outcome {
        Outcome::Scene(_) => None,
        Outcome::Panic(p) => Some(format!("panicked: {p}")),
        Outcome::Error(e) => {
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            if e.contains('\n') {
                Some(format!("error of more than one line: {e:?}"))
            } else if !e.contains(&name) {
                Some(format!("error does not name the file {name}: {e}"))
            } else {
                None
            }
        }
    }
}

/// Renders a scene that loaded at 32x32 with the `k`th of every technique, stencil mode and
/// sample count in turn; a render may refuse it (with a one-line error) but not panic, and
/// the validation layer must stay silent.
/// What `render_small` goes through: every technique, in both stencil modes, at 1 and 4 samples.
fn render_combinations() -> usize {
    4 * TECHNIQUES.len()
}

fn render_small(gpu: &Arc<Gpu>, scene: &Scene, k: usize) -> Result<(), String> {
    let technique = TECHNIQUES[k % TECHNIQUES.len()];
    let round = k / TECHNIQUES.len();
    let stencil = if round % 2 == 0 { StencilMode::Emulated } else { StencilMode::Reference };
    let samples = if round / 2 % 2 == 0 { 1 } else { 4 };
    let options = RenderOptions { width: 32, height: 32, technique, stencil, samples, ..Default::default() };
    let before = gpu.validation_messages().len();
    let result = in_case(|| render_scene(gpu, scene, &options));
    if let Some(message) = gpu.validation_messages().get(before) {
        return Err(format!("validation message in the render: {message}"));
    }
    match result {
        Ok(Ok(_)) => Ok(()),
        Ok(Err(e)) if !e.to_string().contains('\n') => Ok(()),
        Ok(Err(e)) => Err(format!("render error of more than one line: {e:?}")),
        Err(_) => Err(format!("render panicked at {}", PANIC_AT.lock().map(|s| s.clone()).unwrap_or_default())),
    }
}

/// Keeps a failing case for replay by hand: its bytes beside a note of what was done.
fn save_failure(index: usize, source: &Path, bytes: &[u8], note: &str) -> PathBuf {
    let dir = common::scratch_root().join("fuzz_gltf_failures");
    let _ = std::fs::create_dir_all(&dir);
    let ext = if bytes.starts_with(b"glTF") { "glb" } else { "gltf" };
    let path = dir.join(format!("case{index}.{ext}"));
    let _ = std::fs::write(&path, bytes);
    let _ = std::fs::write(dir.join(format!("case{index}.txt")), format!("{}\n{note}\n", source.display()));
    path
}

struct Job {
    index: usize,
    bytes: Vec<u8>,
    path: PathBuf,
    /// Render the scene, if it loads (with the next technique, stencil mode and sample count in
    /// turn: see `render_small`).
    render: bool,
}

struct Report {
    index: usize,
    ended: Ended,
    render: Option<Result<(), String>>,
}

#[test]
fn mutated_files_end_in_a_scene_or_a_one_line_error() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let seed: u64 = env_or("FUZZ_SEED", 16);
    // 2,000 in `cargo test` (it was 20,000, 19 s of every run): every case is still loaded and
    // judged, and every 6th case is rendered if it loads (it was every 16th), the techniques,
    // stencil modes and sample counts in turn: each of them at least once (`render_combinations`).
    let max_cases: usize = env_or("FUZZ_CASES", 2_000);
    let budget = Duration::from_secs_f64(env_or("FUZZ_SECONDS", 60.0));
    let corpus = corpus();
    assert!(corpus.len() > 100, "fuzz corpus has only {} files", corpus.len());
    let gpu = common::gpu();
    quiet_panics();

    // The cases run on a worker so that a hang is seen (and reported) by this thread.
    let (jobs, job_rx) = mpsc::channel::<Job>();
    let (report_tx, reports) = mpsc::channel::<Report>();
    let worker_gpu = gpu.clone();
    let worker = std::thread::spawn(move || {
        let mut rendered = 0;
        for job in job_rx {
            let ended = load(&job.bytes, &job.path);
            let render = match (&ended.outcome, job.render) {
                (Outcome::Scene(scene), true) if scene.objects.len() <= MAX_RENDERED_OBJECTS => {
                    rendered += 1;
                    Some(render_small(&worker_gpu, scene, rendered - 1))
                }
                _ => None,
            };
            if report_tx.send(Report { index: job.index, ended, render }).is_err() {
                break;
            }
        }
    });

    // Three cases in four mutate a file that loads as it is (most validator files are refused
    // unmutated, and a mutant of them stops at the same check); the fourth any file.
    let start = Instant::now();
    let loading: Vec<usize> =
        (0..corpus.len()).filter(|&i| matches!(load(&corpus[i].1, &corpus[i].0).outcome, Outcome::Scene(_))).collect();
    assert!(loading.len() > 20, "only {} corpus files load unmutated", loading.len());
    let mut rng = Rng::new(seed);
    let (mut scenes, mut errors, mut renders, mut slowest) = (0, 0, 0, Duration::ZERO);
    // The highest peak heap of a case, as a share of its limit, and that case's peak.
    let (mut highest, mut highest_peak) = (0.0f64, 0);
    let mut failures = Vec::new();
    let mut cases = 0;
    while cases < max_cases && start.elapsed() < budget {
        let file = if cases % 4 == 3 { cases / 4 % corpus.len() } else { loading[cases % loading.len()] };
        let (path, original) = &corpus[file];
        let mutant = mutate(original, &mut rng);
        // Every 6th case is rendered if it loads (the renders are the slow part on lavapipe).
        let render = cases % 6 == 0;
        let job = Job { index: cases, bytes: mutant.bytes.clone(), path: path.clone(), render };
        if jobs.send(job).is_err() {
            break;
        }
        let report = match reports.recv_timeout(CASE_TIME_LIMIT) {
            Ok(report) => report,
            Err(_) => {
                let saved = save_failure(cases, path, &mutant.bytes, &mutant.what);
                failures.push(format!(
                    "case {cases} ({}; {}): no result within {CASE_TIME_LIMIT:?}; saved as {}",
                    path.display(),
                    mutant.what,
                    saved.display()
                ));
                break;
            }
        };
        debug_assert_eq!(report.index, cases);
        let ended = &report.ended;
        slowest = slowest.max(ended.time);
        let share = ended.peak as f64 / allocation_limit(justified_len(&mutant.bytes, path)) as f64;
        if share > highest {
            (highest, highest_peak) = (share, ended.peak);
        }
        match &ended.outcome {
            Outcome::Scene(_) => scenes += 1,
            _ => errors += 1,
        }
        let mut problem = judge(ended, path, justified_len(&mutant.bytes, path));
        if ended.time > CASE_TIME_LIMIT / 2 {
            problem = problem.or(Some(format!("took {:?}", ended.time)));
        }
        if let Some(render) = report.render {
            renders += 1;
            problem = problem.or(render.err());
        }
        if let Some(problem) = problem {
            let saved = save_failure(cases, path, &mutant.bytes, &format!("{}\n{problem}", mutant.what));
            failures.push(format!(
                "case {cases} ({}; {}): {problem}; saved as {}",
                path.display(),
                mutant.what,
                saved.display()
            ));
        }
        cases += 1;
    }
    drop(jobs);
    let elapsed = start.elapsed();
    // Straight to stderr, past the test harness's capture, so that CI logs show the figures.
    let _ = writeln!(
        std::io::stderr(),
        "fuzz_gltf: seed {seed}, {cases} cases over {} files ({} load unmutated) in {:.1} s: {scenes} loaded ({renders} rendered at \
         32x32 by every technique in turn), {errors} refused with an error; slowest case {:.0} ms, highest peak heap {:.0}% of its limit ({:.1} MB); \
         {} failing",
        corpus.len(),
        loading.len(),
        elapsed.as_secs_f64(),
        slowest.as_secs_f64() * 1e3,
        highest * 100.0,
        highest_peak as f64 / 1e6,
        failures.len()
    );
    if failures.is_empty() {
        let _ = worker.join();
    }
    assert!(failures.is_empty(), "{} failing case(s):\n{}", failures.len(), failures.join("\n"));
    assert!(cases >= 500, "only {cases} cases ran in {elapsed:?}");
    // The default run (seed 16, 2,000 cases) renders 68 of its cases.
    if seed == 16 && cases >= 2_000 {
        assert!(
            renders >= render_combinations(),
            "only {renders} renders: not every technique, stencil and sample count"
        );
    }
    common::assert_no_validation_messages(&gpu);
}

/// What each regression file must now end in (a fragment of its error), where it is refused;
/// a file not listed here only has to end in a scene or a one-line error.
const EXPECTED_ENDINGS: &[(&str, &str)] = &[
    // count 3,000,000 without a bufferView in a 254-byte file: 250 MB before the fix.
    ("zero_filled_huge_count.gltf", "zero-filled data (no bufferView) exceed"),
    // 278 primitives reading the same accessors: 85 MB from a 133 kB file before the fix.
    ("primitives_sharing_accessors_x277.glb", "more bytes of accessor data would make"),
    // One vertex, no triangle: an empty index buffer reached the GPU (a zero-sized copy).
    ("one_vertex_no_triangle.gltf", "no triangle meshes to render"),
    // Made by hand, not found: a PNG header claiming 11000x11000 texels, refused from the header.
    ("png_claiming_11000x11000.gltf", "larger than the mobile profile's 4096x4096 texels"),
];

/// Every file the fuzzer found (tests/gltf_regressions/) still ends in a scene or a one-line
/// error naming the file, within the allocation limit, and each is rendered when it loads.
#[test]
fn regression_files_end_in_a_scene_or_an_error() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf_regressions");
    let mut files = Vec::new();
    gltf_files(&dir, &mut files);
    files.sort();
    assert!(!files.is_empty(), "no regression files in {}", dir.display());
    let gpu = common::gpu();
    quiet_panics();
    let mut failures = Vec::new();
    for path in &files {
        let bytes = std::fs::read(path).unwrap_or_default();
        let ended = load(&bytes, path);
        let mut problem = judge(&ended, path, justified_len(&bytes, path));
        if let Outcome::Scene(scene) = &ended.outcome {
            for k in 0..TECHNIQUES.len() * 4 {
                problem = problem.or(render_small(&gpu, scene, k).err());
            }
        }
        let ending = match &ended.outcome {
            Outcome::Scene(_) => "scene".to_string(),
            Outcome::Error(e) => e.clone(),
            Outcome::Panic(p) => format!("panic: {p}"),
        };
        println!("{}: {ending}", path.display());
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        if let Some((_, fragment)) = EXPECTED_ENDINGS.iter().find(|(file, _)| *file == name) {
            if !ending.contains(fragment) {
                problem = problem.or(Some(format!("expected an error with '{fragment}', got: {ending}")));
            }
        }
        if let Some(problem) = problem {
            failures.push(format!("{}: {problem}", path.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    common::assert_no_validation_messages(&gpu);
}
