//! The options both bakes take (`micromap-index bake`'s level, format,
//! budget, model, texture unit, mips, threads and limit flags), handed over by the Python
//! layer as one dict and checked into the library's `MeshOptions`.

use crate::options::{self, value_error};
use micromap_index::bake::mesh::{LevelRule, MeshOptions};
use micromap_index::bake::{DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET};
use micromap_index::micromap::{BuildOptions, IndexWidth};
use pyo3::prelude::*;

/// The dict `bake` and `bake_gltf` pass (every key present; `None` for
/// an option left at its default).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct BakeOptions<'py> {
    level: Bound<'py, PyAny>,
    max_level: i64,
    format: i64,
    unknown: String,
    model: String,
    subtexel_bits: i64,
    interpolation: String,
    filter_error: f32,
    linear: String,
    budget: Option<i64>,
    index_width: i64,
    max_bytes: i64,
    no_mixed_special: bool,
    mips: Bound<'py, PyAny>,
    threads: Option<i64>,
    work_budget: Option<i64>,
    bake_work_budget: Option<i64>,
}

/// [`BakeOptions`] checked.
pub(crate) struct Common {
    pub(crate) options: MeshOptions,
    pub(crate) width: IndexWidth,
    pub(crate) max_bytes: u64,
}

impl BakeOptions<'_> {
    /// The options as the library's, each bad value a `ValueError` (or a
    /// `TypeError` for a wrong type) naming its keyword.
    pub(crate) fn check(&self) -> PyResult<Common> {
        let fixed = options::level_or_auto(&self.level)?;
        let max = options::bake_level(self.max_level, "max_level")?;
        let budget = self
            .budget
            .map(|b| options::count(b, "budget"))
            .transpose()?;
        if budget.is_some() && fixed.is_some() {
            return Err(value_error(
                "budget chooses levels: it goes with level=\"auto\"",
            ));
        }
        let work = |value: Option<i64>, what: &str, default: u64| {
            value.map_or(Ok(default), |v| options::count(v, what))
        };
        Ok(Common {
            options: MeshOptions {
                levels: fixed.map_or(LevelRule::Useful { max }, LevelRule::Fixed),
                format: options::format(self.format)?,
                unknown: options::unknown(&self.unknown)?,
                budget_bytes: budget,
                triangle_work_budget: work(
                    self.work_budget,
                    "work_budget",
                    DEFAULT_TRIANGLE_WORK_BUDGET,
                )?,
                bake_work_budget: work(
                    self.bake_work_budget,
                    "bake_work_budget",
                    DEFAULT_BAKE_WORK_BUDGET,
                )?,
                model: options::model(&self.model)?,
                texture_unit: options::texture_unit(
                    self.subtexel_bits,
                    &self.interpolation,
                    self.filter_error,
                    &self.linear,
                )?,
                mips: options::mips(&self.mips)?,
                threads: options::threads(self.threads)?,
                buffers: BuildOptions {
                    no_mixed_special_indices: self.no_mixed_special,
                    ..BuildOptions::default()
                },
                ..MeshOptions::default()
            },
            width: options::index_width(self.index_width)?,
            max_bytes: options::count(self.max_bytes, "max_bytes")?,
        })
    }
}
