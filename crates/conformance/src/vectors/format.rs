//! The file format: [`VectorFile`], [`Case`], the [`VectorSet`]s this
//! crate writes, and the canonical text ([`VectorFile::to_json_text`]).

use crate::eval::Variant;
use num_rational::BigRational;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// One vector file: a function and its cases.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct VectorFile {
    /// Always [`FORMAT`](super::FORMAT).
    pub format: String,
    /// Always [`VERSION`](super::VERSION).
    pub version: u64,
    /// The function the expected indices are of: an `eval` variant name
    /// (`spec-f32`, `spec-exact`, `uv2index-exact`).
    pub function: String,
    /// What the function is, in a sentence.
    #[serde(default)]
    pub description: String,
    /// The cases, in id order.
    pub cases: Vec<Case>,
}

/// One input and its expected index.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Case {
    /// Unique within the file.
    pub id: u64,
    /// `u` in the `eval` value syntax ([`Value::parse`](crate::value::Value::parse)).
    pub u: String,
    /// `v` in the `eval` value syntax.
    pub v: String,
    /// The subdivision level.
    pub level: u32,
    /// The expected micro-triangle index.
    pub index: u64,
    /// The classes the case belongs to ([`tag`](super::tag)).
    pub tags: Vec<String>,
    /// For reading only: the shortest decimal that reads back as the same
    /// binary32 value (binary32 set); `u` is normative.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_decimal: Option<String>,
    /// For reading only, like `u_decimal`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_decimal: Option<String>,
}

/// The three sets the lab's generator writes (`reference/vectors/`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VectorSet {
    /// [`spec::index_f32`](micromap_index::spec::index_f32) on binary32 bit patterns.
    SpecF32,
    /// [`spec::index_real`](micromap_index::spec::index_real) on exact rationals.
    SpecExact,
    /// [`uv2index::index_real`](micromap_index::uv2index::index_real) on exact rationals of the closed triangle.
    Uv2indexExact,
}

impl VectorSet {
    /// Every set, in file order.
    pub const ALL: [VectorSet; 3] = [
        VectorSet::SpecF32,
        VectorSet::SpecExact,
        VectorSet::Uv2indexExact,
    ];

    /// The `function` field: the name of the `eval` variant that computes
    /// the set, as the published format (version 1) has it: the variant's
    /// legacy name where it has one (`spec-exact` for `spec-real`,
    /// `uv2index-exact` for `walk-real`), so published files and scripts keep
    /// working.
    #[must_use]
    pub fn function(self) -> &'static str {
        let variant = self.variant();
        variant.legacy_name().unwrap_or(variant.name())
    }

    /// The `eval` variant that computes the set.
    #[must_use]
    pub fn variant(self) -> Variant {
        match self {
            VectorSet::SpecF32 => Variant::SpecF32,
            VectorSet::SpecExact => Variant::SpecReal,
            VectorSet::Uv2indexExact => Variant::WalkReal,
        }
    }

    /// The file name the set is written to: `FUNCTION.json`.
    ///
    /// ```
    /// use micromap_index_conformance::vectors::VectorSet;
    /// assert_eq!(VectorSet::SpecF32.file_name(), "spec-f32.json");
    /// ```
    #[must_use]
    pub fn file_name(self) -> String {
        format!("{}.json", self.function())
    }

    /// The `description` field.
    #[must_use]
    pub fn description(self) -> &'static str {
        match self {
            VectorSet::SpecF32 => {
                "Vulkan BarycentricsToSpaceFillingCurveIndex evaluated in IEEE binary32 \
                 (round to nearest even, no FMA contraction, NaN clamps to 0): what a GPU \
                 must return. u, v: binary32 bit patterns."
            }
            VectorSet::SpecExact => {
                "The Vulkan reference's steps over the reals: exact products, floors and \
                 fractions, exact uf + vf >= 1. u, v: exact rationals p/q."
            }
            VectorSet::Uv2indexExact => {
                "The paper's uv2index walk (Algorithm 4) over the reals, on points of the \
                 closed triangle only. u, v: exact rationals p/q, each exactly a binary32 value."
            }
        }
    }
}

/// `"0x"` and the 8 hex digits of the bits.
#[must_use]
pub fn f32_text(x: f32) -> String {
    format!("0x{:08x}", x.to_bits())
}

/// Always `p/q`, also for integers (`0/1`), so readers need one form only.
#[must_use]
pub fn rational_text(r: &BigRational) -> String {
    format!("{}/{}", r.numer(), r.denom())
}

/// `x` as an exact rational; `None` for NaN and the infinities.
#[must_use]
pub fn exact_of_f32(x: f32) -> Option<BigRational> {
    BigRational::from_float(f64::from(x))
}

impl VectorFile {
    /// The file's canonical text: the header fields one per line, then one
    /// case per line as compact JSON (fields in [`Case`] order), so diffs
    /// are per case and line-based readers work. Ends with a newline.
    ///
    /// ```
    /// use micromap_index_conformance::vectors::{parse_vector_file, Case, VectorFile, FORMAT, VERSION};
    /// let case = Case {
    ///     id: 0, u: "0x3e800000".into(), v: "0x3e800000".into(), level: 2, index: 5,
    ///     tags: vec!["vertex".into()], u_decimal: Some("0.25".into()), v_decimal: None,
    /// };
    /// let file = VectorFile {
    ///     format: FORMAT.into(), version: VERSION, function: "spec-f32".into(),
    ///     description: String::new(), cases: vec![case],
    /// };
    /// assert_eq!(parse_vector_file(file.to_json_text().as_bytes()).unwrap(), file);
    /// ```
    #[must_use]
    pub fn to_json_text(&self) -> String {
        let string = |s: &str| serde_json::Value::from(s).to_string();
        let mut text = String::new();
        text.push_str("{\n");
        let _ = writeln!(text, "  \"format\": {},", string(&self.format));
        let _ = writeln!(text, "  \"version\": {},", self.version);
        let _ = writeln!(text, "  \"function\": {},", string(&self.function));
        let _ = writeln!(text, "  \"description\": {},", string(&self.description));
        text.push_str("  \"cases\": [\n");
        for (n, case) in self.cases.iter().enumerate() {
            // A derived Serialize of strings and integers cannot fail.
            let line = serde_json::to_string(case).unwrap_or_default();
            let comma = if n + 1 < self.cases.len() { "," } else { "" };
            let _ = writeln!(text, "    {line}{comma}");
        }
        text.push_str("  ]\n}\n");
        text
    }
}
