//! One run of a pipeline: a descriptor pool and set for the run's
//! top-level structure and buffers, the push constants, a dispatch (compute)
//! or a ray launch (ray tracing), waited for and timed. And the lab's
//! compute kernels ([`ComputeKernel`]), which run the same way over buffers
//! made per run.

use super::accel::AccelerationStructure;
use super::conv::failed;
use super::device::Device;
use super::memory::Buffer;
use super::pipeline::{Bindings, Pipeline};
use crate::error::RenderError;
use ash::vk;
use std::time::Instant;

/// How a run is launched.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Launch {
    /// A compute dispatch of this many workgroups.
    Groups([u32; 3]),
    /// A ray tracing launch of `width x height` rays.
    Rays(u32, u32),
}

/// How long a run took, in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Timing {
    /// Process CPU time (a CPU device's threads are the process's), where
    /// the platform has a process clock.
    pub(crate) cpu: Option<f64>,
    /// Wall-clock time of the submission.
    pub(crate) wall: f64,
    /// Between the device's timestamps before and after the dispatch or
    /// launch, where its queue writes timestamps.
    pub(crate) device: Option<f64>,
}

/// Process CPU time in seconds (every thread, lavapipe's included), where
/// the platform has it.
fn process_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        let mut t = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: a valid clock id and a pointer to a live timespec.
        let ok = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) } == 0;
        ok.then_some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

impl Device {
    /// Runs `pipeline` once with `tlas` at binding 0 (where its bindings
    /// have one), `storage` at the storage bindings and `textures` (image
    /// views in `SHADER_READ_ONLY_OPTIMAL` layout, each with its sampler)
    /// as its combined image samplers, `push` as the push constants;
    /// returns after the device finished, with the time the submission
    /// took.
    pub(crate) fn run(
        &self,
        pipeline: &Pipeline,
        tlas: Option<&AccelerationStructure>,
        (storage, textures): (&[&Buffer], &[(vk::ImageView, vk::Sampler)]),
        push: &[u8],
        launch: Launch,
    ) -> Result<Timing, RenderError> {
        let d = &self.core.raw;
        let bindings = pipeline.bindings;
        assert_eq!(
            (storage.len(), tlas.is_some(), textures.len()),
            (
                bindings.storage as usize,
                bindings.acceleration_structure,
                bindings.textures as usize
            ),
            "one buffer per storage binding, a structure where one is bound, one image per texture"
        );
        let mut sizes = vec![vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(bindings.storage.max(1))];
        if bindings.acceleration_structure {
            sizes.push(
                vk::DescriptorPoolSize::default()
                    .ty(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                    .descriptor_count(1),
            );
        }
        if bindings.textures > 0 {
            sizes.push(
                vk::DescriptorPoolSize::default()
                    .ty(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                    .descriptor_count(bindings.textures),
            );
        }
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: a valid create info.
        let pool = unsafe { d.create_descriptor_pool(&pool_info, None) }
            .map_err(failed("vkCreateDescriptorPool"))?;
        let mut queries = vk::QueryPool::null();
        if self.core.timestamp_period.is_some() {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(2);
            // SAFETY: a valid create info; destroyed below.
            match unsafe { d.create_query_pool(&info, None) } {
                Ok(q) => queries = q,
                Err(result) => {
                    // SAFETY: unused.
                    unsafe { d.destroy_descriptor_pool(pool, None) };
                    return Err(RenderError::Vulkan {
                        call: "vkCreateQueryPool",
                        result,
                    });
                }
            }
        }
        let result = (|| {
            let set_layouts = [pipeline.set_layout];
            let alloc = vk::DescriptorSetAllocateInfo::default()
                .descriptor_pool(pool)
                .set_layouts(&set_layouts);
            // SAFETY: a pool with room for this set.
            let set = unsafe { d.allocate_descriptor_sets(&alloc) }
                .map_err(failed("vkAllocateDescriptorSets"))?[0];
            let structures: Vec<_> = tlas.iter().map(|t| t.handle).collect();
            let mut as_write = vk::WriteDescriptorSetAccelerationStructureKHR::default()
                .acceleration_structures(&structures);
            let mut writes = Vec::new();
            if tlas.is_some() {
                writes.push(
                    vk::WriteDescriptorSet::default()
                        .dst_set(set)
                        .dst_binding(0)
                        .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                        .descriptor_count(1)
                        .push_next(&mut as_write),
                );
            }
            let infos: Vec<[vk::DescriptorBufferInfo; 1]> = storage
                .iter()
                .map(|b| {
                    [vk::DescriptorBufferInfo::default()
                        .buffer(b.handle)
                        .range(vk::WHOLE_SIZE)]
                })
                .collect();
            for (i, info) in infos.iter().enumerate() {
                writes.push(
                    vk::WriteDescriptorSet::default()
                        .dst_set(set)
                        .dst_binding(bindings.storage_binding(i as u32))
                        .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                        .buffer_info(info),
                );
            }
            let images: Vec<vk::DescriptorImageInfo> = textures
                .iter()
                .map(|&(view, sampler)| {
                    vk::DescriptorImageInfo::default()
                        .image_view(view)
                        .sampler(sampler)
                        .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                })
                .collect();
            if !images.is_empty() {
                writes.push(
                    vk::WriteDescriptorSet::default()
                        .dst_set(set)
                        .dst_binding(bindings.texture_binding())
                        .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                        .image_info(&images),
                );
            }
            // SAFETY: the writes name live buffers, structures, views and
            // samplers of this device; `infos`, `structures` and `images`
            // outlive the call.
            unsafe { d.update_descriptor_sets(&writes, &[]) };
            let point = if pipeline.table.is_some() {
                vk::PipelineBindPoint::RAY_TRACING_KHR
            } else {
                vk::PipelineBindPoint::COMPUTE
            };
            let cpu0 = process_cpu_seconds();
            let wall0 = Instant::now();
            // SAFETY: the pipeline, set and push range match its layout; the
            // table's regions lie in its live buffer; the submission is
            // waited for inside `submit`.
            let timed = queries != vk::QueryPool::null();
            self.submit(|cmd| unsafe {
                if timed {
                    d.cmd_reset_query_pool(cmd, queries, 0, 2);
                    d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, queries, 0);
                }
                d.cmd_bind_pipeline(cmd, point, pipeline.handle);
                d.cmd_bind_descriptor_sets(cmd, point, pipeline.layout, 0, &[set], &[]);
                if !push.is_empty() {
                    d.cmd_push_constants(cmd, pipeline.layout, pipeline.stages, 0, push);
                }
                match (launch, &pipeline.table, &self.core.ray_tracing) {
                    (Launch::Rays(width, height), Some(table), Some(rt)) => {
                        let [raygen, miss, hit] = &table.regions;
                        let callable = vk::StridedDeviceAddressRegionKHR::default();
                        rt.functions
                            .cmd_trace_rays(cmd, raygen, miss, hit, &callable, width, height, 1);
                    }
                    (Launch::Groups([x, y, z]), None, _) => d.cmd_dispatch(cmd, x, y, z),
                    // A launch that does not fit the pipeline records
                    // nothing (the callers pair them).
                    _ => {}
                }
                if timed {
                    d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, queries, 1);
                }
            })?;
            let wall_seconds = wall0.elapsed().as_secs_f64();
            let cpu_seconds = match (cpu0, process_cpu_seconds()) {
                (Some(a), Some(b)) => Some(b - a),
                _ => None,
            };
            let mut device_seconds = None;
            if let (true, Some(period)) = (timed, self.core.timestamp_period) {
                let mut ticks = [0u64; 2];
                // SAFETY: both queries were written by the finished
                // submission; `ticks` holds two 64-bit results.
                unsafe {
                    d.get_query_pool_results(
                        queries,
                        0,
                        &mut ticks,
                        vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
                    )
                }
                .map_err(failed("vkGetQueryPoolResults"))?;
                device_seconds = Some(ticks[1].wrapping_sub(ticks[0]) as f64 * period * 1e-9);
            }
            Ok(Timing {
                cpu: cpu_seconds,
                wall: wall_seconds,
                device: device_seconds,
            })
        })();
        // SAFETY: the submission finished (or never started); a null query
        // pool is ignored.
        unsafe {
            d.destroy_query_pool(queries, None);
            d.destroy_descriptor_pool(pool, None);
        }
        result
    }
}

/// A compute kernel of the lab's shader tests: storage buffers at bindings
/// `0..n` (the last one its output) and push constants.
pub struct ComputeKernel {
    pipeline: Pipeline,
}

impl Device {
    /// A compute kernel of SPIR-V words (entry point `main`, validated by
    /// `spirv-val`) with `storage` storage-buffer bindings and
    /// `push_bytes` bytes of push constants.
    pub fn compute_kernel(
        &self,
        spirv: &[u32],
        storage: u32,
        push_bytes: u32,
    ) -> Result<ComputeKernel, RenderError> {
        let pipeline = self.compute_pipeline(
            spirv,
            Bindings {
                acceleration_structure: false,
                storage,
                textures: 0,
                push_bytes,
            },
        )?;
        Ok(ComputeKernel { pipeline })
    }

    /// Runs `kernel` once over `groups` workgroups: `inputs` at bindings
    /// `0..n-1` (each in a buffer of its own, an empty one as one zero
    /// word), a zeroed output of `out_words` words at the last binding,
    /// `push` as the push constants; returns the output.
    ///
    /// # Panics
    /// If `inputs` is not one fewer than the kernel's bindings.
    pub fn run_kernel(
        &self,
        kernel: &ComputeKernel,
        inputs: &[&[u32]],
        out_words: usize,
        push: &[u8],
        groups: [u32; 3],
    ) -> Result<Vec<u32>, RenderError> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let mut buffers = Vec::new();
        for words in inputs {
            let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
            let b = self.buffer(bytes.len() as u64, usage)?;
            b.write(0, &bytes)?;
            buffers.push(b);
        }
        buffers.push(self.buffer(4 * out_words as u64, usage)?);
        let storage: Vec<&Buffer> = buffers.iter().collect();
        self.run(
            &kernel.pipeline,
            None,
            (&storage, &[]),
            push,
            Launch::Groups(groups),
        )?;
        buffers[buffers.len() - 1].read(out_words)
    }
}
