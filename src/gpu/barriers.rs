//! Every pipeline barrier the project records, one named function per transition, so that the
//! synchronisation of a use (feedback, read-back, upload, mips, presentation) is read in one
//! place. Each records into a command buffer in the recording state, outside a render pass
//! unless it says otherwise.

use std::ops::Range;

use ash::vk;

/// Colour aspect, layer 0, the given mips.
fn colour_mips(mips: Range<u32>) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: mips.start,
        level_count: mips.end - mips.start,
        base_array_layer: 0,
        layer_count: 1,
    }
}

fn image_barrier(
    image: vk::Image,
    mips: Range<u32>,
    (from, to): (vk::ImageLayout, vk::ImageLayout),
    (src_access, dst_access): (vk::AccessFlags, vk::AccessFlags),
) -> vk::ImageMemoryBarrier<'static> {
    vk::ImageMemoryBarrier::default()
        .src_access_mask(src_access)
        .dst_access_mask(dst_access)
        .old_layout(from)
        .new_layout(to)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(colour_mips(mips))
}

fn record_image_barriers(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (src_stages, dst_stages): (vk::PipelineStageFlags, vk::PipelineStageFlags),
    flags: vk::DependencyFlags,
    barriers: &[vk::ImageMemoryBarrier],
) {
    // SAFETY: `cmd` was allocated from `device` and is recording (callers record inside
    // `submit_and_wait`'s closure or between the viewer's begin and end); the images named are
    // alive, and their owners outlive the submission (they wait on its fence before dropping).
    unsafe { device.cmd_pipeline_barrier(cmd, src_stages, dst_stages, flags, &[], &[], barriers) };
}

// ---------------------------------------------------------------------------------------------
// Inside the frame's render pass.

/// Makes earlier colour writes of this subpass visible to input-attachment reads of the
/// following draws: the render pass's by-region self-dependency (the colour target is both
/// colour and input attachment, in GENERAL). Each fragment reads only its own pixel, so on a
/// tiler this stays in tile memory. Recorded inside the render pass.
pub fn colour_feedback(device: &ash::Device, cmd: vk::CommandBuffer, colour_image: vk::Image) {
    let barrier = image_barrier(
        colour_image,
        0..1,
        (vk::ImageLayout::GENERAL, vk::ImageLayout::GENERAL),
        (vk::AccessFlags::COLOR_ATTACHMENT_WRITE, vk::AccessFlags::INPUT_ATTACHMENT_READ),
    );
    record_image_barriers(
        device,
        cmd,
        (vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT, vk::PipelineStageFlags::FRAGMENT_SHADER),
        vk::DependencyFlags::BY_REGION,
        &[barrier],
    );
}

// ---------------------------------------------------------------------------------------------
// Read-back to the CPU.

/// Makes what fragment shaders stored in buffers (a counter they add to) visible to the host
/// once the submission's fence has signalled.
pub fn fragment_stores_to_host(device: &ash::Device, cmd: vk::CommandBuffer) {
    let to_host = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ);
    // SAFETY: `cmd` is recording outside any render pass; a global barrier names no resource.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::FRAGMENT_SHADER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &[to_host],
            &[],
            &[],
        )
    };
}

/// Makes a transfer's writes to `buffer` visible to the host (before mapping it after the fence).
pub fn transfer_to_host(device: &ash::Device, cmd: vk::CommandBuffer, buffer: vk::Buffer) {
    let to_host = vk::BufferMemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .buffer(buffer)
        .size(vk::WHOLE_SIZE);
    // SAFETY: as in `record_image_barriers`; the buffer outlives the submission (its owner maps
    // it only after the fence).
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &[],
            &[to_host],
            &[],
        )
    };
}

// ---------------------------------------------------------------------------------------------
// Textures: uploads, mip chains and read-backs. Textures are sampled by fragment shaders only
// (no vertex shader samples), so "sampled" means the fragment-shader stage. Each transition
// names its exact stages and accesses: the best-practices checks flag ALL_COMMANDS and
// MEMORY_READ/WRITE, and synchronisation validation checks that these scopes are enough.

/// A layout transition of `mips` of a colour image between the given stage and access scopes.
fn colour_transition(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (image, mips): (vk::Image, Range<u32>),
    layouts: (vk::ImageLayout, vk::ImageLayout),
    stages: (vk::PipelineStageFlags, vk::PipelineStageFlags),
    accesses: (vk::AccessFlags, vk::AccessFlags),
) {
    let barrier = image_barrier(image, mips, layouts, accesses);
    record_image_barriers(device, cmd, stages, vk::DependencyFlags::empty(), &[barrier]);
}

/// `mips` whose old contents do not matter become copy and blit destinations. They may have
/// been sampled or blitted to earlier in the same command buffer (a bake rebuilt in one frame):
/// the transition waits for both, and makes earlier blit writes available (write after write).
pub fn upload_destination(device: &ash::Device, cmd: vk::CommandBuffer, image: vk::Image, mips: Range<u32>) {
    colour_transition(
        device,
        cmd,
        (image, mips),
        (vk::ImageLayout::UNDEFINED, vk::ImageLayout::TRANSFER_DST_OPTIMAL),
        (vk::PipelineStageFlags::FRAGMENT_SHADER | vk::PipelineStageFlags::TRANSFER, vk::PipelineStageFlags::TRANSFER),
        (vk::AccessFlags::TRANSFER_WRITE, vk::AccessFlags::TRANSFER_WRITE),
    );
}

/// A mip just written by a copy or blit becomes the source of the blit to the next mip.
pub fn mip_to_blit_source(device: &ash::Device, cmd: vk::CommandBuffer, image: vk::Image, mip: u32) {
    colour_transition(
        device,
        cmd,
        (image, mip..mip + 1),
        (vk::ImageLayout::TRANSFER_DST_OPTIMAL, vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
        (vk::PipelineStageFlags::TRANSFER, vk::PipelineStageFlags::TRANSFER),
        (vk::AccessFlags::TRANSFER_WRITE, vk::AccessFlags::TRANSFER_READ),
    );
}

/// A mip last written by a copy or blit (the last mip of a chain) is sampled.
pub fn written_mip_to_sampled(device: &ash::Device, cmd: vk::CommandBuffer, image: vk::Image, mips: Range<u32>) {
    colour_transition(
        device,
        cmd,
        (image, mips),
        (vk::ImageLayout::TRANSFER_DST_OPTIMAL, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL),
        (vk::PipelineStageFlags::TRANSFER, vk::PipelineStageFlags::FRAGMENT_SHADER),
        (vk::AccessFlags::TRANSFER_WRITE, vk::AccessFlags::SHADER_READ),
    );
}

/// A sampled mip becomes the source of a copy to a read-back buffer (a read after reads: the
/// transition only waits for the sampling to finish).
pub fn sampled_to_read_back(device: &ash::Device, cmd: vk::CommandBuffer, image: vk::Image, mip: u32) {
    colour_transition(
        device,
        cmd,
        (image, mip..mip + 1),
        (vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL, vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
        (vk::PipelineStageFlags::FRAGMENT_SHADER, vk::PipelineStageFlags::TRANSFER),
        (vk::AccessFlags::empty(), vk::AccessFlags::TRANSFER_READ),
    );
}

/// A mip read back (or blitted from) is sampled again; its contents did not change, so the
/// transition only waits for the transfer's reads.
pub fn read_back_to_sampled(device: &ash::Device, cmd: vk::CommandBuffer, image: vk::Image, mip: u32) {
    colour_transition(
        device,
        cmd,
        (image, mip..mip + 1),
        (vk::ImageLayout::TRANSFER_SRC_OPTIMAL, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL),
        (vk::PipelineStageFlags::TRANSFER, vk::PipelineStageFlags::FRAGMENT_SHADER),
        (vk::AccessFlags::empty(), vk::AccessFlags::SHADER_READ),
    );
}

// ---------------------------------------------------------------------------------------------
// Presentation (the viewer copies the offscreen frame into a swapchain image).

/// Before the copy of a frame into a swapchain image: the frame's colour target (left in
/// TRANSFER_SRC_OPTIMAL by the frame's render pass, whose external dependency already makes its
/// colour writes visible to transfer reads) is only waited on, and the acquired image, whose old
/// contents do not matter, becomes the copy's destination.
pub fn frame_to_swapchain_copy(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    frame_colour: vk::Image,
    swapchain_image: vk::Image,
) {
    let barriers = [
        image_barrier(
            frame_colour,
            0..1,
            (vk::ImageLayout::TRANSFER_SRC_OPTIMAL, vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
            (vk::AccessFlags::empty(), vk::AccessFlags::TRANSFER_READ),
        ),
        image_barrier(
            swapchain_image,
            0..1,
            (vk::ImageLayout::UNDEFINED, vk::ImageLayout::TRANSFER_DST_OPTIMAL),
            (vk::AccessFlags::empty(), vk::AccessFlags::TRANSFER_WRITE),
        ),
    ];
    record_image_barriers(
        device,
        cmd,
        (
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::TRANSFER,
        ),
        vk::DependencyFlags::empty(),
        &barriers,
    );
}

/// How the frame got into a swapchain image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SwapchainFrame {
    /// Copied in (TRANSFER_DST_OPTIMAL, transfer writes to make available).
    Copied,
    /// Drawn (or resolved) into by the frame's render pass, which left it in PRESENT_SRC_KHR
    /// and made its writes visible to transfers (its dependency to TRANSFER; this chains).
    Drawn,
}

/// The swapchain image holding the frame becomes the source of a screenshot read-back.
pub fn swapchain_to_read_back(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    swapchain_image: vk::Image,
    frame: SwapchainFrame,
) {
    let (from, src_access) = match frame {
        SwapchainFrame::Copied => (vk::ImageLayout::TRANSFER_DST_OPTIMAL, vk::AccessFlags::TRANSFER_WRITE),
        SwapchainFrame::Drawn => (vk::ImageLayout::PRESENT_SRC_KHR, vk::AccessFlags::empty()),
    };
    let barrier = image_barrier(
        swapchain_image,
        0..1,
        (from, vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
        (src_access, vk::AccessFlags::TRANSFER_READ),
    );
    record_image_barriers(
        device,
        cmd,
        (vk::PipelineStageFlags::TRANSFER, vk::PipelineStageFlags::TRANSFER),
        vk::DependencyFlags::empty(),
        &[barrier],
    );
}

/// What a swapchain image last went through before it is presented.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BeforePresent {
    /// The frame was copied into it (TRANSFER_DST_OPTIMAL, writes to make available).
    Copied,
    /// It was then read back for a screenshot (TRANSFER_SRC_OPTIMAL, reads only).
    ReadBack,
}

/// The swapchain image becomes presentable. Presentation waits on the semaphore the submission
/// signals, which orders it after this command buffer, so no destination access is needed.
pub fn swapchain_to_present(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    swapchain_image: vk::Image,
    before: BeforePresent,
) {
    let (from, src_access) = match before {
        BeforePresent::Copied => (vk::ImageLayout::TRANSFER_DST_OPTIMAL, vk::AccessFlags::TRANSFER_WRITE),
        BeforePresent::ReadBack => (vk::ImageLayout::TRANSFER_SRC_OPTIMAL, vk::AccessFlags::empty()),
    };
    let barrier = image_barrier(
        swapchain_image,
        0..1,
        (from, vk::ImageLayout::PRESENT_SRC_KHR),
        (src_access, vk::AccessFlags::empty()),
    );
    record_image_barriers(
        device,
        cmd,
        (vk::PipelineStageFlags::TRANSFER, vk::PipelineStageFlags::BOTTOM_OF_PIPE),
        vk::DependencyFlags::empty(),
        &[barrier],
    );
}
