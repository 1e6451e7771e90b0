//! Bounded work: the unit, the default budgets, and the auto-level rule
//! for triangles that span many texture periods.
//!
//! # The unit
//!
//! One **work unit** is one lookup of a block's (or a single texel's)
//! classes in the baker's texel tables: the bounding-block lookup of each
//! node the walk visits, the vertex and edge-midpoint lookups of a
//! finest-level micro-triangle (a vertex shared by siblings is read and
//! counted once), and each block or texel test of its exact search; a
//! finest-level micro-triangle its vertices decide costs one unit more
//! (its centroid's texel), so every one costs at least one. Each unit is a few prefix-sum reads plus, for a search test, an
//! exact triangle-block intersection, so units are close to proportional
//! to time: about 50 ns each in the costliest case measured (searches over
//! footprints of many texture periods, 2^26 units in 3.4 s of CPU on a
//! 2-core AMD EPYC; `docs/bake.md`, "Bounded work").
//!
//! # What a budget does
//!
//! [`Baker::bake_within`](super::Baker::bake_within) checks the units
//! spent before each node of its walk: once they reach the budget, that
//! node and every node not yet visited become unknown as whole subtrees
//! (split into unknown-opaque / unknown-transparent by each subtree's
//! centroid texel, as every unknown is), which is sound, and the triangle's
//! status is [`TriangleStatus::WorkBudgetExceeded`](super::TriangleStatus).
//! A triangle may overshoot its budget by the cost of one micro-triangle:
//! at most seven lookups plus the larger of its block budget and 36 under
//! the exact model, and under the GPU model eight lookups plus twice that
//! (a finest-level micro-triangle may be classified under both models, for
//! the widening's count).
//! [`bake_meshes`](super::mesh::bake_meshes) gives each triangle the
//! smaller of the per-triangle budget and what the per-bake budget has
//! left, in triangle order, so the output stays a function of the inputs.

use super::mesh::LevelRule;
use super::texture::{AddressMode, Sampler};
use super::{useful_level, UvTriangle};
use crate::Level;

/// Work units (see the [module docs](self)) one triangle may spend by
/// default: 2^26, about 4 per micro-triangle of a level-12 map; 3.4 s of
/// CPU at the costliest units measured (see the [module docs](self)). The
/// bundled assets' bakes stay under a sixteenth of it per triangle
/// (`crates/cli/tests/cli_bake_work.rs`).
pub const DEFAULT_TRIANGLE_WORK_BUDGET: u64 = 1 << 26;

/// Work units a whole [`bake_meshes`](super::mesh::bake_meshes) may spend
/// by default: 2^34, about 4 per micro-triangle of the 1 GiB of 4-state
/// maps the CLI allows by default (`--max-bytes`).
pub const DEFAULT_BAKE_WORK_BUDGET: u64 = 1 << 34;

/// The length of one texture period along an axis, in texture coordinates:
/// 1 for repeat, 2 for mirrored repeat (a texture and its mirror image);
/// `None` for the clamping modes, which have no period (far outside the
/// texture they read only its edge, so large triangles can stay known).
fn period(mode: AddressMode) -> Option<f64> {
    match mode {
        AddressMode::Repeat => Some(1.0),
        AddressMode::MirroredRepeat => Some(2.0),
        AddressMode::ClampToEdge | AddressMode::ClampToBorder | AddressMode::MirrorClampToEdge => {
            None
        }
    }
}

/// Whether every micro-triangle of `uv` at `level` contains a whole period
/// square of the texture under `sampler` (both axes repeat or mirror).
///
/// Then every micro-triangle at this level, and at every coarser level
/// (whose micro-triangles contain these), can read every texel: it is
/// known only when the whole texture is one class, and then the baker's
/// first lookup decides the whole triangle at any level. So a map at
/// `level` holds nothing a level-0 map does not (apart from the split of
/// unknowns by centroid texel, a heuristic).
///
/// The test: a triangle's incircle (radius `r = 2A / P`, area `A`,
/// perimeter `P`, in periods) holds an axis-aligned square of side
/// `r sqrt 2`; micro-triangles at level `n` are the triangle scaled by
/// `2^-n`. With `P <= 3 L` (`L` the longest edge) it suffices that
/// `8 A^2 >= 9 L^2 4^n`, which needs no square root. It is computed in
/// `f64` from the `f32` coordinates; a rounding error could only move the
/// level choice, which is sound at any level.
///
/// ```
/// use micromap_index::bake::{spans_whole_periods, AddressMode, Sampler};
/// use micromap_index::Level;
/// let repeat = Sampler::default();
/// let huge = [[0.0, 0.0], [1e6, 0.0], [0.0, 1e6]];
/// // Level 12: micro-triangles about 244 periods across.
/// assert!(spans_whole_periods(&huge, repeat, Level::new(12).unwrap()));
/// // A triangle of a few periods does not, at level 12.
/// let small = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]];
/// assert!(!spans_whole_periods(&small, repeat, Level::new(12).unwrap()));
/// // Clamped, far outside the texture only the edge is read: never.
/// let clamp = Sampler { address_u: AddressMode::ClampToEdge, ..repeat };
/// assert!(!spans_whole_periods(&huge, clamp, Level::new(12).unwrap()));
/// ```
#[must_use]
pub fn spans_whole_periods(uv: &UvTriangle, sampler: Sampler, level: Level) -> bool {
    let (Some(pu), Some(pv)) = (period(sampler.address_u), period(sampler.address_v)) else {
        return false;
    };
    let p = uv.map(|c| (f64::from(c[0]) / pu, f64::from(c[1]) / pv));
    let twice_area = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[1].1 - p[0].1) * (p[2].0 - p[0].0);
    let mut longest = 0f64;
    for k in 0..3 {
        let (a, b) = (p[k], p[(k + 1) % 3]);
        let (du, dv) = (b.0 - a.0, b.1 - a.1);
        longest = longest.max(du * du + dv * dv);
    }
    // 8 A^2 = 2 (2A)^2.
    let lhs = 2.0 * twice_area * twice_area;
    let mut rhs = 9.0 * longest;
    for _ in 0..level.get() {
        rhs *= 4.0;
    }
    lhs.is_finite() && rhs.is_finite() && lhs >= rhs
}

/// The auto level rule's answer for a triangle: `useful` (the paper's
/// eq. 1, capped), or level 0 when micro-triangles at `useful` would each
/// contain a whole texture period ([`spans_whole_periods`]): no level up to
/// `useful` knows more than level 0 there, and a level-0 map costs one
/// lookup and no bytes where a level-12 one costs millions of each.
#[must_use]
pub fn level_within_periods(uv: &UvTriangle, sampler: Sampler, useful: Level) -> Level {
    if useful.get() > 0 && spans_whole_periods(uv, sampler, useful) {
        Level(0)
    } else {
        useful
    }
}

impl LevelRule {
    /// The level this rule gives `uv` on a `(width, height)` texture read
    /// through `sampler`, and whether [`level_within_periods`] lowered it
    /// to 0 (only for [`LevelRule::Useful`]). The one level choice of
    /// [`bake_meshes`](super::mesh::bake_meshes), for callers that size
    /// the output first.
    ///
    /// ```
    /// use micromap_index::bake::mesh::LevelRule;
    /// use micromap_index::bake::Sampler;
    /// use micromap_index::Level;
    /// let auto = LevelRule::Useful { max: Level::new(12).unwrap() };
    /// let quad = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    /// assert_eq!(auto.level_of(&quad, (256, 256), Sampler::default()), (Level::new(9).unwrap(), false));
    /// let huge = [[0.0, 0.0], [1e6, 0.0], [0.0, 1e6]];
    /// assert_eq!(auto.level_of(&huge, (256, 256), Sampler::default()), (Level::new(0).unwrap(), true));
    /// ```
    #[must_use]
    pub fn level_of(&self, uv: &UvTriangle, size: (u32, u32), sampler: Sampler) -> (Level, bool) {
        match *self {
            LevelRule::Fixed(level) => (level, false),
            LevelRule::Useful { max } => {
                let useful = useful_level(uv, size, max);
                let level = level_within_periods(uv, sampler, useful);
                (level, level != useful)
            }
        }
    }
}
