//! The render check of micromap-index: opacity micromaps consumed by a real
//! ray tracer. A [`Renderer`] puts a [`Scene`] (alpha-masked meshes, their
//! textures and materials, placed by their instances' transforms) and
//! optionally [`Micromaps`] (the buffers `micromap-index bake` writes) on a
//! Vulkan device with acceleration structures, then traces one primary ray
//! per pixel with a [`Tracer`]: `GL_EXT_ray_query`, deciding every
//! candidate in the `rayQueryProceedEXT` loop, or a
//! `VK_KHR_ray_tracing_pipeline` pipeline, deciding it in the any-hit
//! shader (both by the same shader code, `shaders/render_common.glsl`; each
//! needs only its own extension), by a [`Method`]: the alpha test alone, a
//! micromap emulated in software (flat 4-state, flat forced 2-state, the
//! level-order tree, the paper's Algorithm 3, using the shader library in
//! `shaders/glsl`), or the driver's own micromap (`VK_EXT_opacity_micromap`,
//! built from the same buffers; as baked or forced to 2 states). The alpha
//! test reads the texture by a [`Lookup`]: the shader's own binary32 code,
//! or the device's texture unit through a combined image sampler.
//!
//! A [`Frame`] holds the committed hit of every pixel, the [`Counters`]
//! (rays, candidates, texture fetches, known and unknown decisions,
//! contradicted candidates), the first contradictions in pixel order, which
//! [`classify`] explains exactly on the host, and its times (CPU, wall,
//! and the device's timestamps).
//!
//! [`vulkan`] is the host (the lab's shader tests run their kernels on it
//! too). The loader is opened at run time (`ash`'s `loaded` feature):
//! without a device with what [`RendererOptions`] asks for,
//! [`Renderer::new`] returns an error of class [`ErrorClass::NoDevice`].
//! `micromap-index render` is the command (docs/render.md).
//!
//! ```
//! use micromap_index_render::{Camera, Method, Tracer};
//! assert_eq!(Method::ALL.len(), 7);
//! assert_eq!(Tracer::from_name("pipeline"), Some(Tracer::Pipeline));
//! assert!(Method::Flat4.is_four_state() && !Method::Flat2.is_four_state());
//! let camera = Camera::framing([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]], 1.0);
//! assert!(camera.eye[2] > 0.0);
//! ```

mod camera;
mod classify;
mod error;
mod frame;
mod method;
mod renderer;
mod scene;
mod spirv;
pub mod tables;
mod trees;
pub mod vulkan;

pub use camera::Camera;
pub use classify::{classify, classify_lookup, Classified, ContradictionClass};
pub use error::{ErrorClass, RenderError, SceneError};
pub use frame::{Contradiction, Counters, Frame, MAX_PIXELS};
pub use method::{Faults, Lookup, Method, Tracer};
pub use renderer::{Renderer, RendererOptions};
pub use scene::{
    LevelCounts, Micromaps, Scene, SceneMesh, SceneTexture, IDENTITY_TRANSFORM, MAX_INSTANCES,
};
