//! The rectangles and image regions a whole-image pass or copy uses, written once.

use ash::vk;

/// Mip 0, layer 0 of a colour image.
pub const COLOUR_LAYER: vk::ImageSubresourceLayers = vk::ImageSubresourceLayers {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    mip_level: 0,
    base_array_layer: 0,
    layer_count: 1,
};

/// Mip 0, layer 0 of a colour image, as a view or barrier range.
pub const COLOUR_RANGE: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

/// A viewport covering `extent`, depth 0 to 1.
pub fn full_viewport(extent: vk::Extent2D) -> vk::Viewport {
    vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    }
}

/// A tightly packed copy of a whole `extent` colour image (mip 0, layer 0) to a buffer.
pub fn colour_to_buffer(extent: vk::Extent2D) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default().image_subresource(COLOUR_LAYER).image_extent(vk::Extent3D {
        width: extent.width,
        height: extent.height,
        depth: 1,
    })
}
