//! What a frame is traced with: the [`Tracer`] (where candidates are
//! decided), the [`Lookup`] (what reads the texture for the alpha test),
//! the [`Method`] (how) and the deliberate [`Faults`] of the negative
//! controls. Plain names, used by every other file.

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

/// What reads the texture for the alpha test (every method's fallback and
/// the judge of every known state).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Lookup {
    /// The shader's own binary32 code reads texels from a buffer and
    /// filters them (nearest or bilinear, Vulkan's address modes): every
    /// fetch can be recomputed on the host.
    Shader,
    /// The device's texture unit: `textureLod` at level 0 through a
    /// combined image sampler per mesh (an `R8_UNORM` image of the
    /// texture's alpha; the mesh's filter, address modes and border
    /// colour), as renderers read textures.
    Sampler,
}

impl Lookup {
    /// Both lookups, the shader's first.
    pub const ALL: [Lookup; 2] = [Lookup::Shader, Lookup::Sampler];

    /// The lookup's name in the CLI and `render.json`: `shader`, `sampler`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Lookup::Shader => "shader",
            Lookup::Sampler => "sampler",
        }
    }

    /// The lookup named `name` ([`Lookup::name`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Lookup> {
        Lookup::ALL.into_iter().find(|l| l.name() == name)
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
    /// The driver's own opacity micromap (`VK_EXT_opacity_micromap`)
    /// built from the same buffers and attached to the BLAS: the traversal
    /// decides known states, the shader runs the alpha test on what it is
    /// handed. Its picture must equal the alpha test's.
    Hardware,
    /// [`Method::Hardware`] with every instance forced to 2 states
    /// (`VK_GEOMETRY_INSTANCE_FORCE_OPACITY_MICROMAP_2_STATE_EXT`): the
    /// traversal decides every micromapped candidate. Its picture must
    /// equal [`Method::Flat2`]'s, which checks the driver's index function
    /// and state decoding against the shader library's.
    Hardware2,
}

impl Method {
    /// Every method, in the order of the shader's numbering.
    pub const ALL: [Method; 7] = [
        Method::AlphaTest,
        Method::Flat4,
        Method::Flat2,
        Method::LevelOrderTree,
        Method::PaperTree,
        Method::Hardware,
        Method::Hardware2,
    ];

    /// The methods every device with ray tracing runs: all but the
    /// hardware ones, which need `VK_EXT_opacity_micromap`.
    pub const EMULATED: [Method; 5] = [
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
            Method::Hardware => "hardware",
            Method::Hardware2 => "hardware-2-state",
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
            Method::Flat4 | Method::LevelOrderTree | Method::PaperTree | Method::Hardware
        )
    }

    /// Whether the driver's micromap decides (`VK_EXT_opacity_micromap`).
    #[must_use]
    pub fn is_hardware(self) -> bool {
        matches!(self, Method::Hardware | Method::Hardware2)
    }

    /// The method whose picture this one's must equal: the alpha test for
    /// the 4-state methods (and itself), flat 2-state for the forced
    /// hardware micromap; `None` for flat 2-state, which decides unknowns
    /// without the texture by design.
    #[must_use]
    pub fn reference(self) -> Option<Method> {
        match self {
            Method::Flat2 => None,
            Method::Hardware2 => Some(Method::Flat2),
            _ => Some(Method::AlphaTest),
        }
    }

    /// The shader's number of the method (push constant `method`).
    pub(crate) fn code(self) -> u32 {
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
