//! The bytes a transfer command reads and writes, from its regions and the images' formats:
//! what a tiler pays in system-memory traffic for it. Worked out on the CPU at record time: a
//! block-compressed format (BC, ETC2/EAC, ASTC: what mobile textures are) counts its blocks, a
//! multi-planar format's plane its own texels, other formats `texel_bytes` (4 bytes for one it
//! does not list); a multisampled image moves every sample.

use ash::vk;

use nostencil_tiler::formats::texel_bytes;

use super::work::Moved;

/// What the layer keeps of an image the application created.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageInfo {
    pub format: vk::Format,
    pub extent: vk::Extent3D,
    pub mip_levels: u32,
    pub array_layers: u32,
    pub samples: u32,
    /// A swapchain's image (vkGetSwapchainImagesKHR).
    pub swapchain: bool,
}

/// A block-compressed format's block: (width, height, bytes).
fn block(format: vk::Format) -> Option<(u64, u64, u64)> {
    // ASTC's block sizes in the order the formats are numbered (UNORM and SRGB pairs in core,
    // SFLOAT alone in VK_EXT_texture_compression_astc_hdr).
    const ASTC: [(u64, u64); 14] = [
        (4, 4),
        (5, 4),
        (5, 5),
        (6, 5),
        (6, 6),
        (8, 5),
        (8, 6),
        (8, 8),
        (10, 5),
        (10, 6),
        (10, 8),
        (10, 10),
        (12, 10),
        (12, 12),
    ];
    let raw = format.as_raw();
    let (bc1, bc7) = (vk::Format::BC1_RGB_UNORM_BLOCK.as_raw(), vk::Format::BC7_SRGB_BLOCK.as_raw());
    let (etc, eac) = (vk::Format::ETC2_R8G8B8_UNORM_BLOCK.as_raw(), vk::Format::EAC_R11G11_SNORM_BLOCK.as_raw());
    let (astc, astc_end) = (vk::Format::ASTC_4X4_UNORM_BLOCK.as_raw(), vk::Format::ASTC_12X12_SRGB_BLOCK.as_raw());
    let hdr = vk::Format::ASTC_4X4_SFLOAT_BLOCK.as_raw();
    match raw {
        // BC1 and BC4 blocks are 8 bytes, the others 16.
        _ if (bc1..=bc7).contains(&raw) => {
            let small = raw <= vk::Format::BC1_RGBA_SRGB_BLOCK.as_raw()
                || (vk::Format::BC4_UNORM_BLOCK.as_raw()..=vk::Format::BC4_SNORM_BLOCK.as_raw()).contains(&raw);
            Some((4, 4, if small { 8 } else { 16 }))
        }
        // ETC2 RGB, RGB A1 and EAC R11: 8 bytes; ETC2 RGBA and EAC RG11: 16.
        _ if (etc..=eac).contains(&raw) => {
            let wide = (vk::Format::ETC2_R8G8B8A8_UNORM_BLOCK.as_raw()..=vk::Format::ETC2_R8G8B8A8_SRGB_BLOCK.as_raw())
                .contains(&raw)
                || raw >= vk::Format::EAC_R11G11_UNORM_BLOCK.as_raw();
            Some((4, 4, if wide { 16 } else { 8 }))
        }
        _ if (astc..=astc_end).contains(&raw) => {
            let (w, h) = ASTC[((raw - astc) / 2) as usize];
            Some((w, h, 16))
        }
        _ if (hdr..hdr + 14).contains(&raw) => {
            let (w, h) = ASTC[(raw - hdr) as usize];
            Some((w, h, 16))
        }
        _ => None,
    }
}

/// Bytes of one texel of a multi-planar format's plane `aspect` (8-bit 4:2:0 and 4:2:2 ones:
/// the chroma plane of a 2-plane format holds two bytes a texel).
fn plane_texel(format: vk::Format, aspect: vk::ImageAspectFlags) -> Option<u64> {
    let two_plane = matches!(
        format,
        vk::Format::G8_B8R8_2PLANE_420_UNORM
            | vk::Format::G8_B8R8_2PLANE_422_UNORM
            | vk::Format::G8_B8R8_2PLANE_444_UNORM
    );
    let three_plane = matches!(
        format,
        vk::Format::G8_B8_R8_3PLANE_420_UNORM
            | vk::Format::G8_B8_R8_3PLANE_422_UNORM
            | vk::Format::G8_B8_R8_3PLANE_444_UNORM
    );
    let planes = vk::ImageAspectFlags::PLANE_0 | vk::ImageAspectFlags::PLANE_1 | vk::ImageAspectFlags::PLANE_2;
    if !aspect.intersects(planes) || !(two_plane || three_plane) {
        return None;
    }
    Some(if two_plane && aspect.contains(vk::ImageAspectFlags::PLANE_1) { 2 } else { 1 })
}

impl ImageInfo {
    /// Bytes of one texel (all samples) of the aspects in `aspects` (of an uncompressed format).
    fn texel(&self, aspects: vk::ImageAspectFlags) -> u64 {
        if let Some(bytes) = plane_texel(self.format, aspects) {
            return bytes;
        }
        let (main, stencil) = match self.format {
            vk::Format::R32G32B32_SFLOAT | vk::Format::R32G32B32_UINT | vk::Format::R32G32B32_SINT => (12, 0),
            vk::Format::R8G8B8_UNORM | vk::Format::R8G8B8_SRGB | vk::Format::B8G8R8_UNORM => (3, 0),
            vk::Format::R16G16B16_SFLOAT | vk::Format::R16G16B16_UNORM => (6, 0),
            vk::Format::R64_SFLOAT | vk::Format::R64_UINT => (8, 0),
            _ => texel_bytes(self.format),
        };
        let mut bytes = 0;
        if aspects.intersects(vk::ImageAspectFlags::COLOR | vk::ImageAspectFlags::DEPTH) {
            bytes += main;
        }
        if aspects.contains(vk::ImageAspectFlags::STENCIL) {
            bytes += stencil;
        }
        bytes * self.samples.max(1) as u64
    }

    /// Bytes of a `w` x `h` x `d` region of the aspects in `aspects`: whole blocks of a
    /// compressed format, texels otherwise.
    fn region(&self, aspects: vk::ImageAspectFlags, (w, h, d): (u64, u64, u64)) -> u64 {
        match block(self.format) {
            Some((bw, bh, bytes)) => w.div_ceil(bw) * h.div_ceil(bh) * d * bytes,
            None => self.texel(aspects) * w * h * d,
        }
    }

    /// The extent of mip `level`.
    fn mip(&self, level: u32) -> (u64, u64, u64) {
        let shrink = |v: u32| (v >> level.min(31)).max(1) as u64;
        (shrink(self.extent.width), shrink(self.extent.height), shrink(self.extent.depth))
    }
}

fn layers(subresource: &vk::ImageSubresourceLayers, image: Option<&ImageInfo>) -> u64 {
    if subresource.layer_count == vk::REMAINING_ARRAY_LAYERS {
        image.map_or(1, |i| i.array_layers.saturating_sub(subresource.base_array_layer).max(1) as u64)
    } else {
        subresource.layer_count.max(1) as u64
    }
}

/// Bytes of `extent` texels of `subresource` in `image` (0 for an image the layer never saw).
fn region_bytes(image: Option<&ImageInfo>, subresource: &vk::ImageSubresourceLayers, extent: vk::Extent3D) -> u64 {
    let size = (extent.width as u64, extent.height as u64, extent.depth.max(1) as u64);
    image.map_or(0, |i| i.region(subresource.aspect_mask, size) * layers(subresource, Some(i)))
}

/// Whether `extent` at `offset` of mip 0 covers the whole of a swapchain image.
fn whole_swapchain(image: Option<&ImageInfo>, level: u32, offset: vk::Offset3D, extent: vk::Extent3D) -> bool {
    image.is_some_and(|i| {
        i.swapchain
            && level == 0
            && offset.x == 0
            && offset.y == 0
            && extent.width >= i.extent.width
            && extent.height >= i.extent.height
    })
}

fn swapchain_note(what: &str, image: Option<&ImageInfo>) -> Option<String> {
    let i = image?;
    Some(format!(
        "full-frame {what} into a swapchain image ({}x{}): the whole frame goes through system memory once more",
        i.extent.width, i.extent.height
    ))
}

/// vkCmdCopyBuffer: each region's size, read and written.
pub fn copy_buffer(regions: &[vk::BufferCopy]) -> Moved {
    let bytes = regions.iter().map(|r| r.size).sum();
    Moved { read: bytes, written: bytes, note: None }
}

/// vkCmdCopyImage: each region's texels of the source, read, and as many written.
pub fn copy_image(src: Option<&ImageInfo>, dst: Option<&ImageInfo>, regions: &[vk::ImageCopy]) -> Moved {
    let read = regions.iter().map(|r| region_bytes(src, &r.src_subresource, r.extent)).sum();
    let written = regions.iter().map(|r| region_bytes(dst, &r.dst_subresource, r.extent)).sum();
    let full = regions.iter().any(|r| whole_swapchain(dst, r.dst_subresource.mip_level, r.dst_offset, r.extent));
    Moved { read, written, note: if full { swapchain_note("copy", dst) } else { None } }
}

/// vkCmdCopyBufferToImage / vkCmdCopyImageToBuffer: the image's texels of each region, read
/// from one side and written to the other.
pub fn buffer_image(image: Option<&ImageInfo>, regions: &[vk::BufferImageCopy], into_image: bool) -> Moved {
    let bytes = regions.iter().map(|r| region_bytes(image, &r.image_subresource, r.image_extent)).sum();
    let full = into_image
        && regions
            .iter()
            .any(|r| whole_swapchain(image, r.image_subresource.mip_level, r.image_offset, r.image_extent));
    Moved { read: bytes, written: bytes, note: if full { swapchain_note("copy", image) } else { None } }
}

/// The extent between a blit region's two corners.
fn corners(offsets: &[vk::Offset3D; 2]) -> vk::Extent3D {
    vk::Extent3D {
        width: offsets[0].x.abs_diff(offsets[1].x),
        height: offsets[0].y.abs_diff(offsets[1].y),
        depth: offsets[0].z.abs_diff(offsets[1].z).max(1),
    }
}

/// vkCmdBlitImage: the source region read, the destination region written (each at its size).
pub fn blit_image(src: Option<&ImageInfo>, dst: Option<&ImageInfo>, regions: &[vk::ImageBlit]) -> Moved {
    let read = regions.iter().map(|r| region_bytes(src, &r.src_subresource, corners(&r.src_offsets))).sum();
    let written = regions.iter().map(|r| region_bytes(dst, &r.dst_subresource, corners(&r.dst_offsets))).sum();
    let full = regions.iter().any(|r| {
        let origin = vk::Offset3D {
            x: r.dst_offsets[0].x.min(r.dst_offsets[1].x),
            y: r.dst_offsets[0].y.min(r.dst_offsets[1].y),
            z: 0,
        };
        whole_swapchain(dst, r.dst_subresource.mip_level, origin, corners(&r.dst_offsets))
    });
    Moved { read, written, note: if full { swapchain_note("blit", dst) } else { None } }
}

/// vkCmdResolveImage: every sample of the source read, one written.
pub fn resolve_image(src: Option<&ImageInfo>, dst: Option<&ImageInfo>, regions: &[vk::ImageResolve]) -> Moved {
    let read = regions.iter().map(|r| region_bytes(src, &r.src_subresource, r.extent)).sum();
    let written = regions.iter().map(|r| region_bytes(dst, &r.dst_subresource, r.extent)).sum();
    let full = regions.iter().any(|r| whole_swapchain(dst, r.dst_subresource.mip_level, r.dst_offset, r.extent));
    Moved { read, written, note: if full { swapchain_note("resolve", dst) } else { None } }
}

/// vkCmdClearColorImage / vkCmdClearDepthStencilImage: every texel of the ranges written.
pub fn clear_image(image: Option<&ImageInfo>, ranges: &[vk::ImageSubresourceRange]) -> Moved {
    let Some(i) = image else { return Moved::default() };
    let mut written = 0;
    for range in ranges {
        let levels = if range.level_count == vk::REMAINING_MIP_LEVELS {
            i.mip_levels.saturating_sub(range.base_mip_level)
        } else {
            range.level_count
        };
        let layers = if range.layer_count == vk::REMAINING_ARRAY_LAYERS {
            i.array_layers.saturating_sub(range.base_array_layer)
        } else {
            range.layer_count
        };
        for level in range.base_mip_level..range.base_mip_level.saturating_add(levels) {
            written += i.region(range.aspect_mask, i.mip(level)) * layers as u64;
        }
    }
    Moved { read: 0, written, note: None }
}

/// vkCmdFillBuffer: `size` bytes written (VK_WHOLE_SIZE: to the end of the buffer, in whole
/// words, when the layer knows the buffer's size).
pub fn fill_buffer(buffer_size: Option<u64>, offset: u64, size: u64) -> Moved {
    let written =
        if size == vk::WHOLE_SIZE { buffer_size.map_or(0, |s| s.saturating_sub(offset) / 4 * 4) } else { size };
    Moved { read: 0, written, note: None }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(format: vk::Format, size: u32, samples: u32, swapchain: bool) -> ImageInfo {
        ImageInfo {
            format,
            extent: vk::Extent3D { width: size, height: size, depth: 1 },
            mip_levels: 3,
            array_layers: 1,
            samples,
            swapchain,
        }
    }

    fn layers(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceLayers {
        vk::ImageSubresourceLayers { aspect_mask: aspect, mip_level: 0, base_array_layer: 0, layer_count: 1 }
    }

    #[test]
    fn bytes_follow_the_regions_formats_and_samples() {
        let colour = image(vk::Format::R8G8B8A8_UNORM, 64, 1, false);
        let msaa = image(vk::Format::R8G8B8A8_UNORM, 64, 4, false);
        let swap = image(vk::Format::B8G8R8A8_UNORM, 64, 1, true);
        let extent = vk::Extent3D { width: 32, height: 16, depth: 1 };
        let c = layers(vk::ImageAspectFlags::COLOR);
        let copy = vk::ImageCopy { src_subresource: c, dst_subresource: c, extent, ..Default::default() };
        assert_eq!(copy_image(Some(&colour), Some(&colour), &[copy]), Moved { read: 2048, written: 2048, note: None });
        let resolve = vk::ImageResolve { src_subresource: c, dst_subresource: c, extent, ..Default::default() };
        let moved = resolve_image(Some(&msaa), Some(&colour), &[resolve]);
        assert_eq!((moved.read, moved.written), (8192, 2048));
        let blit = vk::ImageBlit {
            src_subresource: c,
            src_offsets: [vk::Offset3D::default(), vk::Offset3D { x: 32, y: 32, z: 1 }],
            dst_subresource: c,
            dst_offsets: [vk::Offset3D::default(), vk::Offset3D { x: 64, y: 64, z: 1 }],
        };
        let moved = blit_image(Some(&colour), Some(&swap), &[blit]);
        assert_eq!((moved.read, moved.written), (4096, 16384));
        assert!(moved.note.is_some_and(|n| n.contains("full-frame blit into a swapchain image (64x64)")));
        let all = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: vk::REMAINING_MIP_LEVELS,
            base_array_layer: 0,
            layer_count: 1,
        };
        // Mips 64, 32 and 16 square.
        assert_eq!(clear_image(Some(&colour), &[all]).written, 4 * (64 * 64 + 32 * 32 + 16 * 16));
        let depth = image(vk::Format::D24_UNORM_S8_UINT, 8, 1, false);
        let both = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL,
            level_count: 1,
            ..all
        };
        assert_eq!(clear_image(Some(&depth), &[both]).written, 4 * 64);
        assert_eq!(fill_buffer(Some(103), 2, vk::WHOLE_SIZE).written, 100);
        // Compressed: whole blocks (a 30x30 region is 8x8 blocks of BC1's 4x4, 3x3 of ASTC 12x12);
        // a 2-plane 4:2:0 image's chroma plane holds two bytes a texel.
        let region = |format, aspect, w, h| {
            let image = image(format, 64, 1, false);
            let subresource = vk::ImageSubresourceLayers { aspect_mask: aspect, ..layers(aspect) };
            let copy = vk::BufferImageCopy {
                image_subresource: subresource,
                image_extent: vk::Extent3D { width: w, height: h, depth: 1 },
                ..Default::default()
            };
            buffer_image(Some(&image), &[copy], true).written
        };
        let colour = vk::ImageAspectFlags::COLOR;
        assert_eq!(region(vk::Format::BC1_RGB_UNORM_BLOCK, colour, 30, 30), 8 * 8 * 8);
        assert_eq!(region(vk::Format::BC7_UNORM_BLOCK, colour, 30, 30), 8 * 8 * 16);
        assert_eq!(region(vk::Format::ETC2_R8G8B8A8_SRGB_BLOCK, colour, 8, 8), 4 * 16);
        assert_eq!(region(vk::Format::EAC_R11_UNORM_BLOCK, colour, 8, 8), 4 * 8);
        assert_eq!(region(vk::Format::ASTC_12X12_SRGB_BLOCK, colour, 30, 30), 3 * 3 * 16);
        assert_eq!(region(vk::Format::ASTC_6X5_UNORM_BLOCK, colour, 12, 10), 2 * 2 * 16);
        assert_eq!(region(vk::Format::ASTC_8X8_SFLOAT_BLOCK, colour, 16, 16), 4 * 16);
        let nv12 = vk::Format::G8_B8R8_2PLANE_420_UNORM;
        assert_eq!(region(nv12, vk::ImageAspectFlags::PLANE_0, 64, 64), 64 * 64);
        assert_eq!(region(nv12, vk::ImageAspectFlags::PLANE_1, 32, 32), 32 * 32 * 2);
        assert_eq!(region(vk::Format::R32G32B32_SFLOAT, colour, 2, 2), 48);
        assert_eq!(copy_buffer(&[vk::BufferCopy { size: 12, ..Default::default() }]).read, 12);
        assert_eq!(copy_image(None, None, &[copy]), Moved::default(), "unknown images move nothing known");
    }
}
