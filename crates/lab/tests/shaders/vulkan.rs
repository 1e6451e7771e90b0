//! A minimal Vulkan compute host for the shader checks: one instance and
//! device on the first physical device with a compute queue, kernels with
//! storage buffers at bindings `0..n` (the last one written back) and four
//! `u32` push constants. The loader is opened at run time (`ash`'s `loaded`
//! feature); nothing links Vulkan at build time.
//!
//! Vulkan calls are FFI and `unsafe`: this module is the only place of the
//! lab that allows it, for calls whose arguments it builds itself (handles
//! it created, slices it owns for the duration of each call).
#![allow(unsafe_code)]

use ash::vk;

/// The device, its compute queue and a command pool.
pub struct Gpu {
    // Kept alive: the instance and device are loaded through it.
    _entry: ash::Entry,
    instance: ash::Instance,
    device: ash::Device,
    queue: vk::Queue,
    pool: vk::CommandPool,
    memory: vk::PhysicalDeviceMemoryProperties,
    /// `deviceName (driver version, Vulkan version)`.
    pub name: String,
}

/// A compute pipeline with `bindings` storage buffers and 16 bytes of push
/// constants.
pub struct Kernel {
    module: vk::ShaderModule,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    bindings: usize,
}

struct Buffer {
    handle: vk::Buffer,
    memory: vk::DeviceMemory,
    bytes: u64,
}

fn check(result: Result<(), vk::Result>, what: &str) -> Result<(), String> {
    result.map_err(|e| format!("{what}: {e}"))
}

impl Gpu {
    /// The first Vulkan device with a compute queue, or why there is none.
    pub fn new() -> Result<Gpu, String> {
        // SAFETY: loading the system's Vulkan loader library; its
        // initialisation has no preconditions on this program.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| format!("no Vulkan loader (libvulkan.so.1): {e}"))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"micromap-index shader check")
            .api_version(vk::make_api_version(0, 1, 2, 0));
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        // SAFETY: `info` and `app` outlive the call.
        let instance = unsafe { entry.create_instance(&info, None) }.map_err(|e| {
            format!("no Vulkan device: vkCreateInstance: {e} (Debian: mesa-vulkan-drivers)")
        })?;
        match Gpu::open(entry.clone(), &instance) {
            Ok(gpu) => Ok(gpu),
            Err(e) => {
                // SAFETY: nothing was created from the instance that lives on.
                unsafe { instance.destroy_instance(None) };
                Err(e)
            }
        }
    }

    fn open(entry: ash::Entry, instance: &ash::Instance) -> Result<Gpu, String> {
        // SAFETY: a valid instance.
        let devices = unsafe { instance.enumerate_physical_devices() }
            .map_err(|e| format!("vkEnumeratePhysicalDevices: {e}"))?;
        let Some(&physical) = devices.first() else {
            return Err("no Vulkan device (no ICD found: install mesa-vulkan-drivers)".into());
        };
        // SAFETY: a physical device of this instance.
        let (props, families, memory) = unsafe {
            (
                instance.get_physical_device_properties(physical),
                instance.get_physical_device_queue_family_properties(physical),
                instance.get_physical_device_memory_properties(physical),
            )
        };
        let name = props
            .device_name_as_c_str()
            .unwrap_or(c"?")
            .to_string_lossy()
            .into_owned();
        let v = props.api_version;
        // The driver's own name and version (Vulkan 1.2), e.g. "llvmpipe ...
        // (Mesa 25.0.7 ...)": what reports must name.
        let mut driver = String::new();
        if v >= vk::API_VERSION_1_2 {
            let mut about = vk::PhysicalDeviceDriverProperties::default();
            let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut about);
            // SAFETY: a physical device of a Vulkan 1.2 instance, a valid chain.
            unsafe { instance.get_physical_device_properties2(physical, &mut props2) };
            let text = |c: Result<&std::ffi::CStr, _>| {
                c.map_or_else(
                    |_| "?".into(),
                    |c: &std::ffi::CStr| c.to_string_lossy().into_owned(),
                )
            };
            driver = format!(
                ", {} {}",
                text(about.driver_name_as_c_str()),
                text(about.driver_info_as_c_str())
            );
        }
        let name = format!(
            "{name} (Vulkan {}.{}.{}{driver})",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        );
        let family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
            .ok_or_else(|| format!("{name}: no compute queue"))? as u32;
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let info = vk::DeviceCreateInfo::default().queue_create_infos(&queues);
        // SAFETY: `info` and what it points to outlive the call.
        let device = unsafe { instance.create_device(physical, &info, None) }
            .map_err(|e| format!("vkCreateDevice: {e}"))?;
        // SAFETY: the family exists and has one queue.
        let queue = unsafe { device.get_device_queue(family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: a valid device and create info.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }
            .map_err(|e| format!("vkCreateCommandPool: {e}"))?;
        Ok(Gpu {
            _entry: entry,
            instance: instance.clone(),
            device,
            queue,
            pool,
            memory,
            name,
        })
    }

    /// A kernel from SPIR-V words with `bindings` storage buffers.
    pub fn kernel(&self, spirv: &[u32], bindings: usize) -> Result<Kernel, String> {
        let d = &self.device;
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        // SAFETY: valid SPIR-V (spirv-val accepted it) that outlives the call.
        let module = unsafe { d.create_shader_module(&info, None) }
            .map_err(|e| format!("vkCreateShaderModule: {e}"))?;
        let layout_bindings: Vec<_> = (0..bindings as u32)
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let set_info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY: the bindings outlive the call.
        let set_layout = unsafe { d.create_descriptor_set_layout(&set_info, None) }
            .map_err(|e| format!("vkCreateDescriptorSetLayout: {e}"))?;
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .offset(0)
            .size(16)];
        let set_layouts = [set_layout];
        let layout_info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&ranges);
        // SAFETY: as above.
        let layout = unsafe { d.create_pipeline_layout(&layout_info, None) }
            .map_err(|e| format!("vkCreatePipelineLayout: {e}"))?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main");
        let pipeline_info = [vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout)];
        // SAFETY: the module and layout are valid; the infos outlive the call.
        let pipeline =
            unsafe { d.create_compute_pipelines(vk::PipelineCache::null(), &pipeline_info, None) }
                .map_err(|(_, e)| format!("vkCreateComputePipelines: {e}"))?[0];
        Ok(Kernel {
            module,
            set_layout,
            layout,
            pipeline,
            bindings,
        })
    }

    fn buffer(&self, words: usize) -> Result<Buffer, String> {
        let d = &self.device;
        // Never empty: a zero-sized buffer is invalid; the shader sees one
        // word more only where the caller gave none.
        let bytes = 4 * words.max(1) as u64;
        let info = vk::BufferCreateInfo::default()
            .size(bytes)
            .usage(vk::BufferUsageFlags::STORAGE_BUFFER)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: a valid device and create info.
        let buffer = unsafe { d.create_buffer(&info, None) }
            .map_err(|e| format!("vkCreateBuffer ({bytes} bytes): {e}"))?;
        // SAFETY: the buffer was just created on this device.
        let needs = unsafe { d.get_buffer_memory_requirements(buffer) };
        let wanted = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let types = &self.memory.memory_types[..self.memory.memory_type_count as usize];
        let Some(index) = types.iter().enumerate().position(|(i, t)| {
            needs.memory_type_bits & (1 << i) != 0 && t.property_flags.contains(wanted)
        }) else {
            // SAFETY: unused buffer of this device.
            unsafe { d.destroy_buffer(buffer, None) };
            return Err("no host-visible coherent memory type".into());
        };
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(needs.size)
            .memory_type_index(index as u32);
        // SAFETY: a valid allocate info.
        let memory = unsafe { d.allocate_memory(&alloc, None) }
            .map_err(|e| format!("vkAllocateMemory ({} bytes): {e}", needs.size))?;
        // SAFETY: memory of a type the buffer accepts, large enough, unbound.
        check(
            unsafe { d.bind_buffer_memory(buffer, memory, 0) },
            "vkBindBufferMemory",
        )?;
        Ok(Buffer {
            handle: buffer,
            memory,
            bytes,
        })
    }

    fn write(&self, buffer: &Buffer, words: &[u32]) -> Result<(), String> {
        // SAFETY: host-visible memory bound to `buffer`, mapped whole, of
        // `buffer.bytes` >= 4 * words.len() bytes; unmapped before return.
        unsafe {
            let at = self
                .device
                .map_memory(buffer.memory, 0, buffer.bytes, vk::MemoryMapFlags::empty())
                .map_err(|e| format!("vkMapMemory: {e}"))?;
            let at = at.cast::<u32>();
            std::ptr::write_bytes(at, 0, buffer.bytes as usize / 4);
            std::ptr::copy_nonoverlapping(words.as_ptr(), at, words.len());
            self.device.unmap_memory(buffer.memory);
        }
        Ok(())
    }

    fn read(&self, buffer: &Buffer, words: usize) -> Result<Vec<u32>, String> {
        let mut out = vec![0u32; words];
        // SAFETY: as in `write`; `words` <= the buffer's words.
        unsafe {
            let at = self
                .device
                .map_memory(buffer.memory, 0, buffer.bytes, vk::MemoryMapFlags::empty())
                .map_err(|e| format!("vkMapMemory: {e}"))?;
            std::ptr::copy_nonoverlapping(at.cast::<u32>(), out.as_mut_ptr(), words);
            self.device.unmap_memory(buffer.memory);
        }
        Ok(out)
    }

    fn free(&self, buffer: &Buffer) {
        // SAFETY: the buffer is no longer used by any pending command.
        unsafe {
            self.device.destroy_buffer(buffer.handle, None);
            self.device.free_memory(buffer.memory, None);
        }
    }

    /// Runs `kernel` once: `inputs` at bindings `0..n-1`, an output of
    /// `out_words` words at the last binding (zeroed first), `push` as the
    /// push constants, and at least `invocations` invocations of 64-wide
    /// workgroups (in two dimensions past 4,096 groups: `x + y * width`).
    pub fn run(
        &self,
        kernel: &Kernel,
        inputs: &[&[u32]],
        out_words: usize,
        push: [u32; 4],
        invocations: u32,
    ) -> Result<Vec<u32>, String> {
        assert_eq!(
            inputs.len() + 1,
            kernel.bindings,
            "one input per binding but the last"
        );
        let d = &self.device;
        let mut buffers = Vec::new();
        let result = (|| {
            for words in inputs {
                let b = self.buffer(words.len())?;
                self.write(&b, words)?;
                buffers.push(b);
            }
            let out = self.buffer(out_words)?;
            self.write(&out, &[])?;
            buffers.push(out);

            let sizes = [vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(kernel.bindings as u32)];
            let pool_info = vk::DescriptorPoolCreateInfo::default()
                .max_sets(1)
                .pool_sizes(&sizes);
            // SAFETY: a valid create info.
            let pool = unsafe { d.create_descriptor_pool(&pool_info, None) }
                .map_err(|e| format!("vkCreateDescriptorPool: {e}"))?;
            let run = self.record_and_submit(kernel, pool, &buffers, push, invocations);
            // SAFETY: the submission finished (or never started).
            unsafe { d.destroy_descriptor_pool(pool, None) };
            run?;
            self.read(&buffers[buffers.len() - 1], out_words)
        })();
        for b in &buffers {
            self.free(b);
        }
        result
    }

    fn record_and_submit(
        &self,
        kernel: &Kernel,
        pool: vk::DescriptorPool,
        buffers: &[Buffer],
        push: [u32; 4],
        invocations: u32,
    ) -> Result<(), String> {
        let d = &self.device;
        let set_layouts = [kernel.set_layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&set_layouts);
        // SAFETY: a pool with room for this set.
        let set = unsafe { d.allocate_descriptor_sets(&alloc) }
            .map_err(|e| format!("vkAllocateDescriptorSets: {e}"))?[0];
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(b.handle)
                    .offset(0)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let writes: Vec<_> = infos
            .iter()
            .enumerate()
            .map(|(i, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(i as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: the set and buffers are valid; `infos` outlives the call.
        unsafe { d.update_descriptor_sets(&writes, &[]) };

        let groups = invocations.div_ceil(64).max(1);
        let width = groups.min(4096);
        let height = groups.div_ceil(width);
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: this device's pool, used from this thread only.
        let cb = unsafe { d.allocate_command_buffers(&alloc) }
            .map_err(|e| format!("vkAllocateCommandBuffers: {e}"))?[0];
        let push_bytes: Vec<u8> = push.iter().flat_map(|w| w.to_le_bytes()).collect();
        let barrier = [vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::SHADER_WRITE)
            .dst_access_mask(vk::AccessFlags::HOST_READ)];
        // SAFETY: recording into a fresh command buffer with handles of
        // this device; the push range matches the layout's.
        let submitted = unsafe {
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            check(d.begin_command_buffer(cb, &begin), "vkBeginCommandBuffer")?;
            d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, kernel.pipeline);
            d.cmd_bind_descriptor_sets(
                cb,
                vk::PipelineBindPoint::COMPUTE,
                kernel.layout,
                0,
                &[set],
                &[],
            );
            d.cmd_push_constants(
                cb,
                kernel.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                &push_bytes,
            );
            d.cmd_dispatch(cb, width, height, 1);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::PipelineStageFlags::HOST,
                vk::DependencyFlags::empty(),
                &barrier,
                &[],
                &[],
            );
            check(d.end_command_buffer(cb), "vkEndCommandBuffer")?;
            let fence = d
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .map_err(|e| format!("vkCreateFence: {e}"))?;
            let cbs = [cb];
            let submit = [vk::SubmitInfo::default().command_buffers(&cbs)];
            let done =
                check(d.queue_submit(self.queue, &submit, fence), "vkQueueSubmit").and_then(|()| {
                    check(
                        d.wait_for_fences(&[fence], true, u64::MAX),
                        "vkWaitForFences",
                    )
                });
            d.destroy_fence(fence, None);
            done
        };
        // SAFETY: the command buffer is no longer pending.
        unsafe { d.free_command_buffers(self.pool, &[cb]) };
        submitted
    }

    /// Destroys a kernel.
    pub fn drop_kernel(&self, kernel: &Kernel) {
        // SAFETY: no pending command uses it (every run waits).
        unsafe {
            let d = &self.device;
            d.destroy_pipeline(kernel.pipeline, None);
            d.destroy_pipeline_layout(kernel.layout, None);
            d.destroy_descriptor_set_layout(kernel.set_layout, None);
            d.destroy_shader_module(kernel.module, None);
        }
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: every run waited for its work; objects go in reverse order.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}
