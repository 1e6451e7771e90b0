//! Sampled images of the sampler lookup: a 2D `R8_UNORM` image (one
//! texture's alphas, one byte per texel, row 0 at `v = 0`), one mip level,
//! optimal tiling, in its own allocation, uploaded once through a staging
//! buffer and left in `SHADER_READ_ONLY_OPTIMAL` layout; and its view.
//! Freed when dropped.

use super::conv::failed;
use super::device::{Core, Device};
use super::memory::memory_type;
use crate::error::RenderError;
use ash::vk;
use std::rc::Rc;

/// The format of every sampled image: the texture's alpha as an 8-bit
/// UNORM channel, read back as `.r`.
pub(crate) const ALPHA_FORMAT: vk::Format = vk::Format::R8_UNORM;

/// An image, its memory and its view.
pub(crate) struct Image {
    core: Rc<Core>,
    handle: vk::Image,
    memory: vk::DeviceMemory,
    pub(crate) view: vk::ImageView,
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: every submission that read the image was waited for;
        // null handles (an image that failed part-way) are ignored.
        unsafe {
            self.core.raw.destroy_image_view(self.view, None);
            self.core.raw.destroy_image(self.handle, None);
            self.core.raw.free_memory(self.memory, None);
        }
    }
}

impl Device {
    /// A `width x height` [`ALPHA_FORMAT`] image holding `texels` (one
    /// byte per texel, row-major), ready to be sampled.
    ///
    /// # Panics
    /// If `texels` is not `width * height` bytes.
    pub(crate) fn alpha_image(
        &self,
        width: u32,
        height: u32,
        texels: &[u8],
    ) -> Result<Image, RenderError> {
        assert_eq!(
            texels.len() as u64,
            u64::from(width) * u64::from(height),
            "one byte per texel"
        );
        let core = &self.core;
        let d = &core.raw;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(ALPHA_FORMAT)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: a valid device and create info.
        let handle = unsafe { d.create_image(&info, None) }.map_err(failed("vkCreateImage"))?;
        let mut image = Image {
            core: Rc::clone(core),
            handle,
            memory: vk::DeviceMemory::null(),
            view: vk::ImageView::null(),
        };
        // SAFETY: the image was just created on this device.
        let needs = unsafe { d.get_image_memory_requirements(handle) };
        // Device-local where there is such a type, else any it accepts.
        let bits = needs.memory_type_bits;
        let index = memory_type(&core.memory, bits, vk::MemoryPropertyFlags::DEVICE_LOCAL)
            .or_else(|| memory_type(&core.memory, bits, vk::MemoryPropertyFlags::empty()))
            .ok_or(RenderError::Vulkan {
                call: "vkAllocateMemory",
                result: vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
            })?;
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(needs.size)
            .memory_type_index(index);
        // SAFETY: a valid allocate info (on failure `image`'s drop
        // destroys the image).
        image.memory = unsafe { d.allocate_memory(&alloc, None) }.map_err(|result| {
            RenderError::Allocation {
                bytes: needs.size,
                result,
            }
        })?;
        // SAFETY: memory of a type the image accepts, large enough, unbound.
        unsafe { d.bind_image_memory(handle, image.memory, 0) }
            .map_err(failed("vkBindImageMemory"))?;
        let staging = self.buffer(texels.len() as u64, vk::BufferUsageFlags::TRANSFER_SRC)?;
        staging.write(0, texels)?;
        let range = vk::ImageSubresourceRange::default()
            .aspect_mask(vk::ImageAspectFlags::COLOR)
            .level_count(1)
            .layer_count(1);
        let to_transfer = vk::ImageMemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::empty())
            .dst_access_mask(vk::AccessFlags::TRANSFER_WRITE)
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(handle)
            .subresource_range(range);
        let to_read = to_transfer
            .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
            .dst_access_mask(vk::AccessFlags::SHADER_READ)
            .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
        let copy = vk::BufferImageCopy::default()
            .image_subresource(
                vk::ImageSubresourceLayers::default()
                    .aspect_mask(vk::ImageAspectFlags::COLOR)
                    .layer_count(1),
            )
            .image_extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            });
        // SAFETY: the image and the staging buffer are live, the copy lies
        // inside both (tightly packed rows, one byte per texel), the
        // barriers name this image's one level and layer; `submit` waits.
        self.submit(|cmd| unsafe {
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_transfer],
            );
            d.cmd_copy_buffer_to_image(
                cmd,
                staging.handle,
                handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[copy],
            );
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_read],
            );
        })?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(handle)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(ALPHA_FORMAT)
            .subresource_range(range);
        // SAFETY: a view of this live image's one level and layer.
        image.view = unsafe { d.create_image_view(&view_info, None) }
            .map_err(failed("vkCreateImageView"))?;
        Ok(image)
    }
}
