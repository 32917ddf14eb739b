//! winit's X11 backend `expect`s its requests to succeed: once the X server is gone (killed,
//! or a remote display dropped), a call such as `set_title` panics inside winit. The viewer
//! wraps its per-frame window calls here, turning that panic into `None` so that it can end
//! with an error naming the lost display, not a panic message and backtrace.

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    /// Set while a guarded call runs: its panic is expected and reported by the caller.
    static GUARDED: Cell<bool> = const { Cell::new(false) };
}

static QUIET_HOOK: Once = Once::new();

/// Runs a winit window call; `None` when it panicked (the display connection is broken).
pub fn window_call<T>(call: impl FnOnce() -> T) -> Option<T> {
    QUIET_HOOK.call_once(|| {
        let default = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !GUARDED.with(Cell::get) {
                default(info);
            }
        }));
    });
    GUARDED.with(|g| g.set(true));
    let result = panic::catch_unwind(AssertUnwindSafe(call));
    GUARDED.with(|g| g.set(false));
    result.ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panicking_call_becomes_none_and_others_pass_through() {
        assert_eq!(window_call(|| 7), Some(7));
        assert_eq!(window_call(|| -> u32 { panic!("connection broken") }), None);
        assert_eq!(window_call(|| "still usable"), Some("still usable"));
    }
}
