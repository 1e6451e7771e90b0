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
//! - `image.rs`: the sampler lookup's images (a texture's alphas as
//!   `R8_UNORM`, uploaded once) and their views;
//! - `sampler.rs`: the sampler lookup's samplers (filter, address modes,
//!   border colour);
//! - `micromap.rs`: opacity micromaps built by the driver
//!   (`VK_EXT_opacity_micromap`) from a bake's buffers;
//! - `accel.rs`: bottom- and top-level acceleration structures, a
//!   micromap attached where asked;
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
mod image;
mod instance;
mod memory;
mod micromap;
mod pipeline;
mod sampler;
mod trace;

pub use device::Device;
pub use trace::ComputeKernel;

pub(crate) use accel::{AccelerationStructure, BlasInstance, MicromapAttachment};
pub(crate) use image::Image;
pub(crate) use memory::Buffer;
pub(crate) use micromap::Micromap;
pub(crate) use pipeline::{Bindings, Pipeline, RayTracingStages};
pub(crate) use sampler::{Sampler, SamplerKey};
pub(crate) use trace::{Launch, Timing};

use std::fmt;
use std::str::FromStr;

/// Device extensions (and their features) a request can name.
// Independent switches, as Vulkan's own feature structs are.
#[allow(clippy::struct_excessive_bools)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Features {
    /// `VK_KHR_acceleration_structure` (with
    /// `VK_KHR_deferred_host_operations` and buffer device addresses).
    pub acceleration_structure: bool,
    /// `VK_KHR_ray_query`.
    pub ray_query: bool,
    /// `VK_KHR_ray_tracing_pipeline`.
    pub ray_tracing_pipeline: bool,
    /// `VK_EXT_opacity_micromap` with its `micromap` feature (and
    /// `VK_KHR_synchronization2`, which it needs).
    pub opacity_micromap: bool,
}

impl Features {
    /// The features of `self` that `other` lacks.
    #[must_use]
    pub fn minus(self, other: Features) -> Features {
        Features {
            acceleration_structure: self.acceleration_structure && !other.acceleration_structure,
            ray_query: self.ray_query && !other.ray_query,
            ray_tracing_pipeline: self.ray_tracing_pipeline && !other.ray_tracing_pipeline,
            opacity_micromap: self.opacity_micromap && !other.opacity_micromap,
        }
    }

    /// The features in both.
    #[must_use]
    pub fn and(self, other: Features) -> Features {
        Features {
            acceleration_structure: self.acceleration_structure && other.acceleration_structure,
            ray_query: self.ray_query && other.ray_query,
            ray_tracing_pipeline: self.ray_tracing_pipeline && other.ray_tracing_pipeline,
            opacity_micromap: self.opacity_micromap && other.opacity_micromap,
        }
    }

    /// The features in either.
    #[must_use]
    pub fn union(self, other: Features) -> Features {
        Features {
            acceleration_structure: self.acceleration_structure || other.acceleration_structure,
            ray_query: self.ray_query || other.ray_query,
            ray_tracing_pipeline: self.ray_tracing_pipeline || other.ray_tracing_pipeline,
            opacity_micromap: self.opacity_micromap || other.opacity_micromap,
        }
    }

    /// Whether there is none.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self == Features::default()
    }

    /// The extension names, in the order messages list them.
    #[must_use]
    pub fn names(self) -> Vec<&'static str> {
        let mut names = Vec::new();
        for (on, name) in [
            (self.acceleration_structure, "VK_KHR_acceleration_structure"),
            (self.ray_query, "VK_KHR_ray_query"),
            (self.ray_tracing_pipeline, "VK_KHR_ray_tracing_pipeline"),
            (self.opacity_micromap, "VK_EXT_opacity_micromap"),
        ] {
            if on {
                names.push(name);
            }
        }
        names
    }
}

/// Which physical device a request means: its number in the loader's
/// order, or a part of its name (any case).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DeviceSelector {
    /// The `n`-th physical device, from 0.
    Index(usize),
    /// The first physical device whose name contains this (any case).
    Name(String),
}

impl DeviceSelector {
    /// Whether the `index`-th device, named `name`, is meant.
    #[must_use]
    pub fn matches(&self, index: usize, name: &str) -> bool {
        match self {
            DeviceSelector::Index(n) => *n == index,
            DeviceSelector::Name(part) => name.to_lowercase().contains(&part.to_lowercase()),
        }
    }
}

impl FromStr for DeviceSelector {
    type Err = String;

    /// Digits: an index; other text: a part of a name; empty text refused.
    fn from_str(text: &str) -> Result<DeviceSelector, String> {
        if text.is_empty() {
            return Err("expected a device number or a part of its name".into());
        }
        if text.bytes().all(|b| b.is_ascii_digit()) {
            return text
                .parse()
                .map(DeviceSelector::Index)
                .map_err(|_| "a device number too large".to_string());
        }
        Ok(DeviceSelector::Name(text.to_string()))
    }
}

impl fmt::Display for DeviceSelector {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DeviceSelector::Index(n) => write!(f, "number {n}"),
            DeviceSelector::Name(part) => write!(f, "named like {part:?}"),
        }
    }
}

/// Which device to open: the first (or the one `select` names) with
/// everything in `required` (and a compute queue), with whatever of
/// `optional` it has enabled too.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeviceRequest {
    /// The device to open (default: the first that has `required`).
    pub select: Option<DeviceSelector>,
    /// Features the device must have.
    pub required: Features,
    /// Features enabled where the device has them.
    pub optional: Features,
    /// Whether to enable what the sampler lookup needs where the device
    /// has it ([`DeviceInfo::sampler_lookup`]: `runtimeDescriptorArray`,
    /// `shaderSampledImageArrayNonUniformIndexing`; and
    /// `samplerMirrorClampToEdge` where [`DeviceInfo::mirror_clamp_to_edge`]).
    pub sampler_lookup: bool,
}

/// What a physical device is: names and versions as its driver reports
/// them, and the ray tracing extensions it has.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeviceInfo {
    /// Its number in the loader's order.
    pub index: usize,
    /// `deviceName`, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// `VkPhysicalDeviceDriverProperties::driverName` (Vulkan 1.2), e.g.
    /// `llvmpipe`; empty before 1.2.
    pub driver_name: String,
    /// `driverInfo`, e.g. `Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)`.
    pub driver_info: String,
    /// `driverVersion`, as the vendor encodes it
    /// ([`DeviceInfo::driver_version_text`]).
    pub driver_version: u32,
    /// `apiVersion`: the Vulkan version the device supports.
    pub api_version: u32,
    /// `vendorID` (0x10de NVIDIA, 0x10005 Mesa's CPU devices).
    pub vendor_id: u32,
    /// `deviceID`.
    pub device_id: u32,
    /// The features of [`Features`] it has.
    pub has: Features,
    /// Whether it lists `VK_KHR_opacity_micromap` (not used: `ash` 0.38 has
    /// no bindings for it; [`Features::opacity_micromap`] is the EXT one).
    pub khr_opacity_micromap: bool,
    /// `maxOpacity2StateSubdivisionLevel` and
    /// `maxOpacity4StateSubdivisionLevel`, where it has
    /// `VK_EXT_opacity_micromap`.
    pub max_micromap_levels: Option<[u32; 2]>,
    /// Whether it has what the sampler lookup's array of combined image
    /// samplers, indexed per mesh, needs (Vulkan 1.2's
    /// `runtimeDescriptorArray` and
    /// `shaderSampledImageArrayNonUniformIndexing`).
    pub sampler_lookup: bool,
    /// Whether it has `samplerMirrorClampToEdge` (Vulkan 1.2).
    pub mirror_clamp_to_edge: bool,
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

    /// The Vulkan version as `major.minor.patch`.
    #[must_use]
    pub fn api_version_text(&self) -> String {
        conv::version_text(self.api_version)
    }

    /// `driverVersion` decoded as its vendor encodes it: NVIDIA's
    /// `10.8.8.6` bits (`580.95.5.0`), else Vulkan's `major.minor.patch`.
    #[must_use]
    pub fn driver_version_text(&self) -> String {
        let v = self.driver_version;
        if self.vendor_id == 0x10de {
            format!(
                "{}.{}.{}.{}",
                v >> 22,
                (v >> 14) & 0xff,
                (v >> 6) & 0xff,
                v & 0x3f
            )
        } else {
            conv::version_text(v)
        }
    }
}
