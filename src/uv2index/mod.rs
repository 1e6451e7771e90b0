//! The paper's `uv2index` walk (Waldemarson & Doggett, "Succinct Opacity
//! Micromaps", Algorithm 4; the talk's "Lookup Function – 2"), written once
//! and generic over the number type ([`WalkNumber`]).
//!
//! Each step splits the current triangle at its edge midpoints into the
//! Left, Middle, Right and Top children, picks the child holding the point,
//! appends its digit to the index and re-expresses `(u, v, w)` in the child's
//! barycentrics. Two flags carry the orientation: `top_flip` swaps the digits
//! of Left and Right (the Top child's curve runs the other way) and
//! `mid_flip` sends ties on `v = 1/2` to the Middle child (inside an
//! upside-down child the reference's tie-breaks point the other way). See
//! `docs/algorithm.md`.
//!
//! # Guarantees
//!
//! * Over exact numbers the walk equals the Vulkan reference's steps over the
//!   reals at every point of the closed triangle: for levels `0..=16`
//!   against the 32-bit reference and `0..=19` against its 64-bit widening,
//!   checked face by face (`docs/verification.md`); it defines the mapping
//!   up to level 32. [`exact_index_f32`] and [`exact_index_f64`] give that
//!   exact answer for every finite float point with integers only;
//!   `index_real` (feature `exact`) for every rational point.
//! * [`index_in_f32_arithmetic`] and [`index_in_f64_arithmetic`] evaluate each
//!   expression left to right in that float type exactly as the talk's
//!   Python writes it (`w - u - v` is `(w - u) - v`, `w = 1 - (u + v)`), so the
//!   results are reproducible by anyone reading the paper. Rounding makes them
//!   differ from the exact walk near lattice lines; `docs/float.md` measures
//!   where. They are **not** exact.
//! * Every function whose name does not end in `_unchecked` rejects NaN,
//!   infinities and points outside the closed triangle (decided exactly,
//!   before any rounding) with a typed [`Error`]. [`index_unchecked`] checks
//!   nothing and never panics.
//!
//! ```
//! use micromap_index::{uv2index, Level};
//! let level = Level::new(2).unwrap();
//! assert_eq!(uv2index::exact_index_f32(0.3, 0.3, level), Ok(5));
//! assert_eq!(uv2index::index_in_f32_arithmetic(0.3, 0.3, level), Ok(5));
//! assert!(uv2index::exact_index_f64(0.75, 0.5, level).is_err()); // u + v > 1
//! ```

mod exact_float;
mod float;
#[cfg(feature = "exact")]
mod real;

pub use crate::num::WalkNumber;
#[cfg(feature = "unstable-public-internals")]
pub use exact_float::{binary64_clamped_coordinate, binary64_coordinate, binary64_diagonal};
#[cfg(feature = "unstable-public-internals")]
pub use exact_float::{cell_real_f32, cell_real_f64, exact_index_f32_ref, exact_index_f64_ref};
pub use exact_float::{exact_index_f32, exact_index_f64};
pub use float::{index_in_f32_arithmetic, index_in_f64_arithmetic};
#[cfg(feature = "exact")]
pub use real::index_real;
#[cfg(all(feature = "exact", feature = "unstable-public-internals"))]
pub use real::index_real_ref;

use crate::{Error, Level};
use core::cmp::Ordering;

/// The digits of the four children when the current triangle is not
/// flipped; a `top_flip` swaps Left and Right.
pub mod digit {
    /// Left child: the corner at vertex 0 (`w > 1/2`).
    pub const LEFT: u8 = 0;
    /// Middle child: the upside-down centre triangle.
    pub const MIDDLE: u8 = 1;
    /// Right child: the corner at vertex 1 (`u >= 1/2`).
    pub const RIGHT: u8 = 2;
    /// Top child: the corner at vertex 2 (`v >= 1/2`).
    pub const TOP: u8 = 3;
}

/// The state of the walk between steps: the point's barycentrics in the
/// current micro-triangle and the two orientation flags.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Walk<T> {
    /// Weight of the current triangle's vertex 1.
    pub u: T,
    /// Weight of the current triangle's vertex 2.
    pub v: T,
    /// Weight of the current triangle's vertex 0.
    pub w: T,
    /// Ties on `v = 1/2` go to the Middle child (toggled by each Middle step).
    pub mid_flip: bool,
    /// Left and Right digits are swapped (toggled by each Top step).
    pub top_flip: bool,
}

impl<T: WalkNumber> Walk<T> {
    /// The walk at the root triangle, with `w = 1 - (u + v)`.
    #[inline]
    pub fn new(u: T, v: T) -> Self {
        let w = T::one_minus_sum(&u, &v);
        Walk {
            u,
            v,
            w,
            mid_flip: false,
            top_flip: false,
        }
    }

    /// One subdivision step (paper Algorithm 4, talk version 2): returns the
    /// child's digit `0..=3` and moves the state into that child.
    ///
    /// ```
    /// use micromap_index::uv2index::{Walk, digit};
    /// let mut walk = Walk::new(0.25f64, 0.25);
    /// assert_eq!(walk.step(), digit::MIDDLE);
    /// assert!(walk.mid_flip);
    /// assert_eq!((walk.u, walk.v, walk.w), (0.0, 0.5, 0.5));
    /// ```
    #[inline]
    pub fn step(&mut self) -> u8 {
        let (left, right) = if self.top_flip {
            (digit::RIGHT, digit::LEFT)
        } else {
            (digit::LEFT, digit::RIGHT)
        };
        let tie_to_middle = self.mid_flip && self.v.cmp_half() == Ordering::Equal;
        if self.w.cmp_half() == Ordering::Greater {
            let w = self.w.minus(&self.u).minus(&self.v);
            self.u = self.u.twice();
            self.v = self.v.twice();
            self.w = w;
            left
        } else if self.v.cmp_half() != Ordering::Less && !tie_to_middle {
            let v = self.v.minus(&self.u).minus(&self.w);
            self.u = self.u.twice();
            self.v = v;
            self.w = self.w.twice();
            self.top_flip = !self.top_flip;
            digit::TOP
        } else if self.u.cmp_half() != Ordering::Less && !tie_to_middle {
            let u = self.u.minus(&self.v).minus(&self.w);
            self.u = u;
            self.v = self.v.twice();
            self.w = self.w.twice();
            right
        } else {
            self.enter_middle();
            self.mid_flip = !self.mid_flip;
            digit::MIDDLE
        }
    }

    unstable_pub_fn! {
        /// One step of the talk's first version ("Lookup Function – 1"): fixed
        /// digits, and the Top child re-oriented by rotating the coordinates
        /// instead of a flag. Flags are left untouched.
        ///
        /// It agrees with [`Walk::step`] inside every micro-triangle but not on
        /// some edges and vertices; it is kept as an oracle that shows why the
        /// flags exist (`tests/lattice.rs` counts the faces where they differ).
        fn step_version1(&mut self) -> u8 {
            if self.w.cmp_half() == Ordering::Greater {
                let w = self.w.minus(&self.u).minus(&self.v);
                self.u = self.u.twice();
                self.v = self.v.twice();
                self.w = w;
                digit::LEFT
            } else if self.v.cmp_half() != Ordering::Less {
                let v = self.v.minus(&self.u).minus(&self.w);
                let u = self.w.twice();
                self.w = self.u.twice();
                self.u = u;
                self.v = v;
                digit::TOP
            } else if self.u.cmp_half() != Ordering::Less {
                let u = self.u.minus(&self.v).minus(&self.w);
                self.u = u;
                self.v = self.v.twice();
                self.w = self.w.twice();
                digit::RIGHT
            } else {
                self.enter_middle();
                digit::MIDDLE
            }
        }
    }

    /// `(u, v, w) <- (u + v - w, w + u - v, v + w - u)`, shared by both
    /// versions.
    fn enter_middle(&mut self) {
        let u = self.u.plus(&self.v).minus(&self.w);
        let v = self.w.plus(&self.u).minus(&self.v);
        let w = self.v.plus(&self.w).minus(&self.u);
        self.u = u;
        self.v = v;
        self.w = w;
    }
}

/// The walk's index for `(u, v)` at `level`, unchecked: no validation of the
/// point, never panics. For points outside the closed triangle the result
/// is whatever the walk computes (use [`index`] to reject them).
///
/// ```
/// use micromap_index::{uv2index, Level};
/// assert_eq!(uv2index::index_unchecked(0.3f32, 0.3, Level::new(2).unwrap()), 5);
/// ```
#[inline]
#[must_use]
pub fn index_unchecked<T: WalkNumber>(u: T, v: T, level: Level) -> u64 {
    let mut walk = Walk::new(u, v);
    (0..level.get()).fold(0u64, |index, _| (index << 2) | u64::from(walk.step()))
}

unstable_pub_fn! {
    /// The talk's version 1 walk (see [`Walk::step_version1`]), unchecked. A
    /// negative control for the tests: inside micro-triangles both versions
    /// agree; on some lattice vertices and edges they do not (at the vertex
    /// (1/4, 1/4) of level 2 the reference and version 2 say 5, version 1 says 7).
    #[must_use]
    fn index_version1_unchecked<T: WalkNumber>(u: T, v: T, level: Level) -> u64 {
        let mut walk = Walk::new(u, v);
        (0..level.get()).fold(0u64, |index, _| {
            (index << 2) | u64::from(walk.step_version1())
        })
    }
}

/// The walk's index after checking that `(u, v)` is a finite point of the
/// closed triangle ([`Error`] otherwise).
///
/// ```
/// use micromap_index::{uv2index, num::Fixed64, Error, Level, Outside};
/// let level = Level::new(3).unwrap();
/// let x = |n: i64| Fixed64::from_scaled(n, 4).unwrap(); // n / 16
/// assert_eq!(uv2index::index(x(5), x(6), level), Ok(uv2index::index_unchecked(x(5), x(6), level)));
/// assert_eq!(
///     uv2index::index(x(9), x(8), level),
///     Err(Error::OutsideTriangle { reason: Outside::SumAboveOne })
/// );
/// ```
#[inline]
pub fn index<T: WalkNumber>(u: T, v: T, level: Level) -> Result<u64, Error> {
    T::check_point(&u, &v)?;
    Ok(index_unchecked(u, v, level))
}
