//! `bake`'s summary.json: what the bake made, per state, status and job.

use crate::inputs::Input;
use cli_support::output::Failure;
use micromap_index::bake::Comparison;
use micromap_index::micromap::MicromapBuffers;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct StateCounts {
    pub(super) transparent: u64,
    pub(super) opaque: u64,
    pub(super) unknown_transparent: u64,
    pub(super) unknown_opaque: u64,
}

impl From<[u64; 4]> for StateCounts {
    /// Counts by `State::bits`.
    fn from(counts: [u64; 4]) -> Self {
        StateCounts {
            transparent: counts[0],
            opaque: counts[1],
            unknown_transparent: counts[2],
            unknown_opaque: counts[3],
        }
    }
}

impl StateCounts {
    pub(super) fn total(&self) -> u64 {
        self.transparent + self.opaque + self.unknown_transparent + self.unknown_opaque
    }
}

#[derive(Serialize)]
pub(super) struct JobSummary {
    pub(super) name: String,
    pub(super) texture: [u32; 2],
    pub(super) filter: &'static str,
    pub(super) address: [&'static str; 2],
    pub(super) cutoff: f32,
    pub(super) opaque_when: &'static str,
    pub(super) triangles: usize,
    /// Index of this job's first triangle in micromap-indices.bin.
    pub(super) first_index: usize,
    /// Vulkan EXT's usage counts of this job's geometry (as in
    /// micromap-geometry-usage.bin).
    pub(super) geometry_usage_counts: Vec<crate::geometry_usage::UsageJson>,
    /// Whether the job's indices hold both special indices and records.
    pub(super) mixed_special_indices: bool,
}

#[derive(Serialize)]
pub(super) struct Summary {
    pub(super) triangles: usize,
    /// Triangles classified: equal UVs, level and material bake once.
    pub(super) distinct_triangles: usize,
    /// "4-state" or "2-state" (`Format`'s `Display`).
    pub(super) format: String,
    /// The APIs' value of the format (`VkOpacityMicromapFormatEXT`: 1
    /// 2-state, 2 4-state).
    pub(super) format_api_value: u32,
    /// The threads the bake ran on.
    pub(super) threads: usize,
    pub(super) model: &'static str,
    /// The texture unit the known states hold for (`--subtexel-bits`,
    /// `--interpolation`, `--filter-error`, `--linear`).
    pub(super) texture_unit: crate::inputs::sampler::TextureUnitJson,
    /// `--mips`: `0`, `N` or `all`.
    pub(super) mips: String,
    /// What the GPU model's widening cost this bake (zero under `exact`).
    pub(super) widening: Widening,
    pub(super) levels: Vec<u64>,
    /// Auto levels lowered to 0: micro-triangles would each hold a whole
    /// texture period.
    pub(super) period_level_zero_triangles: usize,
    pub(super) micro_triangles: StateCounts,
    pub(super) known_fraction: f64,
    pub(super) known_area_fraction: f64,
    pub(super) status: StatusCounts,
    pub(super) micromaps_after_dedup: usize,
    pub(super) special_index_triangles: usize,
    pub(super) bytes_flat: usize,
    pub(super) bytes_paper_tree: u64,
    pub(super) bytes_level_order_tree: u64,
    pub(super) index_width_bits: usize,
    /// Work units spent (texel-table lookups): the serial walk's, the same
    /// for every `--threads` (`BakeReport::work`; the budgets count these).
    pub(super) work_units: u64,
    /// Work units spent besides and thrown away by triangles split over
    /// several threads whose budget ran out (`BakeReport::speculative_work`);
    /// 0 on one thread. `work_units + speculative_work_units` is all the
    /// work done.
    pub(super) speculative_work_units: u64,
    pub(super) bake_seconds: f64,
    pub(super) micro_triangles_per_second: f64,
    /// Drawing preview.png (0 with --no-preview).
    pub(super) preview_seconds: f64,
    /// Micro-triangles of the triangles drawn in preview.png (each pixel
    /// shows the one under its centre).
    pub(super) preview_micro_triangles: u64,
    /// Those of triangles not drawn: repeated triangles, or past the
    /// preview's pixel budget.
    pub(super) preview_micro_triangles_skipped: u64,
    pub(super) jobs: Vec<JobSummary>,
    pub(super) warnings: Vec<String>,
    /// `--gltf`'s `MASK` primitives left out (exit 5), each with its reason.
    pub(super) refused_primitives: Vec<Refused>,
}

/// A primitive the bake left out.
#[derive(Serialize)]
pub(super) struct Refused {
    pub(super) mesh: usize,
    pub(super) primitive: usize,
    pub(super) reason: String,
}

#[derive(Serialize)]
pub(super) struct Widening {
    /// Unknown micro-triangles the exact model knows (`BakeReport::widened`).
    pub(super) micro_triangles_made_unknown: u64,
    /// The known fraction the same bake has under `--model exact`.
    pub(super) known_fraction_exact_model: f64,
}

#[derive(Serialize)]
pub(super) struct StatusCounts {
    pub(super) exact: usize,
    pub(super) not_finite: usize,
    pub(super) out_of_exact_range: usize,
    pub(super) budget_exceeded: usize,
    pub(super) work_budget_exceeded: usize,
}

impl From<micromap_index::bake::mesh::StatusCounts> for StatusCounts {
    fn from(s: micromap_index::bake::mesh::StatusCounts) -> Self {
        StatusCounts {
            exact: s.exact,
            not_finite: s.not_finite,
            out_of_exact_range: s.out_of_exact_range,
            budget_exceeded: s.block_budget_exceeded,
            work_budget_exceeded: s.work_budget_exceeded,
        }
    }
}

/// One summary per job of `input` (job `g` is geometry `g` of `buffers`).
pub(super) fn jobs(input: &Input, buffers: &MicromapBuffers) -> Result<Vec<JobSummary>, Failure> {
    let mut first_index = 0;
    input
        .jobs
        .iter()
        .enumerate()
        .map(|(g, job)| {
            let image = &input.images[job.image];
            let summary = JobSummary {
                name: job.name.clone(),
                texture: [image.width, image.height],
                filter: job.sampler.filter.name(),
                address: [job.sampler.address_u.name(), job.sampler.address_v.name()],
                cutoff: job.cutoff.alpha(),
                opaque_when: match job.cutoff.comparison() {
                    Comparison::AtLeast => "alpha >= cutoff",
                    Comparison::Above => "alpha > cutoff",
                },
                triangles: job.triangles.len(),
                first_index,
                geometry_usage_counts: crate::geometry_usage::to_json(buffers, g)?,
                mixed_special_indices: buffers
                    .is_mixed(g)
                    .map_err(|e| Failure::Malformed(e.to_string()))?,
            };
            first_index += job.triangles.len();
            Ok(summary)
        })
        .collect()
}
