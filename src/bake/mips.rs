//! Baking for every mip level a sampler could choose ([`Mips::All`]).
//!
//! The model: mip level `k + 1` of a `W x H` texture is
//! `max(1, W >> 1) x max(1, H >> 1)` texels (Vulkan's and OpenGL's sizes),
//! made by a box filter from level `k`, stored in 8 bits or finer: texel
//! `x` covers `floor(x W_k / W_(k+1)) ..= ceil((x + 1) W_k / W_(k+1)) - 1`
//! of level `k`. On an even axis that is two texels, weighted equally (the
//! 2x2 box of `glGenerateMipmap`, the glTF sample viewer and KTX tools on
//! power-of-two textures); on an odd axis one to three texels, with any
//! non-negative weights (implementations differ there). Each level's texels
//! are bounded by intervals: the filter applied to the bounds of the level
//! above, then rounded outwards to the 8-bit grid (so any rounding to 8
//! bits stays inside) and widened by `2^-16` (16-bit and binary32 storage,
//! and this arithmetic). A filter with negative lobes (Lanczos, Kaiser) is
//! not modelled.
//!
//! Each level is then classified twice: against the lower bounds (a texel
//! is opaque only if its lower bound passes the cutoff) and against the
//! upper bounds (transparent only if its upper bound fails it), under
//! linear filtering, whose footprint contains nearest filtering's (so
//! both `minFilter`s and trilinear blending are covered: a blend of two
//! values that pass the cutoff is taken to pass it, as for bilinear
//! filtering within a level). Level 0 is also classified under linear
//! filtering. A micro-triangle is known opaque (transparent) only if it is
//! under the material's sampler at level 0 and under every one of these
//! classifications.

use super::baker::Baker;
use super::gpu::Model;
use super::texture::{AlphaTexture, Filter, Sampler, TextureError};
use super::triangle::{BakeError, BakedTriangle, TriangleStatus, UvTriangle};
use crate::micromap::BakedOpacity;
use crate::micromap::{Format, Micromap, MicromapError, State, UnknownPolicy};
use crate::Level;
use alloc::vec::Vec;

/// Which mip levels a bake must hold for.
///
/// ```
/// use micromap_index::bake::mesh::Mips;
/// assert_eq!(Mips::default(), Mips::Level0);
/// assert_eq!("all".parse(), Ok(Mips::All));
/// assert_eq!("0".parse(), Ok(Mips::Level0));
/// assert_eq!("3".parse(), Ok(Mips::UpTo(3)));
/// assert!("-1".parse::<Mips>().is_err());
/// assert!("".parse::<Mips>().is_err());
/// assert_eq!(Mips::UpTo(3).to_string(), "3");
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Mips {
    /// Level 0 only (the default), under the material's sampler: what ray
    /// tracing shaders sample when they give the level explicitly, as they
    /// usually do.
    #[default]
    Level0,
    /// Levels `0..=n` (past the chain's `1 x 1` level, all of it), under
    /// either filter: a sampler whose level of detail is clamped to `n`
    /// (`maxLod`), or known to stay below it. (`UpTo(0)`: level 0 under
    /// either filter.)
    UpTo(u32),
    /// Every level of the chain down to `1 x 1`, under either filter. The
    /// `1 x 1` level is the texture's mean: at most one class survives it.
    All,
}

impl Mips {
    /// The last mip level the rule covers (`u32::MAX` for all).
    fn last(self) -> u32 {
        match self {
            Mips::Level0 => 0,
            Mips::UpTo(n) => n,
            Mips::All => u32::MAX,
        }
    }
}

impl core::str::FromStr for Mips {
    type Err = crate::names::ParseNameError;

    /// The rule named `name`: `0`, a level `n`, or `all` (the CLI's
    /// `--mips`).
    fn from_str(name: &str) -> Result<Mips, Self::Err> {
        let error = crate::names::ParseNameError::new("mips", "0, a level N or all");
        match name {
            "all" => Ok(Mips::All),
            _ if !name.is_empty() && name.bytes().all(|b| b.is_ascii_digit()) => {
                let n: u32 = name.parse().map_err(|_| error)?;
                Ok(if n == 0 { Mips::Level0 } else { Mips::UpTo(n) })
            }
            _ => Err(error),
        }
    }
}

impl core::fmt::Display for Mips {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Mips::Level0 => f.write_str("0"),
            Mips::UpTo(n) => write!(f, "{n}"),
            Mips::All => f.write_str("all"),
        }
    }
}

/// One mip level's lower or upper alpha bounds.
pub(crate) struct BoundTexture {
    width: u32,
    height: u32,
    alphas: Vec<f64>,
}

impl AlphaTexture for BoundTexture {
    fn width(&self) -> u32 {
        self.width
    }
    fn height(&self) -> u32 {
        self.height
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        self.alphas[y as usize * self.width as usize + x as usize]
    }
}

/// The texels of the level below that texel `x` of a level of `to` texels
/// covers, on an axis of `from` texels.
fn window(x: u32, from: u32, to: u32) -> (u32, u32) {
    let (x, from, to) = (u64::from(x), u64::from(from), u64::from(to));
    let lo = x * from / to;
    let hi = ((x + 1) * from).div_ceil(to) - 1;
    (lo as u32, hi as u32)
}

/// One axis's filter from a window of the level below: the mean of the
/// two texels of an even axis (a box filter's equal weights), any mix of
/// the one to three texels of an odd one (an implementation's own
/// weights: the least lower and the greatest upper bound). Lower bounds
/// keep NaN (an average with a NaN in it is NaN, never opaque); upper
/// bounds carry a NaN as `-inf` (NaN is never opaque, so any bound holds).
fn axis_bounds(bounds: &[(f64, f64)], even: bool) -> (f64, f64) {
    let nan_low = bounds.iter().any(|b| b.0.is_nan());
    let highs = bounds
        .iter()
        .map(|b| if b.1.is_nan() { f64::NEG_INFINITY } else { b.1 });
    let (lo, hi) = if even {
        ((bounds[0].0 + bounds[1].0) / 2.0, highs.sum::<f64>() / 2.0)
    } else {
        (
            bounds.iter().map(|b| b.0).fold(f64::INFINITY, f64::min),
            highs.fold(f64::NEG_INFINITY, f64::max),
        )
    };
    (if nan_low { f64::NAN } else { lo }, hi)
}

/// How far a stored mip texel may be from the filter's value beyond the
/// 8-bit grid: a 16-bit or binary32 texel's rounding, and this `f64`
/// arithmetic's, are far below it.
const STORAGE_SLACK: f64 = 1.0 / 65536.0;

/// The next level's bounds from `(lower, upper)`, rounded outwards to the
/// 8-bit grid (any rounding of an 8-bit texel stays between them) and by
/// [`STORAGE_SLACK`].
fn next_level(
    (lower, upper): (&dyn AlphaTexture, &dyn AlphaTexture),
) -> Result<(BoundTexture, BoundTexture), TextureError> {
    let (w, h) = (lower.width(), lower.height());
    let (nw, nh) = ((w >> 1).max(1), (h >> 1).max(1));
    let len = nw as usize * nh as usize;
    let failed = TextureError::AllocationFailed {
        bytes: (len as u64).saturating_mul(16),
        limit: u64::MAX,
    };
    let mut lows = Vec::new();
    let mut highs = Vec::new();
    lows.try_reserve_exact(len).map_err(|_| failed.clone())?;
    highs.try_reserve_exact(len).map_err(|_| failed)?;
    let (even_x, even_y) = (w % 2 == 0, h % 2 == 0);
    let mut rows = Vec::with_capacity(3);
    let mut row = Vec::with_capacity(3);
    for y in 0..nh {
        let (y0, y1) = window(y, h, nh);
        for x in 0..nw {
            let (x0, x1) = window(x, w, nw);
            rows.clear();
            for sy in y0..=y1 {
                row.clear();
                row.extend((x0..=x1).map(|sx| (lower.alpha(sx, sy), upper.alpha(sx, sy))));
                rows.push(axis_bounds(&row, even_x));
            }
            let (lo, hi) = axis_bounds(&rows, even_y);
            // Floor and ceiling on the 8-bit grid (the values are small:
            // exact casts), NaN and infinities kept.
            let grid = |v: f64, up: bool| {
                if !v.is_finite() {
                    return v;
                }
                let t = v * 255.0;
                let i = t as i64 as f64;
                let r = if up && i < t {
                    i + 1.0
                } else if !up && i > t {
                    i - 1.0
                } else {
                    i
                };
                r / 255.0
            };
            lows.push(grid(lo, false) - STORAGE_SLACK);
            highs.push(grid(hi, true) + STORAGE_SLACK);
        }
    }
    let bound = |alphas| BoundTexture {
        width: nw,
        height: nh,
        alphas,
    };
    Ok((bound(lows), bound(highs)))
}

/// The bakers of `mips` beyond the material's own at level 0 (none for
/// [`Mips::Level0`]): level 0 under linear filtering (when the sampler is
/// nearest), then a lower- and an upper-bound baker for each level `1..`
/// down to the rule's last or `1 x 1`. Each is made by `make` from a
/// texture and the sampler to use.
pub(crate) fn mip_bakers(
    mips: Mips,
    texture: &dyn AlphaTexture,
    sampler: Sampler,
    make: &dyn Fn(&dyn AlphaTexture, Sampler) -> Result<Baker, TextureError>,
) -> Result<Vec<(Baker, Baker)>, TextureError> {
    if mips == Mips::Level0 {
        return Ok(Vec::new());
    }
    let linear = Sampler {
        filter: Filter::Linear,
        ..sampler
    };
    let mut bakers = Vec::new();
    if sampler.filter == Filter::Nearest {
        let b = make(texture, linear)?;
        bakers.push((b.clone(), b));
    }
    let (mut w, mut h) = (texture.width(), texture.height());
    let mut level: Option<(BoundTexture, BoundTexture)> = None;
    let mut k = 0;
    while (w > 1 || h > 1) && k < mips.last() {
        k += 1;
        let next = match &level {
            None => next_level((texture, texture))?,
            Some((lo, hi)) => next_level((lo, hi))?,
        };
        bakers.push((make(&next.0, linear)?, make(&next.1, linear)?));
        (w, h) = (next.0.width, next.0.height);
        level = Some(next);
    }
    Ok(bakers)
}

/// Combines four-state bakes of one triangle against lower bounds (their
/// opaque states hold) and upper bounds (their transparent states hold),
/// pairwise `(lower, upper)`: a micro-triangle is opaque if every lower
/// bake says so, transparent if every upper bake does, else unknown, split
/// by the first upper bake's state. The result is in `format` (2-state
/// unknowns resolved by `two_state`), its counts before resolving; its
/// `widened` is 0 (the caller's to count). A special index (from the
/// coordinates alone, so every bake agrees) is returned as it is.
pub(crate) fn combine_bounds(
    pairs: &[(BakedTriangle, BakedTriangle)],
    level: Level,
    format: Format,
    two_state: UnknownPolicy,
) -> Result<BakedTriangle, MicromapError> {
    let first = &pairs[0];
    if let BakedOpacity::Special(_) = first.0.opacity {
        return Ok(first.0.clone());
    }
    let mut map = Micromap::new(level, format)?;
    let mut counts = [0u64; 4];
    let state_of = |t: &BakedTriangle, i: u64| t.opacity.state(i).unwrap_or(State::UnknownOpaque);
    for i in 0..level.micro_triangle_count() as u64 {
        let state = if pairs.iter().all(|p| state_of(&p.0, i) == State::Opaque) {
            State::Opaque
        } else if pairs
            .iter()
            .all(|p| state_of(&p.1, i) == State::Transparent)
        {
            State::Transparent
        } else if matches!(state_of(&first.1, i), State::Opaque | State::UnknownOpaque) {
            State::UnknownOpaque
        } else {
            State::UnknownTransparent
        };
        counts[state.bits() as usize] += 1;
        let stored = match format {
            Format::FourState => state,
            Format::TwoState => two_state.resolve(state),
        };
        map.set(i, stored)?;
    }
    let any = |status| {
        pairs
            .iter()
            .any(|(a, b)| a.status == status || b.status == status)
    };
    let status = if any(TriangleStatus::WorkBudgetExceeded) {
        TriangleStatus::WorkBudgetExceeded
    } else if any(TriangleStatus::BlockBudgetExceeded) {
        TriangleStatus::BlockBudgetExceeded
    } else {
        first.0.status
    };
    Ok(BakedTriangle {
        opacity: BakedOpacity::Map(map),
        status,
        counts,
        widened: 0,
        work: 0,
        speculative_work: 0,
    })
}

/// Bakes one triangle against bakers of lower and upper bounds, pairwise
/// `(lower, upper)` (a baker may be both), and combines them
/// ([`combine_bounds`]) into `format`. Its `widened` is the exact model's
/// extra known micro-triangles, from a second round of bakes under the
/// exact model, run only when a bake of the first round widened. The bakes
/// of a round share `max_work` work units in order ([`Baker::bake_within`]);
/// the result's `work` is what both rounds spent.
pub(crate) fn bake_bounded(
    pairs: &[(&Baker, &Baker)],
    uv: &UvTriangle,
    level: Level,
    format: Format,
    two_state: UnknownPolicy,
    max_work: u64,
) -> Result<BakedTriangle, BakeError> {
    let round = |model: Model| -> Result<(BakedTriangle, bool), BakeError> {
        let mut spent = 0u64;
        let mut bake = |baker: &Baker| {
            let b = baker.bake_as(
                model,
                uv,
                level,
                Format::FourState,
                two_state,
                max_work - spent.min(max_work),
                false,
            )?;
            spent = spent.saturating_add(b.work);
            Ok::<_, BakeError>(b)
        };
        let mut bakes = Vec::with_capacity(pairs.len());
        for (low, high) in pairs {
            let low_bake = bake(low)?;
            let high_bake = if core::ptr::eq(*low, *high) {
                low_bake.clone()
            } else {
                bake(high)?
            };
            bakes.push((low_bake, high_bake));
        }
        let widened = bakes.iter().any(|(a, b)| a.widened + b.widened > 0);
        let mut combined = combine_bounds(&bakes, level, format, two_state)?;
        combined.work = spent;
        Ok((combined, widened))
    };
    let model = pairs[0].0.model();
    let (mut combined, widened) = round(model)?;
    if widened {
        let (exact, _) = round(Model::Exact)?;
        let known = |c: [u64; 4]| c[0] + c[1];
        combined.widened = known(exact.counts).saturating_sub(known(combined.counts));
        combined.work = combined.work.saturating_add(exact.work);
    }
    Ok(combined)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The windows tile the level below, each one to three texels, the
    /// 2x2 box on even sizes.
    #[test]
    fn windows_cover_the_level_below() {
        for from in 1..=40u32 {
            let to = (from >> 1).max(1);
            let mut next = 0;
            for x in 0..to {
                let (lo, hi) = window(x, from, to);
                assert!(
                    lo <= next && hi >= lo && hi - lo <= 2 && hi < from,
                    "{from} {x}"
                );
                if from % 2 == 0 {
                    assert_eq!((lo, hi), (2 * x, 2 * x + 1));
                }
                next = hi + 1;
            }
            assert_eq!(next, from);
        }
    }
}
