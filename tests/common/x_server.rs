//! An Xvfb server owned by one test, for programs that need a window (the viewer, vkcube).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// An Xvfb server owned by one test, killed when dropped.
pub struct XServer {
    pub child: Child,
    pub display: String,
}

impl Drop for XServer {
    fn drop(&mut self) {
        // SIGTERM first: Xvfb then removes its lock file and socket; SIGKILL only if it hangs.
        let _ = Command::new("kill").arg(self.child.id().to_string()).status();
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(5) {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

static NEXT_DISPLAY: AtomicU32 = AtomicU32::new(0);

/// Starts `Xvfb :N` on a free display number. Tests that need it are run, not skipped: without
/// Xvfb (tools/setup-debian.sh installs it) the test fails saying so.
pub fn start_x_server() -> XServer {
    let base = 100 + (std::process::id() % 400) * 8;
    for _ in 0..16 {
        let n = base + NEXT_DISPLAY.fetch_add(1, Ordering::SeqCst);
        if Path::new(&format!("/tmp/.X{n}-lock")).exists() || Path::new(&format!("/tmp/.X11-unix/X{n}")).exists() {
            continue;
        }
        let child = match Command::new("Xvfb")
            // -noreset: without it the server resets whenever its last client leaves (each
            // xdotool poll), and a client connecting during that reset is refused.
            .args([format!(":{n}").as_str(), "-screen", "0", "1024x768x24", "-nolisten", "tcp", "-noreset"])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
        {
            Ok(child) => child,
            Err(e) => panic!("cannot start Xvfb ({e}); tools/setup-debian.sh installs it"),
        };
        let mut server = XServer { child, display: format!(":{n}") };
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(20) {
            if socket.exists() {
                return server;
            }
            if let Ok(Some(_)) = server.child.try_wait() {
                break; // display taken by someone else meanwhile: try the next one
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
    panic!("no Xvfb display could be started (16 display numbers tried)");
}
