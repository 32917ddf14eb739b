//! Command-buffer hooks for what happens inside a pass: draws (counted, and bracketed by the
//! layer's queries where they begin a segment or are counted one by one), debug labels (which
//! name the sections of the report) and the application's own queries (noted so that the
//! layer's never overlap them).

use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;
use ash::vk::Handle;

use super::commands::{around, record};
use super::slots::QueryKind;
use super::state::{guard, DeviceData, DeviceState};

/// A draw command on `cmd` that makes `draws` draws: counted, and the layer's commands recorded
/// around the application's draw, which `call` makes: segments begin right before the first
/// draw of a pass or subpass (see recording.rs); with per-draw counting each draw command is
/// bracketed. Every draw command Vulkan has comes through here (docs/fillrate-layer.md, "What is
/// measured"): a draw the layer did not see would begin no segment, and its pass would read 0.
fn draw(cmd: vk::CommandBuffer, draws: u64, call: impl FnOnce(&DeviceData)) {
    let Some(device) = guard(None, || super::state::device_of(cmd.as_raw())) else { return };
    let (before, after) = guard(None, || {
        if !device.active() {
            return None;
        }
        let mut st = device.state();
        let DeviceState { tiler, buffers, .. } = &mut *st;
        let data = buffers.get_mut(&cmd)?;
        if device.config.tiler {
            data.tiler.draw(tiler, vk::PipelineBindPoint::GRAPHICS);
        }
        Some(data.recording.draw(draws))
    })
    .unwrap_or_default();
    guard((), || record(&device, cmd, &before));
    call(&device);
    guard((), || record(&device, cmd, &after));
}

/// Notes something on `cmd`'s recording (labels, resets), then makes the application's call.
fn note(cmd: vk::CommandBuffer, f: impl FnOnce(&mut super::recording::Recording)) -> Option<Arc<DeviceData>> {
    let device = guard(None, || super::state::device_of(cmd.as_raw()))?;
    guard((), || {
        if device.active() {
            if let Some(data) = device.state().buffers.get_mut(&cmd) {
                f(&mut data.recording);
            }
        }
    });
    Some(device)
}

pub(super) unsafe extern "system" fn cmd_draw(
    cmd: vk::CommandBuffer,
    vertices: u32,
    instances: u32,
    first_vertex: u32,
    first_instance: u32,
) {
    draw(cmd, 1, |d| {
        if let Some(next) = d.next.cmd_draw {
            // SAFETY: the application's arguments, passed on.
            unsafe { next(cmd, vertices, instances, first_vertex, first_instance) }
        }
    });
}

pub(super) unsafe extern "system" fn cmd_draw_indexed(
    cmd: vk::CommandBuffer,
    indices: u32,
    instances: u32,
    first_index: u32,
    vertex_offset: i32,
    first_instance: u32,
) {
    draw(cmd, 1, |d| {
        if let Some(next) = d.next.cmd_draw_indexed {
            // SAFETY: the application's arguments, passed on.
            unsafe { next(cmd, indices, instances, first_index, vertex_offset, first_instance) }
        }
    });
}

/// The indirect draws, whose arguments a buffer holds: one hook for each name of the same
/// signature (the mesh-task forms included). `count` draws, each with the buffer's arguments.
macro_rules! draw_indirect_hook {
    ($($name:ident),+) => {$(
        pub(super) unsafe extern "system" fn $name(
            cmd: vk::CommandBuffer,
            buffer: vk::Buffer,
            offset: vk::DeviceSize,
            count: u32,
            stride: u32,
        ) {
            draw(cmd, count.into(), |d| {
                if let Some(next) = d.next.$name {
                    // SAFETY: the application's arguments, passed on.
                    unsafe { next(cmd, buffer, offset, count, stride) }
                }
            });
        }
    )+};
}

draw_indirect_hook!(
    cmd_draw_indirect,
    cmd_draw_indexed_indirect,
    cmd_draw_mesh_tasks_indirect_ext,
    cmd_draw_mesh_tasks_indirect_nv
);

/// The indirect-count draws: the number of draws is in a GPU buffer, read only when the GPU
/// runs them, so each command counts as one draw (docs/fillrate-layer.md says so); the
/// fragments and samples are the GPU's own.
macro_rules! draw_count_hook {
    ($name:ident, $field:ident, $pfn:ident) => {
        pub(super) unsafe extern "system" fn $name(
            cmd: vk::CommandBuffer,
            buffer: vk::Buffer,
            offset: vk::DeviceSize,
            count_buffer: vk::Buffer,
            count_offset: vk::DeviceSize,
            max_count: u32,
            stride: u32,
        ) {
            draw(cmd, 1, |d| {
                let next: Option<vk::$pfn> = d.next.$field;
                if let Some(next) = next {
                    // SAFETY: the application's arguments, passed on.
                    unsafe { next(cmd, buffer, offset, count_buffer, count_offset, max_count, stride) }
                }
            });
        }
    };
}

draw_count_hook!(cmd_draw_indirect_count, cmd_draw_indirect_count, PFN_vkCmdDrawIndirectCount);
draw_count_hook!(cmd_draw_indirect_count_khr, cmd_draw_indirect_count_khr, PFN_vkCmdDrawIndirectCount);
draw_count_hook!(cmd_draw_indexed_indirect_count, cmd_draw_indexed_indirect_count, PFN_vkCmdDrawIndexedIndirectCount);
draw_count_hook!(
    cmd_draw_indexed_indirect_count_khr,
    cmd_draw_indexed_indirect_count_khr,
    PFN_vkCmdDrawIndexedIndirectCount
);

draw_count_hook!(
    cmd_draw_mesh_tasks_indirect_count_ext,
    cmd_draw_mesh_tasks_indirect_count_ext,
    PFN_vkCmdDrawMeshTasksIndirectCountEXT
);
draw_count_hook!(
    cmd_draw_mesh_tasks_indirect_count_nv,
    cmd_draw_mesh_tasks_indirect_count_nv,
    PFN_vkCmdDrawMeshTasksIndirectCountNV
);

/// VK_EXT_multi_draw: `count` draws in one command (zink draws every GL draw through it where
/// the device offers it).
pub(super) unsafe extern "system" fn cmd_draw_multi_ext(
    cmd: vk::CommandBuffer,
    count: u32,
    vertex_info: *const vk::MultiDrawInfoEXT,
    instances: u32,
    first_instance: u32,
    stride: u32,
) {
    draw(cmd, count.into(), |d| {
        if let Some(next) = d.next.cmd_draw_multi_ext {
            // SAFETY: the application's arguments, passed on.
            unsafe { next(cmd, count, vertex_info, instances, first_instance, stride) }
        }
    });
}

pub(super) unsafe extern "system" fn cmd_draw_multi_indexed_ext(
    cmd: vk::CommandBuffer,
    count: u32,
    index_info: *const vk::MultiDrawIndexedInfoEXT,
    instances: u32,
    first_instance: u32,
    stride: u32,
    vertex_offset: *const i32,
) {
    draw(cmd, count.into(), |d| {
        if let Some(next) = d.next.cmd_draw_multi_indexed_ext {
            // SAFETY: the application's arguments, passed on.
            unsafe { next(cmd, count, index_info, instances, first_instance, stride, vertex_offset) }
        }
    });
}

/// VK_EXT_transform_feedback's draw of as many vertices as a transform feedback wrote.
pub(super) unsafe extern "system" fn cmd_draw_indirect_byte_count_ext(
    cmd: vk::CommandBuffer,
    instances: u32,
    first_instance: u32,
    counter_buffer: vk::Buffer,
    counter_offset: vk::DeviceSize,
    counter_bias: u32,
    vertex_stride: u32,
) {
    draw(cmd, 1, |d| {
        if let Some(next) = d.next.cmd_draw_indirect_byte_count_ext {
            // SAFETY: the application's arguments, passed on.
            unsafe { next(cmd, instances, first_instance, counter_buffer, counter_offset, counter_bias, vertex_stride) }
        }
    });
}

/// VK_EXT_mesh_shader's and VK_NV_mesh_shader's direct draws.
pub(super) unsafe extern "system" fn cmd_draw_mesh_tasks_ext(cmd: vk::CommandBuffer, x: u32, y: u32, z: u32) {
    draw(cmd, 1, |d| {
        if let Some(next) = d.next.cmd_draw_mesh_tasks_ext {
            // SAFETY: the application's arguments, passed on.
            unsafe { next(cmd, x, y, z) }
        }
    });
}

pub(super) unsafe extern "system" fn cmd_draw_mesh_tasks_nv(cmd: vk::CommandBuffer, tasks: u32, first_task: u32) {
    draw(cmd, 1, |d| {
        if let Some(next) = d.next.cmd_draw_mesh_tasks_nv {
            // SAFETY: the application's arguments, passed on.
            unsafe { next(cmd, tasks, first_task) }
        }
    });
}

/// # Safety
/// `label` is null or a valid VkDebugUtilsLabelEXT.
unsafe fn label_name(label: *const vk::DebugUtilsLabelEXT<'_>) -> Option<String> {
    // SAFETY: the caller's contract; the name is a NUL-terminated string or null.
    let label = unsafe { label.as_ref() }?;
    if label.p_label_name.is_null() {
        return None;
    }
    // SAFETY: as above.
    Some(unsafe { CStr::from_ptr(label.p_label_name) }.to_string_lossy().into_owned())
}

pub(super) unsafe extern "system" fn cmd_begin_debug_utils_label(
    cmd: vk::CommandBuffer,
    label: *const vk::DebugUtilsLabelEXT<'_>,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_begin_debug_utils_label {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, label) }
            }
        },
        |_, st| {
            // SAFETY: the application's label.
            let name = unsafe { label_name(label) };
            let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
            data.recording.push_label(name.unwrap_or_default())
        },
    );
}

/// Ending a label inside a render pass ends its section: the layer's commands go before the
/// application's call (they close the section) and after it (the next section's timestamp).
pub(super) unsafe extern "system" fn cmd_end_debug_utils_label(cmd: vk::CommandBuffer) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_end_debug_utils_label {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd) }
            }
        },
        |_, st| {
            let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
            data.recording.pop_label()
        },
    );
}

pub(super) unsafe extern "system" fn cmd_insert_debug_utils_label(
    cmd: vk::CommandBuffer,
    label: *const vk::DebugUtilsLabelEXT<'_>,
) {
    // SAFETY: the application's label.
    let name = guard(None, || unsafe { label_name(label) });
    if let Some(next) =
        note(cmd, |r| r.insert_label(name.unwrap_or_default())).and_then(|d| d.next.cmd_insert_debug_utils_label)
    {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, label) }
    }
}

pub(super) unsafe extern "system" fn cmd_reset_query_pool(
    cmd: vk::CommandBuffer,
    pool: vk::QueryPool,
    first: u32,
    count: u32,
) {
    if let Some(next) = note(cmd, |r| r.app_resets.push((pool, first, count))).and_then(|d| d.next.cmd_reset_query_pool)
    {
        // SAFETY: the application's arguments, passed on.
        unsafe { next(cmd, pool, first, count) }
    }
}

fn app_kind(st: &DeviceState, pool: vk::QueryPool) -> Option<(QueryKind, vk::QueryPipelineStatisticFlags)> {
    match st.app_pools.get(&pool)? {
        (vk::QueryType::OCCLUSION, _) => Some((QueryKind::Occlusion, vk::QueryPipelineStatisticFlags::empty())),
        (vk::QueryType::PIPELINE_STATISTICS, stats) => Some((QueryKind::Statistics, *stats)),
        _ => None,
    }
}

pub(super) unsafe extern "system" fn cmd_begin_query(
    cmd: vk::CommandBuffer,
    pool: vk::QueryPool,
    query: u32,
    flags: vk::QueryControlFlags,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_begin_query {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, pool, query, flags) }
            }
        },
        |_, st| {
            let Some((kind, stats)) = app_kind(st, pool) else { return Default::default() };
            let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
            let precise = flags.contains(vk::QueryControlFlags::PRECISE);
            (data.recording.app_begin_query(kind, pool, query, precise, stats), Vec::new())
        },
    );
}

/// VK_EXT_transform_feedback's indexed begin: an occlusion or statistics query begun through it
/// (index 0) is the application's query like any other, so the layer's never overlap it.
pub(super) unsafe extern "system" fn cmd_begin_query_indexed_ext(
    cmd: vk::CommandBuffer,
    pool: vk::QueryPool,
    query: u32,
    flags: vk::QueryControlFlags,
    index: u32,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_begin_query_indexed_ext {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, pool, query, flags, index) }
            }
        },
        |_, st| {
            let Some((kind, stats)) = app_kind(st, pool) else { return Default::default() };
            let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
            let precise = flags.contains(vk::QueryControlFlags::PRECISE);
            (data.recording.app_begin_query(kind, pool, query, precise, stats), Vec::new())
        },
    );
}

pub(super) unsafe extern "system" fn cmd_end_query_indexed_ext(
    cmd: vk::CommandBuffer,
    pool: vk::QueryPool,
    query: u32,
    index: u32,
) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_end_query_indexed_ext {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, pool, query, index) }
            }
        },
        |_, st| {
            let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
            (Vec::new(), data.recording.app_end_query(pool, query))
        },
    );
}

pub(super) unsafe extern "system" fn cmd_end_query(cmd: vk::CommandBuffer, pool: vk::QueryPool, query: u32) {
    around(
        cmd,
        |d| {
            if let Some(next) = d.next.cmd_end_query {
                // SAFETY: the application's arguments, passed on.
                unsafe { next(cmd, pool, query) }
            }
        },
        |_, st| {
            let Some(data) = st.buffers.get_mut(&cmd) else { return Default::default() };
            (Vec::new(), data.recording.app_end_query(pool, query))
        },
    );
}
