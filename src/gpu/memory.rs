//! Buffers and images with their memory. Memory comes from gpu-allocator, except transient
//! attachments on devices that offer LAZILY_ALLOCATED memory (tile-based GPUs), which
//! gpu-allocator cannot ask for: those get a dedicated lazy allocation of their own.

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::commands::submit_and_wait;
use super::context::Gpu;
use super::live_objects::ObjectKind;
use crate::error::{Error, Result, VkContext};

pub struct Buffer {
    gpu: Arc<Gpu>,
    pub raw: vk::Buffer,
    pub size: u64,
    allocation: Option<Allocation>,
}

impl Buffer {
    pub fn new(
        gpu: &Arc<Gpu>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let device = gpu.raw();
        let info =
            vk::BufferCreateInfo::default().size(size.max(4)).usage(usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: `device` is alive (`gpu` holds it) and `info` is a valid create info; `raw` is
        // the buffer just created from it.
        let raw = unsafe { device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        gpu.created(ObjectKind::Buffer);
        // SAFETY: as above.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let allocation = gpu
            .allocator()
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| {
                // SAFETY: `raw` has no memory bound and no other owner yet.
                unsafe { device.destroy_buffer(raw, None) };
                gpu.destroyed(ObjectKind::Buffer);
                Error::Memory(format!("buffer '{name}' ({size} bytes): {e}"))
            })?;
        gpu.created(ObjectKind::MemoryAllocation);
        // SAFETY: the allocation was made for `raw`'s requirements and is bound once; the memory
        // handle is only passed to Vulkan, never freed here (the allocator owns it). On failure
        // the returned Buffer's drop destroys `raw` and frees the allocation.
        let bound = unsafe { device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindBufferMemory");
        let buffer = Buffer { gpu: gpu.clone(), raw, size, allocation: Some(allocation) };
        bound.map(|_| buffer)
    }

    /// A host-visible buffer filled with `data`.
    pub fn with_data<T: Pod>(gpu: &Arc<Gpu>, name: &str, data: &[T], usage: vk::BufferUsageFlags) -> Result<Self> {
        let data: &[u8] = bytemuck::cast_slice(data);
        let mut buffer = Buffer::new(gpu, name, data.len() as u64, usage, MemoryLocation::CpuToGpu)?;
        buffer.write(0, data)?;
        Ok(buffer)
    }

    /// A device-local buffer filled through a staging copy.
    pub fn device_local<T: Pod>(gpu: &Arc<Gpu>, name: &str, data: &[T], usage: vk::BufferUsageFlags) -> Result<Self> {
        let data: &[u8] = bytemuck::cast_slice(data);
        let staging = Buffer::with_data(gpu, &format!("{name} (staging)"), data, vk::BufferUsageFlags::TRANSFER_SRC)?;
        let buffer = Buffer::new(
            gpu,
            name,
            data.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        if data.is_empty() {
            // A copy of zero bytes is invalid Vulkan (VUID-VkBufferCopy-size-01988).
            return Ok(buffer);
        }
        submit_and_wait(gpu, |cmd| {
            let region = [vk::BufferCopy { src_offset: 0, dst_offset: 0, size: data.len() as u64 }];
            // SAFETY: `cmd` is recording; both buffers hold `data.len()` bytes (the staging one
            // was filled with them) and live until `submit_and_wait` has waited for the copy.
            unsafe { gpu.raw().cmd_copy_buffer(cmd, staging.raw, buffer.raw, &region) };
            Ok(())
        })?;
        Ok(buffer)
    }

    /// Writes `data` over this buffer in place where it is host-visible and large enough, else
    /// replaces it with a host-visible buffer of `data` (the first pose of geometry whose buffer
    /// was device-local): posed vertices rewritten every frame without an allocation. The GPU
    /// must no longer read it (the frames that drew it were waited for).
    pub fn rewrite<T: Pod>(
        &mut self,
        gpu: &Arc<Gpu>,
        name: &str,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        if self.writable_in_place(bytes.len()) {
            return self.write(0, bytes);
        }
        *self = Buffer::with_data(gpu, name, data, usage)?;
        Ok(())
    }

    /// Whether `bytes` bytes can be written over this buffer from byte 0: it is host-visible and
    /// large enough.
    fn writable_in_place(&self, bytes: usize) -> bool {
        let host_visible = self.allocation.as_ref().is_some_and(|a| a.mapped_ptr().is_some());
        host_visible && self.size >= bytes as u64
    }

    /// Copies `data` to byte `offset` of a host-visible buffer.
    pub fn write<T: Pod>(&mut self, offset: usize, data: &[T]) -> Result<()> {
        let data: &[u8] = bytemuck::cast_slice(data);
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| Error::Memory("buffer is not host-visible".into()))?;
        let end = offset.checked_add(data.len()).filter(|&e| e <= slice.len()).ok_or_else(|| {
            Error::Memory(format!("write of {} bytes at {offset} past a {}-byte buffer", data.len(), slice.len()))
        })?;
        slice[offset..end].copy_from_slice(data);
        Ok(())
    }

    pub fn read(&self) -> Result<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .map(|s| &s[..self.size as usize])
            .ok_or_else(|| Error::Memory("buffer is not host-visible".into()))
    }
}

/// A host-visible buffer rewritten in place frame after frame, made again (with room to grow)
/// only when the data outgrows it: per-frame geometry that allocates nothing in a steady state.
/// The caller writes it only once the GPU no longer reads it (the frames it drew waited for).
pub struct ReusedBuffer {
    name: &'static str,
    usage: vk::BufferUsageFlags,
    buffer: Option<Buffer>,
    /// Elements the last fill wrote.
    len: u32,
}

impl ReusedBuffer {
    pub fn new(name: &'static str, usage: vk::BufferUsageFlags) -> Self {
        ReusedBuffer { name, usage, buffer: None, len: 0 }
    }

    /// Writes `data` from byte 0, first making a buffer twice the size of `data` where the one
    /// it has is too small (none for no data: then it holds nothing to draw).
    pub fn fill<T: Pod>(&mut self, gpu: &Arc<Gpu>, data: &[T]) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let count = self.count(data.len())?;
        self.len = 0;
        if let Some(mapped) = self.mapped(gpu, bytes.len())? {
            mapped.copy_from_slice(bytes);
        }
        self.len = count;
        Ok(())
    }

    /// Writes `len` elements from byte 0 as [`ReusedBuffer::fill`] does, through `write`, which
    /// gets exactly those `len` elements of the buffer's mapped memory: data gathered from
    /// several lists, written once, straight where the GPU reads it.
    pub fn fill_with<T: Pod>(&mut self, gpu: &Arc<Gpu>, len: usize, write: impl FnOnce(&mut [T])) -> Result<()> {
        let count = self.count(len)?;
        let bytes = len
            .checked_mul(std::mem::size_of::<T>())
            .ok_or_else(|| Error::Memory(format!("'{}': {len} elements overflow", self.name)))?;
        self.len = 0;
        let name = self.name;
        if let Some(mapped) = self.mapped(gpu, bytes)? {
            let elements: &mut [T] = bytemuck::try_cast_slice_mut(mapped)
                .map_err(|e| Error::Memory(format!("'{name}': mapped memory does not fit its elements: {e}")))?;
            write(elements);
        }
        self.len = count;
        Ok(())
    }

    /// `len` as the element count a draw takes.
    fn count(&self, len: usize) -> Result<u32> {
        u32::try_from(len).map_err(|_| Error::Memory(format!("'{}': {len} elements", self.name)))
    }

    /// The first `bytes` bytes of the buffer's mapped memory, first making a buffer twice that
    /// size where the one it has is too small; `None` for no bytes.
    fn mapped(&mut self, gpu: &Arc<Gpu>, bytes: usize) -> Result<Option<&mut [u8]>> {
        if bytes == 0 {
            return Ok(None);
        }
        if !self.buffer.as_ref().is_some_and(|b| b.writable_in_place(bytes)) {
            self.buffer = None;
            let size = (bytes as u64 * 2).max(256);
            self.buffer = Some(Buffer::new(gpu, self.name, size, self.usage, MemoryLocation::CpuToGpu)?);
        }
        let slice = self
            .buffer
            .as_mut()
            .and_then(|b| b.allocation.as_mut())
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| Error::Memory(format!("'{}' is not host-visible", self.name)))?;
        Ok(Some(&mut slice[..bytes]))
    }

    /// The buffer and the elements the last fill wrote into it; none when it wrote none.
    pub fn filled(&self) -> Option<(&Buffer, u32)> {
        self.buffer.as_ref().filter(|_| self.len > 0).map(|b| (b, self.len))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the GPU no longer uses the buffer: offscreen submissions are waited for by
        // `submit_and_wait`, and the viewer waits for its frames before dropping what they read.
        unsafe { self.gpu.raw().destroy_buffer(self.raw, None) };
        self.gpu.destroyed(ObjectKind::Buffer);
        if let Some(allocation) = self.allocation.take() {
            let _ = self.gpu.allocator().free(allocation);
            self.gpu.destroyed(ObjectKind::MemoryAllocation);
        }
    }
}

enum ImageMemory {
    Allocator(Allocation),
    /// A LAZILY_ALLOCATED dedicated allocation, for transient attachments on tilers.
    Lazy(vk::DeviceMemory),
}

pub struct Image {
    gpu: Arc<Gpu>,
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub mip_levels: u32,
    /// Array layers (1 but for `new_layered`'s images).
    pub layers: u32,
    memory: Option<ImageMemory>,
}

pub use nostencil_tiler::attachment::sample_count_flags;

pub struct ImageDesc<'a> {
    pub name: &'a str,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub usage: vk::ImageUsageFlags,
    pub aspect: vk::ImageAspectFlags,
    pub mip_levels: u32,
    /// Samples per pixel (1, 2, 4 or 8).
    pub samples: u32,
}

impl Image {
    pub fn new(gpu: &Arc<Gpu>, desc: &ImageDesc) -> Result<Self> {
        Self::with_layers(gpu, desc, None)
    }

    /// A 2D array of `layers` layers (at least 1), its view a `TYPE_2D_ARRAY` over all of them
    /// (one shadow map layer per light, sampled as one `sampler2DArrayShadow`).
    pub fn new_layered(gpu: &Arc<Gpu>, desc: &ImageDesc, layers: u32) -> Result<Self> {
        Self::with_layers(gpu, desc, Some(layers.max(1)))
    }

    /// `array`: the layer count of an arrayed image and view; `None`: one layer, a 2D view.
    fn with_layers(gpu: &Arc<Gpu>, desc: &ImageDesc, array: Option<u32>) -> Result<Self> {
        let layers = array.unwrap_or(1);
        super::mobile_profile::check_image_size(desc.name, desc.extent.width, desc.extent.height)?;
        let device = gpu.raw();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D { width: desc.extent.width, height: desc.extent.height, depth: 1 })
            .mip_levels(desc.mip_levels.max(1))
            .array_layers(layers)
            .samples(sample_count_flags(desc.samples))
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: `device` is alive (`gpu` holds it) and `info` is a valid create info; `raw` is
        // the image just created from it.
        let raw = unsafe { device.create_image(&info, None) }.vk("vkCreateImage")?;
        gpu.created(ObjectKind::Image);
        // SAFETY: as above.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };

        let transient = desc.usage.contains(vk::ImageUsageFlags::TRANSIENT_ATTACHMENT);
        let lazy_type = transient
            .then(|| find_memory_type(gpu, requirements.memory_type_bits, vk::MemoryPropertyFlags::LAZILY_ALLOCATED))
            .flatten();
        let memory = match lazy_type {
            Some(type_index) => {
                let alloc =
                    vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(type_index);
                // SAFETY: `type_index` is a memory type the image accepts, of the size it needs.
                let memory = unsafe { device.allocate_memory(&alloc, None) }.vk("vkAllocateMemory");
                match memory {
                    Ok(m) => ImageMemory::Lazy(m),
                    Err(e) => {
                        // SAFETY: `raw` has no memory bound and no other owner yet.
                        unsafe { device.destroy_image(raw, None) };
                        gpu.destroyed(ObjectKind::Image);
                        return Err(e);
                    }
                }
            }
            None => {
                let allocation = gpu.allocator().allocate(&AllocationCreateDesc {
                    name: desc.name,
                    requirements,
                    location: MemoryLocation::GpuOnly,
                    linear: false,
                    allocation_scheme: AllocationScheme::GpuAllocatorManaged,
                });
                match allocation {
                    Ok(a) => ImageMemory::Allocator(a),
                    Err(e) => {
                        // SAFETY: as above.
                        unsafe { device.destroy_image(raw, None) };
                        gpu.destroyed(ObjectKind::Image);
                        return Err(Error::Memory(format!("image '{}': {e}", desc.name)));
                    }
                }
            }
        };
        gpu.created(ObjectKind::MemoryAllocation);
        let (vk_memory, offset) = match &memory {
            // SAFETY: the memory handle is only bound below, never freed here (the allocator owns it).
            ImageMemory::Allocator(a) => unsafe { (a.memory(), a.offset()) },
            ImageMemory::Lazy(m) => (*m, 0),
        };
        let mut image = Image {
            gpu: gpu.clone(),
            raw,
            view: vk::ImageView::null(),
            format: desc.format,
            mip_levels: desc.mip_levels.max(1),
            layers,
            memory: Some(memory),
        };
        // SAFETY: the memory was allocated for `raw`'s requirements and is bound once. On failure
        // `image` is dropped, which destroys `raw` and frees the memory.
        unsafe { device.bind_image_memory(raw, vk_memory, offset) }.vk("vkBindImageMemory")?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(if array.is_some() { vk::ImageViewType::TYPE_2D_ARRAY } else { vk::ImageViewType::TYPE_2D })
            .format(desc.format)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: desc.aspect,
                base_mip_level: 0,
                level_count: image.mip_levels,
                base_array_layer: 0,
                layer_count: layers,
            });
        // SAFETY: `raw` is alive with its memory bound, and the view covers its format, aspect
        // and mips.
        image.view = unsafe { device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        gpu.created(ObjectKind::ImageView);
        Ok(image)
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: the GPU no longer uses the image (as for `Buffer`); the view goes before the
        // image it points at, and the memory after both.
        unsafe {
            if self.view != vk::ImageView::null() {
                device.destroy_image_view(self.view, None);
                self.gpu.destroyed(ObjectKind::ImageView);
            }
            device.destroy_image(self.raw, None);
        }
        self.gpu.destroyed(ObjectKind::Image);
        if self.memory.is_some() {
            self.gpu.destroyed(ObjectKind::MemoryAllocation);
        }
        match self.memory.take() {
            Some(ImageMemory::Allocator(a)) => {
                let _ = self.gpu.allocator().free(a);
            }
            // SAFETY: the image bound to it was destroyed above.
            Some(ImageMemory::Lazy(m)) => unsafe { device.free_memory(m, None) },
            None => {}
        }
    }
}

fn find_memory_type(gpu: &Gpu, type_bits: u32, flags: vk::MemoryPropertyFlags) -> Option<u32> {
    let props = &gpu.device.memory_properties;
    (0..props.memory_type_count)
        .find(|&i| type_bits & (1 << i) != 0 && props.memory_types[i as usize].property_flags.contains(flags))
}

/// The size of the device's largest device-local heap in bytes (a test-only fault can lower it).
pub fn largest_device_heap(gpu: &Gpu) -> u64 {
    let props = &gpu.device.memory_properties;
    let heaps = &props.memory_heaps[..props.memory_heap_count as usize];
    let largest = heaps.iter().filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL)).map(|h| h.size).max();
    let largest = largest.unwrap_or(0);
    super::faults::heap_limit().map_or(largest, |limit| largest.min(limit))
}

/// Refuses `bytes` of GPU memory for `what` up front when the device's largest heap cannot
/// hold them (before anything is allocated, rendered or written); `hint` says what to lower.
pub fn check_fits_in_heap(gpu: &Gpu, what: &str, bytes: u64, hint: &str) -> Result<()> {
    let heap = largest_device_heap(gpu);
    if bytes > heap {
        const MIB: f64 = (1u64 << 20) as f64;
        return Err(Error::Memory(format!(
            "{what} needs {:.1} MiB, more than the largest heap of '{}' holds ({:.1} MiB){hint}",
            bytes as f64 / MIB,
            gpu.device.info.name,
            heap as f64 / MIB
        )));
    }
    Ok(())
}
