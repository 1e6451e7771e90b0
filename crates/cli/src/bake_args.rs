//! The bake's options, one definition for `bake` and `render` (which bakes
//! when it is given no `--micromaps`): their flags ([`LEVELS`], [`MIPS`],
//! [`LIMITS`]), their parsing into the library's [`MeshOptions`]
//! ([`BakeArgs::parse`]) and the `--max-bytes` guard checked before any
//! micro-triangle is baked ([`BakeArgs::check_output_size`]). Level and
//! enum names are the library's (`BakeLevel`, `FromStr`/`Display`).

use crate::inputs::sampler::{model_option, texture_unit_option};
use cli_support::args::{Flag, Parsed};
use cli_support::output::Failure;
use micromap_index::bake::mesh::{
    chosen_levels, output_bytes_bound, LevelRule, Mesh, MeshOptions, MeshTriangles, Mips,
};
use micromap_index::bake::{
    BakeLevel, Threads, DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET,
};
use micromap_index::micromap::{BuildOptions, Format, IndexWidth, Micromap, UnknownPolicy};
use micromap_index::Level;
use std::collections::HashSet;
use std::fmt::Write as _;

/// The level and format flags (in the usage, before the sampler's).
pub(crate) const LEVELS: [Flag; 5] = [
    Flag::value(
        "--level",
        "L|auto",
        "fixed level 0..=12, or the paper's eq. 1 per triangle (default auto)",
    ),
    Flag::value("--max-level", "L", "cap for auto (default 12)"),
    Flag::value(
        "--budget",
        "BYTES",
        "auto: lower the highest levels until the data fits",
    ),
    Flag::value("--format", "2|4", "micromap format (default 4)"),
    Flag::value(
        "--unknown-as",
        "U",
        "2-state: what unknowns become: fallback (default: the texel under
                         the micro-triangle's centroid), opaque or transparent",
    ),
];

/// `--mips` (in the usage, after the sampler's flags).
pub(crate) const MIPS: [Flag; 1] = [Flag::value(
    "--mips",
    "0|N|all",
    "the mip levels known states hold for: 0 (default: level 0, which ray
                         tracing shaders sample), 0..=N or all, each level the box filter of
                         the one above, under either filter (docs/bake.md)",
)];

/// The size, work and thread limits and the buffer layout switch.
pub(crate) const LIMITS: [Flag; 5] = [
    Flag::value(
        "--max-bytes",
        "N",
        "refuse (exit 2) before baking when the output may exceed N bytes
                         (default 1073741824; the estimate counts every map before dedup)",
    ),
    Flag::value(
        "--work-budget",
        "N",
        "work units (texel-table lookups) one triangle may spend; the rest
                         is unknown (default 67108864)",
    ),
    Flag::value(
        "--bake-work-budget",
        "N",
        "work units all triangles may spend together (default 17179869184)",
    ),
    Flag::value(
        "--threads",
        "N",
        "threads to bake on (default: every core; 1: serial); the bytes are
                         the same for every N",
    ),
    Flag::switch(
        "--no-mixed-special",
        "no job mixes special indices with records: shared level-0 records
                         instead (Vulkan KHR no-mixed pipelines)",
    ),
];

/// Every flag of [`BakeArgs`], `--model` (a sampler flag) aside.
pub(crate) fn names() -> impl Iterator<Item = &'static str> {
    LEVELS
        .iter()
        .chain(&MIPS)
        .chain(&LIMITS)
        .map(|flag| flag.name)
}

/// The default limit on the estimated output (`--max-bytes`): 1 GiB, 256
/// level-12 4-state maps.
const DEFAULT_MAX_OUTPUT_BYTES: u64 = 1 << 30;

/// The bake's options as given.
pub(crate) struct BakeArgs {
    /// What `bake_meshes` gets.
    pub(crate) options: MeshOptions,
    /// `--max-bytes`.
    pub(crate) max_bytes: u64,
    /// `--threads N`; `None`: every core.
    pub(crate) threads: Option<usize>,
}

/// `--level` or `--max-level` as a level `0..=12`, in the library's words.
fn level(flag: &str, text: &str) -> Result<Level, Failure> {
    text.parse::<BakeLevel>()
        .map(BakeLevel::level)
        .map_err(|e| Failure::Malformed(format!("{flag} {text:?}: {e}")))
}

/// A byte count or work-unit count (`what`), as `u64` reads it.
fn count(p: &Parsed<'_>, flag: &str, what: &str) -> Result<Option<u64>, Failure> {
    p.get(flag)
        .map(|t| {
            t.parse::<u64>()
                .map_err(|_| Failure::Malformed(format!("{flag} {t:?}: expected {what}")))
        })
        .transpose()
}

/// `--threads N` (N >= 1); `None`: every core.
fn threads_option(p: &Parsed<'_>) -> Result<Option<usize>, Failure> {
    match p.get("--threads") {
        None => Ok(None),
        Some(text) => match text.parse::<usize>() {
            Ok(n) if n >= 1 && text.bytes().all(|b| b.is_ascii_digit()) => Ok(Some(n)),
            _ => Err(Failure::Malformed(format!(
                "--threads {text:?}: expected a number of threads, at least 1"
            ))),
        },
    }
}

/// A name flag (`--format`, `--unknown-as`, `--mips`) by the library's
/// `FromStr`, `default` when absent.
fn named<T: std::str::FromStr>(p: &Parsed<'_>, flag: &str, default: T) -> Result<T, Failure>
where
    T::Err: std::fmt::Display,
{
    match p.get(flag) {
        None => Ok(default),
        Some(text) => text
            .parse()
            .map_err(|e| Failure::Malformed(format!("{flag} {text:?}: {e}"))),
    }
}

impl BakeArgs {
    /// The bake's flags of `p` (and `--model`), each checked.
    pub(crate) fn parse(p: &Parsed<'_>) -> Result<BakeArgs, Failure> {
        let format: Format = named(p, "--format", Format::FourState)?;
        let unknown: UnknownPolicy = named(p, "--unknown-as", UnknownPolicy::Fallback)?;
        let fixed_level = match p.get("--level").unwrap_or("auto") {
            "auto" => None,
            text => Some(level("--level", text)?),
        };
        let max_level = level("--max-level", p.get("--max-level").unwrap_or("12"))?;
        let budget = count(p, "--budget", "a byte count")?;
        if budget.is_some() && fixed_level.is_some() {
            return Err(Failure::Usage(
                "--budget chooses levels: it goes with --level auto".into(),
            ));
        }
        let max_bytes =
            count(p, "--max-bytes", "a byte count")?.unwrap_or(DEFAULT_MAX_OUTPUT_BYTES);
        let triangle_work_budget =
            count(p, "--work-budget", "a count")?.unwrap_or(DEFAULT_TRIANGLE_WORK_BUDGET);
        let bake_work_budget =
            count(p, "--bake-work-budget", "a count")?.unwrap_or(DEFAULT_BAKE_WORK_BUDGET);
        let model = model_option(p)?;
        let texture_unit = texture_unit_option(p)?;
        let mips: Mips = named(p, "--mips", Mips::default())?;
        let threads = threads_option(p)?;
        Ok(BakeArgs {
            options: MeshOptions {
                levels: match fixed_level {
                    Some(level) => LevelRule::Fixed(level),
                    None => LevelRule::Useful { max: max_level },
                },
                format,
                unknown,
                budget_bytes: budget,
                triangle_work_budget,
                bake_work_budget,
                model,
                texture_unit,
                mips,
                threads: match threads {
                    Some(n) => Threads::Exactly(n),
                    None => Threads::All,
                },
                buffers: BuildOptions {
                    no_mixed_special_indices: p.flag("--no-mixed-special"),
                    ..BuildOptions::default()
                },
                ..MeshOptions::default()
            },
            max_bytes,
            threads,
        })
    }

    /// The `--max-bytes` guard: the output's size before deduplication (an
    /// upper bound: maps that dedup or become special indices only shrink
    /// it), from the levels `bake_meshes` chooses, with indices of `width`;
    /// refused (exit 2) over the limit, before any micro-triangle is baked.
    pub(crate) fn check_output_size(
        &self,
        meshes: &[Mesh<'_>],
        width: IndexWidth,
    ) -> Result<(), Failure> {
        let estimate = output_bytes_bound(meshes, &self.options, width)
            .map_err(|e| Failure::Malformed(e.to_string()))?;
        let max_bytes = self.max_bytes;
        if estimate > max_bytes {
            let mut message = format!(
                "the output may take up to {estimate} bytes (before deduplication), over the \
                 limit of {max_bytes} bytes; nothing written (--max-bytes raises the limit, \
                 --budget or a lower --level/--max-level shrinks the output)"
            );
            if let Some(distinct) = self.distinct_bound(meshes, width) {
                if distinct.bytes < estimate {
                    let _ = write!(
                        message,
                        "; only {} of the {} triangles are distinct (equal UVs, level and \
                         material bake once): the output will take at most {} bytes, but the \
                         limit is checked against the estimate before deduplication, so \
                         --max-bytes {estimate} lets this bake run",
                        distinct.triangles, distinct.of, distinct.bytes
                    );
                }
            }
            return Err(Failure::Malformed(message));
        }
        Ok(())
    }

    /// The output's bound after the deduplication of identical triangles,
    /// cheap to count before baking: triangles with bit-equal UVs, level,
    /// texture, material and vertex alpha bake to the same map (the key is
    /// at least as fine as the library's, so the bound holds); `None` when
    /// the levels cannot be chosen or a mesh is not given as UV triangles.
    fn distinct_bound(&self, meshes: &[Mesh<'_>], width: IndexWidth) -> Option<Distinct> {
        let levels = chosen_levels(meshes, &self.options).ok()?;
        let mut seen = HashSet::new();
        let mut bytes: u64 = 34 * 12;
        let mut of = 0;
        for (mesh, levels) in meshes.iter().zip(&levels) {
            let MeshTriangles::Uv(triangles) = mesh.triangles else {
                return None;
            };
            // The texture object and the material, bit for bit.
            let texture = std::ptr::from_ref(mesh.texture).cast::<()>() as usize;
            let material = format!("{:?}", mesh.material);
            for (t, (uv, level)) in triangles.iter().zip(levels).enumerate() {
                of += 1;
                let alpha = mesh
                    .vertex_alpha
                    .and_then(|a| a.get(t))
                    .map(|a| a.map(f32::to_bits));
                let key = (
                    texture,
                    material.clone(),
                    uv.map(|c| c.map(f32::to_bits)),
                    level.get(),
                    alpha,
                );
                bytes = bytes.saturating_add(width.bytes() as u64);
                if seen.insert(key) {
                    bytes = bytes
                        .saturating_add(Micromap::byte_len(*level, self.options.format) as u64)
                        .saturating_add(8);
                }
            }
        }
        Some(Distinct {
            triangles: seen.len(),
            of,
            bytes,
        })
    }
}

/// Distinct triangles and the output bound after their deduplication.
struct Distinct {
    triangles: usize,
    of: usize,
    bytes: u64,
}
