//! Bodies of the fuzz targets in `fuzz/` (cargo feature `fuzzing`).
//!
//! Each function takes arbitrary bytes, decodes them deterministically into
//! an input (documented on the function; missing bytes read as zero, extra
//! bytes are ignored unless stated otherwise) and checks a differential
//! property. It panics **only** when that property fails, with a message
//! giving the input exactly (float bits in hex, rationals as `p/q`); on every
//! other input it returns normally, whatever the bytes.
//!
//! The same bodies run under libFuzzer (`cargo +nightly fuzz run <target>`,
//! see `docs/fuzzing.md`) and on stable, where `tests/fuzz_corpus.rs` replays
//! every committed seed of `fuzz/corpus/<target>/` and
//! `fuzz/regressions/<target>/`.
//!
//! | function | fuzz target | property |
//! |---|---|---|
//! | [`spec_vs_mirror`] | `spec_vs_mirror` | [`spec::index_f32`] = [`spec::reference_bits_f32_by_integers`] (and, in the target, = the C reference) for every `f32` pair and level |
//! | [`exact_walk_vs_fixed`] | `exact_walk_vs_fixed` | [`internals::index_real_ref`] (BigRational) = [`uv2index::index_real`] = [`uv2index::exact_index_f32`] / [`uv2index::exact_index_f64`] on finite floats, levels `0..=32`, errors included |
//! | [`inverse_round_trip`] | `inverse_round_trip` | [`inverse::micro_triangle`] and the walk invert each other |
//! | [`eval_input`] | `eval_input` | [`eval::eval_line_bytes`] never panics and writes one JSON object line; [`Value::parse`] round-trips |
//! | [`vector_reader`] | `vector_reader` | [`vectors::parse_vector_file`] and [`vectors::parse_answers`] never panic; what they accept round-trips; [`vectors::check`] adds up |
//! | [`micromap_buffers`] | `micromap_buffers` | `micromap::read_buffers` never panics; what it accepts is consistent and rebuilds |
//! | [`strided_buffers`] | `strided_buffers` | `micromap::read_buffers` at any record and index strides never panics, refuses exactly the strides `ReadOptions::check_strides` refuses, and reads buffers re-laid at allowed strides (junk in the gaps) as the tight ones |
//! | [`succinct_tree`] | `succinct_tree` | the succinct-tree readers never panic; both layouts round-trip and agree with the flat micromap |
//! | [`alpha_image`] | `alpha_image` | [`assets::decode_alpha_image`] never panics, stays within [`FUZZ_LIMITS`], and what it accepts has `width * height` texels |
//! | [`triangles_json`] | `triangles_json` | [`assets::read_triangles_json`] never panics; what it accepts writes back and reads back bit for bit |
//! | [`bake_budgets`] | `bake_budgets` | [`mesh::bake_meshes`] under work budgets never panics, spends within one micro-triangle of each budget, counts every cut triangle, and bakes only what the verifier finds sound |
//! | [`bake_transformed`] | `bake_transformed` | [`Baker::with_uv_transform`] never panics; [`UvTransform::new`] refuses exactly non-finite parameters and rotations beyond `MAX_ROTATION`; no known micro-triangle is contradicted by [`uv_transform_oracle`](crate::uv_transform_oracle) (the shader's binary32 transform, nearest filter) |
//! | [`bake_vertex_alpha`] | `bake_vertex_alpha` | [`mesh::bake_mesh`] with vertex alpha under linear filtering by value never panics; each triangle bakes alone as in its mesh (where its UVs are walked with other alphas); every known micro-triangle holds at sampled points under the exact bilinear value times the exact alpha; [`mesh::verify_mesh`] calls the bake sound |
//! | [`texel_tables_within`] | `texel_tables_within` | [`Baker::new_within`] builds the texel tables only within its byte limit and otherwise answers a typed error naming the bytes and the limit (never an abort) |
//! | [`gltf_asset`] | `gltf_asset` | [`assets::read_gltf_bytes`] (URIs served [`FUZZ_PNG`]) never panics, stays within [`FUZZ_LIMITS`], and what it accepts is consistent |
//!
//! ```
//! use micromap_index_lab::fuzzing;
//! // Every body accepts any bytes, the empty input included.
//! for data in [&[][..], &[0xff; 40][..], b"{\"u\": \"0.5\"}"] {
//!     fuzzing::spec_vs_mirror(data);
//!     fuzzing::exact_walk_vs_fixed(data);
//!     fuzzing::inverse_round_trip(data);
//!     fuzzing::eval_input(data);
//!     fuzzing::vector_reader(data);
//!     fuzzing::alpha_image(data);
//!     fuzzing::triangles_json(data);
//!     fuzzing::gltf_asset(data);
//! }
//! ```
//!
//! [`spec::index_f32`]: micromap_index::spec::index_f32
//! [`spec::reference_bits_f32_by_integers`]: micromap_index::spec::reference_bits_f32_by_integers
//! [`internals::index_real_ref`]: micromap_index::internals::index_real_ref
//! [`uv2index::index_real`]: micromap_index::uv2index::index_real
//! [`uv2index::exact_index_f32`]: micromap_index::uv2index::exact_index_f32
//! [`uv2index::exact_index_f64`]: micromap_index::uv2index::exact_index_f64
//! [`inverse::micro_triangle`]: micromap_index::inverse::micro_triangle
//! [`eval::eval_line_bytes`]: crate::eval::eval_line_bytes
//! [`Value::parse`]: crate::value::Value::parse
//! [`vectors::parse_vector_file`]: crate::vectors::parse_vector_file
//! [`vectors::parse_answers`]: crate::vectors::parse_answers
//! [`vectors::check`]: crate::vectors::check
//! [`assets::decode_alpha_image`]: micromap_index_assets::decode_alpha_image
//! [`assets::read_triangles_json`]: micromap_index_assets::read_triangles_json
//! [`assets::read_gltf_bytes`]: micromap_index_assets::read_gltf_bytes
//! [`mesh::bake_meshes`]: micromap_index::bake::mesh::bake_meshes
//! [`mesh::bake_mesh`]: micromap_index::bake::mesh::bake_mesh
//! [`mesh::verify_mesh`]: micromap_index::bake::mesh::verify_mesh
//! [`Baker::new_within`]: micromap_index::bake::Baker::new_within
//! [`Baker::with_uv_transform`]: micromap_index::bake::Baker::with_uv_transform
//! [`UvTransform::new`]: micromap_index::bake::UvTransform::new

mod assets;
mod bake_budgets;
mod bake_transformed;
mod bake_vertex_alpha;
mod eval_input;
mod exact_walk_vs_fixed;
mod inverse_round_trip;
mod micromap_buffers;
mod spec_vs_mirror;
mod strided_buffers;
mod succinct_tree;
mod vector_reader;
pub use assets::{alpha_image, gltf_asset, triangles_json, FUZZ_LIMITS, FUZZ_PNG};
pub use bake_budgets::{bake_budgets, texel_tables_within};
pub use bake_transformed::bake_transformed;
pub use bake_vertex_alpha::bake_vertex_alpha;
pub use eval_input::eval_input;
pub use exact_walk_vs_fixed::exact_walk_vs_fixed;
pub use inverse_round_trip::inverse_round_trip;
pub use micromap_buffers::micromap_buffers;
pub use spec_vs_mirror::{spec_vs_mirror, SpecCase};
pub use strided_buffers::strided_buffers;
pub use succinct_tree::succinct_tree;
pub use vector_reader::vector_reader;

use crate::eval::{eval_line_bytes, Variant};
use crate::value::{Value, MAX_VALUE_LEN};
use crate::vectors;
use micromap_index::inverse::{micro_triangle, MicroTriangle};
use micromap_index::{spec, uv2index, Level, SpecLevel};
use micromap_index_test_support::step_ulps;
use num_bigint::BigInt;
use num_rational::BigRational;

/// Reads the fuzzer's bytes front to back; past the end every byte is 0.
struct Bytes<'a> {
    rest: &'a [u8],
}

impl<'a> Bytes<'a> {
    fn new(data: &'a [u8]) -> Self {
        Bytes { rest: data }
    }

    fn byte(&mut self) -> u8 {
        match self.rest.split_first() {
            Some((&first, rest)) => {
                self.rest = rest;
                first
            }
            None => 0,
        }
    }

    /// `N` bytes, little-endian, zero-padded.
    fn le<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        for slot in &mut out {
            *slot = self.byte();
        }
        out
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.le())
    }

    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.le())
    }
}

/// `text` with the variant's name in a level message ("spec-f32 supports
/// levels 0..=16") replaced by `VARIANT`: two variants that agree give the
/// same text.
fn naming_no_variant(text: &str, variant: Variant) -> String {
    text.replace(&format!(" {variant} supports"), " VARIANT supports")
}
