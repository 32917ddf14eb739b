//! Runs the program `profile-app` measures and decides when it ends: by itself, once the layer
//! has written the frames asked for (`--frames N`), after `--seconds S`, or on Ctrl-C. Ending is
//! SIGTERM, then SIGKILL after [`GRACE`]. How the run ended is returned for the report.

use std::path::Path;
use std::process::{Child, Command, ExitStatus};
use std::sync::atomic::{AtomicI32, Ordering};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};
use nostencil_fillrate_report::report::{FillrateReport, RunEnd};

/// How long a program has to exit after SIGTERM before it gets SIGKILL.
pub const GRACE: Duration = Duration::from_secs(5);

/// How often the child and the result file are looked at.
const POLL: Duration = Duration::from_millis(50);

/// When `profile-app` ends the program.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    /// End it once this many frames are measured (unless `keep_running`).
    pub frames: Option<u32>,
    /// End it after this long.
    pub seconds: Option<f64>,
    /// Never end it for `frames` (as before --frames ended programs); Ctrl-C and --seconds still do.
    pub keep_running: bool,
}

/// The signal (SIGINT or SIGTERM) `profile-app` received, 0 for none.
static INTERRUPTED: AtomicI32 = AtomicI32::new(0);

#[cfg(unix)]
extern "C" fn on_interrupt(signal: libc::c_int) {
    INTERRUPTED.store(signal, Ordering::SeqCst);
}

/// Ctrl-C (SIGINT) or a SIGTERM to `profile-app` sets [`INTERRUPTED`] instead of ending it; it
/// then ends the program and reports. The program runs in its own process group, so the
/// terminal's SIGINT reaches only us.
fn catch_interrupt() {
    #[cfg(unix)]
    // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
    unsafe {
        let handler = on_interrupt as extern "C" fn(libc::c_int) as libc::sighandler_t;
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
}

/// Kills the child if `profile-app` leaves early (an error of its own): never an orphan.
struct ChildGuard(Option<Child>);

impl Drop for ChildGuard {
    fn drop(&mut self) {
        if let Some(child) = &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// Frames measured in the layer's result file so far (it is written atomically, so a read sees
/// a whole file or none).
pub fn frames_written(result: &Path) -> Option<u64> {
    let text = std::fs::read_to_string(result).ok()?;
    FillrateReport::from_json(&text).ok().map(|r| r.frames_measured)
}

/// Runs `command` to its end under `stop`; returns how the run ended (`partial` left for the
/// caller, who knows how many frames the report holds).
pub fn run(mut command: Command, name: &str, result: &Path, stop: Stop) -> Result<RunEnd> {
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        command.process_group(0);
    }
    catch_interrupt();
    let child = command.spawn().map_err(|e| {
        let why = if e.kind() == std::io::ErrorKind::NotFound { "not found".to_owned() } else { e.to_string() };
        Error::InvalidInput(format!("cannot start '{name}': {why}"))
    })?;
    let mut guard = ChildGuard(Some(child));
    let start = Instant::now();
    let mut last_read = start;
    let reason = loop {
        let Some(child) = guard.0.as_mut() else { return Err(Error::Internal("child lost".into())) };
        if let Some(status) = child.try_wait().map_err(|e| Error::Internal(format!("waiting for '{name}': {e}")))? {
            guard.0 = None;
            return Ok(by_itself(status));
        }
        match INTERRUPTED.load(Ordering::SeqCst) {
            0 => {}
            2 => break ("interrupted", "ended on Ctrl-C (SIGINT to profile-app)".to_owned()),
            signal => break ("interrupted", format!("ended on {} to profile-app", signal_name(signal))),
        }
        if let Some(seconds) = stop.seconds {
            if start.elapsed().as_secs_f64() >= seconds {
                break ("ended", format!("ended by profile-app after {seconds} s (--seconds)"));
            }
        }
        if let (Some(frames), false) = (stop.frames, stop.keep_running) {
            // The file is parsed at most every 250 ms: it can be large.
            if last_read.elapsed() >= Duration::from_millis(250) {
                last_read = Instant::now();
                if frames_written(result).is_some_and(|n| n >= frames as u64) {
                    break ("ended", format!("ended by profile-app after {frames} measured frames (--frames)"));
                }
            }
        }
        std::thread::sleep(POLL);
    };
    let Some(child) = guard.0.take() else { return Err(Error::Internal("child lost".into())) };
    let (how, detail) = reason;
    let status = end(child)?;
    let detail = match signal_of(&status) {
        Some(libc_sig) if libc_sig == sigkill() => format!("{detail}; SIGKILL after {} s", GRACE.as_secs()),
        _ => detail,
    };
    Ok(RunEnd { how: how.into(), detail, partial: false })
}

/// SIGTERM, then SIGKILL if the program has not exited after [`GRACE`].
fn end(mut child: Child) -> Result<ExitStatus> {
    let wait_err = |e: std::io::Error| Error::Internal(format!("waiting for the program: {e}"));
    #[cfg(unix)]
    // SAFETY: kill(2) on our own child's pid, which we have not reaped (no reuse possible).
    unsafe {
        libc::kill(child.id() as libc::pid_t, libc::SIGTERM);
    }
    let start = Instant::now();
    while start.elapsed() < GRACE {
        if let Some(status) = child.try_wait().map_err(wait_err)? {
            return Ok(status);
        }
        std::thread::sleep(POLL);
    }
    let _ = child.kill();
    child.wait().map_err(wait_err)
}

fn sigkill() -> i32 {
    #[cfg(unix)]
    return libc::SIGKILL;
    #[cfg(not(unix))]
    return 9;
}

fn signal_of(status: &ExitStatus) -> Option<i32> {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        status.signal()
    }
    #[cfg(not(unix))]
    {
        let _ = status;
        None
    }
}

/// The name of the signals a program dies of.
fn signal_name(signal: i32) -> String {
    let name = match signal {
        1 => "SIGHUP",
        2 => "SIGINT",
        3 => "SIGQUIT",
        4 => "SIGILL",
        6 => "SIGABRT",
        7 => "SIGBUS",
        8 => "SIGFPE",
        9 => "SIGKILL",
        11 => "SIGSEGV",
        13 => "SIGPIPE",
        15 => "SIGTERM",
        _ => return format!("signal {signal}"),
    };
    name.to_owned()
}

/// How a program that ended by itself (or was ended from elsewhere) ended.
fn by_itself(status: ExitStatus) -> RunEnd {
    let (how, detail) = match (status.code(), signal_of(&status)) {
        (Some(0), _) => ("exited", "exited by itself (status 0)".to_owned()),
        (Some(code), _) => ("failed", format!("exited with status {code}")),
        // A signal the program causes itself (a fault or an abort) is a crash; others come from
        // elsewhere (kill, the OOM killer, a terminal).
        (None, Some(signal @ (4 | 6 | 7 | 8 | 11))) => ("crashed", format!("crashed with {}", signal_name(signal))),
        (None, Some(signal)) => ("killed", format!("was killed by {}", signal_name(signal))),
        (None, None) => ("killed", format!("ended abnormally ({status})")),
    };
    RunEnd { how: how.into(), detail, partial: false }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::process::ExitStatusExt;

    #[test]
    fn a_run_is_named_by_how_it_ended() {
        assert_eq!(by_itself(ExitStatus::from_raw(0)).how, "exited");
        assert_eq!(by_itself(ExitStatus::from_raw(3 << 8)).detail, "exited with status 3");
        let crash = by_itself(ExitStatus::from_raw(11));
        assert_eq!((crash.how.as_str(), crash.detail.as_str()), ("crashed", "crashed with SIGSEGV"));
        assert_eq!(by_itself(ExitStatus::from_raw(9)).detail, "was killed by SIGKILL");
    }

    #[test]
    fn a_program_ignoring_sigterm_is_killed_after_the_grace_and_seconds_end_a_run() {
        let dir = std::env::temp_dir().join(format!("nostencil-supervise-{}", std::process::id()));
        let mut command = Command::new("sh");
        command.args(["-c", "trap '' TERM; while :; do sleep 0.1; done"]);
        let stop = Stop { frames: None, seconds: Some(0.2), keep_running: false };
        let start = Instant::now();
        let run = run(command, "sh", &dir.join("none.json"), stop).expect("run");
        assert_eq!(run.how, "ended");
        assert!(run.detail.contains("--seconds") && run.detail.contains("SIGKILL after 5 s"), "{}", run.detail);
        assert!(start.elapsed() >= GRACE && start.elapsed() < GRACE * 3, "{:?}", start.elapsed());
    }
}
