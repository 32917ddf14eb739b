//! Presenting: what a window shows frames through (a swapchain, or nothing while it has no
//! area), the frame slots in flight, and screenshots read back from what was presented. A frame
//! is drawn straight into the acquired image where the swapchain allows it
//! (`Presenter::destination`, `Presenter::presented_frame`); otherwise it is copied in
//! (`Presenter::submit_copy`).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::frame_copy;
use super::renderer::PresentedFrame;
use crate::error::{Error, Result, VkContext};
use crate::frame::render_pass::{FrameDestination, COLOUR_FORMAT};
use crate::gpu::faults::{self, Submission};
use crate::gpu::live_objects::ObjectKind;
use crate::gpu::memory::Buffer;
use crate::gpu::swapchain::{self, Acquired, Surface, Swapchain, Transfer};
use crate::gpu::Gpu;
use image::RgbaImage;

/// Frames a window keeps in flight: its slots' acquire semaphores, and the frames a technique
/// drawing into its images may keep in flight (no more, so that a slot's semaphore is reused
/// only once the frame that waited on it was waited for).
pub const FRAMES_IN_FLIGHT: usize = 2;

/// What the window shows frames through.
pub enum Output {
    /// A swapchain at the window's size.
    Presenting(Box<Presenter>),
    /// The window has no area (minimised): no swapchain can exist until it has one again.
    NoArea,
}

impl Output {
    /// The output for `surface` at its current size (`window_size` where the surface leaves the
    /// size to the application).
    /// `draw_into`: frames are drawn into the swapchain images where they allow it (else
    /// always copied in: `nostencil view --present copy`).
    pub fn new(gpu: &Arc<Gpu>, surface: &Surface, window_size: (u32, u32), draw_into: bool) -> Result<Self> {
        let output = match Swapchain::new(gpu, surface, window_size, COLOUR_FORMAT, None)? {
            Some(swapchain) => Output::Presenting(Box::new(Presenter::new(gpu, swapchain, draw_into)?)),
            None => Output::NoArea,
        };
        output.report();
        Ok(output)
    }

    /// Builds the swapchain again for the window's size now (after a resize, or when the
    /// old one is out of date or suboptimal); the new one replaces the old in place.
    pub fn recreate(
        &mut self,
        gpu: &Arc<Gpu>,
        surface: &Surface,
        window_size: (u32, u32),
        draw_into: bool,
    ) -> Result<()> {
        // The old swapchain's images may still be read or presented.
        gpu.wait_idle();
        let old = match self {
            Output::Presenting(presenter) => Some(&presenter.swapchain),
            Output::NoArea => None,
        };
        match (Swapchain::new(gpu, surface, window_size, COLOUR_FORMAT, old)?, &mut *self) {
            // The old swapchain is destroyed once the new one, created from it, replaces it.
            (Some(swapchain), Output::Presenting(presenter)) => presenter.swapchain = swapchain,
            (Some(swapchain), Output::NoArea) => {
                *self = Output::Presenting(Box::new(Presenter::new(gpu, swapchain, draw_into)?))
            }
            (None, _) => *self = Output::NoArea,
        }
        self.report();
        Ok(())
    }

    /// One stderr line per swapchain: how frames reach its images.
    fn report(&self) {
        match self {
            Output::Presenting(presenter) => {
                let s = &presenter.swapchain;
                let copied = match s.transfer {
                    Transfer::Blit => "copied in by blit",
                    Transfer::Copy => "copied in",
                };
                let how = match (presenter.draw_into, s.drawable) {
                    (true, true) => format!("frames drawn into its images (where a technique cannot: {copied})"),
                    (false, _) => format!("frames {copied} (--present copy)"),
                    (true, false) => format!("frames {copied}: its format cannot be drawn into"),
                };
                eprintln!(
                    "nostencil view: swapchain {}x{} {:?} ({} images), {how}, screenshots read {}",
                    s.extent.width,
                    s.extent.height,
                    s.format,
                    s.images.len(),
                    if s.readable { "the swapchain image" } else { "the frame" }
                )
            }
            Output::NoArea => eprintln!("nostencil view: the window has no area (minimised); waiting"),
        }
    }
}

/// Presents frames through one swapchain. Field order is drop order: the swapchain and the
/// screenshot buffer go before the slots (each waits for the device first).
pub struct Presenter {
    swapchain: Swapchain,
    screenshot: Option<Buffer>,
    slots: FrameSlots,
    gpu: Arc<Gpu>,
    /// Frames may be drawn into the swapchain images (not `--present copy`).
    draw_into: bool,
}

impl Presenter {
    fn new(gpu: &Arc<Gpu>, swapchain: Swapchain, draw_into: bool) -> Result<Self> {
        Ok(Presenter { swapchain, screenshot: None, slots: FrameSlots::new(gpu)?, gpu: gpu.clone(), draw_into })
    }

    /// Where a technique should draw its frames: into the swapchain images where they can be
    /// drawn into (and read back, when a `screenshot` will be taken), else offscreen.
    pub fn destination(&self, screenshot: bool) -> FrameDestination {
        let s = &self.swapchain;
        if self.draw_into && s.drawable && (s.readable || !screenshot) {
            FrameDestination::Swapchain { format: s.format }
        } else {
            FrameDestination::Offscreen
        }
    }

    /// The swapchain's number (`Swapchain::serial`) and its images, for a technique that draws
    /// into them.
    pub fn images(&self) -> (u64, &[vk::Image]) {
        (self.swapchain.serial, &self.swapchain.images)
    }

    /// Image `index`, acquired in the current slot, as the frame drawn into it is handed over:
    /// after the acquire, before the present, and (with `screenshot`) read back on the way.
    pub fn presented_frame(&mut self, index: u32, screenshot: bool) -> Result<PresentedFrame> {
        let screenshot = if screenshot { Some(self.screenshot_buffer()?) } else { None };
        let finished = *self
            .swapchain
            .render_finished
            .get(index as usize)
            .ok_or_else(|| Error::Internal(format!("swapchain image {index} was never acquired")))?;
        Ok(PresentedFrame { index, acquired: self.slots.current().image_available, finished, screenshot })
    }

    /// The screenshot's read-back buffer, sized for the swapchain's images.
    fn screenshot_buffer(&mut self) -> Result<vk::Buffer> {
        let extent = self.swapchain.extent;
        let size = extent.width as u64 * extent.height as u64 * 4;
        match &self.screenshot {
            Some(buffer) if buffer.size == size => Ok(buffer.raw),
            _ => {
                // The old buffer may still be written by a slot's copy.
                self.wait_slots()?;
                let buffer = Buffer::new(
                    &self.gpu,
                    "screenshot",
                    size,
                    vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )?;
                Ok(self.screenshot.insert(buffer).raw)
            }
        }
    }

    /// The swapchain images' size.
    pub fn extent(&self) -> vk::Extent2D {
        self.swapchain.extent
    }

    /// Waits until no frame slot is in flight: their copies read the frame's colour target.
    pub fn wait_slots(&self) -> Result<()> {
        let fences: Vec<vk::Fence> = self.slots.slots.iter().map(|slot| slot.in_flight).collect();
        let began = std::time::Instant::now();
        // SAFETY: the fences are the slots' own, alive while `self` is; each was created
        // signalled or is reset only just before the submission that signals it.
        let waited = unsafe { self.gpu.raw().wait_for_fences(&fences, true, u64::MAX) };
        self.gpu.waited(began.elapsed());
        waited.map_err(|result| Error::Submit {
            work: "the previous frames' copies to the window".into(),
            call: "vkWaitForFences",
            result,
        })
    }

    /// Acquires the next swapchain image for the current slot.
    pub fn acquire(&self) -> Result<Acquired> {
        self.swapchain.acquire(self.slots.current().image_available)
    }

    /// Records and submits, in the current slot, the copy of `colour` (the frame) into
    /// swapchain image `index`; with `screenshot`, also its read-back.
    pub fn submit_copy(&mut self, index: u32, colour: vk::Image, screenshot: bool) -> Result<()> {
        if !self.swapchain.copyable {
            return Err(Error::Device(format!(
                "the frame is drawn offscreen, and the window's swapchain images ({:?}) cannot be copied into",
                self.swapchain.format
            )));
        }
        let screenshot_buffer = if screenshot { Some(self.screenshot_buffer()?) } else { None };
        let device = self.gpu.raw();
        let FrameSlot { cmd, image_available, in_flight } = *self.slots.current();
        // SAFETY: the caller waited for this slot's fence (`wait_slots`), so `cmd` is not
        // pending; it was allocated from the pool whose flags allow a reset of one buffer.
        unsafe {
            device.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty()).vk("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(cmd, &begin).vk("vkBeginCommandBuffer")?;
        }
        frame_copy::record(device, cmd, colour, &self.swapchain, index, screenshot_buffer);
        // SAFETY: `cmd` is recording; the fence is not in use (waited for above); the semaphores
        // are this slot's (unsignalled, signalled by the acquire of `index`) and image `index`'s
        // (waited on by its last present, which came before this acquire); the queue is used from
        // this one thread.
        unsafe {
            device.end_command_buffer(cmd).vk("vkEndCommandBuffer")?;
            device.reset_fences(&[in_flight]).vk("vkResetFences")?;
            let waits = [image_available];
            let stages = [vk::PipelineStageFlags::TRANSFER];
            let signals = [self.swapchain.render_finished[index as usize]];
            let cmds = [cmd];
            let submit = [vk::SubmitInfo::default()
                .wait_semaphores(&waits)
                .wait_dst_stage_mask(&stages)
                .command_buffers(&cmds)
                .signal_semaphores(&signals)];
            let submitted = device.queue_submit(self.gpu.device.queue, &submit, in_flight);
            // An injected fault (tests only) comes after the real submit, so that the frame's
            // semaphores and fence still complete and the teardown is the normal one.
            let submitted = submitted.and_then(|_| faults::submit_fault(Submission::Present).map_or(Ok(()), Err));
            submitted.map_err(|result| Error::Submit {
                work: format!("the copy of the frame to the window (swapchain image {index})"),
                call: "vkQueueSubmit",
                result,
            })?;
        }
        Ok(())
    }

    /// Presents image `index` and moves on to the next slot; Ok(true) when the swapchain
    /// should be recreated (out of date or suboptimal).
    pub fn present(&mut self, index: u32) -> Result<bool> {
        let recreate = self.swapchain.present(index)?;
        self.slots.advance();
        Ok(recreate)
    }

    /// The last screenshot read back, as RGBA (swizzled back from a BGRA swapchain).
    pub fn read_screenshot(&self) -> Result<RgbaImage> {
        self.wait_slots()?;
        let buffer = self
            .screenshot
            .as_ref()
            .ok_or_else(|| Error::Internal("a screenshot was read before one was taken".into()))?;
        let extent = self.swapchain.extent;
        let mut pixels = buffer.read()?[..extent.width as usize * extent.height as usize * 4].to_vec();
        if self.swapchain.readable && swapchain::is_bgra(self.swapchain.format) {
            pixels.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
        }
        crate::frame::image_from_rgba8(extent.width, extent.height, pixels)
    }
}

/// What a frame in flight owns until its fence signals.
#[derive(Clone, Copy)]
struct FrameSlot {
    cmd: vk::CommandBuffer,
    image_available: vk::Semaphore,
    in_flight: vk::Fence,
}

/// The frame slots, used in turn: while one frame's copy runs, the next can be acquired.
struct FrameSlots {
    gpu: Arc<Gpu>,
    slots: Vec<FrameSlot>,
    current: usize,
}

impl FrameSlots {
    fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let device = gpu.raw();
        let mut slots = FrameSlots { gpu: gpu.clone(), slots: Vec::new(), current: 0 };
        for _ in 0..FRAMES_IN_FLIGHT {
            let cmd = crate::gpu::commands::allocate_primary(gpu)?;
            let image_available =
                // SAFETY: `gpu` holds the device; plain create infos.
                unsafe { device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }.vk("vkCreateSemaphore");
            // SAFETY: as above.
            let in_flight = unsafe {
                device.create_fence(&vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED), None)
            }
            .vk("vkCreateFence");
            // Push first, so that Drop frees whatever was created.
            if image_available.is_ok() {
                gpu.created(ObjectKind::Semaphore);
            }
            if in_flight.is_ok() {
                gpu.created(ObjectKind::Fence);
            }
            slots.slots.push(FrameSlot {
                cmd,
                image_available: *image_available.as_ref().unwrap_or(&vk::Semaphore::null()),
                in_flight: *in_flight.as_ref().unwrap_or(&vk::Fence::null()),
            });
            image_available?;
            in_flight?;
        }
        Ok(slots)
    }

    fn current(&self) -> &FrameSlot {
        &self.slots[self.current]
    }

    fn advance(&mut self) {
        self.current = (self.current + 1) % self.slots.len();
    }
}

impl Drop for FrameSlots {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: after the wait no fence or semaphore is waited on and no command buffer is
        // pending; each handle is destroyed once (null ones, from a failed creation, skipped).
        unsafe {
            // A slot's fence or semaphore may still be waited on, its command buffer pending.
            let _ = device.device_wait_idle();
            for slot in self.slots.drain(..) {
                if slot.in_flight != vk::Fence::null() {
                    device.destroy_fence(slot.in_flight, None);
                    self.gpu.destroyed(ObjectKind::Fence);
                }
                if slot.image_available != vk::Semaphore::null() {
                    device.destroy_semaphore(slot.image_available, None);
                    self.gpu.destroyed(ObjectKind::Semaphore);
                }
                crate::gpu::commands::free_primary(&self.gpu, slot.cmd);
            }
        }
    }
}
