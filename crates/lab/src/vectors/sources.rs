//! This crate's own functions as answer sources ([`AnswerSource`],
//! [`compute_answers`]) for demonstrations and self-checks: answers
//! generated here, checked by `micromap_index_conformance`.

use super::{Answer, Answers, Case, VectorFile};
use micromap_index::uv2index::WalkNumber;
use micromap_index::Level;
use micromap_index_conformance::eval::Variant;
use micromap_index_conformance::value::Value;
use num_rational::BigRational;

/// A function of this crate that can answer a vector file: any `eval`
/// variant, or the talk's first walk (`walk-version1-real` over exact
/// rationals, `walk-version1-f32-arithmetic` in binary32; the legacy names
/// `uv2index-version1-exact` and `uv2index-version1-f32` are accepted).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnswerSource {
    /// An `eval` variant.
    Variant(Variant),
    /// [`micromap_index::internals::index_version1_unchecked`] over exact rationals, after the walk's
    /// point check.
    Version1Exact,
    /// [`micromap_index::internals::index_version1_unchecked`] in binary32, after the walk's point check.
    Version1F32,
}

impl AnswerSource {
    /// The source's name: the variant's name, `walk-version1-real` or
    /// `walk-version1-f32-arithmetic`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            AnswerSource::Variant(variant) => variant.name(),
            AnswerSource::Version1Exact => "walk-version1-real",
            AnswerSource::Version1F32 => "walk-version1-f32-arithmetic",
        }
    }

    /// The name earlier releases used, if it differs.
    #[must_use]
    pub fn legacy_name(self) -> Option<&'static str> {
        match self {
            AnswerSource::Variant(variant) => variant.legacy_name(),
            AnswerSource::Version1Exact => Some("uv2index-version1-exact"),
            AnswerSource::Version1F32 => Some("uv2index-version1-f32"),
        }
    }

    /// The source with that name.
    ///
    /// ```
    /// use micromap_index_lab::vectors::AnswerSource;
    /// assert_eq!(AnswerSource::from_name("uv2index-version1-f32"), Some(AnswerSource::Version1F32));
    /// assert_eq!(AnswerSource::from_name("nope"), None);
    /// ```
    #[must_use]
    pub fn from_name(name: &str) -> Option<AnswerSource> {
        Self::all()
            .into_iter()
            .find(|source| source.name() == name || source.legacy_name() == Some(name))
    }

    /// Every source: the `eval` variants, then the two version-1 walks.
    pub fn all() -> Vec<AnswerSource> {
        let mut all: Vec<AnswerSource> = Variant::ALL.map(AnswerSource::Variant).to_vec();
        all.extend([AnswerSource::Version1Exact, AnswerSource::Version1F32]);
        all
    }

    /// This source's answer for one case (a refusal if it rejects the input).
    #[must_use]
    pub fn answer(self, case: &Case) -> Answer {
        match self.evaluate(case) {
            Ok(index) => Answer::Index(index),
            Err(message) => Answer::Refused(message),
        }
    }

    fn evaluate(self, case: &Case) -> Result<u64, String> {
        let u = Value::parse(&case.u).map_err(|e| e.to_string())?;
        let v = Value::parse(&case.v).map_err(|e| e.to_string())?;
        let level = Level::new(case.level).map_err(|e| e.to_string())?;
        match self {
            AnswerSource::Variant(variant) => variant
                .evaluate(&u, &v, u64::from(case.level))
                .map_err(|e| e.to_string()),
            AnswerSource::Version1Exact => {
                let u = u.to_exact().map_err(|e| e.to_string())?;
                let v = v.to_exact().map_err(|e| e.to_string())?;
                BigRational::check_point(&u, &v).map_err(|e| e.to_string())?;
                Ok(micromap_index::internals::index_version1_unchecked(
                    u, v, level,
                ))
            }
            AnswerSource::Version1F32 => {
                let u = u.to_f32().map_err(|e| e.to_string())?;
                let v = v.to_f32().map_err(|e| e.to_string())?;
                f32::check_point(&u, &v).map_err(|e| e.to_string())?;
                Ok(micromap_index::internals::index_version1_unchecked(
                    u, v, level,
                ))
            }
        }
    }
}

/// `source`'s answers to every case of `vectors`.
///
/// ```
/// use micromap_index_lab::vectors::{compute_answers, generate_sets, AnswerSource, Answer};
/// let sets = generate_sets();
/// let answers = compute_answers(AnswerSource::from_name("uv2index-exact").unwrap(), &sets[2]);
/// assert!(sets[2].cases.iter().all(|c| answers.by_id[&c.id] == Answer::Index(c.index)));
/// ```
#[must_use]
pub fn compute_answers(source: AnswerSource, vectors: &VectorFile) -> Answers {
    Answers {
        by_id: vectors
            .cases
            .iter()
            .map(|case| (case.id, source.answer(case)))
            .collect(),
    }
}
