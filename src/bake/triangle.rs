//! One triangle's bake as the walk hands it out: its UVs ([`UvTriangle`]),
//! what it became ([`BakedOpacity`]), how it went ([`TriangleStatus`],
//! [`BakedTriangle`]) and why it could fail ([`BakeError`]).

use crate::micromap::{BakedOpacity, MicromapError};
use core::fmt;

/// A mesh triangle's texture coordinates `[(u, v); 3]` for its vertices 0,
/// 1, 2: the hit with barycentrics `(b1, b2)` reads the texture at
/// `(1 - b1 - b2) uv[0] + b1 uv[1] + b2 uv[2]`.
pub type UvTriangle = [[f32; 2]; 3];

/// How a triangle was baked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TriangleStatus {
    /// Every micro-triangle classified exactly.
    Exact,
    /// A texture coordinate is NaN or infinite: the whole triangle is the
    /// unknown-opaque special index (-4), whatever the format (the OMM
    /// SDK's default for such triangles too).
    NotFinite,
    /// The coordinates' binary exponents are too far apart for the exact
    /// 100-bit grid (e.g. `1e-30` next to `1.0`, or values near `1e30`):
    /// the whole triangle is unknown-opaque (-4), which is sound.
    OutOfExactRange,
    /// Some micro-triangles needed more block tests than the block budget
    /// ([`Baker::with_block_budget`](super::Baker::with_block_budget));
    /// those are unknown (sound, maybe not tight). Never happens to a
    /// micro-triangle whose footprint spans fewer texels than the budget.
    BlockBudgetExceeded,
    /// The triangle spent its work budget ([`Baker::bake_within`](crate::bake::Baker::bake_within), units
    /// in [bounded work](crate::bake#bounded-work)): the micro-triangles not yet decided then
    /// are unknown (sound, maybe not tight).
    WorkBudgetExceeded,
}

/// One baked triangle: its opacity (a micromap, or a special index for a
/// triangle the baker could not place on its grid) and what it found.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct BakedTriangle {
    /// The micromap, or [`State::UnknownOpaque`](crate::micromap::State::UnknownOpaque) as a special index when
    /// [`status`](Self::status) is `NotFinite` or `OutOfExactRange`.
    pub opacity: BakedOpacity,
    /// How it went.
    pub status: TriangleStatus,
    /// Micro-triangles per state, indexed by [`State::bits`](crate::micromap::State::bits), counted
    /// before a 2-state format resolves the unknowns (so a 2-state bake
    /// still tells how many were unknown).
    pub counts: [u64; 4],
    /// Of the unknown micro-triangles, those the exact model
    /// ([`Model::Exact`](crate::bake::Model::Exact)) knows: what the GPU model's widening cost this
    /// triangle (always 0 under the exact model). Each is decided exactly,
    /// by the exact model's classification of that micro-triangle on the
    /// same grid, so `counts`' known ones plus these are the exact model's
    /// known ones (but where the block or work budget runs out under one
    /// model only).
    pub widened: u64,
    /// Work units spent ([bounded work](crate::bake#bounded-work)): what
    /// the serial walk spends, whatever the threads (the budgets count
    /// these).
    pub work: u64,
    /// Work units spent besides, and thrown away: a triangle split over
    /// several threads whose work budget runs out walks some subtrees
    /// speculatively, past where the serial walk stopped or with a budget
    /// it turned out not to have (see `docs/bake.md`, "Bounded work"). 0
    /// on one thread, and whenever the budget does not run out.
    pub speculative_work: u64,
}

/// Why [`Baker::bake`](crate::bake::Baker::bake) failed.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum BakeError {
    /// The micromap could not be made (level above 16, allocation).
    Micromap(MicromapError),
}

impl fmt::Display for BakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BakeError::Micromap(e) => write!(f, "cannot bake: {e}"),
        }
    }
}

impl core::error::Error for BakeError {}

impl From<MicromapError> for BakeError {
    fn from(e: MicromapError) -> Self {
        BakeError::Micromap(e)
    }
}
