//! A descriptor set beyond the base's two (set 0 the frame's uniforms, set 1 a material), bound
//! at set 2, with the pipeline layout that has it: what a sample's textures (a ramp, a shadow
//! map, an atlas page) are read through. Destroyed with itself.

use std::any::Any;
use std::sync::Arc;

use ash::vk;

use super::{SampleBase, PUSH_BYTES};
use crate::error::{Result, VkContext};
use crate::gpu::Gpu;

/// Set 2 and the layout `[frame, material, set 2]` with the base's push constants: a pipeline
/// made with [`SampleBase::pipeline_in`]`(extra.layout, ..)` reads it; sets 0 and 1 bound with the
/// base's layout stay bound (the two layouts agree on them and on the push constants).
pub struct ExtraSet {
    pub layout: vk::PipelineLayout,
    set: vk::DescriptorSet,
    /// The set's owner and what its bindings point at (textures, samplers, images), alive as
    /// long as it is.
    _owner: Box<dyn Any>,
    gpu: Arc<Gpu>,
}

impl SampleBase {
    /// Set 2 as `set` (of layout `set_layout`), which `owner` keeps alive.
    pub(crate) fn extra_set_of(
        &self,
        set_layout: vk::DescriptorSetLayout,
        set: vk::DescriptorSet,
        owner: Box<dyn Any>,
    ) -> Result<ExtraSet> {
        let set_layouts = [self.frame.layout, self.gpu_scene.materials.layout(), set_layout];
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
            .size(PUSH_BYTES)];
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts).push_constant_ranges(&push);
        // SAFETY: the device is alive; the three set layouts are (their owners outlive the call).
        let layout = unsafe { self.device().create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
        Ok(ExtraSet { layout, set, _owner: owner, gpu: self.gpu.clone() })
    }
}

impl ExtraSet {
    /// Binds the set at set 2 for the pipelines made with its layout.
    pub fn bind(&self, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is recording; the set and the layout are alive while `self` is.
        unsafe {
            self.gpu.raw().cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout,
                2,
                &[self.set],
                &[],
            )
        };
    }
}

impl Drop for ExtraSet {
    fn drop(&mut self) {
        // SAFETY: the sample's submissions were waited for (`SampleBase::render` waits); the
        // layout is destroyed once. The set and what it points at are dropped after.
        unsafe { self.gpu.raw().destroy_pipeline_layout(self.layout, None) };
    }
}
