//! A small OpenGL program of the tests' own, for the fill-rate layer's GL path (`profile-app
//! --gl`): a 32 x 32 GLX window on the test's X server, each frame cleared and drawn as
//! [`RECTS`] rectangles by one `glDrawArrays` each (the edges of `rect.vert`'s rectangles, on
//! pixel boundaries, so its draws, vertices and samples are known by hand), then
//! `glXSwapBuffers`. It loads libGL and libX11 itself, as a game does, and reads its last frame
//! back with `glReadPixels`.

use std::ffi::{c_char, c_int, c_uint, c_ulong, c_void, CStr};

/// The window's side, in pixels.
pub const SIZE: i32 = 32;
/// Rectangles drawn per frame, one draw each.
pub const RECTS: u32 = 4;

/// Samples a frame passes: rectangle k covers 16 (k + 1) pixels.
pub fn samples_per_frame() -> u64 {
    (0..RECTS as u64).map(|k| 16 * (k + 1)).sum()
}

type Display = c_void;
type Window = c_ulong;

const GLX_RGBA: c_int = 4;
const GLX_DOUBLEBUFFER: c_int = 5;
const GLX_RED_SIZE: c_int = 8;
const GLX_GREEN_SIZE: c_int = 9;
const GLX_BLUE_SIZE: c_int = 10;
const GL_COLOR_BUFFER_BIT: c_uint = 0x4000;
const GL_TRIANGLES: c_uint = 0x0004;
const GL_VERTEX_ARRAY: c_uint = 0x8074;
const GL_FLOAT: c_uint = 0x1406;
const GL_RGBA: c_uint = 0x1908;
const GL_UNSIGNED_BYTE: c_uint = 0x1401;
const GL_PACK_ALIGNMENT: c_uint = 0x0D05;

#[repr(C)]
struct XVisualInfo {
    visual: *mut c_void,
    visualid: c_ulong,
    screen: c_int,
    depth: c_int,
    class: c_int,
    red_mask: c_ulong,
    green_mask: c_ulong,
    blue_mask: c_ulong,
    colormap_size: c_int,
    bits_per_rgb: c_int,
}

#[repr(C)]
#[derive(Default)]
struct XSetWindowAttributes {
    background_pixmap: c_ulong,
    background_pixel: c_ulong,
    border_pixmap: c_ulong,
    border_pixel: c_ulong,
    bit_gravity: c_int,
    win_gravity: c_int,
    backing_store: c_int,
    backing_planes: c_ulong,
    backing_pixel: c_ulong,
    save_under: c_int,
    event_mask: std::ffi::c_long,
    do_not_propagate_mask: std::ffi::c_long,
    override_redirect: c_int,
    colormap: c_ulong,
    cursor: c_ulong,
}

/// A function of a library opened with dlopen, by name.
unsafe fn symbol<T: Copy>(library: *mut c_void, name: &CStr) -> T {
    let f = libc::dlsym(library, name.as_ptr());
    assert!(!f.is_null(), "{name:?} not found");
    assert_eq!(std::mem::size_of::<T>(), std::mem::size_of::<*mut c_void>());
    std::mem::transmute_copy(&f)
}

unsafe fn open(name: &CStr) -> *mut c_void {
    let library = libc::dlopen(name.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL);
    assert!(!library.is_null(), "cannot open {name:?} (Debian's libgl1, libx11-6)");
    library
}

/// The two triangles of rectangle `k`, in normalised device coordinates.
fn rectangle(k: u32) -> [f32; 12] {
    let (x0, x1, y1) = (4.0 * k as f32, 4.0 * k as f32 + 4.0, 4.0 * k as f32 + 4.0);
    let n = |p: f32| p / 16.0 - 1.0;
    let (x0, x1, y0, y1) = (n(x0), n(x1), n(0.0), n(y1));
    [x0, y0, x1, y0, x0, y1, x0, y1, x1, y0, x1, y1]
}

/// Runs `frames` frames; returns the last frame's pixels (RGBA, bottom row first).
///
/// # Safety
/// Plain use of GLX and Xlib on the display `DISPLAY` names; everything made is released.
pub unsafe fn run(frames: u32) -> Vec<u8> {
    let x11 = open(c"libX11.so.6");
    let gl = open(c"libGL.so.1");
    let x_open: unsafe extern "C" fn(*const c_char) -> *mut Display = symbol(x11, c"XOpenDisplay");
    let x_default_screen: unsafe extern "C" fn(*mut Display) -> c_int = symbol(x11, c"XDefaultScreen");
    let x_root: unsafe extern "C" fn(*mut Display, c_int) -> Window = symbol(x11, c"XRootWindow");
    let x_colormap: unsafe extern "C" fn(*mut Display, Window, *mut c_void, c_int) -> c_ulong =
        symbol(x11, c"XCreateColormap");
    type CreateWindow = unsafe extern "C" fn(
        *mut Display,
        Window,
        c_int,
        c_int,
        c_uint,
        c_uint,
        c_uint,
        c_int,
        c_uint,
        *mut c_void,
        c_ulong,
        *mut XSetWindowAttributes,
    ) -> Window;
    let x_create_window: CreateWindow = symbol(x11, c"XCreateWindow");
    let x_map: unsafe extern "C" fn(*mut Display, Window) -> c_int = symbol(x11, c"XMapWindow");
    let x_destroy_window: unsafe extern "C" fn(*mut Display, Window) -> c_int = symbol(x11, c"XDestroyWindow");
    let x_free_colormap: unsafe extern "C" fn(*mut Display, c_ulong) -> c_int = symbol(x11, c"XFreeColormap");
    let x_free: unsafe extern "C" fn(*mut c_void) -> c_int = symbol(x11, c"XFree");
    let x_close: unsafe extern "C" fn(*mut Display) -> c_int = symbol(x11, c"XCloseDisplay");
    let choose: unsafe extern "C" fn(*mut Display, c_int, *const c_int) -> *mut XVisualInfo =
        symbol(gl, c"glXChooseVisual");
    let create: unsafe extern "C" fn(*mut Display, *mut XVisualInfo, *mut c_void, c_int) -> *mut c_void =
        symbol(gl, c"glXCreateContext");
    let make_current: unsafe extern "C" fn(*mut Display, Window, *mut c_void) -> c_int = symbol(gl, c"glXMakeCurrent");
    let destroy_context: unsafe extern "C" fn(*mut Display, *mut c_void) = symbol(gl, c"glXDestroyContext");
    // Looked up by name, as SDL does: the layer's preloaded library hands out its hook here.
    let swap: unsafe extern "C" fn(*mut Display, Window) = symbol(gl, c"glXSwapBuffers");
    let viewport: unsafe extern "C" fn(c_int, c_int, c_int, c_int) = symbol(gl, c"glViewport");
    let clear_colour: unsafe extern "C" fn(f32, f32, f32, f32) = symbol(gl, c"glClearColor");
    let clear: unsafe extern "C" fn(c_uint) = symbol(gl, c"glClear");
    let colour: unsafe extern "C" fn(f32, f32, f32) = symbol(gl, c"glColor3f");
    let enable_client_state: unsafe extern "C" fn(c_uint) = symbol(gl, c"glEnableClientState");
    let vertex_pointer: unsafe extern "C" fn(c_int, c_uint, c_int, *const c_void) = symbol(gl, c"glVertexPointer");
    let draw_arrays: unsafe extern "C" fn(c_uint, c_int, c_int) = symbol(gl, c"glDrawArrays");
    let pixel_store: unsafe extern "C" fn(c_uint, c_int) = symbol(gl, c"glPixelStorei");
    let read_pixels: unsafe extern "C" fn(c_int, c_int, c_int, c_int, c_uint, c_uint, *mut c_void) =
        symbol(gl, c"glReadPixels");
    let finish: unsafe extern "C" fn() = symbol(gl, c"glFinish");

    let display = x_open(std::ptr::null());
    assert!(!display.is_null(), "no X display (DISPLAY)");
    let screen = x_default_screen(display);
    let attributes =
        [GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, 0 /* None */];
    let visual = choose(display, screen, attributes.as_ptr());
    assert!(!visual.is_null(), "no double-buffered RGBA visual");
    let root = x_root(display, screen);
    let colormap = x_colormap(display, root, (*visual).visual, 0);
    let mut window_attributes = XSetWindowAttributes { colormap, ..Default::default() };
    const CW_BORDER_PIXEL: c_ulong = 1 << 3;
    const CW_COLORMAP: c_ulong = 1 << 13;
    let window = x_create_window(
        display,
        root,
        0,
        0,
        SIZE as c_uint,
        SIZE as c_uint,
        0,
        (*visual).depth,
        1, // InputOutput
        (*visual).visual,
        CW_BORDER_PIXEL | CW_COLORMAP,
        &mut window_attributes,
    );
    x_map(display, window);
    let context = create(display, visual, std::ptr::null_mut(), 1);
    assert!(!context.is_null(), "no GLX context");
    assert!(make_current(display, window, context) != 0, "glXMakeCurrent");

    let vertices: Vec<f32> = (0..RECTS).flat_map(rectangle).collect();
    let mut pixels = vec![0u8; (SIZE * SIZE * 4) as usize];
    for frame in 0..frames {
        viewport(0, 0, SIZE, SIZE);
        clear_colour(0.0, 0.0, 0.0, 1.0);
        clear(GL_COLOR_BUFFER_BIT);
        enable_client_state(GL_VERTEX_ARRAY);
        vertex_pointer(2, GL_FLOAT, 0, vertices.as_ptr().cast());
        for k in 0..RECTS {
            colour(1.0, k as f32 / RECTS as f32, 0.0);
            draw_arrays(GL_TRIANGLES, 6 * k as c_int, 6);
        }
        if frame + 1 == frames {
            // zink reads the frame back through a draw of its own (a blit of the whole target).
            pixel_store(GL_PACK_ALIGNMENT, 1);
            read_pixels(0, 0, SIZE, SIZE, GL_RGBA, GL_UNSIGNED_BYTE, pixels.as_mut_ptr().cast());
        }
        swap(display, window);
    }
    finish();
    make_current(display, 0, std::ptr::null_mut());
    destroy_context(display, context);
    x_destroy_window(display, window);
    x_free_colormap(display, colormap);
    x_free(visual.cast());
    x_close(display);
    pixels
}
