//! The technique the viewer shows, built once per (technique, options, size) and kept between
//! frames; each frame renders the live scene (moved camera, light, objects) into the acquired
//! swapchain image, or where the technique or the swapchain cannot, into the RGBA8 target,
//! where it stays on the GPU for the copy to the window.

use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::{FrameCounters, PresentedFrame};
use crate::scene::Scene;
use crate::technique::{RenderOptions, SceneRenderer};

/// Everything that selects how a frame is rendered (the size aside, which follows the window);
/// a change rebuilds the live technique.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub render: RenderOptions,
}

impl Settings {
    /// "shadow-volume (emulated, seed, k=1)" for the window title.
    pub fn describe(&self) -> String {
        self.render.technique.describe(&self.render)
    }
}

pub struct LiveTechnique<'s> {
    pub settings: Settings,
    pub extent: vk::Extent2D,
    renderer: SceneRenderer<'s>,
    /// Whether each light of the scene it was built for casts shadows: its passes' lights.
    lights: Vec<bool>,
    /// The swapchain (`Swapchain::serial`) whose images its frames are drawn into.
    attached: Option<u64>,
}

/// What one frame reports.
pub struct LiveFrame {
    pub counters: FrameCounters,
    /// What the technique says of the frame in a few words ("z-fail"), for the title.
    pub brief: Option<String>,
    /// The settings it was drawn with, described (`Settings::describe`).
    pub description: String,
}

impl<'s> LiveTechnique<'s> {
    /// `base` is the scene as loaded: meshes are uploaded and casters prepared from it once.
    pub fn new(gpu: &Arc<Gpu>, base: &'s Scene, settings: Settings, extent: vk::Extent2D) -> Result<Self> {
        let options = RenderOptions { width: extent.width, height: extent.height, ..settings.render.clone() };
        let mut renderer = options.technique.build(gpu, base, &options)?;
        renderer.renderer_mut().keep_on_gpu(true);
        let lights = base.lights.iter().map(|l| l.casts_shadow).collect();
        Ok(LiveTechnique { settings, extent, renderer, lights, attached: None })
    }

    /// Whether it was built for `scene`'s lights (their number, and which cast shadows).
    pub fn lit_as(&self, scene: &Scene) -> bool {
        self.lights.iter().copied().eq(scene.lights.iter().map(|l| l.casts_shadow))
    }

    /// What the technique could not honour in the scene (see `SceneRenderer::warnings`).
    pub fn warnings(&self) -> &[String] {
        self.renderer.warnings()
    }

    /// Whether `scene` needs a rebuild (see `SceneRenderer::stale_for`).
    pub fn stale_for(&self, scene: &Scene) -> bool {
        self.renderer.stale_for(scene)
    }

    /// Renders `scene` (into the acquired image or the colour target); the counters are those
    /// of the frame that last used its slot, none while no frame of it has finished.
    pub fn frame(&mut self, scene: &Scene) -> Result<LiveFrame> {
        let frame = self.renderer.frame_with(scene)?;
        let description = self.settings.describe();
        Ok(LiveFrame { counters: frame.output.counters, brief: frame.stats.brief(), description })
    }

    /// Waits for the frame that last used the next frame's slot (`SceneRenderer::wait_for_slot`),
    /// before an image is acquired with the semaphore that frame waited on.
    pub fn wait_for_slot(&mut self) -> Result<()> {
        self.renderer.wait_for_slot()
    }

    /// Whether its frames are drawn into the swapchain images (`SceneRenderer::presents`).
    pub fn presents(&mut self) -> bool {
        self.renderer.presents()
    }

    /// Draws the next frame into image `frame.index` of the swapchain numbered `serial`, whose
    /// images are `images` (attached anew when the swapchain is another; the old one's frames
    /// are done: the swapchain is recreated after a device wait).
    pub fn present_next(&mut self, (serial, images): (u64, &[vk::Image]), frame: PresentedFrame) -> Result<()> {
        if self.attached != Some(serial) {
            self.renderer.attach_swapchain(images)?;
            self.attached = Some(serial);
        }
        self.renderer.present_next(frame)
    }

    /// The colour target holding the last frame (layout TRANSFER_SRC_OPTIMAL), for a frame
    /// drawn offscreen.
    pub fn colour_image(&mut self) -> Result<vk::Image> {
        let targets = &self.renderer.renderer_mut().targets;
        targets.colour().map(|image| image.raw).ok_or_else(|| {
            crate::error::Error::Internal("a frame drawn into the swapchain has no colour target to copy".into())
        })
    }
}
