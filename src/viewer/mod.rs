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

pub mod live;
pub mod swapchain;
mod x_guard;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec3};
use gpu_allocator::MemoryLocation;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::raw_window_handle::HasDisplayHandle;
use winit::window::{Window, WindowId};

use crate::error::{Error, Result, VkContext};
use crate::frame::{RgbaImage, StencilMode};
use crate::gpu::memory::Buffer;
use crate::gpu::mobile_profile;
use crate::gpu::{Gpu, GpuOptions};
use crate::scene::{Light, Scene};
use crate::technique::{LightMode, Normalize, SilhouetteMethod, Technique};
use live::{LiveFrame, LiveTechnique, Settings};
use swapchain::{Acquired, Surface, Swapchain, Transfer};

const FRAMES_IN_FLIGHT: usize = 2;

/// How long `--resize-after` waits for the window system to apply the new size.
const RESIZE_TIMEOUT_FRAMES: u32 = 600;

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
    /// Start with the animation paused (frames then match `nostencil render`).
    pub paused: bool,
    /// The animation time the scene was built at (`--time`); the viewer's clock starts there.
    pub start_time: f32,
}

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

    let mut app = App::new(gpu, &scene, options);
    event_loop.run_app(&mut app).map_err(|e| Error::Device(format!("the window's event loop failed: {e}")))?;
    app.finish()
}

/// One frame slot: what a frame in flight owns until its fence signals.
struct FrameSlot {
    cmd: vk::CommandBuffer,
    image_available: vk::Semaphore,
    in_flight: vk::Fence,
}

/// Everything tied to the window, destroyed before it (and before the Gpu).
struct Presenter {
    gpu: Arc<Gpu>,
    slots: Vec<FrameSlot>,
    swapchain: Option<Swapchain>,
    surface: Surface,
    screenshot: Option<Buffer>,
}

impl Presenter {
    fn new(gpu: &Arc<Gpu>, window: &Window) -> Result<Self> {
        let surface = Surface::new(gpu, window)?;
        let device = gpu.raw();
        let mut presenter =
            Presenter { gpu: gpu.clone(), slots: Vec::new(), swapchain: None, surface, screenshot: None };
        for _ in 0..FRAMES_IN_FLIGHT {
            let cmd = {
                let pool = gpu.command_pool();
                let info = vk::CommandBufferAllocateInfo::default()
                    .command_pool(*pool)
                    .level(vk::CommandBufferLevel::PRIMARY)
                    .command_buffer_count(1);
                unsafe { device.allocate_command_buffers(&info) }.vk("vkAllocateCommandBuffers")?[0]
            };
            let image_available =
                unsafe { device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }.vk("vkCreateSemaphore");
            let in_flight = unsafe {
                device.create_fence(&vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED), None)
            }
            .vk("vkCreateFence");
            // Push first, so that Drop frees whatever was created.
            presenter.slots.push(FrameSlot {
                cmd,
                image_available: *image_available.as_ref().unwrap_or(&vk::Semaphore::null()),
                in_flight: *in_flight.as_ref().unwrap_or(&vk::Fence::null()),
            });
            image_available?;
            in_flight?;
        }
        let size = window.inner_size();
        presenter.swapchain = Swapchain::new(gpu, &presenter.surface, (size.width, size.height), None)?;
        presenter.report();
        Ok(presenter)
    }

    fn recreate(&mut self, window_size: (u32, u32)) -> Result<()> {
        self.wait_idle();
        let old = self.swapchain.take();
        self.swapchain = Swapchain::new(&self.gpu, &self.surface, window_size, old.as_ref())?;
        drop(old);
        self.report();
        Ok(())
    }

    /// One stderr line per swapchain: what the frame is copied into, and how.
    fn report(&self) {
        match &self.swapchain {
            Some(s) => eprintln!(
                "nostencil view: swapchain {}x{} {:?} ({} images), frame copied by {}, screenshots read {}",
                s.extent.width,
                s.extent.height,
                s.format,
                s.images.len(),
                match s.transfer {
                    Transfer::Blit => "blit",
                    Transfer::Copy => "copy",
                },
                if s.readable { "the swapchain image" } else { "the frame" }
            ),
            None => eprintln!("nostencil view: the window has no area (minimised); waiting"),
        }
    }

    fn wait_idle(&self) {
        unsafe {
            let _ = self.gpu.raw().device_wait_idle();
        }
    }

    fn wait_slot(&self, slot: usize) -> Result<()> {
        let fence = [self.slots[slot].in_flight];
        unsafe { self.gpu.raw().wait_for_fences(&fence, true, u64::MAX) }.vk("vkWaitForFences")
    }

    /// Records and submits the copy of `colour` (the frame) into swapchain image `index`.
    fn submit_copy(&mut self, slot: usize, index: u32, colour: vk::Image, screenshot: bool) -> Result<()> {
        let swapchain = self.swapchain.as_ref().ok_or_else(|| Error::InvalidInput("no swapchain".into()))?;
        let extent = swapchain.extent;
        let image = swapchain.images[index as usize];
        if screenshot
            && self.screenshot.as_ref().map_or(true, |b| b.size != extent.width as u64 * extent.height as u64 * 4)
        {
            self.screenshot = Some(Buffer::new(
                &self.gpu,
                "screenshot",
                extent.width as u64 * extent.height as u64 * 4,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?);
        }
        let device = self.gpu.raw();
        let FrameSlot { cmd, image_available, in_flight } = self.slots[slot];
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let barrier = |image, old, new, src_access, dst_access| {
            vk::ImageMemoryBarrier::default()
                .src_access_mask(src_access)
                .dst_access_mask(dst_access)
                .old_layout(old)
                .new_layout(new)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .image(image)
                .subresource_range(range)
        };
        unsafe {
            device.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty()).vk("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(cmd, &begin).vk("vkBeginCommandBuffer")?;
            // The frame's render pass left the colour target in TRANSFER_SRC_OPTIMAL; the
            // acquired image's old contents do not matter.
            let to_transfer = [
                barrier(
                    colour,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                    vk::AccessFlags::TRANSFER_READ,
                ),
                barrier(
                    image,
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::AccessFlags::empty(),
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
            ];
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &to_transfer,
            );
            let corner = vk::Offset3D { x: extent.width as i32, y: extent.height as i32, z: 1 };
            match swapchain.transfer {
                Transfer::Blit => {
                    let region = vk::ImageBlit {
                        src_subresource: layers,
                        src_offsets: [vk::Offset3D::default(), corner],
                        dst_subresource: layers,
                        dst_offsets: [vk::Offset3D::default(), corner],
                    };
                    device.cmd_blit_image(
                        cmd,
                        colour,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        image,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        &[region],
                        vk::Filter::NEAREST,
                    );
                }
                Transfer::Copy => {
                    let region = vk::ImageCopy {
                        src_subresource: layers,
                        src_offset: vk::Offset3D::default(),
                        dst_subresource: layers,
                        dst_offset: vk::Offset3D::default(),
                        extent: vk::Extent3D { width: extent.width, height: extent.height, depth: 1 },
                    };
                    device.cmd_copy_image(
                        cmd,
                        colour,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        image,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        &[region],
                    );
                }
            }
            let mut present_from = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
            let mut present_access = vk::AccessFlags::TRANSFER_WRITE;
            if let (true, Some(buffer)) = (screenshot, &self.screenshot) {
                // Read back what will be presented, from the swapchain image itself (or, where
                // its images cannot be read, from the frame it was copied from).
                let (source, layout) = if swapchain.readable {
                    device.cmd_pipeline_barrier(
                        cmd,
                        vk::PipelineStageFlags::TRANSFER,
                        vk::PipelineStageFlags::TRANSFER,
                        vk::DependencyFlags::empty(),
                        &[],
                        &[],
                        &[barrier(
                            image,
                            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                            vk::AccessFlags::TRANSFER_WRITE,
                            vk::AccessFlags::TRANSFER_READ,
                        )],
                    );
                    present_from = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                    present_access = vk::AccessFlags::empty();
                    (image, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                } else {
                    (colour, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                };
                let region = vk::BufferImageCopy::default().image_subresource(layers).image_extent(vk::Extent3D {
                    width: extent.width,
                    height: extent.height,
                    depth: 1,
                });
                device.cmd_copy_image_to_buffer(cmd, source, layout, buffer.raw, &[region]);
                crate::gpu::barriers::transfer_to_host(device, cmd, buffer.raw);
            }
            // Presentation waits on the semaphore, which orders it after this command buffer.
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[barrier(
                    image,
                    present_from,
                    vk::ImageLayout::PRESENT_SRC_KHR,
                    present_access,
                    vk::AccessFlags::empty(),
                )],
            );
            device.end_command_buffer(cmd).vk("vkEndCommandBuffer")?;

            device.reset_fences(&[in_flight]).vk("vkResetFences")?;
            let waits = [image_available];
            let stages = [vk::PipelineStageFlags::TRANSFER];
            let signals = [swapchain.render_finished[index as usize]];
            let cmds = [cmd];
            let submit = [vk::SubmitInfo::default()
                .wait_semaphores(&waits)
                .wait_dst_stage_mask(&stages)
                .command_buffers(&cmds)
                .signal_semaphores(&signals)];
            device.queue_submit(self.gpu.device.queue, &submit, in_flight).vk("vkQueueSubmit")?;
        }
        Ok(())
    }

    /// The screenshot buffer as RGBA (swizzled back from a BGRA swapchain).
    fn read_screenshot(&self, slot: usize) -> Result<RgbaImage> {
        self.wait_slot(slot)?;
        let (Some(swapchain), Some(buffer)) = (&self.swapchain, &self.screenshot) else {
            return Err(Error::InvalidInput("no screenshot was taken".into()));
        };
        let extent = swapchain.extent;
        let mut pixels = buffer.read()?[..extent.width as usize * extent.height as usize * 4].to_vec();
        if swapchain.readable && swapchain::is_bgra(swapchain.format) {
            pixels.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
        }
        Ok(RgbaImage { width: extent.width, height: extent.height, pixels })
    }
}

impl Drop for Presenter {
    fn drop(&mut self) {
        self.wait_idle();
        self.swapchain = None;
        self.screenshot = None;
        let device = self.gpu.raw();
        for slot in self.slots.drain(..) {
            unsafe {
                if slot.in_flight != vk::Fence::null() {
                    device.destroy_fence(slot.in_flight, None);
                }
                if slot.image_available != vk::Semaphore::null() {
                    device.destroy_semaphore(slot.image_available, None);
                }
                let pool = self.gpu.command_pool();
                device.free_command_buffers(*pool, &[slot.cmd]);
            }
        }
    }
}

/// Camera orbit around the scene camera's target, in spherical coordinates.
#[derive(Debug, Clone, Copy)]
struct Orbit {
    azimuth: f32,
    elevation: f32,
    distance: f32,
}

impl Orbit {
    fn of(scene: &Scene) -> Self {
        let offset = scene.camera.eye - scene.camera.target;
        let distance = offset.length().max(1e-3);
        Orbit { azimuth: offset.x.atan2(offset.z), elevation: (offset.y / distance).clamp(-1.0, 1.0).asin(), distance }
    }

    fn eye(&self, target: Vec3) -> Vec3 {
        let (sa, ca) = self.azimuth.sin_cos();
        let (se, ce) = self.elevation.sin_cos();
        target + Vec3::new(sa * ce, se, ca * ce) * self.distance
    }
}

/// The live state a person changes, applied to a copy of the loaded scene each frame.
struct Live {
    orbit: Orbit,
    /// Light rotation about the vertical axis, and tilt (radians).
    light_yaw: f32,
    light_tilt: f32,
    paused: bool,
    /// Seconds of animation since the viewer started: animated models (glTF animations, the
    /// built-in character's walk) move, and shadow casters turn about their vertical axis.
    time: f32,
    /// The animation time the scene was built at.
    start_time: f32,
}

impl Live {
    fn apply(&self, base: &Scene, scene: &mut Scene) -> Result<()> {
        scene.camera.eye = self.orbit.eye(base.camera.target);
        scene.light = match base.light {
            Light::Directional { direction } => {
                let yawed = Mat4::from_rotation_y(self.light_yaw).transform_vector3(direction);
                let side = yawed.cross(Vec3::Y).normalize_or_zero();
                let tilted = if side == Vec3::ZERO {
                    yawed
                } else {
                    Mat4::from_axis_angle(side, self.light_tilt).transform_vector3(yawed)
                };
                // Keep the light above the horizon.
                Light::Directional { direction: Vec3::new(tilted.x, tilted.y.min(-0.05), tilted.z).normalize() }
            }
            Light::Point { position } => Light::Point {
                position: Mat4::from_rotation_y(self.light_yaw).transform_point3(position)
                    + Vec3::Y * self.light_tilt * 2.0,
            },
        };
        // Animated objects take their pose at this time (transforms and joint palettes; GPU
        // skinning shows the new palettes, CPU-skinned meshes keep the starting pose). Every
        // frame: the turn below is applied to the posed transforms.
        if scene.is_animated() {
            scene.pose_at(self.start_time + self.time)?;
        }
        let posed: Vec<Mat4> = scene
            .objects
            .iter()
            .zip(&base.objects)
            .map(|(object, original)| if object.rig.is_some() { object.transform } else { original.transform })
            .collect();
        let angle = self.time * 0.6;
        for ((object, original), placed) in scene.objects.iter_mut().zip(&base.objects).zip(posed) {
            object.transform = if original.casts_shadow && angle != 0.0 {
                let centre = placed.w_axis.truncate();
                Mat4::from_translation(centre) * Mat4::from_rotation_y(angle) * Mat4::from_translation(-centre) * placed
            } else {
                placed
            };
        }
        Ok(())
    }
}

struct App<'s> {
    // Field order is drop order: the technique and the presenter go before the window, and
    // everything before the Gpu.
    technique: Option<LiveTechnique<'s>>,
    presenter: Option<Presenter>,
    window: Option<Window>,
    gpu: Arc<Gpu>,
    base: &'s Scene,
    scene: Scene,
    options: ViewerOptions,
    settings: Settings,
    live: Live,
    error: Option<Error>,
    slot: usize,
    presented: u32,
    /// The inner size asked for by `--resize-after`, until the swapchain has it.
    resize_pending: Option<(u32, u32)>,
    frames_since_resize: u32,
    needs_recreate: bool,
    minimised: bool,
    /// The window system says nothing of the window is visible: frames are not drawn.
    occluded: bool,
    /// `--frames` are done: events still queued before the loop ends draw nothing more.
    done: bool,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    last_tick: Instant,
    last: Option<LiveFrame>,
}

impl<'s> App<'s> {
    fn new(gpu: Arc<Gpu>, base: &'s Scene, options: ViewerOptions) -> Self {
        let live = Live {
            orbit: Orbit::of(base),
            light_yaw: 0.0,
            light_tilt: 0.0,
            paused: options.paused,
            time: 0.0,
            start_time: options.start_time,
        };
        App {
            technique: None,
            presenter: None,
            window: None,
            gpu,
            base,
            scene: base.clone(),
            settings: options.settings.clone(),
            options,
            live,
            error: None,
            slot: 0,
            presented: 0,
            resize_pending: None,
            frames_since_resize: 0,
            needs_recreate: false,
            minimised: false,
            occluded: false,
            done: false,
            drag: None,
            cursor: (0.0, 0.0),
            last_tick: Instant::now(),
            last: None,
        }
    }

    fn finish(mut self) -> Result<()> {
        self.wait_idle();
        // Validation messages go to stderr as they happen; tear down before reporting.
        self.technique = None;
        self.presenter = None;
        self.window = None;
        match self.error.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    fn window_size(&self) -> (u32, u32) {
        self.window.as_ref().map_or((0, 0), |w| {
            // (0, 0) on a broken display connection: drawing pauses as when minimised, and the
            // next title update reports the lost display.
            let s = x_guard::window_call(|| w.inner_size()).unwrap_or_default();
            (s.width, s.height)
        })
    }

    /// Shows the technique and the frame's counters in the title. Fails when the display
    /// connection is broken (the X server went away).
    fn update_title(&self) -> Result<()> {
        let (Some(window), Some(frame)) = (&self.window, &self.last) else { return Ok(()) };
        let counters = &frame.counters;
        let pixels = counters.pixels() as f64;
        let fragments =
            counters.total_fragment_invocations().map_or("n/a".to_owned(), |f| format!("{:.2}", f as f64 / pixels));
        let method = match frame.zfail {
            Some(true) => " z-fail",
            Some(false) => " z-pass",
            None => "",
        };
        let title = format!(
            "nostencil view | {} | {}{method} | {fragments} fragments/px, {:.2} samples/px | {:.2} ms GPU | {}x{}{}",
            self.base.name,
            self.settings.describe(),
            counters.overdraw(),
            counters.total_gpu_ms(),
            counters.width,
            counters.height,
            if self.live.paused { " | paused" } else { "" }
        );
        x_guard::window_call(|| window.set_title(&title))
            .ok_or_else(|| Error::Device("the connection to the display was lost (X server gone?)".into()))
    }

    /// One frame: render the technique, copy it into a swapchain image, present.
    fn draw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        if self.done {
            return Ok(());
        }
        let now = Instant::now();
        if !self.live.paused {
            self.live.time += (now - self.last_tick).as_secs_f32();
        }
        self.last_tick = now;

        if self.needs_recreate {
            let size = self.window_size();
            let presenter = self.presenter.as_mut().ok_or_else(|| Error::InvalidInput("no window".into()))?;
            presenter.recreate(size)?;
            self.needs_recreate = false;
        }
        let Some(presenter) = self.presenter.as_mut() else { return Ok(()) };
        let Some(swapchain) = presenter.swapchain.as_ref() else {
            // No area to draw on (minimised): wait for a resize.
            self.minimised = true;
            return Ok(());
        };
        self.minimised = false;
        let extent = swapchain.extent;
        if let Some(wanted) = self.resize_pending {
            if (extent.width, extent.height) == wanted {
                self.resize_pending = None;
            } else {
                self.frames_since_resize += 1;
                if self.frames_since_resize > RESIZE_TIMEOUT_FRAMES {
                    return Err(Error::Device(format!(
                        "the window system never resized the window to {}x{} (it is {}x{})",
                        wanted.0, wanted.1, extent.width, extent.height
                    )));
                }
            }
        }

        // The previous frame's copy reads the colour target the technique is about to clear.
        for slot in 0..FRAMES_IN_FLIGHT {
            presenter.wait_slot(slot)?;
        }

        // The frame size follows the window, within the mobile profile's limit.
        let frame_extent = vk::Extent2D {
            width: extent.width.min(mobile_profile::MAX_IMAGE_SIDE),
            height: extent.height.min(mobile_profile::MAX_IMAGE_SIDE),
        };
        if frame_extent != extent {
            return Err(Error::InvalidInput(format!(
                "the window is {}x{}; frames are at most {} pixels a side (the mobile profile)",
                extent.width,
                extent.height,
                mobile_profile::MAX_IMAGE_SIDE
            )));
        }
        self.live.apply(self.base, &mut self.scene)?;
        let stale = match &self.technique {
            Some(t) => t.settings != self.settings || t.extent != frame_extent || t.stale_for(&self.scene),
            None => true,
        };
        if stale {
            self.technique = None;
            self.technique = Some(LiveTechnique::new(&self.gpu, self.base, self.settings.clone(), frame_extent)?);
        }
        let technique = self.technique.as_mut().ok_or_else(|| Error::InvalidInput("no technique".into()))?;
        let frame = technique.frame(&self.scene)?;
        let colour = technique.colour_image();

        let slot = self.slot;
        let index = match swapchain.acquire(presenter.slots[slot].image_available)? {
            Acquired::OutOfDate => {
                self.needs_recreate = true;
                return Ok(());
            }
            Acquired::SurfaceLost => {
                self.surface_lost(event_loop);
                return Ok(());
            }
            Acquired::Image { index, suboptimal } => {
                self.needs_recreate |= suboptimal;
                index
            }
        };
        let last_frame = self.options.frames.is_some_and(|n| self.presented + 1 >= n) && self.resize_pending.is_none();
        let screenshot = last_frame && self.options.screenshot.is_some();
        presenter.submit_copy(slot, index, colour, screenshot)?;
        let swapchain = presenter.swapchain.as_ref().ok_or_else(|| Error::InvalidInput("no swapchain".into()))?;
        match swapchain.present(index) {
            Ok(recreate) => self.needs_recreate |= recreate,
            Err(Error::Vulkan { result: vk::Result::ERROR_SURFACE_LOST_KHR, .. }) => {
                self.surface_lost(event_loop);
                return Ok(());
            }
            Err(e) => return Err(e),
        }
        self.slot = (slot + 1) % FRAMES_IN_FLIGHT;
        self.presented += 1;
        self.last = Some(frame);
        self.update_title()?;

        if let Some((after, size)) = self.options.resize_after {
            if self.presented == after {
                self.resize_pending = Some(size);
                self.frames_since_resize = 0;
                if let Some(window) = &self.window {
                    let _ = window.request_inner_size(PhysicalSize::new(size.0, size.1));
                }
            }
        }
        if last_frame {
            self.done = true;
            if let (Some(path), Some(presenter)) = (&self.options.screenshot, &self.presenter) {
                let image = presenter.read_screenshot(slot)?;
                image.write_png(path, false)?;
                eprintln!(
                    "nostencil view: wrote {} ({}x{}, frame {}, {})",
                    path.display(),
                    image.width,
                    image.height,
                    self.presented,
                    self.settings.describe()
                );
            }
            event_loop.exit();
        }
        Ok(())
    }

    /// The window was destroyed under the swapchain: not an error, the viewer just ends.
    fn surface_lost(&mut self, event_loop: &ActiveEventLoop) {
        eprintln!("nostencil view: the window's surface was lost; closing");
        event_loop.exit();
    }

    fn key(&mut self, key: &Key, event_loop: &ActiveEventLoop) {
        const STEP: f32 = 0.15;
        let s = &mut self.settings.render;
        match key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::ArrowLeft) => self.live.light_yaw -= STEP,
            Key::Named(NamedKey::ArrowRight) => self.live.light_yaw += STEP,
            Key::Named(NamedKey::ArrowUp) => self.live.light_tilt = (self.live.light_tilt + STEP).min(1.2),
            Key::Named(NamedKey::ArrowDown) => self.live.light_tilt = (self.live.light_tilt - STEP).max(-1.2),
            Key::Named(NamedKey::Space) => self.live.paused = !self.live.paused,
            // Shift+T goes back through the techniques.
            Key::Character(c) if c.as_str() == "T" => s.technique = cycle(Technique::ALL, s.technique, -1),
            Key::Character(c) => match c.to_lowercase().as_str() {
                "q" => event_loop.exit(),
                "t" => s.technique = cycle(Technique::ALL, s.technique, 1),
                "s" => {
                    s.stencil = match s.stencil {
                        StencilMode::Emulated => StencilMode::Reference,
                        StencilMode::Reference => StencilMode::Emulated,
                    }
                }
                "n" => s.shadow_volume.normalize = cycle(&Normalize::ALL, s.shadow_volume.normalize, 1),
                "k" => s.shadow_volume.increment = cycle(&[1, 2, 4, 8], s.shadow_volume.increment, 1),
                "e" => s.cartoon.silhouette = cycle(&SilhouetteMethod::ALL, s.cartoon.silhouette, 1),
                "l" => s.shadow_atlas.light = cycle(&[LightMode::Fixed, LightMode::Moving], s.shadow_atlas.light, 1),
                "p" => self.live.paused = !self.live.paused,
                "r" => {
                    self.live.orbit = Orbit::of(self.base);
                    self.live.light_yaw = 0.0;
                    self.live.light_tilt = 0.0;
                    self.live.time = 0.0;
                }
                _ => {}
            },
            _ => {}
        }
        if let Err(error) = self.update_title() {
            self.fail(event_loop, error);
        }
    }
}

impl App<'_> {
    /// The last frame's copy may still read the technique's targets.
    fn wait_idle(&self) {
        unsafe {
            let _ = self.gpu.raw().device_wait_idle();
        }
    }
}

impl Drop for App<'_> {
    fn drop(&mut self) {
        // Runs before the fields drop: nothing they own may still be in use on the GPU.
        self.wait_idle();
    }
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let attributes = Window::default_attributes()
            .with_title("nostencil view")
            .with_inner_size(PhysicalSize::new(self.options.size.0, self.options.size.1));
        let window = match event_loop.create_window(attributes) {
            Ok(w) => w,
            Err(e) => return self.fail(event_loop, Error::Device(format!("cannot create a window: {e}"))),
        };
        match Presenter::new(&self.gpu, &window) {
            Ok(p) => self.presenter = Some(p),
            Err(e) => return self.fail(event_loop, e),
        }
        self.window = Some(window);
        self.last_tick = Instant::now();
        event_loop.set_control_flow(ControlFlow::Poll);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => event_loop.exit(),
            WindowEvent::Resized(_) => self.needs_recreate = true,
            WindowEvent::Occluded(occluded) if occluded != self.occluded => {
                self.occluded = occluded;
                eprintln!(
                    "nostencil view: window {}",
                    if occluded { "hidden: drawing paused" } else { "visible again" }
                );
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.draw(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            // Synthetic presses are winit's replay of keys already held when the window gained
            // focus: acting on them would apply a toggle twice (that press also arrives for real).
            WindowEvent::KeyboardInput { event, is_synthetic: false, .. } if event.state == ElementState::Pressed => {
                self.key(&event.logical_key, event_loop)
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = self.drag {
                    let orbit = &mut self.live.orbit;
                    orbit.azimuth -= ((position.x - x) * 0.01) as f32;
                    orbit.elevation = (orbit.elevation + ((position.y - y) * 0.01) as f32).clamp(-1.45, 1.45);
                    self.drag = Some((position.x, position.y));
                }
                self.cursor = (position.x, position.y);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                let orbit = &mut self.live.orbit;
                orbit.distance = (orbit.distance * 0.9f32.powf(lines)).max(self.base.camera.near * 4.0);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        // Nothing to draw on until the window has an area again (a Resized event), nothing
        // seen while it is hidden: sleep instead of burning a phone's battery. A `--frames` run
        // keeps drawing, or it would never end.
        let hidden = self.occluded && self.options.frames.is_none();
        if (self.minimised && !self.needs_recreate) || hidden {
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        event_loop.set_control_flow(ControlFlow::Poll);
        if let Some(window) = &self.window {
            window.request_redraw();
        }
    }
}

/// The item `step` places after `current` in `all`, wrapping (the first when `current` is not
/// in `all`).
fn cycle<T: Copy + PartialEq>(all: &[T], current: T, step: isize) -> T {
    let n = all.len() as isize;
    match all.iter().position(|x| *x == current) {
        Some(i) => all[(i as isize + step).rem_euclid(n) as usize],
        None => all[0],
    }
}
