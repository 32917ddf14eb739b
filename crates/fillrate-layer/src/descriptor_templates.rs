//! Descriptor update templates, followed for the tiler check: zink and most engines write their
//! descriptor sets through `vkUpdateDescriptorSetWithTemplate` (and push them through
//! `vkCmdPushDescriptorSetWithTemplateKHR`), so the check reads each template's entries when it
//! is created and, at each update, the image views the program's data names at their offsets.
//! What a template writes is then known as a `vkUpdateDescriptorSets` write would be.

use std::collections::HashMap;

use ash::vk;

use super::arrays::app_array;

/// One entry of a template that writes images: where its `VkDescriptorImageInfo`s lie in the
/// program's data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageEntry {
    pub binding: u32,
    pub first_element: u32,
    pub count: u32,
    pub offset: usize,
    pub stride: usize,
}

/// The image-writing entries of every live template.
#[derive(Debug, Default)]
pub struct Templates(HashMap<vk::DescriptorUpdateTemplate, Vec<ImageEntry>>);

/// Descriptor types whose writes name an image the shaders read (input attachments are read in
/// tile memory, inside their pass).
pub fn reads_image(ty: vk::DescriptorType) -> bool {
    matches!(
        ty,
        vk::DescriptorType::SAMPLED_IMAGE
            | vk::DescriptorType::COMBINED_IMAGE_SAMPLER
            | vk::DescriptorType::STORAGE_IMAGE
    )
}

impl Templates {
    /// A template created: its image entries are kept.
    ///
    /// # Safety
    /// `info` is a valid create info (its entries array as long as its count).
    pub unsafe fn created(
        &mut self,
        template: vk::DescriptorUpdateTemplate,
        info: &vk::DescriptorUpdateTemplateCreateInfo<'_>,
    ) {
        // SAFETY: the caller's contract.
        let entries = unsafe { app_array(info.p_descriptor_update_entries, info.descriptor_update_entry_count) };
        let images = entries
            .iter()
            .filter(|e| reads_image(e.descriptor_type))
            .map(|e| ImageEntry {
                binding: e.dst_binding,
                first_element: e.dst_array_element,
                count: e.descriptor_count,
                offset: e.offset,
                stride: e.stride,
            })
            .collect();
        self.0.insert(template, images);
    }

    pub fn destroyed(&mut self, template: vk::DescriptorUpdateTemplate) {
        self.0.remove(&template);
    }

    /// The image views an update through `template` writes, by (binding, array element); None
    /// when the template was created before the layer saw it.
    ///
    /// # Safety
    /// `data` is the program's update data for `template`: each image entry's
    /// `VkDescriptorImageInfo`s lie at its offset and stride.
    pub unsafe fn written_views(
        &self,
        template: vk::DescriptorUpdateTemplate,
        data: *const std::ffi::c_void,
    ) -> Option<Vec<((u32, u32), vk::ImageView)>> {
        let entries = self.0.get(&template)?;
        let mut views = Vec::new();
        for e in entries {
            for i in 0..e.count {
                let at = (data as *const u8).wrapping_add(e.offset + i as usize * e.stride);
                // SAFETY: the caller's contract; unaligned reads, as the program's data may pack.
                let info = unsafe { std::ptr::read_unaligned(at as *const vk::DescriptorImageInfo) };
                views.push(((e.binding, e.first_element + i), info.image_view));
            }
        }
        Some(views)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    #[test]
    fn an_update_through_a_template_names_the_views_at_their_offsets() {
        let entries = [
            vk::DescriptorUpdateTemplateEntry {
                dst_binding: 0,
                dst_array_element: 0,
                descriptor_count: 1,
                descriptor_type: vk::DescriptorType::UNIFORM_BUFFER,
                offset: 0,
                stride: 0,
            },
            vk::DescriptorUpdateTemplateEntry {
                dst_binding: 2,
                dst_array_element: 1,
                descriptor_count: 2,
                descriptor_type: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                offset: 8,
                stride: 24,
            },
        ];
        let info = vk::DescriptorUpdateTemplateCreateInfo::default().descriptor_update_entries(&entries);
        let mut templates = Templates::default();
        let template = vk::DescriptorUpdateTemplate::from_raw(9);
        // SAFETY: a valid create info.
        unsafe { templates.created(template, &info) };
        let mut data = [0u8; 8 + 2 * 24];
        for (i, view) in [41u64, 42].iter().enumerate() {
            let info = vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: vk::ImageView::from_raw(*view),
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            };
            // SAFETY: within `data`.
            unsafe {
                std::ptr::write_unaligned(data.as_mut_ptr().add(8 + i * 24) as *mut vk::DescriptorImageInfo, info)
            };
        }
        // SAFETY: `data` laid out as the template says.
        let views = unsafe { templates.written_views(template, data.as_ptr().cast()) }.expect("a known template");
        assert_eq!(views, [((2, 1), vk::ImageView::from_raw(41)), ((2, 2), vk::ImageView::from_raw(42))]);
        templates.destroyed(template);
        // SAFETY: as above.
        assert!(unsafe { templates.written_views(template, data.as_ptr().cast()) }.is_none());
    }
}
