//! A window's surface and swapchain. Where the surface offers an 8-bit sRGB format with alpha
//! (the frame's own values, in either byte order), frames are drawn straight into its images
//! (`Swapchain::drawable`); otherwise they are built offscreen and blitted (or copied) into the
//! acquired image. The frame's colour format is the caller's (`frame_format`).

use std::sync::Arc;

use ash::{khr, vk};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};

use super::live_objects::ObjectKind;
use crate::error::{Error, Result, VkContext};
use crate::gpu::Gpu;

pub struct Surface {
    /// Keeps the instance alive until the surface is destroyed.
    _gpu: Arc<Gpu>,
    loader: khr::surface::Instance,
    pub raw: vk::SurfaceKHR,
}

impl Surface {
    pub fn new(gpu: &Arc<Gpu>, window: &(impl HasDisplayHandle + HasWindowHandle)) -> Result<Self> {
        let handle_error = |e: winit::raw_window_handle::HandleError| {
            Error::Device(format!("the window system gave no window handle: {e}"))
        };
        let display = window.display_handle().map_err(handle_error)?.as_raw();
        let handle = window.window_handle().map_err(handle_error)?.as_raw();
        // SAFETY: the handles come from a live window; the viewer destroys the surface before
        // the window (field order in the viewer's `RunningWindow`).
        let raw = unsafe { ash_window::create_surface(&gpu.instance.entry, &gpu.instance.raw, display, handle, None) }
            .vk("vkCreate*SurfaceKHR")?;
        let loader = khr::surface::Instance::new(&gpu.instance.entry, &gpu.instance.raw);
        let surface = Surface { _gpu: gpu.clone(), loader, raw };
        // SAFETY: the surface was just made on this instance; `queue_family` is one of the
        // physical device's families. On failure `surface` is dropped, destroying it.
        let supported = unsafe {
            surface.loader.get_physical_device_surface_support(
                gpu.device.physical,
                gpu.device.queue_family,
                surface.raw,
            )
        }
        .vk("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(Error::Device(format!(
                "device '{}' cannot present to this window from its graphics queue",
                gpu.device.info.name
            )));
        }
        Ok(surface)
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: every swapchain made on the surface is gone first (the viewer holds its
        // presenter, which holds the swapchain, in a field before the surface), and `_gpu` keeps the instance.
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

/// How the RGBA8 frame reaches a swapchain image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transfer {
    /// `vkCmdBlitImage` converts between formats (RGBA to BGRA swizzles) with no filtering at
    /// equal sizes.
    Blit,
    /// `vkCmdCopyImage`: raw bytes, for swapchain formats with the frame's byte order (also
    /// the sRGB ones, whose blit would re-encode the values).
    Copy,
}

/// The swapchain formats that can show a `frame_format` frame unchanged, best first, and how.
///
/// The frame is R8G8B8A8_SRGB: its bytes are already sRGB-encoded. An `_SRGB` swapchain image
/// takes them as they are (a copy in the same byte order; a blit otherwise, which decodes and
/// re-encodes, exactly for 8-bit values). A UNORM swapchain image shows its bytes as sRGB too,
/// so a raw copy in the same byte order is right; a blit into UNORM would store the *decoded*
/// (linear) values and darken the picture, so a UNORM image in another byte order is refused.
fn classify(gpu: &Gpu, frame_format: vk::Format, format: vk::Format) -> Option<(u32, Transfer)> {
    // SAFETY: the physical device was enumerated from this live instance.
    let features = |f| unsafe { gpu.instance.raw.get_physical_device_format_properties(gpu.device.physical, f) };
    let can_blit = features(frame_format).optimal_tiling_features.contains(vk::FormatFeatureFlags::BLIT_SRC)
        && features(format).optimal_tiling_features.contains(vk::FormatFeatureFlags::BLIT_DST);
    let frame_is_srgb = is_srgb(frame_format);
    let same_bytes = byte_order(format) == byte_order(frame_format);
    match (same_bytes, is_srgb(format) == frame_is_srgb) {
        // The frame's own format, or its UNORM/sRGB twin: the bytes are the picture.
        (true, true) => Some((0, Transfer::Copy)),
        (true, false) => Some((2, Transfer::Copy)),
        // Another byte order of the same encoding: the blit swizzles and keeps the values.
        (false, true) if can_blit => Some((1, Transfer::Blit)),
        _ => None,
    }
}

/// The 8-bit sRGB formats with alpha a frame can be drawn into directly: their stored values
/// (and the alpha counter's arithmetic) are the frame's own, only the byte order differs.
fn drawable_format(format: vk::Format) -> bool {
    matches!(format, vk::Format::R8G8B8A8_SRGB | vk::Format::B8G8R8A8_SRGB)
}

/// Every swapchain made gets the next number, so that what was attached to one is never
/// mistaken for another (handles may be reused).
static SERIALS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

fn is_srgb(format: vk::Format) -> bool {
    matches!(format, vk::Format::R8G8B8A8_SRGB | vk::Format::B8G8R8A8_SRGB | vk::Format::A8B8G8R8_SRGB_PACK32)
}

pub use nostencil_tiler::formats::byte_order;

/// Whether a swapchain format stores blue in the first byte (the screenshot swizzles back).
pub fn is_bgra(format: vk::Format) -> bool {
    matches!(format, vk::Format::B8G8R8A8_UNORM | vk::Format::B8G8R8A8_SRGB)
}

pub struct Swapchain {
    gpu: Arc<Gpu>,
    loader: khr::swapchain::Device,
    pub raw: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub transfer: Transfer,
    /// The images can be read back (screenshots read the presented image itself).
    pub readable: bool,
    /// Frames can be drawn into the images (COLOR_ATTACHMENT usage, a drawable format that
    /// blends); else they are copied in.
    pub drawable: bool,
    /// Frames can be copied into the images (TRANSFER_DST usage).
    pub copyable: bool,
    /// This swapchain's number among all made (`SERIALS`).
    pub serial: u64,
    /// Signalled when an image's frame is copied in, waited on by its present: one per image,
    /// so a semaphore is never reused while the presentation engine may still hold it.
    pub render_finished: Vec<vk::Semaphore>,
}

pub enum Acquired {
    Image {
        index: u32,
        suboptimal: bool,
    },
    OutOfDate,
    /// The window went away under the swapchain (destroyed by another client).
    SurfaceLost,
}

/// The images' size: the surface's, or `window_size` within its limits when the surface leaves
/// it to the application.
fn image_extent(caps: &vk::SurfaceCapabilitiesKHR, window_size: (u32, u32)) -> vk::Extent2D {
    if caps.current_extent.width != u32::MAX {
        return caps.current_extent;
    }
    vk::Extent2D {
        width: window_size.0.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
        height: window_size.1.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
    }
}

/// The surface's sRGB format that shows frames of `frame_format` best ([`classify`]), and how
/// a frame is copied into it.
fn surface_format(gpu: &Gpu, surface: &Surface, frame_format: vk::Format) -> Result<(vk::SurfaceFormatKHR, Transfer)> {
    // SAFETY: the surface is alive (borrowed) and was made on this device's instance.
    let formats = unsafe { surface.loader.get_physical_device_surface_formats(gpu.device.physical, surface.raw) }
        .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
    formats
        .iter()
        .filter(|f| f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
        .filter_map(|f| classify(gpu, frame_format, f.format).map(|(rank, transfer)| (rank, *f, transfer)))
        .min_by_key(|(rank, _, _)| *rank)
        .map(|(_, f, transfer)| (f, transfer))
        .ok_or_else(|| {
            Error::Device(format!(
                "no swapchain format can show the {frame_format:?} frame unchanged; the window offers {:?}",
                formats.iter().map(|f| f.format).collect::<Vec<_>>()
            ))
        })
}

/// Opaque where the surface allows it, else the first mode it has.
fn composite_alpha(caps: &vk::SurfaceCapabilitiesKHR) -> vk::CompositeAlphaFlagsKHR {
    [
        vk::CompositeAlphaFlagsKHR::OPAQUE,
        vk::CompositeAlphaFlagsKHR::INHERIT,
        vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
        vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
    ]
    .into_iter()
    .find(|a| caps.supported_composite_alpha.contains(*a))
    .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE)
}

impl Swapchain {
    /// A swapchain for the surface at its current size (`window_size` when the surface leaves
    /// it to the application), for frames of `frame_format`; None while the window has no area
    /// (minimised).
    pub fn new(
        gpu: &Arc<Gpu>,
        surface: &Surface,
        window_size: (u32, u32),
        frame_format: vk::Format,
        old: Option<&Swapchain>,
    ) -> Result<Option<Self>> {
        let physical = gpu.device.physical;
        // SAFETY: the surface is alive (borrowed) and was made on this device's instance.
        let caps = unsafe { surface.loader.get_physical_device_surface_capabilities(physical, surface.raw) }
            .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        let extent = image_extent(&caps, window_size);
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let readable = caps.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let copyable = caps.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_DST);

        let (surface_format, transfer) = surface_format(gpu, surface, frame_format)?;
        // SAFETY: the physical device was enumerated from this live instance.
        let features =
            unsafe { gpu.instance.raw.get_physical_device_format_properties(physical, surface_format.format) };
        let drawable = drawable_format(surface_format.format)
            && caps.supported_usage_flags.contains(vk::ImageUsageFlags::COLOR_ATTACHMENT)
            && features.optimal_tiling_features.contains(vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND);
        if !copyable && !drawable {
            return Err(Error::Device(format!(
                "the window's swapchain images ({:?}) can neither be drawn into nor copied into",
                surface_format.format
            )));
        }

        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let composite_alpha = composite_alpha(&caps);
        let mut usage = vk::ImageUsageFlags::empty();
        if copyable {
            usage |= vk::ImageUsageFlags::TRANSFER_DST;
        }
        if readable {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        if drawable {
            usage |= vk::ImageUsageFlags::COLOR_ATTACHMENT;
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(surface_format.format)
            .image_color_space(surface_format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(composite_alpha)
            // FIFO: the one mode every device has, and no tearing.
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.raw));
        let loader = khr::swapchain::Device::new(&gpu.instance.raw, gpu.raw());
        // SAFETY: the device enabled VK_KHR_swapchain (`Gpu::for_presentation`) and its queue can
        // present to the surface (checked in `Surface::new`); extent, image count, usage,
        // transform and composite alpha are taken from the surface's capabilities, the format
        // from its list, and FIFO is always supported. `old` is the surface's current swapchain.
        let raw = unsafe { loader.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?;
        gpu.created(ObjectKind::Swapchain);
        let mut swapchain = Swapchain {
            gpu: gpu.clone(),
            loader,
            raw,
            images: Vec::new(),
            format: surface_format.format,
            extent,
            transfer,
            readable,
            drawable,
            copyable,
            serial: SERIALS.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            render_finished: Vec::new(),
        };
        // SAFETY: `raw` was just created. On any failure from here `swapchain` is dropped, which
        // destroys it and the semaphores made so far.
        swapchain.images = unsafe { swapchain.loader.get_swapchain_images(raw) }.vk("vkGetSwapchainImagesKHR")?;
        for _ in 0..swapchain.images.len() {
            // SAFETY: `gpu` holds the device.
            let semaphore = unsafe { gpu.raw().create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                .vk("vkCreateSemaphore")?;
            gpu.created(ObjectKind::Semaphore);
            swapchain.render_finished.push(semaphore);
        }
        Ok(Some(swapchain))
    }

    pub fn acquire(&self, signal: vk::Semaphore) -> Result<Acquired> {
        // SAFETY: the swapchain is alive; `signal` is the caller's unsignalled semaphore with no
        // pending wait (its frame slot's fence was waited for).
        match unsafe { self.loader.acquire_next_image(self.raw, u64::MAX, signal, vk::Fence::null()) } {
            Ok((index, suboptimal)) => Ok(Acquired::Image { index, suboptimal }),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => Ok(Acquired::SurfaceLost),
            Err(result) => Err(Error::Vulkan { call: "vkAcquireNextImageKHR", result }),
        }
    }

    /// Presents `index`; Ok(true) when the swapchain should be recreated (out of date or
    /// suboptimal).
    pub fn present(&self, index: u32) -> Result<bool> {
        let wait = [self.render_finished[index as usize]];
        let swapchains = [self.raw];
        let indices = [index];
        let info = vk::PresentInfoKHR::default().wait_semaphores(&wait).swapchains(&swapchains).image_indices(&indices);
        // SAFETY: `index` was acquired and its copy submitted, signalling `render_finished[index]`
        // (the caller's order); the queue is used from the viewer's one thread.
        match unsafe { self.loader.queue_present(self.gpu.device.queue, &info) } {
            Ok(suboptimal) => Ok(suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(true),
            Err(result) => Err(Error::Submit {
                work: format!("the present of swapchain image {index}"),
                call: "vkQueuePresentKHR",
                result,
            }),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: after the wait nothing waits on the semaphores or reads the images; the
        // images belong to the swapchain and go with it.
        unsafe {
            // Nothing may still wait on the semaphores or read the images.
            let _ = device.device_wait_idle();
            for semaphore in self.render_finished.drain(..) {
                device.destroy_semaphore(semaphore, None);
                self.gpu.destroyed(ObjectKind::Semaphore);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
        self.gpu.destroyed(ObjectKind::Swapchain);
    }
}
