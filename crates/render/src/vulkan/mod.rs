//! The one Vulkan host of the workspace: the render check traces on it and
//! the lab's shader tests (`crates/lab/tests/shaders.rs`) run their compute
//! kernels on it. One file per Vulkan object's lifetime, after wgpu-hal's
//! layout:
//!
//! - `instance.rs`: the loader (opened at run time, `ash`'s `loaded`
//!   feature: nothing links Vulkan at build time) and the instance;
//! - `adapter.rs`: the physical devices, what each has ([`DeviceInfo`])
//!   and the one a [`DeviceRequest`] picks;
//! - `device.rs`: the logical device with its queue and command pool, and
//!   submissions (each waited for);
//! - `memory.rs`: buffers in host-visible, coherent memory;
//! - `accel.rs`: bottom- and top-level acceleration structures;
//! - `pipeline.rs`: shader modules, layouts, the compute and ray tracing
//!   pipelines and the shader binding table;
//! - `trace.rs`: one dispatch or ray launch with its descriptor set, timed;
//!   the lab's compute kernels;
//! - `conv.rs`: `vk::Result` into [`RenderError`](crate::RenderError),
//!   driver strings and version words into text.
//!
//! Every object holds a reference-counted handle of the device it was made
//! on and destroys itself when dropped, so the device and instance go last
//! and an error part-way through leaves nothing behind. Vulkan calls are
//! FFI and `unsafe`: this module is the only place of the crate that allows
//! it, for calls whose arguments it builds itself (handles it created,
//! slices it owns for the duration of each call, memory it mapped whole);
//! every `unsafe` block says why it is sound. Objects are `!Send`: a
//! device's command pool and queue are used from one thread.
#![allow(unsafe_code)]

mod accel;
mod adapter;
mod conv;
mod device;
mod instance;
mod memory;
mod pipeline;
mod trace;

pub use device::Device;
pub use trace::ComputeKernel;

pub(crate) use accel::{AccelerationStructure, BlasInstance};
pub(crate) use memory::Buffer;
pub(crate) use pipeline::{Bindings, Pipeline, RayTracingStages};
pub(crate) use trace::Launch;

/// Device extensions (and their features) a request can name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Features {
    /// `VK_KHR_acceleration_structure` (with
    /// `VK_KHR_deferred_host_operations` and buffer device addresses).
    pub acceleration_structure: bool,
    /// `VK_KHR_ray_query`.
    pub ray_query: bool,
    /// `VK_KHR_ray_tracing_pipeline`.
    pub ray_tracing_pipeline: bool,
}

impl Features {
    /// Whether every feature of `self` is in `other`.
    #[must_use]
    pub fn within(self, other: Features) -> bool {
        (!self.acceleration_structure || other.acceleration_structure)
            && (!self.ray_query || other.ray_query)
            && (!self.ray_tracing_pipeline || other.ray_tracing_pipeline)
    }

    /// Whether any feature is asked for (which needs Vulkan 1.2).
    #[must_use]
    pub fn any(self) -> bool {
        self.acceleration_structure || self.ray_query || self.ray_tracing_pipeline
    }

    /// Both sets together.
    #[must_use]
    pub fn union(self, other: Features) -> Features {
        Features {
            acceleration_structure: self.acceleration_structure || other.acceleration_structure,
            ray_query: self.ray_query || other.ray_query,
            ray_tracing_pipeline: self.ray_tracing_pipeline || other.ray_tracing_pipeline,
        }
    }
}

/// Which device to open: the first with everything in `required` (and a
/// compute queue), with whatever of `optional` it has enabled too.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeviceRequest {
    /// Features the device must have.
    pub required: Features,
    /// Features enabled where the device has them.
    pub optional: Features,
}

/// What a physical device is: names and versions as its driver reports
/// them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeviceInfo {
    /// `deviceName`, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// `VkPhysicalDeviceDriverProperties::driverName` (Vulkan 1.2), e.g.
    /// `llvmpipe`; empty before 1.2.
    pub driver_name: String,
    /// `driverInfo`, e.g. `Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)`.
    pub driver_info: String,
    /// `driverVersion`, as the vendor encodes it.
    pub driver_version: u32,
    /// `apiVersion`: the Vulkan version the device supports.
    pub api_version: u32,
    /// `vendorID` (0x10de NVIDIA, 0x10005 Mesa's CPU devices).
    pub vendor_id: u32,
    /// `deviceID`.
    pub device_id: u32,
}

impl DeviceInfo {
    /// The device, its Vulkan version and driver in one line, e.g.
    /// `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan 1.4.305, llvmpipe Mesa
    /// 25.0.7-2~bpo12+1 (LLVM 15.0.6))` (without the driver before Vulkan
    /// 1.2).
    #[must_use]
    pub fn label(&self) -> String {
        let driver = if self.driver_name.is_empty() && self.driver_info.is_empty() {
            String::new()
        } else {
            format!(", {} {}", self.driver_name, self.driver_info)
        };
        format!(
            "{} (Vulkan {}{driver})",
            self.name,
            conv::version_text(self.api_version)
        )
    }
}
