//! Proofs about the copies of the reference that users' calls run, beyond
//! the generic code the transducer proof of [`crate::prove_all_levels`]
//! derives from (`docs/verification.md`, section 10.12).
//!
//! * [`prove_kernel_integer_halves`]: the kernel's integer half and
//!   interleave (the point kernel and the chunked pipeline's lanes, narrow
//!   and wide) equal the reference's generic integer half at every level
//!   and every cell, by binary decision diagrams ([`bdd`]) over the cell's
//!   bits: the library's functions run on diagram words ([`word`]).
//! * [`prove_cell_dyadic`]: `spec::cell_dyadic`'s steps equal the
//!   definition of the first half (floor, fraction, fractions summing to
//!   1) at every input, scale and level, the same way.
//! * [`prove_binary64_first_half`]: `uv2index::exact_index_f64`'s closed
//!   form's first half (`binary64_coordinate`, `binary64_diagonal`) equal
//!   to the exact first half's definition, every binary64 and level.
//! * [`prove_binary32_first_half`]: the kernel's binary32 first half on the
//!   bits (`binary32_coordinate`, wide, and `clamp_binary32` +
//!   `binary32_unit_coordinate`, narrow) equal to the definition, every
//!   binary32 and level.
//! * [`prove_float_first_half`]: the kernel's float first half
//!   (`clamp_flushed`, `truncate_float`) against its claims, by exhaustion.
//! * [`prove_float_clamp`]: the float clamp's flushing and its stop below 1
//!   leave the index alone (the stop value's cell, the flush value's
//!   fraction, and the integer halves not reading the diagonal at a last
//!   cell, by diagrams).
//! * [`prove_literal_first_half`]: the reference's literal port's first
//!   half (`spec::cell_f32`: `clamp_unit`, `truncate_scaled`) against its
//!   claims, by exhaustion.
//! * [`prove_simd_lanes`]: the x86-64 SIMD lanes (SSE2, AVX2, AVX-512)
//!   are, token for token, the modelled intrinsics, and those intrinsics,
//!   run on this CPU, compute the model's scalar steps at every input they
//!   are given.
//! * [`prove_rationals_source`]: `spec::cell_real`'s fast path is, token
//!   for token, the code `crates/lab/certificates/rationals.py` proves.
//! * [`prove_fixed_arithmetic`]: `num::Fixed64` / `Fixed128`'s walk
//!   arithmetic is, token for token, the modelled exact integer steps
//!   (exact because `product.py` proves every value stays in `[0, 1]`).
//! * [`prove_walk_fold`]: `uv2index::index_unchecked` and `index` are, token
//!   for token, the fold of `Walk::step` the transducer proof models.
//!
//! ```
//! use micromap_index_lab::entry_points::prove_kernel_integer_halves;
//! let proof = prove_kernel_integer_halves().unwrap();
//! assert_eq!(proof.forms.len(), 4);
//! ```

pub mod bdd;
mod binary32;
mod binary64;
mod clamp;
mod dyadic;
mod first_half;
mod fixed;
mod float;
mod fold;
mod kernel;
mod lanes;
mod literal;
mod rationals;
#[cfg(test)]
mod tests;
pub mod word;

pub use binary32::*;
pub use binary64::*;
pub use clamp::*;
pub use dyadic::*;
pub use fixed::*;
pub use float::*;
pub use fold::*;
pub use kernel::*;
pub use lanes::*;
pub use literal::*;
pub use rationals::*;
