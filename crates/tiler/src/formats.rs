//! What the formats the project meets are made of: bytes per texel and aspect, and the byte
//! order of 8-bit colour.

use ash::vk;

/// Whether `format` has a stencil aspect.
pub fn format_has_stencil(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::S8_UINT
            | vk::Format::D16_UNORM_S8_UINT
            | vk::Format::D24_UNORM_S8_UINT
            | vk::Format::D32_SFLOAT_S8_UINT
    )
}

/// (colour-or-depth bytes, stencil bytes) per texel; 4 bytes for a format not listed.
pub fn texel_bytes(format: vk::Format) -> (u64, u64) {
    match format {
        vk::Format::R8_UNORM
        | vk::Format::R8_SNORM
        | vk::Format::R8_UINT
        | vk::Format::R8_SINT
        | vk::Format::R8_SRGB => (1, 0),
        vk::Format::R8G8_UNORM
        | vk::Format::R8G8_UINT
        | vk::Format::R16_UNORM
        | vk::Format::R16_SFLOAT
        | vk::Format::R16_UINT
        | vk::Format::R5G6B5_UNORM_PACK16
        | vk::Format::D16_UNORM => (2, 0),
        vk::Format::R16G16B16A16_SFLOAT
        | vk::Format::R16G16B16A16_UNORM
        | vk::Format::R16G16B16A16_UINT
        | vk::Format::R32G32_SFLOAT
        | vk::Format::R32G32_UINT => (8, 0),
        vk::Format::R32G32B32A32_SFLOAT | vk::Format::R32G32B32A32_UINT => (16, 0),
        vk::Format::D16_UNORM_S8_UINT => (2, 1),
        vk::Format::D24_UNORM_S8_UINT => (3, 1),
        vk::Format::D32_SFLOAT_S8_UINT => (4, 1),
        vk::Format::S8_UINT => (0, 1),
        _ => (4, 0),
    }
}

/// The order of the four 8-bit channels in memory, for the RGBA8-family formats.
pub fn byte_order(format: vk::Format) -> Option<&'static str> {
    match format {
        vk::Format::R8G8B8A8_UNORM
        | vk::Format::R8G8B8A8_SRGB
        | vk::Format::A8B8G8R8_UNORM_PACK32
        | vk::Format::A8B8G8R8_SRGB_PACK32 => Some("RGBA"),
        vk::Format::B8G8R8A8_UNORM | vk::Format::B8G8R8A8_SRGB => Some("BGRA"),
        _ => None,
    }
}
