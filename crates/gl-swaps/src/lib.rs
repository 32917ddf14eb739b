//! `libnostencil_gl_swaps.so`: the frames of GL and GLES programs, which run on Vulkan through
//! Mesa's zink (`nostencil profile-app --gl`). zink on a software X server shows a frame
//! without `vkQueuePresentKHR` (it reads the image back and puts it in the window), so the
//! fill-rate layer cannot find frames in the Vulkan stream. As MangoHud does, they are found at
//! the program's buffer swaps: this library, preloaded into the program (`LD_PRELOAD`), defines
//! `glXSwapBuffers` and `eglSwapBuffers` ahead of the GL libraries. Each passes the swap on, then
//! calls the callback the layer registered (`nostencil_gl_swaps_register`, found by the layer
//! with `dlsym(RTLD_DEFAULT)`): the swap has submitted the frame's work by then.
//!
//! A program that loads its GL library itself and looks the swap up by name (SDL does:
//! `dlopen` + `dlsym`), or through `glXGetProcAddress` / `eglGetProcAddress`, is given these
//! hooks too: `dlsym` and the two lookups are defined here as well, and hand out the hook in
//! place of the library's swap, remembering the library's own to call. One limit, MangoHud's
//! too: a `dlsym(RTLD_NEXT, ...)` made by another library reaches libc through this one, so it
//! searches from here rather than from its caller.
//!
//! A library of its own, not part of the layer's: these names, linked into any other binary
//! (the layer's crate is also an rlib the tests link), would take over those functions there.

use std::ffi::{c_char, c_uint, c_ulong, c_void, CStr};
use std::sync::atomic::{AtomicPtr, AtomicU64, Ordering};

/// Swaps seen in this process.
static SWAPS: AtomicU64 = AtomicU64::new(0);

/// What the layer asked to be called after each swap.
static ON_SWAP: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());

/// The layer registers `on_swap`, called after every buffer swap from then on; returns the swaps
/// made so far.
#[no_mangle]
pub extern "C" fn nostencil_gl_swaps_register(on_swap: extern "C" fn()) -> u64 {
    ON_SWAP.store(on_swap as *mut c_void, Ordering::Release);
    SWAPS.load(Ordering::Relaxed)
}

/// The library's own functions, found at the first call (or handed to `dlsym`).
static REAL_GLX_SWAP: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static REAL_EGL_SWAP: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static REAL_EGL_SWAP_DAMAGE_KHR: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static REAL_EGL_SWAP_DAMAGE_EXT: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static REAL_GLX_PROC: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static REAL_GLX_PROC_ARB: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static REAL_EGL_PROC: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static REAL_DLSYM: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());

type GlxSwap = unsafe extern "C" fn(*mut c_void, c_ulong);
type EglSwap = unsafe extern "C" fn(*mut c_void, *mut c_void) -> c_uint;
type EglSwapDamage = unsafe extern "C" fn(*mut c_void, *mut c_void, *const i32, i32) -> c_uint;
type GetProc = unsafe extern "C" fn(*const c_char) -> *mut c_void;
type Dlsym = unsafe extern "C" fn(*mut c_void, *const c_char) -> *mut c_void;

/// The real `dlsym`, by version, so that the lookup does not come back here.
fn real_dlsym() -> Option<Dlsym> {
    let mut found = REAL_DLSYM.load(Ordering::Acquire);
    if found.is_null() {
        for version in [c"GLIBC_2.34", c"GLIBC_2.2.5", c"GLIBC_2.17", c"GLIBC_2.0"] {
            // SAFETY: dlvsym with RTLD_NEXT and NUL-terminated names.
            found = unsafe { libc::dlvsym(libc::RTLD_NEXT, c"dlsym".as_ptr(), version.as_ptr()) };
            if !found.is_null() {
                break;
            }
        }
        REAL_DLSYM.store(found, Ordering::Release);
    }
    // SAFETY: a non-null address of libc's dlsym, whose type this is.
    (!found.is_null()).then(|| unsafe { std::mem::transmute::<*mut c_void, Dlsym>(found) })
}

/// The function `slot` remembers, or the next definition of `name` after this library.
fn real(slot: &AtomicPtr<c_void>, name: &CStr) -> *mut c_void {
    let mut found = slot.load(Ordering::Acquire);
    if found.is_null() {
        if let Some(dlsym) = real_dlsym() {
            // SAFETY: libc's dlsym with RTLD_NEXT and a NUL-terminated name.
            found = unsafe { dlsym(libc::RTLD_NEXT, name.as_ptr()) };
            slot.store(found, Ordering::Release);
        }
    }
    found
}

/// A swap was made: the layer's callback, if it registered one.
fn swapped() {
    SWAPS.fetch_add(1, Ordering::Relaxed);
    let f = ON_SWAP.load(Ordering::Acquire);
    if !f.is_null() {
        // SAFETY: the address the layer registered, of an `extern "C" fn()`.
        unsafe { std::mem::transmute::<*mut c_void, extern "C" fn()>(f)() };
    }
}

/// # Safety
/// The program's GLX call: `display` and `drawable` as glXSwapBuffers takes them.
#[no_mangle]
pub unsafe extern "C" fn glXSwapBuffers(display: *mut c_void, drawable: c_ulong) {
    let f = real(&REAL_GLX_SWAP, c"glXSwapBuffers");
    if !f.is_null() {
        // SAFETY: the GL library's glXSwapBuffers, with the program's arguments.
        unsafe { std::mem::transmute::<*mut c_void, GlxSwap>(f)(display, drawable) };
    }
    swapped();
}

/// # Safety
/// The program's EGL call.
#[no_mangle]
pub unsafe extern "C" fn eglSwapBuffers(display: *mut c_void, surface: *mut c_void) -> c_uint {
    let f = real(&REAL_EGL_SWAP, c"eglSwapBuffers");
    if f.is_null() {
        return 0;
    }
    // SAFETY: the EGL library's eglSwapBuffers, with the program's arguments.
    let ok = unsafe { std::mem::transmute::<*mut c_void, EglSwap>(f)(display, surface) };
    swapped();
    ok
}

/// An EGL swap with damage rectangles through the library's function `name` (remembered in
/// `slot`), then the frame's end.
///
/// # Safety
/// The program's arguments to that function.
unsafe fn swap_with_damage(
    slot: &AtomicPtr<c_void>,
    name: &CStr,
    (display, surface, rects, count): (*mut c_void, *mut c_void, *const i32, i32),
) -> c_uint {
    let f = real(slot, name);
    if f.is_null() {
        return 0;
    }
    // SAFETY: the EGL library's function of this type, with the program's arguments.
    let ok = unsafe { std::mem::transmute::<*mut c_void, EglSwapDamage>(f)(display, surface, rects, count) };
    swapped();
    ok
}

/// # Safety
/// The program's EGL call.
#[no_mangle]
pub unsafe extern "C" fn eglSwapBuffersWithDamageKHR(
    display: *mut c_void,
    surface: *mut c_void,
    rects: *const i32,
    count: i32,
) -> c_uint {
    // SAFETY: the program's arguments.
    unsafe {
        swap_with_damage(&REAL_EGL_SWAP_DAMAGE_KHR, c"eglSwapBuffersWithDamageKHR", (display, surface, rects, count))
    }
}

/// # Safety
/// The program's EGL call.
#[no_mangle]
pub unsafe extern "C" fn eglSwapBuffersWithDamageEXT(
    display: *mut c_void,
    surface: *mut c_void,
    rects: *const i32,
    count: i32,
) -> c_uint {
    // SAFETY: the program's arguments.
    unsafe {
        swap_with_damage(&REAL_EGL_SWAP_DAMAGE_EXT, c"eglSwapBuffersWithDamageEXT", (display, surface, rects, count))
    }
}

/// The hook for a swap function's `name`, remembering `library`'s own (`found`) to call.
fn hook_for(name: &[u8], found: *mut c_void) -> Option<*mut c_void> {
    let (slot, hook): (&AtomicPtr<c_void>, *mut c_void) = match name {
        b"glXSwapBuffers" => (&REAL_GLX_SWAP, glXSwapBuffers as GlxSwap as *mut c_void),
        b"eglSwapBuffers" => (&REAL_EGL_SWAP, eglSwapBuffers as EglSwap as *mut c_void),
        b"eglSwapBuffersWithDamageKHR" => {
            (&REAL_EGL_SWAP_DAMAGE_KHR, eglSwapBuffersWithDamageKHR as EglSwapDamage as *mut c_void)
        }
        b"eglSwapBuffersWithDamageEXT" => {
            (&REAL_EGL_SWAP_DAMAGE_EXT, eglSwapBuffersWithDamageEXT as EglSwapDamage as *mut c_void)
        }
        b"glXGetProcAddress" => (&REAL_GLX_PROC, glXGetProcAddress as GetProc as *mut c_void),
        b"glXGetProcAddressARB" => (&REAL_GLX_PROC_ARB, glXGetProcAddressARB as GetProc as *mut c_void),
        b"eglGetProcAddress" => (&REAL_EGL_PROC, eglGetProcAddress as GetProc as *mut c_void),
        _ => return None,
    };
    if found.is_null() {
        return None;
    }
    if found != hook {
        slot.store(found, Ordering::Release);
    }
    Some(hook)
}

/// A lookup through `get` (the library's own GetProcAddress): the swap's hook where asked for.
///
/// # Safety
/// `name` is a NUL-terminated string.
unsafe fn get_proc(slot: &AtomicPtr<c_void>, own: &CStr, name: *const c_char) -> *mut c_void {
    let f = real(slot, own);
    if f.is_null() || name.is_null() {
        return std::ptr::null_mut();
    }
    // SAFETY: the library's GetProcAddress with the program's name.
    let found = unsafe { std::mem::transmute::<*mut c_void, GetProc>(f)(name) };
    // SAFETY: the caller's NUL-terminated name.
    let asked = unsafe { CStr::from_ptr(name) }.to_bytes();
    hook_for(asked, found).unwrap_or(found)
}

/// # Safety
/// The program's GLX call.
#[no_mangle]
pub unsafe extern "C" fn glXGetProcAddress(name: *const c_char) -> *mut c_void {
    // SAFETY: the caller's name.
    unsafe { get_proc(&REAL_GLX_PROC, c"glXGetProcAddress", name) }
}

/// # Safety
/// The program's GLX call.
#[no_mangle]
pub unsafe extern "C" fn glXGetProcAddressARB(name: *const c_char) -> *mut c_void {
    // SAFETY: the caller's name.
    unsafe { get_proc(&REAL_GLX_PROC_ARB, c"glXGetProcAddressARB", name) }
}

/// # Safety
/// The program's EGL call.
#[no_mangle]
pub unsafe extern "C" fn eglGetProcAddress(name: *const c_char) -> *mut c_void {
    // SAFETY: the caller's name.
    unsafe { get_proc(&REAL_EGL_PROC, c"eglGetProcAddress", name) }
}

/// `dlsym`, preloaded: a GL or EGL swap (or GetProcAddress) looked up by name in a library the
/// program opened gets the hook, which calls the library's own; every other name is libc's.
///
/// # Safety
/// As libc's dlsym.
#[no_mangle]
pub unsafe extern "C" fn dlsym(handle: *mut c_void, name: *const c_char) -> *mut c_void {
    let Some(real_dlsym) = real_dlsym() else { return std::ptr::null_mut() };
    // SAFETY: libc's dlsym with the caller's arguments.
    let found = unsafe { real_dlsym(handle, name) };
    if name.is_null() || found.is_null() {
        return found;
    }
    // SAFETY: the caller's NUL-terminated name.
    let asked = unsafe { CStr::from_ptr(name) }.to_bytes();
    if !matches!(asked.first(), Some(b'g' | b'e')) {
        return found;
    }
    hook_for(asked, found).unwrap_or(found)
}
