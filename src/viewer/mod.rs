//! `nostencil view`: the techniques in a window (winit + ash-window), every one switchable live.
//!
//! Each frame:
//! 1. the live technique renders the scene into the RGBA8 + depth targets, exactly as offscreen
//!    (`LiveTechnique::frame`, submitted and waited for: its counters title the window);
//! 2. a swapchain image is acquired (its semaphore belongs to the frame slot);
//! 3. one command buffer blits the frame into that image (a blit converts RGBA to BGRA) and,
//!    for `--screenshot`, copies the image to a buffer; it waits for the acquire semaphore,
//!    signals the image's present semaphore and the slot's fence;
//! 4. present. Out-of-date or suboptimal swapchains are recreated; a window with no area
//!    (minimised) renders nothing until it has one again.
//!
//! Two frame slots (command buffer, acquire semaphore, fence) are in flight. The technique's
//! targets, uniforms and query pool are single, so a frame's technique pass starts only once the
//! previous frame's copy out of the colour target has finished (its fence).
//!
//! The parts: `app` (the event loop and the window's state), `controls` (orbit, light, clock),
//! `keys` (the key map), `live` (the technique shown), `options` (what `view` was asked),
//! `tour` (the soak's script), `x_guard` (a lost X display). Getting the
//! frame on screen is `render::present` and `render::frame_copy`, over `gpu::swapchain`.

mod app;
pub mod controls;
pub(crate) mod keys;
pub mod live;
mod options;
mod tour;
mod x_guard;

use winit::event_loop::EventLoop;
use winit::raw_window_handle::HasDisplayHandle;

use crate::error::{Error, Result, VkContext};
use crate::gpu::Gpu;
use crate::scene::Scene;
use app::App;
pub use options::{PresentPath, ViewerOptions};

/// Opens the window and runs until it is closed (or `--frames` are done).
pub fn run(options: ViewerOptions, scene: Scene) -> Result<()> {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Err(Error::Device("nostencil view needs a display: DISPLAY is not set (try xvfb-run)".into()));
    }
    let event_loop = EventLoop::new().map_err(|e| Error::Device(format!("cannot open the display: {e}")))?;
    let display = event_loop
        .display_handle()
        .map_err(|e| Error::Device(format!("the window system gave no display handle: {e}")))?
        .as_raw();
    let extensions =
        ash_window::enumerate_required_extensions(display).vk("ash_window::enumerate_required_extensions")?;
    let gpu = Gpu::for_presentation(&options.gpu, extensions)?;

    let lit_scenes = typed_arena::Arena::new();
    let mut app = App::new(gpu, &scene, &lit_scenes, options);
    event_loop.run_app(&mut app).map_err(|e| Error::Device(format!("the window's event loop failed: {e}")))?;
    app.finish()
}
