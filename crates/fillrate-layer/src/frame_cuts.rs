//! Where frames end when a present does not end them: VK_EXT_frame_boundary's
//! `VkFrameBoundaryEXT` with `FRAME_END` in a submission's or present's chain (once a program
//! has used one, only its boundaries cut frames), or else the configured `FrameOn`: every
//! submit call, or every host wait.

use ash::vk;

use super::config::FrameOn;
use super::readback::write_if_due;
use super::state::{DeviceData, DeviceState};

/// Whether a pNext chain holds a VkFrameBoundaryEXT that ends a frame.
///
/// # Safety
/// `p_next` is a valid pNext chain.
pub unsafe fn frame_end(mut p_next: *const std::ffi::c_void) -> bool {
    while !p_next.is_null() {
        let base = p_next as *const vk::BaseInStructure;
        // SAFETY: every chain node starts like VkBaseInStructure.
        let (ty, next) = unsafe { ((*base).s_type, (*base).p_next.cast()) };
        if ty == vk::StructureType::FRAME_BOUNDARY_EXT {
            // SAFETY: a node of this sType is a VkFrameBoundaryEXT.
            let flags = unsafe { (*(p_next as *const vk::FrameBoundaryEXT<'_>)).flags };
            if flags.contains(vk::FrameBoundaryFlagsEXT::FRAME_END) {
                return true;
            }
        }
        p_next = next;
    }
    false
}

/// Ends the current frame (if anything was submitted to it) and finishes what is read back.
pub fn cut(device: &DeviceData, state: &mut DeviceState) {
    state.frames().cut();
    if super::readback::finish_frames(device, state) > 0 {
        write_if_due(device, state, false);
    }
}

/// A frame boundary was seen: from now on only boundaries cut frames.
pub fn boundary(device: &DeviceData, state: &mut DeviceState) {
    state.boundaries = true;
    cut(device, state);
}

/// Whether `event` ends a frame under the configuration (and no frame boundary was seen).
pub fn cuts_on(device: &DeviceData, state: &DeviceState, event: FrameOn) -> bool {
    !state.boundaries && device.config.frame_on == event
}
