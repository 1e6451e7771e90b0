//! Why rendering failed: [`RenderError`], one variant per cause, with the
//! failed Vulkan call's `vk::Result` kept as a value, and its
//! [`ErrorClass`] (what a front end makes of it: exit 4, 2 or 3 in the
//! CLI). The messages name what was found and what to install.

use crate::frame::MAX_PIXELS;
use crate::method::{Lookup, Method, Tracer};
use ash::vk;
use micromap_index::micromap::{BufferError, ReadError};
use micromap_index::succinct::TreeError;
use std::fmt;

/// What kind of failure a [`RenderError`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ErrorClass {
    /// No Vulkan loader, driver or device with what was asked for: nothing
    /// can be traced here (the CLI's exit 4).
    NoDevice,
    /// The scene, micromaps, camera or frame cannot be rendered as given
    /// (the CLI's exit 2).
    Input,
    /// A Vulkan call failed on a device that was there (the CLI's exit 3).
    Device,
}

/// Why a scene could not take a mesh ([`crate::Scene::add_mesh`]).
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SceneError {
    /// The mesh names a texture the scene does not have.
    NoTexture {
        /// The mesh's number.
        mesh: usize,
        /// The texture it named.
        texture: usize,
    },
    /// A texture without `width * height` alphas (or without texels).
    TextureSize {
        /// The texture.
        texture: usize,
        /// Its alphas.
        alphas: usize,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
    },
    /// Position and UV lists of different lengths.
    Lengths {
        /// The mesh's number.
        mesh: usize,
        /// Position triangles.
        positions: usize,
        /// UV triangles.
        uvs: usize,
    },
    /// A position or UV that is not finite.
    NotFinite {
        /// The mesh's number.
        mesh: usize,
        /// The triangle in the mesh.
        triangle: usize,
    },
    /// Vertex alphas for another number of triangles than the UVs.
    VertexAlphaLength {
        /// The mesh's number.
        mesh: usize,
        /// Vertex-alpha triangles.
        vertex_alpha: usize,
        /// UV triangles.
        uvs: usize,
    },
    /// A vertex alpha outside `[0, 1]` (or NaN).
    VertexAlpha {
        /// The mesh's number.
        mesh: usize,
        /// The triangle in the mesh.
        triangle: usize,
    },
    /// More than `2^24` triangles in all.
    TooManyTriangles,
    /// A transform that is not finite.
    Transform {
        /// The mesh's number.
        mesh: usize,
        /// The instance.
        instance: usize,
    },
    /// More than [`MAX_INSTANCES`](crate::MAX_INSTANCES) instances
    /// in all.
    TooManyInstances,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::NoTexture { mesh, texture } => {
                write!(f, "mesh {mesh}: no texture {texture}")
            }
            SceneError::TextureSize {
                texture,
                alphas,
                width,
                height,
            } => write!(f, "texture {texture}: {alphas} alphas for {width}x{height}"),
            SceneError::Lengths {
                mesh,
                positions,
                uvs,
            } => write!(
                f,
                "mesh {mesh}: {positions} positions for {uvs} UV triangles"
            ),
            SceneError::NotFinite { mesh, triangle } => write!(
                f,
                "mesh {mesh} triangle {triangle}: a position or UV is not finite"
            ),
            SceneError::VertexAlphaLength {
                mesh,
                vertex_alpha,
                uvs,
            } => write!(
                f,
                "mesh {mesh}: vertex alphas for {vertex_alpha} triangles, {uvs} UV triangles"
            ),
            SceneError::VertexAlpha { mesh, triangle } => write!(
                f,
                "mesh {mesh} triangle {triangle}: a vertex alpha outside [0, 1]"
            ),
            SceneError::TooManyTriangles => f.write_str("more than 2^24 triangles"),
            SceneError::Transform { mesh, instance } => write!(
                f,
                "mesh {mesh} instance {instance}: a transform that is not finite"
            ),
            SceneError::TooManyInstances => f.write_str("more than 2^20 mesh instances"),
        }
    }
}

impl std::error::Error for SceneError {}

/// Why rendering failed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum RenderError {
    /// The Vulkan loader (`libvulkan.so.1`) could not be opened (ash's
    /// message).
    NoLoader(String),
    /// `vkCreateInstance` failed: the loader found no driver.
    NoInstance(vk::Result),
    /// The instance has no physical device.
    NoPhysicalDevice,
    /// No physical device (or not the one selected) has what the request
    /// needs.
    NoSuitableDevice {
        /// The extensions the request names (besides Vulkan 1.2).
        needed: Vec<&'static str>,
        /// The devices considered and what each lacks (`Vulkan 1.2` or
        /// extension names).
        found: Vec<(String, Vec<&'static str>)>,
    },
    /// No physical device is the one a selector names.
    DeviceNotFound {
        /// The selector, as text (`number 3`, `named like "nvidia"`).
        selector: String,
        /// The devices there are, `N: name`.
        found: Vec<String>,
    },
    /// The device's driver cannot take a micromap this deep.
    MicromapLevel {
        /// The record.
        record: usize,
        /// Its level.
        level: u32,
        /// Its format's states (2 or 4).
        states: u32,
        /// The device's most.
        max: u32,
    },
    /// `VK_EXT_opacity_micromap` takes 16- and 32-bit indices only.
    MicromapIndexWidth,
    /// The chosen device has no compute queue.
    NoComputeQueue {
        /// The device.
        device: String,
    },
    /// `vkCreateDevice` failed.
    DeviceCreation {
        /// The device.
        device: String,
        /// What the driver said.
        result: vk::Result,
    },
    /// A tracer that the device does not have was asked for.
    NoTracer {
        /// The device.
        device: String,
        /// The tracer.
        tracer: Tracer,
    },
    /// A hardware method was asked of a renderer built without the
    /// driver's micromaps.
    NoHardwareMicromaps {
        /// The device.
        device: String,
    },
    /// A Vulkan call failed.
    Vulkan {
        /// The call, e.g. `vkCreateBuffer`.
        call: &'static str,
        /// What the driver said.
        result: vk::Result,
    },
    /// `vkAllocateMemory` failed for this many bytes.
    Allocation {
        /// The size asked for.
        bytes: u64,
        /// What the driver said.
        result: vk::Result,
    },
    /// The device has no host-visible, coherent memory type for a buffer.
    NoHostVisibleMemory,
    /// The scene could not take a mesh.
    Scene(SceneError),
    /// The micromap files were refused (`micromap::read_buffers`).
    Micromaps(ReadError),
    /// A bake's buffers gave no index buffer.
    MicromapBuffers(BufferError),
    /// Not one micromap index per scene triangle.
    IndexCount {
        /// Indices in the micromaps.
        indices: usize,
        /// Triangles in the scene.
        triangles: usize,
    },
    /// A micromap record has no succinct tree encoding.
    Tree {
        /// The record.
        record: usize,
        /// Why.
        error: TreeError,
    },
    /// A camera with points not finite or not apart, a field of view
    /// outside `(0, 180)` degrees, or looking straight up or down.
    Camera {
        /// Its eye.
        eye: [f32; 3],
        /// Its target.
        target: [f32; 3],
        /// Its field of view.
        fov_y_degrees: f32,
    },
    /// A frame size without pixels or over [`MAX_PIXELS`].
    Size {
        /// Pixels per row.
        width: u32,
        /// Rows.
        height: u32,
    },
    /// A micromap method was asked for without micromaps.
    NeedsMicromaps(Method),
    /// The device lacks what the sampler lookup's array of combined image
    /// samplers needs (`runtimeDescriptorArray`,
    /// `shaderSampledImageArrayNonUniformIndexing`).
    SamplerIndexing {
        /// The device.
        device: String,
    },
    /// A mesh samples with mirror clamp to edge and the device has no
    /// `samplerMirrorClampToEdge` (sampler lookup).
    SamplerMirrorClamp {
        /// The device.
        device: String,
        /// The mesh.
        mesh: usize,
    },
    /// A mesh clamps to a border whose alpha no Vulkan border colour has
    /// (the sampler lookup takes 0, `VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK`,
    /// and 1, `VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE`).
    SamplerBorder {
        /// The mesh.
        mesh: usize,
        /// Its border alpha.
        alpha: f32,
    },
    /// A texture with an alpha that is no `c / 255`, which the sampler
    /// lookup's `R8_UNORM` image cannot hold.
    SamplerTexture {
        /// The texture.
        texture: usize,
        /// Its first such texel, `(x, y)`.
        texel: (u32, u32),
        /// Its alpha.
        alpha: f32,
    },
    /// A lookup the renderer was not built with.
    NoLookup(Lookup),
}

impl RenderError {
    /// What kind of failure this is.
    #[must_use]
    pub fn class(&self) -> ErrorClass {
        match self {
            RenderError::NoLoader(_)
            | RenderError::NoInstance(_)
            | RenderError::NoPhysicalDevice
            | RenderError::NoSuitableDevice { .. }
            | RenderError::DeviceNotFound { .. }
            | RenderError::NoComputeQueue { .. }
            | RenderError::DeviceCreation { .. }
            | RenderError::NoTracer { .. }
            | RenderError::NoHardwareMicromaps { .. }
            | RenderError::SamplerIndexing { .. }
            | RenderError::SamplerMirrorClamp { .. } => ErrorClass::NoDevice,
            RenderError::Vulkan { .. }
            | RenderError::Allocation { .. }
            | RenderError::NoHostVisibleMemory => ErrorClass::Device,
            RenderError::Scene(_)
            | RenderError::Micromaps(_)
            | RenderError::MicromapBuffers(_)
            | RenderError::IndexCount { .. }
            | RenderError::Tree { .. }
            | RenderError::Camera { .. }
            | RenderError::Size { .. }
            | RenderError::NeedsMicromaps(_)
            | RenderError::MicromapLevel { .. }
            | RenderError::MicromapIndexWidth
            | RenderError::SamplerBorder { .. }
            | RenderError::SamplerTexture { .. }
            | RenderError::NoLookup(_) => ErrorClass::Input,
        }
    }
}

/// `a`, `a and b`, `a, b and c`.
fn listed(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::NoLoader(e) => write!(
                f,
                "no Vulkan loader (libvulkan.so.1): {e} (Debian: apt-get install libvulkan1 mesa-vulkan-drivers)"
            ),
            RenderError::NoInstance(e) => write!(
                f,
                "no Vulkan device: vkCreateInstance: {e} (Debian: mesa-vulkan-drivers)"
            ),
            RenderError::NoPhysicalDevice => f.write_str(
                "no Vulkan device (no ICD found: Debian: mesa-vulkan-drivers from bookworm-backports)",
            ),
            RenderError::NoSuitableDevice { needed, found } => {
                let lacking: Vec<String> = found
                    .iter()
                    .map(|(name, lacks)| format!("{name} without {}", listed(lacks)))
                    .collect();
                write!(
                    f,
                    "no Vulkan device with {} (found: {})",
                    listed(needed),
                    lacking.join("; ")
                )?;
                let lacks = |name| found.iter().any(|(_, l)| l.contains(&name));
                if lacks("VK_EXT_opacity_micromap") {
                    f.write_str(
                        "; no CPU Vulkan driver has VK_EXT_opacity_micromap (Mesa's lavapipe neither)",
                    )?;
                }
                if ["Vulkan 1.2", "VK_KHR_acceleration_structure", "VK_KHR_ray_query"]
                    .into_iter()
                    .any(lacks)
                {
                    f.write_str("; lavapipe has ray queries from Mesa 25, Debian bookworm-backports")?;
                }
                Ok(())
            }
            RenderError::DeviceNotFound { selector, found } => write!(
                f,
                "no Vulkan device {selector} (found: {})",
                found.join(", ")
            ),
            RenderError::MicromapLevel {
                record,
                level,
                states,
                max,
            } => write!(
                f,
                "micromaps: record {record} has level {level}, above the device's most for {states}-state micromaps, {max}"
            ),
            RenderError::MicromapIndexWidth => f.write_str(
                "micromaps: VK_EXT_opacity_micromap takes 16- and 32-bit indices only (8-bit given)",
            ),
            RenderError::NoComputeQueue { device } => write!(f, "{device}: no compute queue"),
            RenderError::DeviceCreation { device, result } => {
                write!(f, "{device}: vkCreateDevice: {result}")
            }
            RenderError::NoTracer { device, tracer } => write!(
                f,
                "{device}: no {} tracer was built",
                tracer.name()
            ),
            RenderError::NoHardwareMicromaps { device } => write!(
                f,
                "{device}: the driver's micromaps were not built (they need VK_EXT_opacity_micromap)"
            ),
            RenderError::Vulkan { call, result } => write!(f, "{call}: {result}"),
            RenderError::Allocation { bytes, result } => {
                write!(f, "vkAllocateMemory ({bytes} bytes): {result}")
            }
            RenderError::NoHostVisibleMemory => f.write_str("no host-visible coherent memory type"),
            RenderError::Scene(e) => e.fmt(f),
            RenderError::Micromaps(e) => write!(f, "micromaps: {e}"),
            RenderError::MicromapBuffers(e) => e.fmt(f),
            RenderError::IndexCount { indices, triangles } => {
                write!(f, "micromaps: {indices} indices for {triangles} triangles")
            }
            RenderError::Tree { record, error } => write!(f, "record {record}: {error}"),
            RenderError::Camera {
                eye,
                target,
                fov_y_degrees,
            } => write!(
                f,
                "camera Camera {{ eye: {eye:?}, target: {target:?}, fov_y_degrees: {fov_y_degrees:?} }}: expected finite points apart and a field of view in (0, 180) degrees, not looking straight up or down"
            ),
            RenderError::Size { width, height } => {
                write!(f, "size {width}x{height}: expected 1..={MAX_PIXELS} pixels")
            }
            RenderError::NeedsMicromaps(method) => write!(f, "{} needs micromaps", method.name()),
            RenderError::SamplerIndexing { device } => write!(
                f,
                "{device}: the sampler lookup needs runtimeDescriptorArray and shaderSampledImageArrayNonUniformIndexing (Vulkan 1.2), which the device lacks (--lookup shader samples in the shader)"
            ),
            RenderError::SamplerMirrorClamp { device, mesh } => write!(
                f,
                "{device}: mesh {mesh} samples with mirror clamp to edge and the device has no samplerMirrorClampToEdge, so the sampler lookup cannot read it (--lookup shader samples in the shader)"
            ),
            RenderError::SamplerBorder { mesh, alpha } => write!(
                f,
                "mesh {mesh}: clamp to border with border alpha {alpha}: the sampler lookup takes border alpha 0 (VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK) or 1 (VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE) only (--lookup shader samples any)"
            ),
            RenderError::SamplerTexture {
                texture,
                texel: (x, y),
                alpha,
            } => write!(
                f,
                "texture {texture}: texel ({x}, {y}) has alpha {alpha}, no c / 255: the sampler lookup's R8_UNORM image cannot hold it (--lookup shader reads it as it is)"
            ),
            RenderError::NoLookup(lookup) => write!(
                f,
                "the {} lookup was not built (RendererOptions::lookups)",
                lookup.name()
            ),
        }
    }
}

impl std::error::Error for RenderError {}

impl From<SceneError> for RenderError {
    fn from(e: SceneError) -> RenderError {
        RenderError::Scene(e)
    }
}
