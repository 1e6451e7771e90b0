//! The logical device: created on the adapter a request chose, with the
//! extensions and features it asked for (and those of its optional ones
//! the device has), one compute queue and a command pool; [`Device::submit`]
//! records, submits and waits. Destroyed when the last object made on it
//! goes.

use super::adapter::{extension_names, Adapter};
use super::conv::failed;
use super::instance::Instance;
use super::{DeviceInfo, DeviceRequest, Features};
use crate::error::RenderError;
use ash::ext::opacity_micromap;
use ash::khr::{acceleration_structure, ray_tracing_pipeline};
use ash::vk;
use std::rc::Rc;

/// `VK_KHR_ray_tracing_pipeline`'s functions and the shader binding
/// table's sizes.
pub(crate) struct RayTracing {
    pub(crate) functions: ray_tracing_pipeline::Device,
    /// `shaderGroupHandleSize`.
    pub(crate) handle_size: u32,
    /// `shaderGroupBaseAlignment` (at least 1).
    pub(crate) base_alignment: u32,
}

/// What every object of a device shares: the device and what it was made
/// with. Dropped after the last object (each holds an `Rc`).
pub(crate) struct Core {
    pub(crate) raw: ash::Device,
    pub(crate) queue: vk::Queue,
    pool: vk::CommandPool,
    pub(crate) memory: vk::PhysicalDeviceMemoryProperties,
    /// `VK_KHR_acceleration_structure`'s functions, where enabled.
    pub(crate) accel: Option<acceleration_structure::Device>,
    /// `VK_KHR_ray_tracing_pipeline`, where enabled.
    pub(crate) ray_tracing: Option<RayTracing>,
    /// `VK_EXT_opacity_micromap`'s functions, where enabled.
    pub(crate) micromap: Option<opacity_micromap::Device>,
    /// Nanoseconds per timestamp tick, where the queue writes timestamps.
    pub(crate) timestamp_period: Option<f64>,
    /// Whether buffers get device addresses (`bufferDeviceAddress`,
    /// enabled with acceleration structures).
    pub(crate) buffer_addresses: bool,
    pub(crate) info: DeviceInfo,
    pub(crate) enabled: Features,
    /// Whether the sampler lookup's features were enabled.
    pub(crate) sampler_lookup: bool,
    // Destroyed after the device (fields drop after `drop`).
    _instance: Rc<Instance>,
}

impl Drop for Core {
    fn drop(&mut self) {
        // SAFETY: every object made on the device holds an `Rc` of this
        // core, so none is left; every submission was waited for.
        unsafe {
            let _ = self.raw.device_wait_idle();
            self.raw.destroy_command_pool(self.pool, None);
            self.raw.destroy_device(None);
        }
    }
}

/// An open Vulkan device: one compute queue, the extensions its request
/// enabled.
pub struct Device {
    pub(crate) core: Rc<Core>,
}

impl Device {
    /// Opens the first device with what `request` requires (and enables
    /// what it has of the optional features), or says why there is none
    /// ([`ErrorClass::NoDevice`](crate::ErrorClass::NoDevice)).
    pub fn open(request: &DeviceRequest) -> Result<Device, RenderError> {
        let instance = Instance::new()?;
        let adapter = Adapter::choose(&instance, request)?;
        let mut enabled = request
            .required
            .union(request.optional)
            .and(adapter.info.has);
        // Each ray tracing extension needs acceleration structures.
        enabled.acceleration_structure |=
            enabled.ray_query || enabled.ray_tracing_pipeline || enabled.opacity_micromap;
        let sampler_lookup = request.sampler_lookup && adapter.info.sampler_lookup;
        Device::create(instance, &adapter, enabled, sampler_lookup)
    }

    fn create(
        instance: Rc<Instance>,
        adapter: &Adapter,
        enabled: Features,
        sampler_lookup: bool,
    ) -> Result<Device, RenderError> {
        let (raw, physical) = (&instance.raw, adapter.physical);
        let name = adapter.info.label();
        // SAFETY: a physical device of this instance.
        let (families, memory, limits) = unsafe {
            (
                raw.get_physical_device_queue_family_properties(physical),
                raw.get_physical_device_memory_properties(physical),
                raw.get_physical_device_properties(physical).limits,
            )
        };
        let family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
            .ok_or_else(|| RenderError::NoComputeQueue {
                device: name.clone(),
            })? as u32;
        let timestamp_period = (families[family as usize].timestamp_valid_bits > 0
            && limits.timestamp_period > 0.0)
            .then_some(f64::from(limits.timestamp_period));
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let extensions: Vec<_> = extension_names(enabled)
            .iter()
            .map(|n| n.as_ptr())
            .collect();
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default()
            .buffer_device_address(enabled.acceleration_structure);
        if sampler_lookup {
            v12 = v12
                .runtime_descriptor_array(true)
                .shader_sampled_image_array_non_uniform_indexing(true)
                .sampler_mirror_clamp_to_edge(adapter.info.mirror_clamp_to_edge);
        }
        let mut accel_features = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
            .acceleration_structure(true);
        let mut query_features = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        let mut pipeline_features =
            vk::PhysicalDeviceRayTracingPipelineFeaturesKHR::default().ray_tracing_pipeline(true);
        let mut micromap_features =
            vk::PhysicalDeviceOpacityMicromapFeaturesEXT::default().micromap(true);
        let mut info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&extensions);
        if enabled.acceleration_structure || sampler_lookup {
            info = info.push_next(&mut v12);
        }
        if enabled.acceleration_structure {
            info = info.push_next(&mut accel_features);
        }
        if enabled.ray_query {
            info = info.push_next(&mut query_features);
        }
        if enabled.ray_tracing_pipeline {
            info = info.push_next(&mut pipeline_features);
        }
        if enabled.opacity_micromap {
            info = info.push_next(&mut micromap_features);
        }
        // SAFETY: `info` and its chain outlive the call.
        let device = unsafe { raw.create_device(physical, &info, None) }.map_err(|result| {
            RenderError::DeviceCreation {
                device: name.clone(),
                result,
            }
        })?;
        let accel = enabled
            .acceleration_structure
            .then(|| acceleration_structure::Device::new(raw, &device));
        let ray_tracing = enabled.ray_tracing_pipeline.then(|| {
            let mut rt = vk::PhysicalDeviceRayTracingPipelinePropertiesKHR::default();
            let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut rt);
            // SAFETY: a physical device of a Vulkan 1.2 instance, a valid chain.
            unsafe { raw.get_physical_device_properties2(physical, &mut props2) };
            RayTracing {
                functions: ray_tracing_pipeline::Device::new(raw, &device),
                handle_size: rt.shader_group_handle_size,
                base_alignment: rt.shader_group_base_alignment.max(1),
            }
        });
        let micromap = enabled
            .opacity_micromap
            .then(|| opacity_micromap::Device::new(raw, &device));
        // SAFETY: the family exists and has one queue.
        let queue = unsafe { device.get_device_queue(family, 0) };
        let mut core = Core {
            raw: device,
            queue,
            pool: vk::CommandPool::null(),
            memory,
            accel,
            ray_tracing,
            micromap,
            timestamp_period,
            buffer_addresses: enabled.acceleration_structure,
            info: adapter.info.clone(),
            enabled,
            sampler_lookup,
            _instance: instance,
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: a valid device and create info (on failure `core`'s drop
        // destroys the device; a null pool is ignored).
        core.pool = unsafe { core.raw.create_command_pool(&pool_info, None) }
            .map_err(failed("vkCreateCommandPool"))?;
        Ok(Device {
            core: Rc::new(core),
        })
    }

    /// What the device is.
    #[must_use]
    pub fn info(&self) -> &DeviceInfo {
        &self.core.info
    }

    /// The features enabled on it.
    #[must_use]
    pub fn enabled(&self) -> Features {
        self.core.enabled
    }

    /// Whether what the sampler lookup needs was enabled
    /// ([`DeviceRequest::sampler_lookup`] on a device that has it).
    #[must_use]
    pub fn sampler_lookup_enabled(&self) -> bool {
        self.core.sampler_lookup
    }

    /// Records commands with `record` into a fresh command buffer between
    /// two global memory barriers (everything earlier in submission order,
    /// earlier submissions included, before the commands; the commands
    /// before host reads), submits it and waits until it finished.
    pub(crate) fn submit(&self, record: impl FnOnce(vk::CommandBuffer)) -> Result<(), RenderError> {
        let d = &self.core.raw;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.core.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: a valid pool of this device, used from this thread only
        // (`Device` is not `Send`).
        let cmd = unsafe { d.allocate_command_buffers(&alloc) }
            .map_err(failed("vkAllocateCommandBuffers"))?[0];
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        let barrier = |src, dst, dst_access| {
            [vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::MEMORY_WRITE)
                .dst_access_mask(dst_access)]
            .map(|b| (src, dst, b))
        };
        let result = (|| {
            // SAFETY: a fresh command buffer.
            unsafe { d.begin_command_buffer(cmd, &begin) }
                .map_err(failed("vkBeginCommandBuffer"))?;
            let [(src, dst, before)] = barrier(
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
            );
            // SAFETY: a command buffer in the recording state.
            unsafe {
                d.cmd_pipeline_barrier(
                    cmd,
                    src,
                    dst,
                    vk::DependencyFlags::empty(),
                    &[before],
                    &[],
                    &[],
                );
            }
            record(cmd);
            let [(src, dst, after)] = barrier(
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::PipelineStageFlags::HOST,
                vk::AccessFlags::HOST_READ,
            );
            // SAFETY: as above; recording began above.
            unsafe {
                d.cmd_pipeline_barrier(
                    cmd,
                    src,
                    dst,
                    vk::DependencyFlags::empty(),
                    &[after],
                    &[],
                    &[],
                );
                d.end_command_buffer(cmd)
            }
            .map_err(failed("vkEndCommandBuffer"))?;
            let cmds = [cmd];
            let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
            // SAFETY: a recorded command buffer; waited for before return.
            unsafe {
                d.queue_submit(self.core.queue, &submit, vk::Fence::null())
                    .map_err(failed("vkQueueSubmit"))?;
                d.queue_wait_idle(self.core.queue)
                    .map_err(failed("vkQueueWaitIdle"))
            }
        })();
        // SAFETY: the queue is idle (or the buffer was never submitted).
        unsafe { d.free_command_buffers(self.core.pool, &[cmd]) };
        result
    }
}
