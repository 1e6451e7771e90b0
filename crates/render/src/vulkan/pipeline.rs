//! Pipelines: shader modules from SPIR-V words, the descriptor set and
//! pipeline layouts of a [`Bindings`], and the two kinds the host runs: a
//! compute pipeline (the ray query tracer, the lab's kernels) and a ray
//! tracing pipeline (raygen, miss, a triangle hit group of closest-hit and
//! any-hit) with its shader binding table. Destroyed when dropped.

use super::conv::failed;
use super::device::{Core, Device};
use super::memory::Buffer;
use crate::error::RenderError;
use ash::vk;
use std::rc::Rc;

/// The descriptor set of a pipeline: with `acceleration_structure`, the
/// top-level structure at binding 0 and `storage` storage buffers at
/// bindings `1..=storage`; without, the buffers at `0..storage`; then,
/// where `textures > 0`, an array of `textures` combined image samplers at
/// the next binding (the sampler lookup's, binding 12). And the
/// push-constant bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Bindings {
    pub(crate) acceleration_structure: bool,
    pub(crate) storage: u32,
    pub(crate) textures: u32,
    pub(crate) push_bytes: u32,
}

impl Bindings {
    /// The binding of storage buffer `i`.
    pub(crate) fn storage_binding(self, i: u32) -> u32 {
        i + u32::from(self.acceleration_structure)
    }

    /// The binding of the combined image samplers (after the buffers).
    pub(crate) fn texture_binding(self) -> u32 {
        self.storage_binding(self.storage)
    }
}

/// The SPIR-V words of a ray tracing pipeline's four stages.
pub(crate) struct RayTracingStages<'a> {
    pub(crate) raygen: &'a [u32],
    pub(crate) miss: &'a [u32],
    pub(crate) closest_hit: &'a [u32],
    pub(crate) any_hit: &'a [u32],
}

/// A ray tracing pipeline's shader binding table: one record each for
/// raygen, miss and the hit group, at base-aligned addresses.
pub(crate) struct ShaderTable {
    _buffer: Buffer,
    /// Raygen, miss and hit regions.
    pub(crate) regions: [vk::StridedDeviceAddressRegionKHR; 3],
}

/// A compute or ray tracing pipeline with its layouts and modules.
pub(crate) struct Pipeline {
    core: Rc<Core>,
    modules: Vec<vk::ShaderModule>,
    pub(crate) set_layout: vk::DescriptorSetLayout,
    pub(crate) layout: vk::PipelineLayout,
    pub(crate) handle: vk::Pipeline,
    /// The stages the layouts are visible to.
    pub(crate) stages: vk::ShaderStageFlags,
    pub(crate) bindings: Bindings,
    /// `None` for a compute pipeline.
    pub(crate) table: Option<ShaderTable>,
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        let d = &self.core.raw;
        // SAFETY: no pending command uses them (every submission is waited
        // for); null handles (a pipeline that failed part-way) are ignored.
        unsafe {
            d.destroy_pipeline(self.handle, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            for m in &self.modules {
                d.destroy_shader_module(*m, None);
            }
        }
    }
}

impl Device {
    /// An empty pipeline for `stages` and `bindings`, its layouts made.
    fn pipeline_shell(
        &self,
        stages: vk::ShaderStageFlags,
        bindings: Bindings,
    ) -> Result<Pipeline, RenderError> {
        let d = &self.core.raw;
        let mut made = Pipeline {
            core: Rc::clone(&self.core),
            modules: Vec::new(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            handle: vk::Pipeline::null(),
            stages,
            bindings,
            table: None,
        };
        let mut layout_bindings = Vec::new();
        if bindings.acceleration_structure {
            layout_bindings.push(
                vk::DescriptorSetLayoutBinding::default()
                    .binding(0)
                    .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                    .descriptor_count(1)
                    .stage_flags(stages),
            );
        }
        layout_bindings.extend((0..bindings.storage).map(|i| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(bindings.storage_binding(i))
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(stages)
        }));
        if bindings.textures > 0 {
            layout_bindings.push(
                vk::DescriptorSetLayoutBinding::default()
                    .binding(bindings.texture_binding())
                    .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                    .descriptor_count(bindings.textures)
                    .stage_flags(stages),
            );
        }
        let set_info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY: the bindings outlive the call.
        made.set_layout = unsafe { d.create_descriptor_set_layout(&set_info, None) }
            .map_err(failed("vkCreateDescriptorSetLayout"))?;
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(stages)
            .size(bindings.push_bytes)];
        let set_layouts = [made.set_layout];
        let mut layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        if bindings.push_bytes > 0 {
            layout_info = layout_info.push_constant_ranges(&ranges);
        }
        // SAFETY: as above.
        made.layout = unsafe { d.create_pipeline_layout(&layout_info, None) }
            .map_err(failed("vkCreatePipelineLayout"))?;
        Ok(made)
    }

    /// A shader module of `spirv`, owned by `pipeline`.
    fn module(
        &self,
        pipeline: &mut Pipeline,
        spirv: &[u32],
    ) -> Result<vk::ShaderModule, RenderError> {
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        // SAFETY: SPIR-V words the caller compiled and validated
        // (`spirv-val`), outliving the call.
        let module = unsafe { self.core.raw.create_shader_module(&info, None) }
            .map_err(failed("vkCreateShaderModule"))?;
        pipeline.modules.push(module);
        Ok(module)
    }

    /// A compute pipeline of `spirv` (entry point `main`).
    pub(crate) fn compute_pipeline(
        &self,
        spirv: &[u32],
        bindings: Bindings,
    ) -> Result<Pipeline, RenderError> {
        let stages = vk::ShaderStageFlags::COMPUTE;
        let mut made = self.pipeline_shell(stages, bindings)?;
        let module = self.module(&mut made, spirv)?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(stages)
            .module(module)
            .name(c"main");
        let info = [vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(made.layout)];
        // SAFETY: the module and layout are valid; the infos outlive the call.
        made.handle = unsafe {
            self.core
                .raw
                .create_compute_pipelines(vk::PipelineCache::null(), &info, None)
        }
        .map_err(|(_, result)| RenderError::Vulkan {
            call: "vkCreateComputePipelines",
            result,
        })?[0];
        Ok(made)
    }

    /// A ray tracing pipeline of `stages` (entry points `main`; groups:
    /// raygen, miss, a triangle hit group of closest-hit and any-hit) and
    /// its shader binding table. A device without
    /// `VK_KHR_ray_tracing_pipeline` enabled answers
    /// [`RenderError::Vulkan`] with `ERROR_EXTENSION_NOT_PRESENT` (callers
    /// check [`Device::enabled`] first).
    pub(crate) fn ray_tracing_pipeline(
        &self,
        stages: &RayTracingStages<'_>,
        bindings: Bindings,
    ) -> Result<Pipeline, RenderError> {
        // Allowed to meet opacity micromaps where the device has them.
        let flags = if self.core.micromap.is_some() {
            vk::PipelineCreateFlags::RAY_TRACING_OPACITY_MICROMAP_EXT
        } else {
            vk::PipelineCreateFlags::empty()
        };
        let Some(rt) = &self.core.ray_tracing else {
            return Err(RenderError::Vulkan {
                call: "vkCreateRayTracingPipelinesKHR",
                result: vk::Result::ERROR_EXTENSION_NOT_PRESENT,
            });
        };
        let kinds = [
            (stages.raygen, vk::ShaderStageFlags::RAYGEN_KHR),
            (stages.miss, vk::ShaderStageFlags::MISS_KHR),
            (stages.closest_hit, vk::ShaderStageFlags::CLOSEST_HIT_KHR),
            (stages.any_hit, vk::ShaderStageFlags::ANY_HIT_KHR),
        ];
        let all = kinds
            .iter()
            .fold(vk::ShaderStageFlags::empty(), |a, (_, s)| a | *s);
        let mut made = self.pipeline_shell(all, bindings)?;
        let mut infos = Vec::new();
        for (spirv, stage) in kinds {
            let module = self.module(&mut made, spirv)?;
            infos.push(
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(stage)
                    .module(module)
                    .name(c"main"),
            );
        }
        let general = |i: u32| {
            vk::RayTracingShaderGroupCreateInfoKHR::default()
                .ty(vk::RayTracingShaderGroupTypeKHR::GENERAL)
                .general_shader(i)
                .closest_hit_shader(vk::SHADER_UNUSED_KHR)
                .any_hit_shader(vk::SHADER_UNUSED_KHR)
                .intersection_shader(vk::SHADER_UNUSED_KHR)
        };
        let groups = [
            general(0),
            general(1),
            vk::RayTracingShaderGroupCreateInfoKHR::default()
                .ty(vk::RayTracingShaderGroupTypeKHR::TRIANGLES_HIT_GROUP)
                .general_shader(vk::SHADER_UNUSED_KHR)
                .closest_hit_shader(2)
                .any_hit_shader(3)
                .intersection_shader(vk::SHADER_UNUSED_KHR),
        ];
        let info = [vk::RayTracingPipelineCreateInfoKHR::default()
            .flags(flags)
            .stages(&infos)
            .groups(&groups)
            .max_pipeline_ray_recursion_depth(1)
            .layout(made.layout)];
        // SAFETY: valid modules and layout; the infos outlive the call.
        made.handle = unsafe {
            rt.functions.create_ray_tracing_pipelines(
                vk::DeferredOperationKHR::null(),
                vk::PipelineCache::null(),
                &info,
                None,
            )
        }
        .map_err(|(_, result)| RenderError::Vulkan {
            call: "vkCreateRayTracingPipelinesKHR",
            result,
        })?[0];
        let (handle_size, base_alignment) = (rt.handle_size, rt.base_alignment);
        let group_count = groups.len() as u32;
        // SAFETY: a ray tracing pipeline of this device with these groups.
        let handles = unsafe {
            rt.functions.get_ray_tracing_shader_group_handles(
                made.handle,
                0,
                group_count,
                (group_count * handle_size) as usize,
            )
        }
        .map_err(failed("vkGetRayTracingShaderGroupHandlesKHR"))?;
        // One record per region, each at a base-aligned offset.
        let stride = u64::from(handle_size.next_multiple_of(base_alignment));
        let mut bytes = vec![0u8; (stride * u64::from(group_count)) as usize];
        for (g, h) in handles.chunks_exact(handle_size as usize).enumerate() {
            let at = g * stride as usize;
            bytes[at..at + h.len()].copy_from_slice(h);
        }
        // Aligned start: over-allocate by one alignment.
        let buffer = self.buffer(
            bytes.len() as u64 + u64::from(base_alignment),
            vk::BufferUsageFlags::SHADER_BINDING_TABLE_KHR,
        )?;
        let start = buffer.address.next_multiple_of(u64::from(base_alignment));
        buffer.write(start - buffer.address, &bytes)?;
        let region = |g: u64| {
            vk::StridedDeviceAddressRegionKHR::default()
                .device_address(start + g * stride)
                .stride(stride)
                .size(stride)
        };
        made.table = Some(ShaderTable {
            _buffer: buffer,
            regions: [region(0), region(1), region(2)],
        });
        Ok(made)
    }
}
