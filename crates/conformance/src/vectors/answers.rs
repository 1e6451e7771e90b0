//! Answers: what another implementation printed ([`Answer`], [`Answers`]).
//! (The lab's own functions as answer sources, `AnswerSource` and
//! `compute_answers`, stay in `micromap-index-lab`.)

use std::collections::BTreeMap;
use std::fmt;
use std::fmt::Write as _;

/// What another implementation answered for one case.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Answer {
    /// `{"id": N, "index": I}`.
    Index(u64),
    /// `{"id": N, "error": "..."}`: the implementation refused the input
    /// (a mismatch).
    Refused(String),
    /// `{"id": N, "unsupported": true}`: the implementation does not
    /// support this case by design (a level above its maximum, an input it
    /// rejects on purpose); counted apart from mismatches.
    Unsupported,
}

impl fmt::Display for Answer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Answer::Index(index) => index.fmt(f),
            Answer::Refused(message) => write!(f, "error {message:?}"),
            Answer::Unsupported => f.write_str("unsupported"),
        }
    }
}

/// Another implementation's answers, by id.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Answers {
    /// The answers, by case id.
    pub by_id: BTreeMap<u64, Answer>,
}

impl Answers {
    /// The answers as JSON lines in id order, each ending with a newline:
    /// `{"id":N,"index":I}`, `{"id":N,"error":"..."}` or
    /// `{"id":N,"unsupported":true}`.
    ///
    /// ```
    /// use micromap_index_conformance::vectors::{parse_answers, Answer, Answers};
    /// let mut answers = Answers::default();
    /// answers.by_id.insert(3, Answer::Index(12));
    /// answers.by_id.insert(4, Answer::Refused("u is NaN".into()));
    /// let text = answers.to_json_lines();
    /// assert_eq!(text, "{\"id\":3,\"index\":12}\n{\"id\":4,\"error\":\"u is NaN\"}\n");
    /// assert_eq!(parse_answers(text.as_bytes()).unwrap(), answers);
    /// ```
    #[must_use]
    pub fn to_json_lines(&self) -> String {
        let mut text = String::new();
        for (id, answer) in &self.by_id {
            let _ = match answer {
                Answer::Index(index) => writeln!(text, "{{\"id\":{id},\"index\":{index}}}"),
                Answer::Refused(message) => writeln!(
                    text,
                    "{{\"id\":{id},\"error\":{}}}",
                    serde_json::Value::from(message.as_str())
                ),
                Answer::Unsupported => writeln!(text, "{{\"id\":{id},\"unsupported\":true}}"),
            };
        }
        text
    }
}
