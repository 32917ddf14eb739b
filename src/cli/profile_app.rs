//! `nostencil profile-app -- COMMAND ARGS...`: runs any program with the fill-rate layer
//! enabled through the loader's environment, waits for it, reads the layer's result file and
//! reports it, checked against a budget if asked.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use super::app_counts::{
    chart_rows, largest_area, trace_frames, worst_frame_bandwidth, worst_per_position, worst_work, PositionCounts,
};
use super::install::{InstallPaths, HOW_TO_INSTALL};
use super::output_path::check_output_path;
use super::supervise::{self, Stop};
use crate::error::{Error, Result};
use crate::gpu::device::DeviceIdentity;
use crate::gpu::DeviceChoice;
use crate::profile::budget::{Budget, BudgetFigure};
use crate::profile::report::ReportFormat;
use nostencil_fillrate_report::aggregate::report_from_journal;
use nostencil_fillrate_report::manifest::{
    manifest_json, newest_build_of, newest_library, GL_SWAPS_FILE, LAYER_NAME, LIBRARY_FILE, MANIFEST_FILE,
};
use nostencil_fillrate_report::output::OutputFormat;
use nostencil_fillrate_report::report::{journal_path, FillrateReport};

/// Shown after `profile-app --help`.
pub const AFTER_HELP: &str = "\
The layer (libnostencil_fillrate.so, built beside the nostencil executable, or installed for the user by
`nostencil layer install`) is enabled for the program only: VK_INSTANCE_LAYERS gets VK_LAYER_NOSTENCIL_fillrate first (nearest the application; layers
the user named stay, below it), VK_ADD_LAYER_PATH (or VK_LAYER_PATH, if set) its folder, and
NOSTENCIL_FILLRATE_OUT/_FORMAT/_FRAMES/_EVERY tell it where and what to write (--capture sets
NOSTENCIL_FILLRATE_CAPTURE/_CAPTURE_FRAME; the report is
rewritten at most every 100 ms, and each finished frame is appended to a journal beside it as it
finishes). The program's stdio is its own; it runs in its own process group.
The report follows once the program ends: by itself; after --frames N measured frames or
--seconds S (SIGTERM, then SIGKILL 5 s later; --keep-running leaves it running after its N
frames); or on Ctrl-C. A program that crashes or is killed still gets a report of the frames
measured before, marked partial, and profile-app then exits 1. A frame is the work submitted
between two presents: render pass instances, and the dispatch groups and transfers outside them
(a program that never presents has one, ended when its device is destroyed, unless it marks
frames with VK_EXT_frame_boundary, which the layer offers, or --frame-on submit|wait cuts them
per queue submission or per host wait; with --gl, a GL program's frames end at its buffer
swaps). Draws, passes, dispatches and transfers in secondary command buffers are measured where
they are executed, multiview passes over all their views. Device extensions whose commands the
layer cannot measure are not offered to the program, and the report names them.

Not measured (and named in the report): render passes begun while the program has an occlusion
or statistics query of its own open, and a secondary command buffer executed twice in one
primary. --chart draws `profile`'s bar chart per
render pass and work row; there is
no heat map: `profile --heatmap` counts fragments with this crate's own shaders, which a foreign
program does not have.";

/// What `profile-app` writes besides the report.
pub struct AppOutputs {
    pub budget: Option<PathBuf>,
    pub record_budget: Option<PathBuf>,
    pub chart: Option<PathBuf>,
    /// The measured frames on a timeline (Chrome trace-event JSON).
    pub trace: Option<PathBuf>,
    /// The report goes here instead of stdout.
    pub out: Option<PathBuf>,
    /// Each draw counted on its own too (NOSTENCIL_FILLRATE_PER_DRAW).
    pub per_draw: bool,
    /// The tiler check (NOSTENCIL_FILLRATE_TILER): exit 1 on any flag.
    pub tiler_check: bool,
    /// What ends a frame: "present", "submit", "wait" or "swap" (NOSTENCIL_FILLRATE_FRAME_ON).
    pub frame_on: &'static str,
    /// An OpenGL or GLES program, run on zink over this Vulkan device with the swap library
    /// preloaded (None: a Vulkan program).
    pub gl: Option<DeviceChoice>,
    /// The run's page (`--html`).
    pub html: Option<PathBuf>,
    /// The budget's verdict as JUnit XML (`--junit`, with `--budget`).
    pub junit: Option<PathBuf>,
    /// The image presented at the end of a frame, written as a PNG (NOSTENCIL_FILLRATE_CAPTURE):
    /// (file, frame).
    pub capture: Option<(PathBuf, u64)>,
}

pub fn run(command: &[String], stop: Stop, format: ReportFormat, outputs: &AppOutputs) -> Result<()> {
    let frames = stop.frames;
    let Some((program, args)) = command.split_first() else {
        return Err(Error::InvalidInput(
            "profile-app needs the program to run after `--`, e.g. `nostencil profile-app -- vkcube --c 10`".into(),
        ));
    };
    if frames == Some(0) {
        return Err(Error::InvalidInput("--frames 0 would measure nothing; give 1 or more".into()));
    }
    if outputs.gl.is_some() && outputs.capture.is_some() {
        // zink on a software X server shows a frame by reading it on the host: there is no
        // swapchain image to copy, and a read-back of the GL back buffer before the swap would add
        // a pass of zink's own to the very frame it measures.
        return Err(Error::InvalidInput(
            "--capture copies a presented swapchain image, and a GL program on zink presents none: drop --capture              (docs/fillrate-layer.md, \"OpenGL and GLES programs\")"
                .into(),
        ));
    }
    if let (Some(n), Some((_, frame))) = (frames, &outputs.capture) {
        if *frame >= n as u64 {
            return Err(Error::InvalidInput(format!(
                "--capture-frame {frame} is not among the {n} frames measured (0 to {}); the program is ended before",
                n - 1
            )));
        }
    }
    if let Some(seconds) = stop.seconds {
        if !(seconds.is_finite() && seconds > 0.0) {
            return Err(Error::InvalidInput(format!("--seconds {seconds} is not a positive number of seconds")));
        }
    }
    let capture_path = outputs.capture.as_ref().map(|(path, _)| path.clone());
    for path in [
        &outputs.record_budget,
        &outputs.chart,
        &outputs.trace,
        &outputs.out,
        &capture_path,
        &outputs.html,
        &outputs.junit,
    ]
    .into_iter()
    .flatten()
    {
        check_output_path(path)?;
    }
    let budget = outputs.budget.as_deref().map(Budget::load).transpose()?;
    let work = ScratchDir::new()?;
    let layer_dir = layer_folder(&work.0)?;
    let result = work.0.join("result.json");
    let mut environment = layer_environment(|name| std::env::var_os(name), layer_dir.as_deref(), &result, frames);
    if let Some(choice) = &outputs.gl {
        let library = gl_swaps_library()?;
        let device = crate::gpu::device::identify(choice)?;
        eprintln!("profile-app: the GL program runs on zink over '{}'", device.name);
        environment.extend(gl_environment(|name| std::env::var_os(name), &library, &device));
    }
    if outputs.per_draw {
        environment.push(("NOSTENCIL_FILLRATE_PER_DRAW".into(), "1".into()));
    }
    if outputs.frame_on != "present" {
        environment.push(("NOSTENCIL_FILLRATE_FRAME_ON".into(), outputs.frame_on.into()));
    }
    if outputs.tiler_check {
        environment.push(("NOSTENCIL_FILLRATE_TILER".into(), "1".into()));
    }
    // The layer writes the capture into the scratch folder; it is moved to the user's path
    // only if the layer wrote one (a file already there is not taken for it).
    let captured = work.0.join("capture.png");
    if let Some((_, frame)) = &outputs.capture {
        environment.push(("NOSTENCIL_FILLRATE_CAPTURE".into(), captured.clone().into_os_string()));
        environment.push(("NOSTENCIL_FILLRATE_CAPTURE_FRAME".into(), frame.to_string().into()));
    }

    let mut child = std::process::Command::new(program);
    child.args(args).envs(environment);
    let mut ending = supervise::run(child, program, &result, stop)?;
    // The frame journal beside the result holds every finished frame even when the program
    // died between two rewrites of the result: the fuller of the two is the report.
    let journal = std::fs::read_to_string(journal_path(&result))
        .ok()
        .and_then(|text| report_from_journal(&text, frames.is_some()));
    let written = match std::fs::read_to_string(&result) {
        Ok(text) => Some(
            FillrateReport::from_json(&text)
                .map_err(|e| Error::Asset { path: result.clone(), problem: e.to_string() })?,
        ),
        Err(_) => None,
    };
    let report = match (written, journal) {
        (Some(written), Some(journal)) if journal.frames_measured > written.frames_measured => Some(journal),
        (Some(written), _) => Some(written),
        (None, journal) => journal,
    };
    let mut report = report.ok_or_else(|| {
        if ending.how == "exited" {
            Error::InvalidInput(format!(
                "'{program}' exited normally but the layer wrote no result: it created no Vulkan device or never \
                 finished a frame, or the loader did not load {LAYER_NAME} (VK_LOADER_DEBUG=layer shows why)"
            ))
        } else {
            Error::InvalidInput(format!("'{program}' {} before a frame was measured; no report", ending.detail))
        }
    })?;
    let short = frames.is_some_and(|n| report.frames_measured < n as u64);
    let failed = matches!(ending.how.as_str(), "crashed" | "killed" | "failed");
    ending.partial = short || failed;
    let measured = report.frames_measured;
    let frames_word = if measured == 1 { "frame" } else { "frames" };
    let failure = failed.then(|| {
        format!("'{program}' {} after {measured} measured {frames_word}; the report covers those", ending.detail)
    });
    report.run = Some(ending);

    let rendered = nostencil_fillrate_report::output::render(&report, output_format(format));
    match &outputs.out {
        Some(path) => {
            crate::frame::write_atomically(path, rendered.as_bytes())?;
            eprintln!("wrote {}", path.display());
        }
        None => print!("{rendered}"),
    }
    let worst = worst_per_position(&report);
    if let Some(path) = &outputs.chart {
        let title = format!("{} on {} ({} frames)", report.application, report.device, report.frames_measured);
        let svg = crate::profile::chart::chart_rows_svg(&title, &chart_rows(&report));
        crate::frame::write_atomically(path, svg.as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &outputs.trace {
        let mut trace = crate::profile::trace::Trace::new(&format!("{} (profile-app)", report.application), false);
        trace_frames(&mut trace, &report);
        trace.write(path)?;
        eprintln!("wrote {}", path.display());
    }
    if let Some((path, frame)) = &outputs.capture {
        keep_capture(&captured, path, *frame, program)?;
    }
    if let Some(path) = &outputs.record_budget {
        let work = worst_work(&report);
        if worst.is_empty() && work.is_empty() {
            return Err(Error::InvalidInput(format!(
                "no render pass, dispatch or transfer of '{program}' was measured: no budget to record"
            )));
        }
        let (width, height) = largest_area(&report);
        let counts: Vec<_> = worst.iter().map(|p| p.count.clone()).collect();
        let bytes = worst_frame_bandwidth(&report);
        Budget::for_application(&report.application, width, height, &counts, bytes, &work).write(path)?;
        let work_note =
            if work.is_empty() { String::new() } else { format!(", {} dispatch groups and transfers", work.len()) };
        eprintln!("wrote budget {} ({} render passes{work_note})", path.display(), counts.len());
    }
    let figures = match &budget {
        Some(budget) => {
            let counts: Vec<_> = worst.iter().map(|p| p.count.clone()).collect();
            let bytes = worst_frame_bandwidth(&report);
            Some(budget.compared_application(&report.application, &counts, bytes, &worst_work(&report))?)
        }
        None => None,
    };
    let budget_file = outputs.budget.as_ref().map(|p| p.display().to_string());
    let verdict = budget_file.as_deref().zip(figures.as_deref());
    if let (Some(path), Some((file, figures))) = (&outputs.junit, verdict) {
        crate::profile::junit::write(path, &report.application, file, figures)?;
    }
    if let Some(path) = &outputs.html {
        let capture = match &outputs.capture {
            Some((file, frame)) => std::fs::read(file).ok().map(|png| (*frame, png)),
            None => None,
        };
        let json = nostencil_fillrate_report::output::render(&report, OutputFormat::Json);
        let extras = crate::profile::html::from_app::AppExtras { budget: verdict, capture, json };
        crate::profile::html::from_app::page(&report, extras).write(path)?;
    }
    if let (Some(figures), Some(path)) = (&figures, &outputs.budget) {
        check_budget(figures, path, &report, &worst)?;
    }
    if outputs.tiler_check {
        check_tiler(&report, program)?;
    }
    match failure {
        Some(message) => Err(Error::InvalidInput(message)),
        None => Ok(()),
    }
}

/// Moves the layer's capture of `frame` to `path`, or says why there is none.
fn keep_capture(captured: &Path, path: &Path, frame: u64, program: &str) -> Result<()> {
    let bytes = std::fs::read(captured).map_err(|_| {
        Error::InvalidInput(format!(
            "the layer captured no image of frame {frame} of '{program}': it presented fewer frames, or the \
             capture failed (the layer's line on stderr says why)"
        ))
    })?;
    crate::frame::write_atomically(path, &bytes)?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// The tiler check's flags on stderr (when the report went elsewhere than a table on stdout),
/// then an error counting them.
fn check_tiler(report: &FillrateReport, program: &str) -> Result<()> {
    let Some(check) = &report.tiler_check else {
        return Err(Error::InvalidInput(format!(
            "the layer wrote no tiler check for '{program}': is the layer older than this nostencil?"
        )));
    };
    if check.flags.is_empty() {
        eprintln!("tiler check: no flag");
        return Ok(());
    }
    eprint!("{}", nostencil_fillrate_report::output::tiler_lines(check));
    let kinds: std::collections::BTreeSet<&str> = check.flags.iter().map(|f| f.kind.as_str()).collect();
    Err(Error::InvalidInput(format!(
        "{} tiler-check flag(s) for '{program}': {}",
        check.flags.len(),
        kinds.into_iter().collect::<Vec<_>>().join(", ")
    )))
}

/// Every render pass over its budget (among `figures`, all those compared) on stderr, then an
/// error naming them all.
fn check_budget(
    figures: &[BudgetFigure],
    path: &Path,
    report: &FillrateReport,
    worst: &[PositionCounts],
) -> Result<()> {
    let overruns: Vec<&BudgetFigure> = figures.iter().filter(|f| f.over()).collect();
    if overruns.is_empty() {
        eprintln!("within budget {}", path.display());
        return Ok(());
    }
    // Render passes are named with their area; work rows (dispatches, transfers) have none.
    let area = |name: &str| worst.iter().find(|p| p.count.name == name).map(|p| p.area.as_str());
    for overrun in &overruns {
        match area(&overrun.pass) {
            Some(area) => eprintln!("over budget: {overrun} (render area {area})"),
            None => eprintln!("over budget: {overrun}"),
        }
    }
    let mut passes: Vec<String> = overruns
        .iter()
        .map(|o| match area(&o.pass) {
            Some(area) => format!("{} ({area})", o.pass),
            None => o.pass.clone(),
        })
        .collect();
    passes.dedup();
    let what = if overruns.iter().all(|o| area(&o.pass).is_some()) { "render pass(es)" } else { "part(s)" };
    Err(Error::InvalidInput(format!(
        "{} {what} of '{}' over the budget in {}: {}",
        passes.len(),
        report.application,
        path.display(),
        passes.join(", ")
    )))
}

fn output_format(format: ReportFormat) -> OutputFormat {
    match format {
        ReportFormat::Table => OutputFormat::Table,
        ReportFormat::Json => OutputFormat::Json,
        ReportFormat::Csv => OutputFormat::Csv,
    }
}

/// The folder holding the layer's manifest, or None when the layer is installed for the user
/// (`nostencil layer install`; the loader finds it there). The build's folder, beside the
/// executable, when the library it names (`./libnostencil_fillrate.so`) is the newest build of the layer;
/// else a manifest written into `scratch` naming the newest library by its absolute path
/// (`cargo test` leaves a fresher one in deps/).
fn layer_folder(scratch: &Path) -> Result<Option<PathBuf>> {
    let exe =
        std::env::current_exe().map_err(|e| Error::Internal(format!("cannot find the nostencil executable: {e}")))?;
    let dir = exe.parent().unwrap_or(Path::new(".")).to_path_buf();
    let Some(library) = newest_library(&dir) else {
        if InstallPaths::current().is_ok_and(|p| p.installed()) {
            return Ok(None);
        }
        return Err(Error::InvalidInput(format!(
            "the fill-rate layer is neither installed for this user nor beside nostencil ({LIBRARY_FILE} in {}); \
             install it {HOW_TO_INSTALL}",
            dir.display()
        )));
    };
    if library == dir.join(LIBRARY_FILE) && dir.join(MANIFEST_FILE).is_file() {
        return Ok(Some(dir));
    }
    let text = manifest_json(&library.to_string_lossy());
    crate::frame::write_atomically(&scratch.join(MANIFEST_FILE), text.as_bytes())?;
    Ok(Some(scratch.to_path_buf()))
}

/// `libnostencil_gl_swaps.so`, which `--gl` preloads to find the program's buffer swaps: the
/// newest build beside nostencil, else the one installed with the layer.
fn gl_swaps_library() -> Result<PathBuf> {
    let exe =
        std::env::current_exe().map_err(|e| Error::Internal(format!("cannot find the nostencil executable: {e}")))?;
    let dir = exe.parent().unwrap_or(Path::new(".")).to_path_buf();
    let installed = InstallPaths::current().ok().and_then(|p| Some(p.library.parent()?.join(GL_SWAPS_FILE)));
    let library = newest_build_of(&dir, GL_SWAPS_FILE).or(installed.filter(|p| p.is_file())).ok_or_else(|| {
        Error::InvalidInput(format!(
            "--gl preloads {GL_SWAPS_FILE} to find the program's buffer swaps, and there is none beside nostencil              ({}) nor installed: build it with `cargo build` in nostencil's source folder (it builds every crate),              or install it with the layer {HOW_TO_INSTALL}",
            dir.display()
        ))
    })?;
    library.canonicalize().map_err(|e| Error::InvalidInput(format!("{} cannot be preloaded: {e}", library.display())))
}

/// What `--gl` adds: the program's GL runs on Vulkan through Mesa's zink over `device`
/// (Mesa's device-select layer keeps only that one: `MESA_VK_DEVICE_SELECT=vendor:device!`), as
/// Mesa's software GL driver on the CPU's device and as Mesa's GL driver for a GPU; Mesa's GLX
/// is the one chosen where several vendors are installed, and the swap library is preloaded
/// (before any library the user preloads).
pub fn gl_environment(
    current: impl Fn(&str) -> Option<OsString>,
    library: &Path,
    device: &DeviceIdentity,
) -> Vec<(String, OsString)> {
    let mut preload = library.as_os_str().to_owned();
    if let Some(user) = current("LD_PRELOAD").filter(|v| !v.is_empty()) {
        preload.push(":");
        preload.push(user);
    }
    let select = format!("{:x}:{:x}!", device.vendor_id, device.device_id);
    let mut environment = vec![
        ("LD_PRELOAD".into(), preload),
        ("MESA_VK_DEVICE_SELECT".into(), select.into()),
        ("__GLX_VENDOR_LIBRARY_NAME".into(), "mesa".into()),
    ];
    if device.software {
        environment.push(("GALLIUM_DRIVER".into(), "zink".into()));
        environment.push(("LIBGL_ALWAYS_SOFTWARE".into(), "1".into()));
    } else {
        environment.push(("MESA_LOADER_DRIVER_OVERRIDE".into(), "zink".into()));
    }
    environment
}

/// The variables that enable the layer for the child: `current` reads the parent's environment.
/// The layer goes first in VK_INSTANCE_LAYERS (nearest the application), before any the user
/// named; its folder is added to the loader's search (VK_ADD_LAYER_PATH keeps the system's
/// folders, so a validation layer can still be found; a VK_LAYER_PATH the user set replaces
/// those, so the folder goes there instead).
pub fn layer_environment(
    current: impl Fn(&str) -> Option<OsString>,
    layer_dir: Option<&Path>,
    result: &Path,
    frames: Option<u32>,
) -> Vec<(String, OsString)> {
    let prepend = |name: &str, first: OsString| -> (String, OsString) {
        match current(name).filter(|v| !v.is_empty()) {
            Some(rest) => {
                let mut joined = first;
                joined.push(":");
                joined.push(rest);
                (name.to_owned(), joined)
            }
            None => (name.to_owned(), first),
        }
    };
    let search =
        if current("VK_LAYER_PATH").is_some_and(|v| !v.is_empty()) { "VK_LAYER_PATH" } else { "VK_ADD_LAYER_PATH" };
    let layers = match current("VK_INSTANCE_LAYERS") {
        Some(user) if user.to_string_lossy().split(':').any(|l| l == LAYER_NAME) => ("VK_INSTANCE_LAYERS".into(), user),
        _ => prepend("VK_INSTANCE_LAYERS", LAYER_NAME.into()),
    };
    let mut environment: Vec<(String, OsString)> =
        layer_dir.map(|dir| prepend(search, dir.as_os_str().to_owned())).into_iter().collect();
    environment.extend([
        layers,
        ("NOSTENCIL_FILLRATE_OUT".into(), result.as_os_str().to_owned()),
        ("NOSTENCIL_FILLRATE_FORMAT".into(), "json".into()),
        // Finished frames go to disk as they come (the report at most every 100 ms, each frame to
        // the journal at once): a program that crashes or is killed has a report of every one.
        ("NOSTENCIL_FILLRATE_EVERY".into(), "1".into()),
    ]);
    if let Some(frames) = frames {
        environment.push(("NOSTENCIL_FILLRATE_FRAMES".into(), frames.to_string().into()));
    }
    environment
}

/// A private folder under the system's temp folder, removed when dropped.
struct ScratchDir(PathBuf);

impl ScratchDir {
    fn new() -> Result<Self> {
        let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_nanos());
        let dir = std::env::temp_dir().join(format!("nostencil-profile-app-{}-{nanos}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|source| Error::Io { path: dir.clone(), source })?;
        Ok(ScratchDir(dir))
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env_of<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<OsString> + 'a {
        move |name| vars.iter().find(|(n, _)| *n == name).map(|(_, v)| OsString::from(v))
    }

    fn value<'a>(environment: &'a [(String, OsString)], name: &str) -> Option<&'a str> {
        environment.iter().find(|(n, _)| n == name).and_then(|(_, v)| v.to_str())
    }

    #[test]
    fn the_layer_comes_first_and_the_users_settings_stay() {
        let (dir, out) = (Path::new("/l"), Path::new("/t/r.json"));
        let plain = layer_environment(env_of(&[]), Some(dir), out, Some(5));
        assert_eq!(value(&plain, "VK_INSTANCE_LAYERS"), Some(LAYER_NAME));
        assert_eq!(value(&plain, "VK_ADD_LAYER_PATH"), Some("/l"));
        assert_eq!(value(&plain, "VK_LAYER_PATH"), None);
        assert_eq!(value(&plain, "NOSTENCIL_FILLRATE_OUT"), Some("/t/r.json"));
        assert_eq!(value(&plain, "NOSTENCIL_FILLRATE_FORMAT"), Some("json"));
        assert_eq!(value(&plain, "NOSTENCIL_FILLRATE_FRAMES"), Some("5"));

        let user = [("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation"), ("VK_LAYER_PATH", "/mine")];
        let mixed = layer_environment(env_of(&user), Some(dir), out, None);
        let expected = format!("{LAYER_NAME}:VK_LAYER_KHRONOS_validation");
        assert_eq!(value(&mixed, "VK_INSTANCE_LAYERS"), Some(expected.as_str()));
        assert_eq!(value(&mixed, "VK_LAYER_PATH"), Some("/l:/mine"));
        assert_eq!(value(&mixed, "VK_ADD_LAYER_PATH"), None);
        assert_eq!(value(&mixed, "NOSTENCIL_FILLRATE_FRAMES"), None);

        // Named already (to put it elsewhere in the order): left as the user wrote it.
        let placed = format!("VK_LAYER_KHRONOS_validation:{LAYER_NAME}");
        let named = layer_environment(env_of(&[("VK_INSTANCE_LAYERS", &placed)]), Some(dir), out, None);
        assert_eq!(value(&named, "VK_INSTANCE_LAYERS"), Some(placed.as_str()));

        // Installed for the user: the loader finds it, no folder is added.
        let installed = layer_environment(env_of(&[]), None, out, None);
        assert_eq!((value(&installed, "VK_ADD_LAYER_PATH"), value(&installed, "VK_LAYER_PATH")), (None, None));
        assert_eq!(value(&installed, "VK_INSTANCE_LAYERS"), Some(LAYER_NAME));
        assert_eq!(value(&installed, "NOSTENCIL_FILLRATE_EVERY"), Some("1"));
    }

    #[test]
    fn gl_runs_zink_over_the_chosen_device_with_the_swap_library_first() {
        let library = Path::new("/b/libnostencil_gl_swaps.so");
        let cpu = DeviceIdentity { name: "llvmpipe".into(), vendor_id: 0x10005, device_id: 0, software: true };
        let env = gl_environment(env_of(&[("LD_PRELOAD", "/mine.so")]), library, &cpu);
        assert_eq!(value(&env, "LD_PRELOAD"), Some("/b/libnostencil_gl_swaps.so:/mine.so"));
        assert_eq!(value(&env, "MESA_VK_DEVICE_SELECT"), Some("10005:0!"));
        assert_eq!((value(&env, "GALLIUM_DRIVER"), value(&env, "LIBGL_ALWAYS_SOFTWARE")), (Some("zink"), Some("1")));
        assert_eq!(value(&env, "MESA_LOADER_DRIVER_OVERRIDE"), None);
        let gpu = DeviceIdentity { name: "NVIDIA H100".into(), vendor_id: 0x10de, device_id: 0x2330, software: false };
        let env = gl_environment(env_of(&[]), library, &gpu);
        assert_eq!(value(&env, "MESA_VK_DEVICE_SELECT"), Some("10de:2330!"));
        assert_eq!(value(&env, "MESA_LOADER_DRIVER_OVERRIDE"), Some("zink"));
        assert_eq!(value(&env, "LIBGL_ALWAYS_SOFTWARE"), None, "a GPU is not run as software");
    }
}
