//! The level rule, whole: the range the front ends bake
//! ([`MAX_BAKE_LEVEL`]), the paper's useful level (eq. 1), the byte budget
//! over many triangles, the texture-period rule, and [`LevelRule`], which
//! combines them for [`bake_meshes`](super::mesh::bake_meshes).

use super::texture::{AddressMode, Sampler};
use super::triangle::UvTriangle;
use crate::micromap::{Format, Micromap};
use crate::Level;
use alloc::vec::Vec;
use core::fmt;

/// The highest level the front ends bake (the CLI's `--level` and
/// `--max-level`, C's `mmi_bake_options.level` and `max_level`, Python's
/// `level` and `max_level`): 12, the highest DXR allows and the level
/// Vulkan devices report as their maximum. The library itself bakes up to
/// [`Micromap::MAX_LEVEL`] (16) for callers that choose a level
/// themselves.
pub const MAX_BAKE_LEVEL: u32 = 12;

/// A level outside `0..=`[`MAX_BAKE_LEVEL`] (or not a number) given to a
/// front end. Its message names the range in the words every front end
/// uses.
///
/// ```
/// use micromap_index::bake::{bake_level, MAX_BAKE_LEVEL};
/// assert_eq!(bake_level(12).unwrap().get(), 12);
/// let e = bake_level(13).unwrap_err();
/// assert_eq!(
///     e.to_string(),
///     "expected a level 0..=12 (the highest DXR allows and Vulkan devices report)"
/// );
/// assert_eq!("7".parse::<micromap_index::bake::BakeLevel>().unwrap().level().get(), 7);
/// assert!("+7".parse::<micromap_index::bake::BakeLevel>().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct BakeLevelError;

impl fmt::Display for BakeLevelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "expected a level 0..={MAX_BAKE_LEVEL} (the highest DXR allows and Vulkan devices report)"
        )
    }
}

impl core::error::Error for BakeLevelError {}

/// `level` if it is in `0..=`[`MAX_BAKE_LEVEL`]: the one check every front
/// end makes of a bake level.
pub fn bake_level(level: u32) -> Result<Level, BakeLevelError> {
    if level <= MAX_BAKE_LEVEL {
        Ok(Level(level as u8))
    } else {
        Err(BakeLevelError)
    }
}

/// A level a front end bakes at, parsed from decimal digits only (no sign,
/// no spaces): what `--level 7` and `--max-level 7` read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BakeLevel(Level);

impl BakeLevel {
    /// The level.
    #[must_use]
    pub fn level(self) -> Level {
        self.0
    }
}

impl core::str::FromStr for BakeLevel {
    type Err = BakeLevelError;

    fn from_str(text: &str) -> Result<BakeLevel, BakeLevelError> {
        if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
            return Err(BakeLevelError);
        }
        let level = text.parse::<u32>().map_err(|_| BakeLevelError)?;
        bake_level(level).map(BakeLevel)
    }
}

/// The paper's highest useful level (eq. 1): the smallest `n` with every UV
/// edge, measured in texels (`(du W, dv H)`), at most `2^n` long, capped at
/// `max` and at [`Micromap::MAX_LEVEL`] (16, the highest level a micromap
/// has and the baker bakes). A triangle with a non-finite coordinate gets
/// level 0.
///
/// ```
/// use micromap_index::bake::useful_level;
/// use micromap_index::Level;
/// let max = Level::new(12).unwrap();
/// // 64 texels across on a 256-texel texture: level 6.
/// assert_eq!(useful_level(&[[0.0, 0.0], [0.25, 0.0], [0.0, 0.25]], (256, 256), max).get(), 7);
/// assert_eq!(useful_level(&[[0.0, 0.0], [0.25, 0.0], [0.25, 0.0]], (256, 256), max).get(), 6);
/// assert_eq!(useful_level(&[[0.0, 0.0], [f32::NAN, 0.0], [0.0, 1.0]], (256, 256), max).get(), 0);
/// assert_eq!(useful_level(&[[0.0, 0.0], [100.0, 0.0], [0.0, 1.0]], (256, 256), max).get(), 12);
/// ```
#[must_use]
pub fn useful_level(uv: &UvTriangle, (width, height): (u32, u32), max: Level) -> Level {
    let mut longest = 0f64;
    for k in 0..3 {
        let (a, b) = (uv[k], uv[(k + 1) % 3]);
        let du = (f64::from(b[0]) - f64::from(a[0])) * f64::from(width);
        let dv = (f64::from(b[1]) - f64::from(a[1])) * f64::from(height);
        // Squared lengths: no square root needed (nor available without
        // std); `length <= 2^n` iff `length^2 <= 4^n`.
        let squared = du * du + dv * dv;
        if !squared.is_finite() {
            return Level(0);
        }
        longest = longest.max(squared);
    }
    let max = max.get().min(Micromap::MAX_LEVEL);
    let mut level = 0;
    let mut span = 1f64;
    while span < longest && level < max {
        level += 1;
        span *= 4.0;
    }
    Level(level as u8)
}

/// Levels for many triangles that fit `budget_bytes` of micromap data: each
/// triangle's `wanted` level, capped by one level for all, the highest cap
/// whose total [`Micromap::byte_len`] fits. If even level 0 does not fit,
/// every triangle gets level 0. Wanted levels above
/// [`Micromap::MAX_LEVEL`] (16) are taken as 16; the total saturates, so
/// no level or count overflows it.
///
/// ```
/// use micromap_index::bake::levels_within_budget;
/// use micromap_index::micromap::Format;
/// use micromap_index::Level;
/// let l = |n| Level::new(n).unwrap();
/// // Level 4 (4-state) is 64 bytes, level 3 is 16 bytes.
/// let wanted = [l(4), l(4), l(2)];
/// assert_eq!(levels_within_budget(&wanted, Format::FourState, 200), vec![l(4), l(4), l(2)]);
/// assert_eq!(levels_within_budget(&wanted, Format::FourState, 100), vec![l(3), l(3), l(2)]);
/// ```
#[must_use]
pub fn levels_within_budget(wanted: &[Level], format: Format, budget_bytes: u64) -> Vec<Level> {
    let total = |cap: u32| -> u64 {
        wanted.iter().fold(0u64, |sum, l| {
            let bytes = Micromap::byte_len(Level(l.get().min(cap) as u8), format) as u64;
            sum.saturating_add(bytes)
        })
    };
    let mut cap = wanted
        .iter()
        .map(|l| l.get())
        .max()
        .unwrap_or(0)
        .min(Micromap::MAX_LEVEL);
    while cap > 0 && total(cap) > budget_bytes {
        cap -= 1;
    }
    wanted
        .iter()
        .map(|l| Level(l.get().min(cap) as u8))
        .collect()
}

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

/// The level each triangle is baked at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelRule {
    /// One level for every triangle.
    Fixed(Level),
    /// Each triangle's [`useful_level`](super::useful_level) (the paper's eq. 1: edges at most
    /// one texel long), capped at `max`; level 0 where micro-triangles at
    /// that level would each hold a whole texture period
    /// ([`level_within_periods`](super::level_within_periods); the rule as
    /// [`LevelRule::level_of`] applies it).
    Useful {
        /// The highest level chosen.
        max: Level,
    },
}

impl Default for LevelRule {
    /// [`LevelRule::Useful`] up to level 12, the highest DXR allows and
    /// Vulkan devices report.
    fn default() -> Self {
        LevelRule::Useful { max: Level(12) }
    }
}
