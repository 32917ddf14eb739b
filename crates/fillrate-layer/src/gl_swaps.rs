//! Frames cut at a GL or GLES program's buffer swaps (`NOSTENCIL_FILLRATE_FRAME_ON=swap`,
//! `profile-app --gl`). The swaps are seen by `libnostencil_gl_swaps.so` (crates/gl-swaps),
//! preloaded into the program: the layer registers a callback with it when the instance is
//! created, and each swap then ends the frame on every device the layer measures, the tiler
//! check's frame too.

use std::ffi::c_void;
use std::sync::Once;

use super::config::FrameOn;
use super::state::{all_devices, guard};

/// The preloaded library's registration function.
type Register = unsafe extern "C" fn(extern "C" fn()) -> u64;

/// Registers `swapped` with the preloaded swap library; false (and a warning, once) when the
/// library is not in the process.
pub fn register() -> bool {
    // SAFETY: dlsym with RTLD_DEFAULT and a NUL-terminated name.
    let f = unsafe { libc::dlsym(libc::RTLD_DEFAULT, c"nostencil_gl_swaps_register".as_ptr()) };
    if f.is_null() {
        static ONCE: Once = Once::new();
        ONCE.call_once(|| {
            eprintln!(
                "nostencil fill-rate layer: NOSTENCIL_FILLRATE_FRAME_ON=swap, but libnostencil_gl_swaps.so is not \
                 preloaded (profile-app --gl preloads it): no frame ends at a swap"
            )
        });
        return false;
    }
    // SAFETY: the library's `nostencil_gl_swaps_register`, of this type; `swapped` lives as
    // long as the process (the layer is never unloaded while a program runs).
    unsafe { std::mem::transmute::<*mut c_void, Register>(f)(swapped) };
    true
}

/// A buffer swap: the frame ends on every device measuring with frames cut at swaps.
extern "C" fn swapped() {
    guard((), || {
        for device in all_devices() {
            if device.active() && device.config.frame_on == FrameOn::Swap {
                let mut st = device.state();
                if !st.boundaries {
                    super::frame_cuts::cut(&device, &mut st);
                }
                if device.config.tiler {
                    st.tiler.check.swapped();
                }
            }
        }
    });
}
