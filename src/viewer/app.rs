//! The viewer's event loop: winit's `ApplicationHandler`. Everything bound to the window lives
//! in one `RunningWindow`, which exists from the first `resumed` until the viewer ends or fails;
//! what is shown (scene, settings, clock) lives in the `Session`, which outlasts it.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::controls::Live;
use super::keys::{self, Action, Flow};
use super::live::{LiveFrame, LiveTechnique, Settings};
use super::options::{PresentPath, ViewerOptions};
use super::tour::{self, Tour};
use super::x_guard;
use crate::error::{Error, Result};
use crate::frame::render_pass::FrameDestination;
use crate::frame::targets::check_samples;
use crate::gpu::swapchain::{Acquired, Surface};
use crate::gpu::{mobile_profile, Gpu};
use crate::render::present::{Output, FRAMES_IN_FLIGHT};
use crate::scene::Scene;

/// How long `--resize-after` waits for the window system to apply the new size.
const RESIZE_TIMEOUT_FRAMES: u32 = 600;

pub(super) struct App<'s> {
    // Field order is drop order: the window's parts go before the session's Gpu.
    state: AppState<'s>,
    session: Session<'s>,
}

enum AppState<'s> {
    /// The event loop has not resumed yet: no window.
    Starting,
    Running(Box<RunningWindow<'s>>),
    /// Ended by an error; the window is already gone.
    Failed(Error),
}

/// What the viewer shows and how far it got, apart from the window.
struct Session<'s> {
    gpu: Arc<Gpu>,
    /// The scene as loaded; `scene` is its copy posed by `live` each frame.
    base: &'s Scene,
    /// What the technique is built from: `base`, or once lights were added or removed, `base`
    /// with the live lights, kept in `lit_scenes` while a renderer may borrow it.
    lit: &'s Scene,
    lit_scenes: &'s typed_arena::Arena<Scene>,
    scene: Scene,
    options: ViewerOptions,
    settings: Settings,
    live: Live,
    presented: u32,
    /// `--frames` are done: events still queued before the loop ends draw nothing more.
    done: bool,
    last_tick: Instant,
    /// The last presented frame's counters, for the title.
    last: Option<LiveFrame>,
    /// `--tour`: the soak's script, and the frame count whose stop was last applied.
    tour: Option<(Tour, Option<u32>)>,
}

/// The window and everything bound to it. Field order is drop order: the technique and the
/// output go before the surface, the surface before the window.
struct RunningWindow<'s> {
    technique: TechniqueCache<'s>,
    output: Output,
    surface: Surface,
    window: Window,
    gpu: Arc<Gpu>,
    needs_recreate: bool,
    /// The inner size asked for by `--resize-after`, until the swapchain has it.
    resize_pending: Option<(u32, u32)>,
    frames_since_resize: u32,
    /// The window system says nothing of the window is visible: frames are not drawn.
    occluded: bool,
    /// Where the left button went down (or last moved to) while dragging.
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
}

/// The live technique for the current settings and frame size: built for the first frame,
/// rebuilt when either changes or the scene outgrows it.
struct TechniqueCache<'s> {
    built: Option<LiveTechnique<'s>>,
    /// Technique warnings already printed: a rebuild (resize, another method) says them once.
    warned: std::collections::HashSet<String>,
}

impl<'s> App<'s> {
    pub(super) fn new(
        gpu: Arc<Gpu>,
        base: &'s Scene,
        lit_scenes: &'s typed_arena::Arena<Scene>,
        options: ViewerOptions,
    ) -> Self {
        let tour = options.tour.map(|every| (Tour::new(every, options.size), None));
        let session = Session {
            gpu,
            base,
            lit: base,
            lit_scenes,
            scene: base.clone(),
            settings: options.settings.clone(),
            live: Live::new(base, options.paused, options.start_time),
            options,
            presented: 0,
            done: false,
            last_tick: Instant::now(),
            last: None,
            tour,
        };
        App { state: AppState::Starting, session }
    }

    /// Tears the window down (validation messages go to stderr as they happen: before the
    /// error is reported), then returns the error that ended the viewer, if any.
    pub(super) fn finish(self) -> Result<()> {
        match self.state {
            AppState::Failed(error) => Err(error),
            AppState::Starting | AppState::Running(_) => Ok(()),
        }
    }

    /// Ends the viewer with `error` (the first one, if several arrive before the loop ends).
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        if !matches!(self.state, AppState::Failed(_)) {
            self.state = AppState::Failed(error);
        }
        event_loop.exit();
    }

    /// A key press: its action from the key map, then the title (which shows most settings).
    fn key(&mut self, key: &winit::keyboard::Key, event_loop: &ActiveEventLoop) {
        let AppState::Running(running) = &self.state else { return };
        let session = &mut self.session;
        if let Some(action) = keys::action_for(key) {
            if session.act(action) == Flow::Quit {
                event_loop.exit();
            }
        }
        if let Err(error) = update_title(&running.window, session) {
            self.fail(event_loop, error);
        }
    }
}

impl Session<'_> {
    /// Applies a key's action. A sample count the device does not offer for the frame is
    /// named on stderr and skipped: the next one is tried (1 is always offered).
    fn act(&mut self, action: Action) -> Flow {
        let flow = action.apply(&mut self.settings, &mut self.live, self.base);
        if action == Action::NextSampleCount {
            for _ in 1..keys::SAMPLE_COUNTS.len() {
                let render = &self.settings.render;
                let Err(error) = check_samples(&self.gpu, render.stencil, render.samples) else { break };
                eprintln!("nostencil view: {}x skipped: {error}", render.samples);
                action.apply(&mut self.settings, &mut self.live, self.base);
            }
        }
        flow
    }
}

impl<'s> RunningWindow<'s> {
    fn open(event_loop: &ActiveEventLoop, session: &Session) -> Result<Self> {
        let (width, height) = session.options.size;
        let attributes =
            Window::default_attributes().with_title("nostencil view").with_inner_size(PhysicalSize::new(width, height));
        let window =
            event_loop.create_window(attributes).map_err(|e| Error::Device(format!("cannot create a window: {e}")))?;
        let surface = Surface::new(&session.gpu, &window)?;
        let size = window.inner_size();
        let draw_into = session.options.present == PresentPath::Direct;
        let output = Output::new(&session.gpu, &surface, (size.width, size.height), draw_into)?;
        Ok(RunningWindow {
            technique: TechniqueCache { built: None, warned: Default::default() },
            output,
            surface,
            window,
            gpu: session.gpu.clone(),
            needs_recreate: false,
            resize_pending: None,
            frames_since_resize: 0,
            occluded: false,
            drag: None,
            cursor: (0.0, 0.0),
        })
    }

    fn size(&self) -> (u32, u32) {
        // (0, 0) on a broken display connection: drawing pauses as when minimised, and the
        // next title update reports the lost display.
        let s = x_guard::window_call(|| self.window.inner_size()).unwrap_or_default();
        (s.width, s.height)
    }

    /// One frame: acquire a swapchain image, render the technique into it (or offscreen, then
    /// copy it in), present; then the scripted test hooks, and the screenshot after the last
    /// frame.
    fn draw(&mut self, session: &mut Session<'s>, event_loop: &ActiveEventLoop) -> Result<()> {
        if session.done {
            return Ok(());
        }
        advance_clock(session);
        if self.needs_recreate {
            let size = self.size();
            let draw_into = session.options.present == PresentPath::Direct;
            self.output.recreate(&session.gpu, &self.surface, size, draw_into)?;
            self.needs_recreate = false;
        }
        self.next_stop(session);
        // No area to draw on (minimised): wait for a resize.
        let Output::Presenting(presenter) = &mut self.output else { return Ok(()) };
        let extent = presenter.extent();
        follow_resize(&mut self.resize_pending, &mut self.frames_since_resize, extent)?;
        // The previous frame's copy reads the colour target the technique is about to clear.
        presenter.wait_slots()?;
        let frame_extent = frame_extent_of(extent)?;
        session.live.apply(session.base, &mut session.scene)?;
        if !session.live.lights_shaped_as(session.lit) {
            // Lights added or removed: the technique is planned anew for them.
            session.lit = if session.live.lights_shaped_as(session.base) {
                session.base
            } else {
                session.lit_scenes.alloc(session.live.lit(session.base))
            };
        }
        let last_frame =
            session.options.frames.is_some_and(|n| session.presented + 1 >= n) && self.resize_pending.is_none();
        let screenshot = last_frame && session.options.screenshot.is_some();
        let destination = presenter.destination(session.options.screenshot.is_some());
        session.settings.render.destination = destination;
        // Drawn into the swapchain images, frames stay in flight as the window's slots allow;
        // drawn offscreen, each is copied from the one colour target before the next clears it.
        session.settings.render.frames_in_flight = match destination {
            FrameDestination::Swapchain { .. } => FRAMES_IN_FLIGHT as u32,
            FrameDestination::Offscreen => 1,
        };
        let technique =
            self.technique.get(&session.gpu, session.lit, &session.settings, frame_extent, &session.scene)?;
        // The frame that last used this slot waited on the semaphore the acquire signals.
        technique.wait_for_slot()?;

        let index = match presenter.acquire()? {
            Acquired::OutOfDate => {
                self.needs_recreate = true;
                return Ok(());
            }
            Acquired::SurfaceLost => {
                surface_lost(event_loop);
                return Ok(());
            }
            Acquired::Image { index, suboptimal } => {
                self.needs_recreate |= suboptimal;
                index
            }
        };
        let frame = if technique.presents() {
            // Drawn into the acquired image, resolved there at several samples: nothing to copy.
            let presented = presenter.presented_frame(index, screenshot)?;
            technique.present_next(presenter.images(), presented)?;
            technique.frame(&session.scene)?
        } else {
            let frame = technique.frame(&session.scene)?;
            presenter.submit_copy(index, technique.colour_image()?, screenshot)?;
            frame
        };
        match presenter.present(index) {
            Ok(recreate) => self.needs_recreate |= recreate,
            Err(Error::Vulkan { result: vk::Result::ERROR_SURFACE_LOST_KHR, .. }) => {
                surface_lost(event_loop);
                return Ok(());
            }
            Err(e) => return Err(e),
        }
        session.presented += 1;
        if crate::gpu::faults::crash_after_presents() == Some(session.presented) {
            std::process::abort();
        }
        // With frames in flight the counters come back frames late; a technique just built has
        // none for its first frames, and the title keeps the last ones measured until then.
        if !frame.counters.passes.is_empty() {
            session.last = Some(frame);
        }
        report_tour(session);
        update_title(&self.window, session)?;
        self.run_script(session, event_loop);
        if last_frame {
            self.finish(session, event_loop)?;
        }
        Ok(())
    }

    /// `--press-after` and `--resize-after`, at their frame.
    fn run_script(&mut self, session: &mut Session<'s>, event_loop: &ActiveEventLoop) {
        if let Some((after, letter)) = session.options.press_after {
            if session.presented == after {
                if let Some(action) = keys::action_for_letter(letter) {
                    if session.act(action) == Flow::Quit {
                        event_loop.exit();
                    }
                }
            }
        }
        if let Some((after, size)) = session.options.resize_after {
            if session.presented == after {
                self.resize_pending = Some(size);
                self.frames_since_resize = 0;
                let _ = self.window.request_inner_size(PhysicalSize::new(size.0, size.1));
            }
        }
    }

    /// After `--frames N`: write `--screenshot`, and end the loop.
    fn finish(&mut self, session: &mut Session<'s>, event_loop: &ActiveEventLoop) -> Result<()> {
        session.done = true;
        if let (Some(path), Output::Presenting(presenter)) = (&session.options.screenshot, &mut self.output) {
            // The last frames, the screenshot's read-back among them, may still be in flight.
            session.gpu.wait_idle();
            let image = presenter.read_screenshot()?;
            crate::frame::write_png(&image, path, false)?;
            eprintln!(
                "nostencil view: wrote {} ({}x{}, frame {}, {})",
                path.display(),
                image.width(),
                image.height(),
                session.presented,
                session.settings.describe()
            );
        }
        event_loop.exit();
        Ok(())
    }
}

/// The animation clock: it runs unless paused.
fn advance_clock(session: &mut Session) {
    let now = Instant::now();
    if !session.live.paused {
        session.live.time += (now - session.last_tick).as_secs_f32();
    }
    session.last_tick = now;
}

/// A resize the viewer asked for (`--resize-after`): done once the swapchain has the size;
/// an error if the window system never gives it.
fn follow_resize(pending: &mut Option<(u32, u32)>, frames_waited: &mut u32, extent: vk::Extent2D) -> Result<()> {
    let Some(wanted) = *pending else { return Ok(()) };
    if (extent.width, extent.height) == wanted {
        *pending = None;
        return Ok(());
    }
    *frames_waited += 1;
    if *frames_waited > RESIZE_TIMEOUT_FRAMES {
        return Err(Error::Device(format!(
            "the window system never resized the window to {}x{} (it is {}x{})",
            wanted.0, wanted.1, extent.width, extent.height
        )));
    }
    Ok(())
}

/// The frame size: the window's, which must be within the mobile profile's limit.
fn frame_extent_of(extent: vk::Extent2D) -> Result<vk::Extent2D> {
    let side = mobile_profile::MAX_IMAGE_SIDE;
    if extent.width > side || extent.height > side {
        return Err(Error::InvalidInput(format!(
            "the window is {}x{}; frames are at most {side} pixels a side (the mobile profile)",
            extent.width, extent.height
        )));
    }
    Ok(extent)
}

impl RunningWindow<'_> {
    /// `--tour`: at a stop's first frame, its technique, stencil, samples and window size.
    fn next_stop(&mut self, session: &mut Session) {
        let Some((tour, applied)) = &mut session.tour else { return };
        if *applied == Some(session.presented) {
            return; // a retried frame (out-of-date swapchain): the stop is already applied
        }
        let Some(stop) = tour.at(session.presented).0 else { return };
        *applied = Some(session.presented);
        stop.apply(&session.gpu, &mut session.settings.render);
        self.resize_pending = Some(stop.size);
        self.frames_since_resize = 0;
        let _ = self.window.request_inner_size(PhysicalSize::new(stop.size.0, stop.size.1));
    }
}

/// `--tour`: after a tour's last frame, the resident memory and the live Vulkan objects.
fn report_tour(session: &Session) {
    let Some((tour, _)) = &session.tour else { return };
    if let Some(completed) = tour.at(session.presented).1 {
        let resident = tour::resident_kib().map_or("n/a".to_owned(), |kib| format!("{kib} KiB"));
        eprintln!(
            "nostencil view: tour {completed} done after {} frames: resident {resident}; live objects: {}",
            session.presented,
            session.gpu.live_objects()
        );
    }
}

impl Drop for RunningWindow<'_> {
    fn drop(&mut self) {
        // Runs before the fields drop: the last frame's copy may still read the technique's
        // targets.
        self.gpu.wait_idle();
    }
}

impl<'s> TechniqueCache<'s> {
    /// The technique for `settings` at `extent`, able to draw `scene`.
    fn get(
        &mut self,
        gpu: &Arc<Gpu>,
        base: &'s Scene,
        settings: &Settings,
        extent: vk::Extent2D,
        scene: &Scene,
    ) -> Result<&mut LiveTechnique<'s>> {
        let fresh = self
            .built
            .as_ref()
            .is_some_and(|t| t.settings == *settings && t.extent == extent && t.lit_as(scene) && !t.stale_for(scene));
        let technique = match self.built.take() {
            Some(technique) if fresh => technique,
            old => {
                // The old technique's GPU memory is freed before the new one allocates its own.
                drop(old);
                let mut technique = LiveTechnique::new(gpu, base, settings.clone(), extent)?;
                let name = settings.render.technique.name();
                let mut lines: Vec<String> =
                    technique.warnings().iter().map(|w| format!("nostencil: warning: {name}: {w}")).collect();
                if settings.render.destination != FrameDestination::Offscreen && !technique.presents() {
                    lines.push(format!(
                        "nostencil view: {name}: a one-sample frame whose subpass reads its own colour is drawn \
                         offscreen and copied into the swapchain image (the fallback)"
                    ));
                }
                for line in lines {
                    if self.warned.insert(line.clone()) {
                        eprintln!("{line}");
                    }
                }
                technique
            }
        };
        Ok(self.built.insert(technique))
    }
}

/// Shows the technique and the frame's counters in the title. Fails when the display
/// connection is broken (the X server went away).
fn update_title(window: &Window, session: &Session) -> Result<()> {
    let Some(frame) = &session.last else { return Ok(()) };
    let counters = &frame.counters;
    let pixels = counters.pixels() as f64;
    let fragments =
        counters.total_fragment_invocations().map_or("n/a".to_owned(), |f| format!("{:.2}", f as f64 / pixels));
    let method = frame.brief.as_ref().map_or(String::new(), |b| format!(" {b}"));
    let title = format!(
        "nostencil view | {} | {}{method} | {} | {}x MSAA | {fragments} fragments/px, overdraw {:.2} | {:.2} ms GPU | {}x{}{}",
        session.base.name,
        frame.description,
        session.live.describe_light(),
        counters.samples,
        counters.overdraw(),
        counters.total_gpu_ms(),
        counters.width,
        counters.height,
        if session.live.paused { " | paused" } else { "" }
    );
    x_guard::window_call(|| window.set_title(&title))
        .ok_or_else(|| Error::Device("the connection to the display was lost (X server gone?)".into()))
}

/// The window was destroyed under the swapchain: not an error, the viewer just ends.
fn surface_lost(event_loop: &ActiveEventLoop) {
    eprintln!("nostencil view: the window's surface was lost; closing");
    event_loop.exit();
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if !matches!(self.state, AppState::Starting) {
            return;
        }
        match RunningWindow::open(event_loop, &self.session) {
            Ok(running) => self.state = AppState::Running(Box::new(running)),
            Err(e) => return self.fail(event_loop, e),
        }
        self.session.last_tick = Instant::now();
        event_loop.set_control_flow(ControlFlow::Poll);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let AppState::Running(running) = &mut self.state else { return };
        let session = &mut self.session;
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => event_loop.exit(),
            WindowEvent::Resized(_) => running.needs_recreate = true,
            WindowEvent::Occluded(occluded) if occluded != running.occluded => {
                running.occluded = occluded;
                eprintln!(
                    "nostencil view: window {}",
                    if occluded { "hidden: drawing paused" } else { "visible again" }
                );
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = running.draw(session, event_loop) {
                    self.fail(event_loop, e);
                }
            }
            // Synthetic presses are winit's replay of keys already held when the window gained
            // focus: acting on them would apply a toggle twice (that press also arrives for real).
            WindowEvent::KeyboardInput { event, is_synthetic: false, .. } if event.state == ElementState::Pressed => {
                self.key(&event.logical_key, event_loop)
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                running.drag = (state == ElementState::Pressed).then_some(running.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = running.drag {
                    session.live.orbit.drag(position.x - x, position.y - y);
                    running.drag = Some((position.x, position.y));
                }
                running.cursor = (position.x, position.y);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                session.live.orbit.zoom(lines, session.base.camera.near * 4.0);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let AppState::Running(running) = &self.state else { return };
        // Nothing to draw on until the window has an area again (a Resized event), nothing
        // seen while it is hidden: sleep instead of burning a phone's battery. A `--frames` run
        // keeps drawing, or it would never end.
        let no_area = matches!(running.output, Output::NoArea);
        let hidden = running.occluded && self.session.options.frames.is_none();
        if (no_area && !running.needs_recreate) || hidden {
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        event_loop.set_control_flow(ControlFlow::Poll);
        running.window.request_redraw();
    }
}
