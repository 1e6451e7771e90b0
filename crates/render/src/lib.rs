//! The render check of micromap-index: opacity micromaps consumed by a real
//! ray tracer. A [`Renderer`] puts a [`Scene`] (alpha-masked triangles,
//! their textures and materials) and optionally [`Micromaps`] (the buffers
//! `micromap-index bake` writes) on a Vulkan device with
//! `VK_KHR_ray_query`, then traces one primary ray per pixel with a
//! [`Tracer`]: `GL_EXT_ray_query`, deciding every candidate in the
//! `rayQueryProceedEXT` loop, or a `VK_KHR_ray_tracing_pipeline` pipeline,
//! deciding it in the any-hit shader (both by the same shader code,
//! `shaders/render_common.glsl`), by a [`Method`]: the alpha test alone, or a micromap emulated in
//! software (flat 4-state, flat forced 2-state, the level-order tree, the
//! paper's Algorithm 3), using the shader library in `shaders/glsl`.
//!
//! A [`Frame`] holds the committed hit of every pixel, the [`Counters`]
//! (rays, candidates, texture fetches, known and unknown decisions,
//! contradicted candidates) and the first contradictions, which
//! [`classify`] explains exactly on the host.
//!
//! The loader is opened at run time (`ash`'s `loaded` feature): without a
//! Vulkan device with ray queries, [`Renderer::new`] returns
//! [`RenderError::NoDevice`]. `micromap-index render` is the command
//! (docs/render.md).
//!
//! ```
//! use micromap_index_render::{Camera, Method, Tracer};
//! assert_eq!(Method::ALL.len(), 5);
//! assert_eq!(Tracer::from_name("pipeline"), Some(Tracer::Pipeline));
//! assert!(Method::Flat4.is_four_state() && !Method::Flat2.is_four_state());
//! let camera = Camera::framing([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]], 1.0);
//! assert!(camera.eye[2] > 0.0);
//! ```

mod classify;
mod scene;
pub mod tables;
mod vulkan;

pub use classify::{classify, Classified, ContradictionClass};
pub use scene::{Micromaps, Scene, SceneMesh, SceneTexture};

use micromap_index::succinct::{LevelOrderTree, PaperTree};
use std::fmt;
use std::time::Instant;
use vulkan::{Buffer, Device, Pipeline, Structures, STORAGE_BINDINGS};

/// How the rays are traced; both decide candidates by the same shader code
/// (`shaders/render_common.glsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Tracer {
    /// A compute shader with `GL_EXT_ray_query`: decisions in the
    /// `rayQueryProceedEXT` loop.
    Query,
    /// A ray tracing pipeline (`VK_KHR_ray_tracing_pipeline`: raygen,
    /// any-hit, closest-hit, miss, a shader binding table): decisions in
    /// the any-hit shader.
    Pipeline,
}

impl Tracer {
    /// Both tracers, the ray query first.
    pub const ALL: [Tracer; 2] = [Tracer::Query, Tracer::Pipeline];

    /// The tracer's name in the CLI and `render.json`: `query`, `pipeline`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Tracer::Query => "query",
            Tracer::Pipeline => "pipeline",
        }
    }

    /// The tracer named `name` ([`Tracer::name`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Tracer> {
        Tracer::ALL.into_iter().find(|t| t.name() == name)
    }
}

/// How a candidate hit is decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Every candidate runs the alpha test (fetches the texture).
    AlphaTest,
    /// The flat micromap, 4-state: known states decide, unknown ones run
    /// the alpha test (`micromap_state.glsl`).
    Flat4,
    /// The flat micromap forced to 2 states (Vulkan's
    /// `FORCE_OPACITY_MICROMAP_2_STATE`): the state's low bit decides, no
    /// texture is fetched. Not expected to equal the alpha test.
    Flat2,
    /// The level-order succinct tree (`level_order_tree.glsl`), 4-state.
    LevelOrderTree,
    /// The paper's Algorithm 3 over `PaperTree` bytes (`paper_tree.glsl`),
    /// 4-state.
    PaperTree,
}

impl Method {
    /// Every method, in the order of the shader's numbering.
    pub const ALL: [Method; 5] = [
        Method::AlphaTest,
        Method::Flat4,
        Method::Flat2,
        Method::LevelOrderTree,
        Method::PaperTree,
    ];

    /// The name used in file names and `render.json`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::AlphaTest => "alpha-test",
            Method::Flat4 => "flat-4-state",
            Method::Flat2 => "flat-2-state",
            Method::LevelOrderTree => "level-order-tree",
            Method::PaperTree => "paper-tree",
        }
    }

    /// The method of a [`name`](Self::name).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Whether the method keeps unknown states unknown (falls back to the
    /// alpha test), so its picture must equal the alpha test's.
    #[must_use]
    pub fn is_four_state(self) -> bool {
        matches!(
            self,
            Method::Flat4 | Method::LevelOrderTree | Method::PaperTree
        )
    }

    fn code(self) -> u32 {
        Method::ALL.iter().position(|&m| m == self).unwrap_or(0) as u32
    }
}

/// Deliberate faults, for the check's negative controls: each must make a
/// correct bake fail the check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Faults {
    /// Look the micromap up at `(b2, b1)` instead of `(b1, b2)`.
    pub swap_barycentrics: bool,
    /// Flip every known state (opaque <-> transparent).
    pub flip_known: bool,
}

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Where the rays start.
    pub eye: [f32; 3],
    /// The point at the picture's centre.
    pub target: [f32; 3],
    /// The vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_degrees: f32,
}

impl Camera {
    /// A camera that frames the box `[min, max]` in a picture of `aspect`
    /// (width over height): looking down `-z` and slightly down from above,
    /// 40 degrees vertically, at a distance that shows the box's `x` and
    /// `y` extents with a 10% margin.
    #[must_use]
    pub fn framing(bounds: [[f32; 3]; 2], aspect: f32) -> Camera {
        let [min, max] = bounds;
        let centre = [0, 1, 2].map(|i| 0.5 * (min[i] + max[i]));
        let half = [0, 1, 2].map(|i| (0.5 * (max[i] - min[i])).max(1e-3));
        let fov: f32 = 40.0;
        let t = (0.5 * fov.to_radians()).tan();
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let distance = 1.1 * (half[0] / (t * aspect)).max(half[1] / t) + half[2];
        let dir = [0.0f32, 0.35, 1.0];
        let norm = dir.iter().map(|d| d * d).sum::<f32>().sqrt();
        Camera {
            eye: [0, 1, 2].map(|i| centre[i] + distance * dir[i] / norm),
            target: centre,
            fov_y_degrees: fov,
        }
    }

    /// The push-constant vectors: eye, forward, right and up, the last two
    /// scaled to half the picture at distance 1.
    fn basis(&self, width: u32, height: u32) -> Result<[[f32; 4]; 4], RenderError> {
        let sub = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let cross = |a: [f32; 3], b: [f32; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let unit = |a: [f32; 3]| {
            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            (n.is_finite() && n > 0.0).then(|| [a[0] / n, a[1] / n, a[2] / n])
        };
        let bad = || {
            RenderError::Input(format!(
                "camera {self:?}: expected finite points apart and a field of view in (0, 180) degrees, not looking straight up or down"
            ))
        };
        if !(self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0)
            || self.eye.iter().chain(&self.target).any(|x| !x.is_finite())
        {
            return Err(bad());
        }
        let forward = unit(sub(self.target, self.eye)).ok_or_else(bad)?;
        let right = unit(cross(forward, [0.0, 1.0, 0.0])).ok_or_else(bad)?;
        let up = cross(right, forward);
        let half_h = (0.5 * self.fov_y_degrees.to_radians()).tan();
        let half_w = half_h * width as f32 / height as f32;
        let e = self.eye;
        Ok([
            [e[0], e[1], e[2], 0.0],
            [forward[0], forward[1], forward[2], 0.0],
            [right[0] * half_w, right[1] * half_w, right[2] * half_w, 0.0],
            [up[0] * half_h, up[1] * half_h, up[2] * half_h, 0.0],
        ])
    }
}

/// Why rendering failed.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum RenderError {
    /// No Vulkan loader, or no device with acceleration structures and ray
    /// queries (with what was found).
    NoDevice(String),
    /// The scene, micromaps or frame cannot be rendered as given.
    Input(String),
    /// A Vulkan call failed.
    Vulkan(String),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::NoDevice(m) | RenderError::Input(m) | RenderError::Vulkan(m) => {
                f.write_str(m)
            }
        }
    }
}

impl std::error::Error for RenderError {}

/// What one frame counted, over all its rays. The device counts in 32
/// bits: a frame would need 2^32 candidates to wrap, far above the
/// [`MAX_PIXELS`] frames with tens of candidates per ray seen here.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Primary rays (one per pixel).
    pub rays: u64,
    /// Candidate hits the traversal reported to the shader.
    pub candidates: u64,
    /// Alpha tests the method ran (texture fetches; a bilinear fetch reads
    /// four texels and counts once).
    pub texture_fetches: u64,
    /// Candidates decided by a known state.
    pub known: u64,
    /// Candidates whose state was unknown (decided by the alpha test).
    pub unknown: u64,
    /// Known decisions the alpha test contradicts.
    pub contradicted: u64,
    /// Lookups that returned the shader library's invalid state (a
    /// malformed buffer; never expected after the host's checks).
    pub invalid: u64,
}

/// A candidate whose known state the alpha test contradicted, as the
/// shader recorded it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contradiction {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// The triangle (the scene's order, the BLAS's primitive index).
    pub triangle: u32,
    /// The micro-triangle the shader looked up (0 for a special index).
    pub micro_triangle: u32,
    /// The hit's barycentric `b1` (weight of vertex 1), binary32 bits.
    pub b1_bits: u32,
    /// `b2`, binary32 bits.
    pub b2_bits: u32,
    /// The known state the method decided by (0 transparent, 1 opaque).
    pub state: u32,
}

/// One traced frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The tracer that traced it.
    pub tracer: Tracer,
    /// The method it was traced with.
    pub method: Method,
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Per pixel (row-major, row 0 at the top): the committed triangle + 1
    /// (0: no hit) and the hit distance's binary32 bits.
    pub hits: Vec<[u32; 2]>,
    /// The counters.
    pub counters: Counters,
    /// The first contradictions (at most the `max_records` asked for).
    pub contradictions: Vec<Contradiction>,
    /// Process CPU seconds of the dispatch (the CPU device's threads are
    /// the process's), where the platform has a process clock.
    pub cpu_seconds: Option<f64>,
    /// Wall-clock seconds of the dispatch.
    pub wall_seconds: f64,
}

/// Counter words before the contradiction records (shader `COUNTERS`).
const COUNTER_WORDS: usize = 8;
/// Words per contradiction record (shader `RECORD_WORDS`).
const RECORD_WORDS: usize = 8;
/// Words per tree directory entry (shader `TREE_WORDS`).
const TREE_WORDS: usize = 10;
/// Most pixels of a frame (the pixel buffer's words stay below 2^31).
pub const MAX_PIXELS: u64 = 1 << 22;

/// A scene on the device, ready to trace.
pub struct Renderer {
    // Dropped last (fields drop in order): everything below was made on it.
    device: Device,
    pipeline: Option<Pipeline>,
    /// The ray tracing pipeline, where the device has one.
    ray_tracing: Option<Pipeline>,
    structures: Option<Structures>,
    /// Bindings 1..=9 (scene and micromaps).
    inputs: Vec<Buffer>,
    has_micromaps: bool,
    index_width: u32,
}

impl Drop for Renderer {
    fn drop(&mut self) {
        for b in &self.inputs {
            self.device.free(b);
        }
        if let Some(s) = &self.structures {
            self.device.free_structures(s);
        }
        for p in self.pipeline.iter().chain(&self.ray_tracing) {
            self.device.free_pipeline(p);
        }
    }
}

fn words_to_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// `bytes` zero-padded to whole words.
fn padded(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks(4)
        .map(|c| {
            let mut w = [0u8; 4];
            w[..c.len()].copy_from_slice(c);
            u32::from_le_bytes(w)
        })
        .collect()
}

/// The trees of every record as the shader reads them: one word buffer and
/// a directory of [`TREE_WORDS`] words per record. The level-order trees
/// get a top table of depth `min(level - 1, 4)`.
fn tree_buffers(micromaps: &Micromaps) -> Result<(Vec<u32>, Vec<u32>), RenderError> {
    let mut words = Vec::new();
    let mut dir = Vec::new();
    let mut push = |part: &[u32]| {
        let base = words.len() as u32;
        words.extend_from_slice(part);
        [base, part.len() as u32]
    };
    for (record, map) in micromaps.read().micromaps.iter().enumerate() {
        let states: Vec<_> = map.states().collect();
        let tree_error = |e: micromap_index::succinct::TreeError| {
            RenderError::Input(format!("record {record}: {e}"))
        };
        let lot = LevelOrderTree::encode(map.level(), map.format(), &states)
            .map_err(tree_error)?
            .to_bytes();
        let paper = PaperTree::encode(map.level(), map.format(), &states)
            .map_err(tree_error)?
            .to_bytes();
        let depth = map.level().get().saturating_sub(1).min(4);
        let rank = tables::rank_directory(&lot);
        let (top, top_start) = tables::top_table(&lot, depth);
        let [lot_base, lot_len] = push(&padded(&lot));
        let [rank_base, rank_len] = push(&rank);
        let [top_base, top_len] = push(&top);
        let [paper_base, paper_len] = push(&padded(&paper));
        dir.extend([
            lot_base, lot_len, rank_base, rank_len, top_base, top_len, depth, top_start,
            paper_base, paper_len,
        ]);
    }
    debug_assert_eq!(dir.len(), TREE_WORDS * micromaps.read().micromaps.len());
    Ok((words, dir))
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
        let device = Device::open()?;
        let mut renderer = Renderer {
            device,
            pipeline: None,
            ray_tracing: None,
            structures: None,
            inputs: Vec::new(),
            has_micromaps: micromaps.is_some(),
            index_width: micromaps.map_or(4, Micromaps::index_width_bytes),
        };
        renderer.pipeline = Some(renderer.device.pipeline()?);
        if renderer.device.has_ray_tracing_pipeline() {
            renderer.ray_tracing = Some(renderer.device.ray_tracing_pipeline()?);
        }
        let vertices: Vec<[f32; 3]> = scene.positions().iter().flatten().copied().collect();
        renderer.structures = Some(renderer.device.structures(&vertices)?);
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
        for bytes in &contents {
            let b = renderer.device.buffer(
                bytes.len() as u64,
                ash::vk::BufferUsageFlags::STORAGE_BUFFER,
            )?;
            let written = renderer.device.write(&b, 0, bytes);
            renderer.inputs.push(b);
            written?;
        }
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
    pub fn device_name(&self) -> &str {
        &self.device.name
    }

    /// The tracers this device has: [`Tracer::Query`] always, and
    /// [`Tracer::Pipeline`] where it has `VK_KHR_ray_tracing_pipeline`.
    #[must_use]
    pub fn tracers(&self) -> Vec<Tracer> {
        let mut t = vec![Tracer::Query];
        if self.ray_tracing.is_some() {
            t.push(Tracer::Pipeline);
        }
        t
    }

    /// Traces one `width x height` frame with `tracer` and `method`,
    /// keeping the first `max_records` contradictions;
    /// [`RenderError::NoDevice`] for a tracer not in [`Renderer::tracers`].
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
            return Err(RenderError::Input(format!(
                "{} needs micromaps",
                method.name()
            )));
        }
        let chosen = match tracer {
            Tracer::Query => self.pipeline.as_ref(),
            Tracer::Pipeline => self.ray_tracing.as_ref(),
        };
        let Some(pipeline) = chosen else {
            return Err(RenderError::NoDevice(format!(
                "{}: no {} tracer (VK_KHR_ray_tracing_pipeline is missing)",
                self.device.name,
                tracer.name()
            )));
        };
        let pixels = u64::from(width) * u64::from(height);
        if width == 0 || height == 0 || pixels > MAX_PIXELS {
            return Err(RenderError::Input(format!(
                "size {width}x{height}: expected 1..={MAX_PIXELS} pixels"
            )));
        }
        let max_records = max_records.min(1 << 16);
        let basis = camera.basis(width, height)?;
        let d = &self.device;
        let usage = ash::vk::BufferUsageFlags::STORAGE_BUFFER;
        let hits = d.buffer(8 * pixels, usage)?;
        let counter_words = COUNTER_WORDS + RECORD_WORDS * max_records as usize;
        let counters = match d.buffer(4 * counter_words as u64, usage) {
            Ok(c) => c,
            Err(e) => {
                d.free(&hits);
                return Err(e);
            }
        };
        let result = (|| {
            let i = &self.inputs;
            let storage: [&Buffer; STORAGE_BINDINGS] = [
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
            let Some(structures) = &self.structures else {
                return Err(RenderError::Vulkan("the renderer is not set up".into()));
            };
            let cpu0 = vulkan::process_cpu_seconds();
            let wall0 = Instant::now();
            d.trace(pipeline, structures, &storage, &push, (width, height))?;
            let wall_seconds = wall0.elapsed().as_secs_f64();
            let cpu_seconds = match (cpu0, vulkan::process_cpu_seconds()) {
                (Some(a), Some(b)) => Some(b - a),
                _ => None,
            };
            let hit_words = d.read(&hits, 2 * pixels as usize)?;
            let c = d.read(&counters, counter_words)?;
            let recorded = (c[7] as usize).min(max_records as usize);
            let contradictions = (0..recorded)
                .map(|r| {
                    let w = &c[COUNTER_WORDS + RECORD_WORDS * r..][..RECORD_WORDS];
                    Contradiction {
                        x: w[0] % width,
                        y: w[0] / width,
                        triangle: w[1],
                        micro_triangle: w[2],
                        b1_bits: w[3],
                        b2_bits: w[4],
                        state: w[5],
                    }
                })
                .collect();
            Ok(Frame {
                tracer,
                method,
                width,
                height,
                hits: hit_words.chunks_exact(2).map(|h| [h[0], h[1]]).collect(),
                counters: Counters {
                    rays: u64::from(c[0]),
                    candidates: u64::from(c[1]),
                    texture_fetches: u64::from(c[2]),
                    known: u64::from(c[3]),
                    unknown: u64::from(c[4]),
                    contradicted: u64::from(c[5]),
                    invalid: u64::from(c[6]),
                },
                contradictions,
                cpu_seconds,
                wall_seconds,
            })
        })();
        d.free(&hits);
        d.free(&counters);
        result
    }
}
