//! The [`Renderer`]: a scene and its micromaps on a Vulkan device (the
//! inputs in storage buffers, a BLAS of the triangles and a TLAS with one
//! instance of it, the tracers' pipelines), and one traced [`Frame`] per
//! [`Renderer::render`].

use crate::camera::Camera;
use crate::error::RenderError;
use crate::frame::{Frame, COUNTER_WORDS, MAX_PIXELS, RECORD_WORDS};
use crate::method::{Faults, Method, Tracer};
use crate::scene::{Micromaps, Scene};
use crate::spirv;
use crate::trees::tree_buffers;
use crate::vulkan::{
    AccelerationStructure, Bindings, BlasInstance, Buffer, Device, DeviceRequest, Features, Launch,
    Pipeline, RayTracingStages,
};
use ash::vk;

/// Storage buffers of the tracers, bindings `1..=STORAGE_BINDINGS` (the
/// acceleration structure is binding 0): the scene and micromaps (1..=9),
/// the pixels and the counters.
const STORAGE_BINDINGS: u32 = 11;
/// Push-constant bytes (8 words, 4 `vec4`).
const PUSH_BYTES: u32 = 96;
/// The tracers' descriptor set and push constants.
const BINDINGS: Bindings = Bindings {
    acceleration_structure: true,
    storage: STORAGE_BINDINGS,
    push_bytes: PUSH_BYTES,
};

/// A scene on the device, ready to trace.
pub struct Renderer {
    device: Device,
    /// The ray query tracer's compute pipeline.
    query: Option<Pipeline>,
    /// The ray tracing pipeline, where the device has one.
    ray_tracing: Option<Pipeline>,
    tlas: AccelerationStructure,
    // Instanced by the TLAS: kept while it is.
    _blas: AccelerationStructure,
    /// Bindings 1..=9 (scene and micromaps).
    inputs: Vec<Buffer>,
    has_micromaps: bool,
    index_width: u32,
}

fn words_to_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

impl Renderer {
    /// Opens the first Vulkan device with ray queries (and builds the
    /// [`Tracer::Pipeline`] tracer where it has `VK_KHR_ray_tracing_pipeline`:
    /// [`Renderer::tracers`]) and puts `scene` and
    /// `micromaps` (one index per scene triangle; `None`: only
    /// [`Method::AlphaTest`] can be traced) on it.
    pub fn new(scene: &Scene, micromaps: Option<&Micromaps>) -> Result<Renderer, RenderError> {
        if let Some(m) = micromaps {
            m.check_for(scene)?;
        }
        let device = Device::open(&DeviceRequest {
            required: Features {
                acceleration_structure: true,
                ray_query: true,
                ray_tracing_pipeline: false,
            },
            optional: Features {
                ray_tracing_pipeline: true,
                ..Features::default()
            },
        })?;
        let query = Some(device.compute_pipeline(&spirv::query(), BINDINGS)?);
        let ray_tracing = if device.enabled().ray_tracing_pipeline {
            let [raygen, miss, closest_hit, any_hit] = spirv::pipeline();
            let stages = RayTracingStages {
                raygen: &raygen,
                miss: &miss,
                closest_hit: &closest_hit,
                any_hit: &any_hit,
            };
            Some(device.ray_tracing_pipeline(&stages, BINDINGS)?)
        } else {
            None
        };
        let vertices: Vec<[f32; 3]> = scene.positions().iter().flatten().copied().collect();
        let blas = device.triangle_blas(&vertices)?;
        let tlas = device.tlas(&[BlasInstance {
            blas: &blas,
            transform: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0],
            custom_index: 0,
            flags: vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE,
        }])?;
        let (trees, dir) = match micromaps {
            Some(m) => tree_buffers(m)?,
            None => (Vec::new(), Vec::new()),
        };
        let empty: &[u8] = &[];
        let (data, records, indices) = micromaps.map_or((empty, empty, empty), |m| {
            (m.data(), m.records(), m.indices())
        });
        let contents: [Vec<u8>; 9] = [
            scene.uv_bytes(),
            scene.mesh_of_bytes(),
            scene.mesh_info_bytes(),
            scene.texel_bytes(),
            data.to_vec(),
            records.to_vec(),
            indices.to_vec(),
            words_to_bytes(&trees),
            words_to_bytes(&dir),
        ];
        let mut inputs = Vec::new();
        for bytes in &contents {
            let b = device.buffer(bytes.len() as u64, vk::BufferUsageFlags::STORAGE_BUFFER)?;
            b.write(0, bytes)?;
            inputs.push(b);
        }
        let renderer = Renderer {
            device,
            query,
            ray_tracing,
            tlas,
            _blas: blas,
            inputs,
            has_micromaps: micromaps.is_some(),
            index_width: micromaps.map_or(4, Micromaps::index_width_bytes),
        };
        // lavapipe compiles a pipeline at its first dispatch: one pixel
        // here keeps that out of every frame's time.
        for tracer in renderer.tracers() {
            renderer.render(
                tracer,
                Method::AlphaTest,
                &Camera::framing(scene.bounds().unwrap_or_default(), 1.0),
                (1, 1),
                Faults::default(),
                0,
            )?;
        }
        Ok(renderer)
    }

    /// The device, driver and Vulkan version, e.g. `llvmpipe (LLVM 15.0.6,
    /// 256 bits) (Vulkan 1.4.305, llvmpipe Mesa 25.0.7-2~bpo12+1 ...)`.
    #[must_use]
    pub fn device_name(&self) -> String {
        self.device.info().label()
    }

    /// The tracers this device has: [`Tracer::Query`] always, and
    /// [`Tracer::Pipeline`] where it has `VK_KHR_ray_tracing_pipeline`.
    #[must_use]
    pub fn tracers(&self) -> Vec<Tracer> {
        let mut t = Vec::new();
        if self.query.is_some() {
            t.push(Tracer::Query);
        }
        if self.ray_tracing.is_some() {
            t.push(Tracer::Pipeline);
        }
        t
    }

    /// Traces one `width x height` frame with `tracer` and `method`,
    /// keeping the first `max_records` contradictions;
    /// [`RenderError::NoTracer`] for a tracer not in [`Renderer::tracers`].
    pub fn render(
        &self,
        tracer: Tracer,
        method: Method,
        camera: &Camera,
        (width, height): (u32, u32),
        faults: Faults,
        max_records: u32,
    ) -> Result<Frame, RenderError> {
        if method != Method::AlphaTest && !self.has_micromaps {
            return Err(RenderError::NeedsMicromaps(method));
        }
        let chosen = match tracer {
            Tracer::Query => self.query.as_ref(),
            Tracer::Pipeline => self.ray_tracing.as_ref(),
        };
        let Some(pipeline) = chosen else {
            return Err(RenderError::NoTracer {
                device: self.device_name(),
                tracer,
            });
        };
        let pixels = u64::from(width) * u64::from(height);
        if width == 0 || height == 0 || pixels > MAX_PIXELS {
            return Err(RenderError::Size { width, height });
        }
        let max_records = max_records.min(1 << 16);
        let basis = camera.basis(width, height)?;
        let d = &self.device;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let hits = d.buffer(8 * pixels, usage)?;
        let counter_words = COUNTER_WORDS + RECORD_WORDS * max_records as usize;
        let counters = d.buffer(4 * counter_words as u64, usage)?;
        let i = &self.inputs;
        let storage: [&Buffer; STORAGE_BINDINGS as usize] = [
            &i[0], &i[1], &i[2], &i[3], &i[4], &i[5], &i[6], &i[7], &i[8], &hits, &counters,
        ];
        let fault = u32::from(faults.swap_barycentrics) | (u32::from(faults.flip_known) << 1);
        let mut push: Vec<u8> = [
            width,
            height,
            method.code(),
            self.index_width,
            max_records,
            fault,
            0,
            0,
        ]
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
        push.extend(basis.iter().flatten().flat_map(|x| x.to_le_bytes()));
        let launch = match tracer {
            Tracer::Query => Launch::Groups([width.div_ceil(8), height.div_ceil(8), 1]),
            Tracer::Pipeline => Launch::Rays(width, height),
        };
        let timing = d.run(pipeline, Some(&self.tlas), &storage, &push, launch)?;
        let hit_words = hits.read(2 * pixels as usize)?;
        let c = counters.read(counter_words)?;
        let mut frame = Frame::from_words(
            (tracer, method),
            (width, height),
            &hit_words,
            &c,
            max_records,
        );
        frame.cpu_seconds = timing.cpu_seconds;
        frame.wall_seconds = timing.wall_seconds;
        Ok(frame)
    }
}
