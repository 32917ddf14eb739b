//! One descriptor set with its own layout and pool: what every technique needs for a handful of
//! bindings (a uniform buffer, a texture, an input attachment), destroyed on drop.

use std::sync::Arc;

use ash::vk;

use super::live_objects::ObjectKind;
use super::Gpu;
use crate::error::{Result, VkContext};

/// What one binding holds. Bindings are numbered in the order given, from 0.
#[derive(Debug, Clone, Copy)]
pub enum Binding {
    UniformBuffer {
        buffer: vk::Buffer,
        range: u64,
        stages: vk::ShaderStageFlags,
    },
    /// `range` bytes of a uniform buffer from `offset` (a multiple of
    /// `minUniformBufferOffsetAlignment`): one slot of a buffer of many.
    UniformSlice {
        buffer: vk::Buffer,
        offset: u64,
        range: u64,
        stages: vk::ShaderStageFlags,
    },
    /// A storage buffer the shaders only read (no device feature needed).
    ReadOnlyStorage {
        buffer: vk::Buffer,
        range: u64,
        stages: vk::ShaderStageFlags,
    },
    /// A sampled image; `layout` is the layout it is in when sampled.
    Texture {
        view: vk::ImageView,
        sampler: vk::Sampler,
        layout: vk::ImageLayout,
        stages: vk::ShaderStageFlags,
    },
    /// An input attachment of the current subpass, read in the fragment shader.
    InputAttachment {
        view: vk::ImageView,
        layout: vk::ImageLayout,
    },
    /// A storage buffer the fragment shader writes (needs `fragmentStoresAndAtomics`).
    FragmentStorageBuffer {
        buffer: vk::Buffer,
        range: u64,
    },
}

impl Binding {
    fn descriptor_type(&self) -> vk::DescriptorType {
        match self {
            Binding::UniformBuffer { .. } | Binding::UniformSlice { .. } => vk::DescriptorType::UNIFORM_BUFFER,
            Binding::ReadOnlyStorage { .. } => vk::DescriptorType::STORAGE_BUFFER,
            Binding::Texture { .. } => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            Binding::InputAttachment { .. } => vk::DescriptorType::INPUT_ATTACHMENT,
            Binding::FragmentStorageBuffer { .. } => vk::DescriptorType::STORAGE_BUFFER,
        }
    }

    fn stages(&self) -> vk::ShaderStageFlags {
        match *self {
            Binding::UniformBuffer { stages, .. }
            | Binding::UniformSlice { stages, .. }
            | Binding::ReadOnlyStorage { stages, .. }
            | Binding::Texture { stages, .. } => stages,
            Binding::InputAttachment { .. } | Binding::FragmentStorageBuffer { .. } => vk::ShaderStageFlags::FRAGMENT,
        }
    }
}

pub struct DescriptorSet {
    gpu: Arc<Gpu>,
    pub layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
}

impl DescriptorSet {
    pub fn new(gpu: &Arc<Gpu>, bindings: &[Binding]) -> Result<Self> {
        let device = gpu.raw();
        let layout_bindings: Vec<_> = bindings
            .iter()
            .enumerate()
            .map(|(i, b)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(b.descriptor_type())
                    .descriptor_count(1)
                    .stage_flags(b.stages())
            })
            .collect();
        // SAFETY: `device` is alive (`gpu` holds it); the bindings array outlives the call.
        let layout = unsafe {
            device.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings),
                None,
            )
        }
        .vk("vkCreateDescriptorSetLayout")?;
        gpu.created(ObjectKind::DescriptorSetLayout);
        let sizes: Vec<_> =
            bindings.iter().map(|b| vk::DescriptorPoolSize { ty: b.descriptor_type(), descriptor_count: 1 }).collect();
        // SAFETY: as above; one set, one descriptor per binding.
        let pool = match unsafe {
            device.create_descriptor_pool(&vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes), None)
        }
        .vk("vkCreateDescriptorPool")
        {
            Ok(pool) => {
                gpu.created(ObjectKind::DescriptorPool);
                pool
            }
            Err(e) => {
                // SAFETY: the layout was just created and nothing uses it.
                unsafe { device.destroy_descriptor_set_layout(layout, None) };
                gpu.destroyed(ObjectKind::DescriptorSetLayout);
                return Err(e);
            }
        };
        let mut set = DescriptorSet { gpu: gpu.clone(), layout, pool, set: vk::DescriptorSet::null() };
        let layouts = [layout];
        // SAFETY: the pool holds room for exactly this one set of this layout, so `[0]` exists;
        // on failure `set` is dropped, which destroys pool and layout.
        set.set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&layouts),
            )
        }
        .vk("vkAllocateDescriptorSets")?[0];

        write_bindings(device, set.set, bindings);
        Ok(set)
    }
}

/// Points binding i of the fresh `set` at `bindings[i]`.
fn write_bindings(device: &ash::Device, set: vk::DescriptorSet, bindings: &[Binding]) {
    let buffer_infos: Vec<[vk::DescriptorBufferInfo; 1]> = bindings
        .iter()
        .map(|b| match *b {
            Binding::UniformBuffer { buffer, range, .. }
            | Binding::ReadOnlyStorage { buffer, range, .. }
            | Binding::FragmentStorageBuffer { buffer, range } => {
                [vk::DescriptorBufferInfo { buffer, offset: 0, range }]
            }
            Binding::UniformSlice { buffer, offset, range, .. } => [vk::DescriptorBufferInfo { buffer, offset, range }],
            _ => [vk::DescriptorBufferInfo::default()],
        })
        .collect();
    let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = bindings
        .iter()
        .map(|b| match *b {
            Binding::Texture { view, sampler, layout, .. } => {
                [vk::DescriptorImageInfo { sampler, image_view: view, image_layout: layout }]
            }
            Binding::InputAttachment { view, layout } => {
                [vk::DescriptorImageInfo { sampler: vk::Sampler::null(), image_view: view, image_layout: layout }]
            }
            Binding::UniformBuffer { .. }
            | Binding::UniformSlice { .. }
            | Binding::ReadOnlyStorage { .. }
            | Binding::FragmentStorageBuffer { .. } => [vk::DescriptorImageInfo::default()],
        })
        .collect();
    let writes: Vec<_> = bindings
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let write = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(i as u32)
                .descriptor_type(b.descriptor_type());
            match b {
                Binding::UniformBuffer { .. }
                | Binding::UniformSlice { .. }
                | Binding::ReadOnlyStorage { .. }
                | Binding::FragmentStorageBuffer { .. } => write.buffer_info(&buffer_infos[i]),
                _ => write.image_info(&image_infos[i]),
            }
        })
        .collect();
    // SAFETY: each write matches its binding's type and points into `buffer_infos` or
    // `image_infos`, alive during the call; the set was just allocated (by `DescriptorSet::new`, the only caller) and no command uses it yet. The
    // buffers, views and samplers named are the caller's, alive now, and kept by it for as
    // long as the set (the owners order their fields so).
    unsafe { device.update_descriptor_sets(&writes, &[]) };
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: no pending command uses the set (see `Buffer`'s drop); destroying the pool
        // frees the set, then the layout goes.
        unsafe {
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_descriptor_set_layout(self.layout, None);
        }
        self.gpu.destroyed(ObjectKind::DescriptorPool);
        self.gpu.destroyed(ObjectKind::DescriptorSetLayout);
    }
}
