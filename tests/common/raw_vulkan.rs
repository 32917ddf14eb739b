//! A Vulkan 1.3 instance made by hand, as a program nobody here wrote would make it: for the
//! tests that run a small program of their own under the fill-rate layer (the loader inserts the
//! layers named in `VK_INSTANCE_LAYERS`). Every warning and error message is kept in
//! [`MESSAGES`].

use std::ffi::{c_void, CStr};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use ash::vk;

/// Every warning and error the messenger received (validation below the layer included).
pub static MESSAGES: Mutex<Vec<String>> = Mutex::new(Vec::new());

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    _user: *mut c_void,
) -> vk::Bool32 {
    if severity
        .intersects(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
    {
        // SAFETY: the validation layer passes a valid callback data with a C string message.
        let text = unsafe { data.as_ref() }
            .filter(|d| !d.p_message.is_null())
            // SAFETY: as above.
            .map(|d| unsafe { CStr::from_ptr(d.p_message) }.to_string_lossy().into_owned())
            .unwrap_or_default();
        MESSAGES.lock().unwrap_or_else(|e| e.into_inner()).push(text);
    }
    vk::FALSE
}

/// The instance, its messenger, and the first device's graphics queue family.
pub struct RawInstance {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub debug: ash::ext::debug_utils::Instance,
    pub messenger: vk::DebugUtilsMessengerEXT,
    pub physical: vk::PhysicalDevice,
    pub family: u32,
}

/// Makes the instance named `name` with VK_EXT_debug_utils and a messenger for warnings and
/// errors (validation and general) kept in [`MESSAGES`].
///
/// # Safety
/// Plain Vulkan use: the caller destroys what it gets with [`RawInstance::destroy`], after every
/// object made from it.
pub unsafe fn raw_instance(name: &CStr) -> RawInstance {
    let entry = ash::Entry::load().expect("libvulkan");
    let app = vk::ApplicationInfo::default().application_name(name).api_version(vk::API_VERSION_1_3);
    let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
    let info = vk::InstanceCreateInfo::default().application_info(&app).enabled_extension_names(&extensions);
    let instance = entry.create_instance(&info, None).expect("instance");
    let debug = ash::ext::debug_utils::Instance::new(&entry, &instance);
    let messenger = debug
        .create_debug_utils_messenger(
            &vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
                )
                .pfn_user_callback(Some(on_message)),
            None,
        )
        .expect("messenger");
    let physical = instance.enumerate_physical_devices().expect("devices")[0];
    let family = instance
        .get_physical_device_queue_family_properties(physical)
        .iter()
        .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
        .expect("graphics queue") as u32;
    RawInstance { entry, instance, debug, messenger, physical, family }
}

impl RawInstance {
    /// Destroys the messenger, then the instance.
    ///
    /// # Safety
    /// Every object made from this instance is destroyed already.
    pub unsafe fn destroy(self) {
        self.debug.destroy_debug_utils_messenger(self.messenger, None);
        self.instance.destroy_instance(None);
    }
}

/// SPIR-V that the crate's build.rs compiled from one file of `shaders/`.
#[derive(Clone, Copy)]
pub struct Spirv(&'static [u8]);

/// The SPIR-V of `shaders/FILE`, taken when the test builds: a shader that does not exist fails
/// the build.
macro_rules! spirv_of {
    ($file:literal) => {
        Spirv(include_bytes!(concat!(env!("OUT_DIR"), "/", $file, ".spv")))
    };
}

pub const FULLSCREEN_VERT: Spirv = spirv_of!("fullscreen.vert");
pub const SHADOW_MAP_FRAG: Spirv = spirv_of!("shadow_map.frag");
pub const SOLID_FRAG: Spirv = spirv_of!("solid.frag");
pub const ADD_TO_WORDS_COMP: Spirv = spirv_of!("add_to_words.comp");
pub const RECT_VERT: Spirv = spirv_of!("rect.vert");

/// A shader module of `shader`.
///
/// # Safety
/// `device` is alive; the caller destroys the module.
pub unsafe fn shader(device: &ash::Device, shader: Spirv) -> vk::ShaderModule {
    let code = ash::util::read_spv(&mut std::io::Cursor::new(shader.0)).expect("SPIR-V");
    device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None).expect("module")
}

/// A pipeline drawing `fullscreen.vert` depth-only over a `size` x `size` viewport, every sample
/// passing (depth test ALWAYS, no depth write), for `render_pass` or (when null) dynamic
/// rendering into a `depth` attachment. Each draw of 3 vertices covers every pixel once.
///
/// # Safety
/// `device` is alive, with dynamic rendering enabled when `render_pass` is null.
pub unsafe fn depth_pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    render_pass: vk::RenderPass,
    size: u32,
    depth: vk::Format,
) -> vk::Pipeline {
    let depth_state = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(false)
        .depth_compare_op(vk::CompareOp::ALWAYS);
    fullscreen_pipeline(device, layout, render_pass, size, SHADOW_MAP_FRAG, Some((depth, depth_state)), &[])
}

/// `fullscreen.vert` + `fragment` over a `size`-square viewport, no culling, one sample:
/// `depth` (its format for dynamic rendering, and its test) when the pass has one, `blends` one
/// state per colour attachment. `render_pass` null: dynamic rendering.
///
/// # Safety
/// `device` is alive, with dynamic rendering enabled when `render_pass` is null.
pub unsafe fn fullscreen_pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    render_pass: vk::RenderPass,
    size: u32,
    fragment: Spirv,
    depth: Option<(vk::Format, vk::PipelineDepthStencilStateCreateInfo)>,
    blends: &[vk::PipelineColorBlendAttachmentState],
) -> vk::Pipeline {
    let target = Target { render_pass, size, depth, colour_formats: &[] };
    pipeline(device, layout, (FULLSCREEN_VERT, fragment), target, blends)
}

/// What a test pipeline draws into: `render_pass` (null: dynamic rendering of `colour_formats`
/// and `depth`'s format), a `size`-square viewport, `depth`'s test when it has one.
pub struct Target<'a> {
    pub render_pass: vk::RenderPass,
    pub size: u32,
    pub depth: Option<(vk::Format, vk::PipelineDepthStencilStateCreateInfo<'a>)>,
    pub colour_formats: &'a [vk::Format],
}

/// `vertex` + `fragment` (no vertex input, triangle lists, no culling, one sample) into
/// `target`, `blends` one state per colour attachment.
///
/// # Safety
/// `device` is alive, with dynamic rendering enabled when the target's render pass is null.
pub unsafe fn pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    (vertex, fragment): (Spirv, Spirv),
    target: Target<'_>,
    blends: &[vk::PipelineColorBlendAttachmentState],
) -> vk::Pipeline {
    let (vert, frag) = (shader(device, vertex), shader(device, fragment));
    let stages = [
        vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::VERTEX).module(vert).name(c"main"),
        vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::FRAGMENT).module(frag).name(c"main"),
    ];
    let size = target.size;
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewports =
        [vk::Viewport { x: 0.0, y: 0.0, width: size as f32, height: size as f32, min_depth: 0.0, max_depth: 1.0 }];
    let scissors = [vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: size, height: size } }];
    let viewport = vk::PipelineViewportStateCreateInfo::default().viewports(&viewports).scissors(&scissors);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .line_width(1.0);
    let multisample =
        vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(blends);
    let depth_format = target.depth.map_or(vk::Format::UNDEFINED, |(format, _)| format);
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .depth_attachment_format(depth_format)
        .color_attachment_formats(target.colour_formats);
    let mut info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .color_blend_state(&blend)
        .layout(layout)
        .render_pass(target.render_pass);
    if let Some((_, state)) = &target.depth {
        info = info.depth_stencil_state(state);
    }
    if target.render_pass == vk::RenderPass::null() {
        info = info.push_next(&mut rendering);
    }
    let pipeline = device
        .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        .map_err(|(_, e)| e)
        .expect("pipeline")[0];
    device.destroy_shader_module(vert, None);
    device.destroy_shader_module(frag, None);
    pipeline
}

/// The one mip and layer of a depth image.
pub const DEPTH_RANGE: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::DEPTH,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

/// A `size`-square depth image of `format` in device memory, and its view: the depth target
/// the layer tests' programs render into. Destroy the three in reverse order.
///
/// # Safety
/// `device` was created from `physical` of `instance`.
pub unsafe fn depth_target(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    device: &ash::Device,
    format: vk::Format,
    size: u32,
) -> (vk::Image, vk::DeviceMemory, vk::ImageView) {
    let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
    image_target((instance, physical, device), format, size, vk::SampleCountFlags::TYPE_1, usage, DEPTH_RANGE)
}

/// A `size`-square image of `format` with `samples` and `usage` in device memory, and its
/// view of `range`. Destroy the three in reverse order.
///
/// # Safety
/// `device` was created from `physical` of `instance`.
pub unsafe fn image_target(
    objects: (&ash::Instance, vk::PhysicalDevice, &ash::Device),
    format: vk::Format,
    size: u32,
    samples: vk::SampleCountFlags,
    usage: vk::ImageUsageFlags,
    range: vk::ImageSubresourceRange,
) -> (vk::Image, vk::DeviceMemory, vk::ImageView) {
    layered_target(objects, (format, size, range.layer_count.max(1)), samples, usage, range)
}

/// [`image_target`] with `layers` array layers (`range` covering them): its view a 2D array
/// when it has more than one.
///
/// # Safety
/// As [`image_target`].
pub unsafe fn layered_target(
    (instance, physical, device): (&ash::Instance, vk::PhysicalDevice, &ash::Device),
    (format, size, layers): (vk::Format, u32, u32),
    samples: vk::SampleCountFlags,
    usage: vk::ImageUsageFlags,
    range: vk::ImageSubresourceRange,
) -> (vk::Image, vk::DeviceMemory, vk::ImageView) {
    let image = device
        .create_image(
            &vk::ImageCreateInfo::default()
                .image_type(vk::ImageType::TYPE_2D)
                .format(format)
                .extent(vk::Extent3D { width: size, height: size, depth: 1 })
                .mip_levels(1)
                .array_layers(layers)
                .samples(samples)
                .usage(usage),
            None,
        )
        .expect("image");
    let requirements = device.get_image_memory_requirements(image);
    let props = instance.get_physical_device_memory_properties(physical);
    let memory_type = device_local_memory_type(&props, requirements.memory_type_bits);
    let memory = device
        .allocate_memory(
            &vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(memory_type),
            None,
        )
        .expect("memory");
    device.bind_image_memory(image, memory, 0).expect("bind");
    let view_type = if layers > 1 { vk::ImageViewType::TYPE_2D_ARRAY } else { vk::ImageViewType::TYPE_2D };
    let view = device
        .create_image_view(
            &vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(view_type)
                .format(format)
                .subresource_range(range),
            None,
        )
        .expect("view");
    (image, memory, view)
}

/// A `size`-square framebuffer of `pass` over the one attachment `view`.
///
/// # Safety
/// `device` is alive; `view` fits `pass`'s attachment.
pub unsafe fn framebuffer(
    device: &ash::Device,
    pass: vk::RenderPass,
    view: vk::ImageView,
    size: u32,
) -> vk::Framebuffer {
    let views = [view];
    let info =
        vk::FramebufferCreateInfo::default().render_pass(pass).attachments(&views).width(size).height(size).layers(1);
    device.create_framebuffer(&info, None).expect("framebuffer")
}

/// Puts the fill-rate layer built beside this test's `nostencil` binary, with the validation
/// layer below it, into every instance this process creates from now on, reporting to the
/// returned path in a scratch folder named after `test`. It sets the process environment:
/// only inside [`super::in_own_process`].
pub fn under_the_layer(test: &str) -> PathBuf {
    use nostencil_fillrate_report::manifest::{manifest_json, newest_library, LAYER_NAME, MANIFEST_FILE};
    let dir = super::scratch_dir(test);
    let program = super::program();
    let bin_dir = program.parent().expect("binary folder");
    let library = newest_library(bin_dir).expect("libnostencil_fillrate.so built");
    std::fs::write(dir.join(MANIFEST_FILE), manifest_json(library.to_str().expect("utf-8"))).expect("manifest");
    let out = dir.join("fillrate.json");
    std::env::set_var("VK_ADD_LAYER_PATH", &dir);
    std::env::set_var("VK_INSTANCE_LAYERS", format!("{LAYER_NAME}:VK_LAYER_KHRONOS_validation"));
    std::env::set_var("NOSTENCIL_FILLRATE_OUT", &out);
    std::env::remove_var("NOSTENCIL_FILLRATE_FRAMES");
    out
}

/// Fails the test on any message the validation layer below the program's layers raised (kept
/// in [`MESSAGES`] by the raw instance's messenger).
pub fn assert_no_messages() {
    let messages = MESSAGES.lock().unwrap_or_else(|e| e.into_inner()).clone();
    assert!(messages.is_empty(), "{} validation message(s):\n{}", messages.len(), messages.join("\n"));
}

/// The fill-rate layer's report at `out`, which it writes at vkDestroyDevice.
pub fn layer_report(out: &Path) -> nostencil_fillrate_report::report::FillrateReport {
    let text = std::fs::read_to_string(out).expect("the layer wrote its result at vkDestroyDevice");
    nostencil_fillrate_report::report::FillrateReport::from_json(&text).expect("a fill-rate report")
}

/// A vk_layer_settings.txt in `dir` that turns on the validation layer's synchronisation checks
/// (the messenger of the program under test reports what they find); returns its path.
#[allow(dead_code)] // each test crate uses its own part of `common`
pub fn synchronisation_settings(dir: &Path) -> PathBuf {
    let path = dir.join("vk_layer_settings.txt");
    let settings = "khronos_validation.enables = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT\n";
    std::fs::write(&path, settings).expect("vk_layer_settings.txt");
    path
}

/// A buffer of `size` bytes that copies write into (TRANSFER_DST), in host-visible, coherent
/// memory: where the layer tests' programs read their images back. Destroy the buffer, then
/// free the memory.
///
/// # Safety
/// `device` was created from `physical` of `instance`.
pub unsafe fn host_buffer(
    (instance, physical, device): (&ash::Instance, vk::PhysicalDevice, &ash::Device),
    size: u64,
) -> (vk::Buffer, vk::DeviceMemory) {
    let info = vk::BufferCreateInfo::default().size(size).usage(vk::BufferUsageFlags::TRANSFER_DST);
    let buffer = device.create_buffer(&info, None).expect("buffer");
    let requirements = device.get_buffer_memory_requirements(buffer);
    let props = instance.get_physical_device_memory_properties(physical);
    let host = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
    let memory_type = memory_type(&props, requirements.memory_type_bits, host).expect("host-visible memory");
    let allocate = vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(memory_type);
    let memory = device.allocate_memory(&allocate, None).expect("memory");
    device.bind_buffer_memory(buffer, memory, 0).expect("bind");
    (buffer, memory)
}

/// A device-local memory type among `bits`.
pub fn device_local_memory_type(props: &vk::PhysicalDeviceMemoryProperties, bits: u32) -> u32 {
    memory_type(props, bits, vk::MemoryPropertyFlags::DEVICE_LOCAL).expect("a device-local memory type")
}

/// The first memory type among `bits` with every property in `wanted`.
pub fn memory_type(
    props: &vk::PhysicalDeviceMemoryProperties,
    bits: u32,
    wanted: vk::MemoryPropertyFlags,
) -> Option<u32> {
    (0..props.memory_type_count)
        .find(|&i| bits & (1 << i) != 0 && props.memory_types[i as usize].property_flags.contains(wanted))
}
