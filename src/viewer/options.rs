//! What `nostencil view` was asked for: the settings it starts with, the window, and the
//! scripted actions the tests drive it with.

use std::path::PathBuf;

use super::live::Settings;
use crate::gpu::GpuOptions;

crate::names::named_enum! {
    /// How frames reach the window's swapchain images.
    pub enum PresentPath {
        /// Drawn into the acquired image, a multisampled frame resolved into it inside the
        /// render pass, where the swapchain's format allows it (else copied, and said so).
        #[default]
        Direct = "direct",
        /// Always drawn offscreen and copied in: the cost of the copy a tiler pays, compared.
        Copy = "copy",
    }
}

#[derive(Debug, Clone)]
pub struct ViewerOptions {
    pub settings: Settings,
    pub size: (u32, u32),
    pub gpu: GpuOptions,
    /// Render this many frames, then exit (after the screenshot, if any).
    pub frames: Option<u32>,
    /// Save the last presented image here (RGB PNG, written atomically).
    pub screenshot: Option<PathBuf>,
    /// After this many presented frames, ask the window system for a new inner size.
    pub resize_after: Option<(u32, (u32, u32))>,
    /// After this many presented frames, act as if this key (a letter the key map binds) was
    /// pressed: a scripted switch, for tests.
    pub press_after: Option<(u32, char)>,
    /// Start with the animation paused (frames then match `nostencil render`).
    pub paused: bool,
    /// Every this many presented frames, the next stop of the soak's tour (see `tour`).
    pub tour: Option<u32>,
    /// The animation time the scene was built at (`--time`); the viewer's clock starts there.
    pub start_time: f32,
    /// `--present`: how frames reach the swapchain images.
    pub present: PresentPath,
}
