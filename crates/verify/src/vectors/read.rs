//! Reading vector files and answers, never panicking: [`parse_vector_file`],
//! [`parse_answers`] and their [`VectorError`].

use super::{Answer, Answers, VectorFile, FORMAT, VERSION};
use crate::value::Value;
use micromap_index::Level;
use serde::Deserialize;
use std::collections::BTreeSet;
use std::fmt;

/// Why a vector or answers file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum VectorError {
    /// The bytes (of the file, or of one answers line) are not UTF-8.
    NotUtf8 {
        /// The answers line (1-based), if it is about one.
        line: Option<usize>,
    },
    /// Not JSON of the expected shape.
    Json {
        /// The answers line (1-based), if it is about one.
        line: Option<usize>,
        /// serde_json's message (with its own line and column for a vector file).
        message: String,
    },
    /// Valid JSON, but not a vector file this crate reads (format, version,
    /// a value or level of a case).
    Schema(String),
    /// Two cases, or two answers, with the same id.
    DuplicateId {
        /// The id.
        id: u64,
        /// The answers line (1-based) of the second one, if about answers.
        line: Option<usize>,
    },
    /// An answers line with neither or both of `index` and `error`.
    BadAnswer {
        /// The line (1-based).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

impl fmt::Display for VectorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = |line: &Option<usize>| match line {
            Some(line) => format!("line {line}: "),
            None => String::new(),
        };
        match self {
            VectorError::NotUtf8 { line } => write!(f, "{}not UTF-8", at(line)),
            VectorError::Json { line, message } => write!(f, "{}bad JSON: {message}", at(line)),
            VectorError::Schema(message) => f.write_str(message),
            VectorError::DuplicateId { id, line } => write!(f, "{}duplicate id {id}", at(line)),
            VectorError::BadAnswer { line, message } => write!(f, "line {line}: {message}"),
        }
    }
}

impl std::error::Error for VectorError {}

/// Reads a vector file: the JSON object, checked for [`FORMAT`],
/// [`VERSION`], unique ids, levels `0..=32` and coordinates in the value
/// syntax. Never panics, whatever the bytes.
///
/// ```
/// use micromap_index_verify::vectors::{parse_vector_file, VectorError};
/// let text = r#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32",
///   "cases": [{"id": 7, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#;
/// let file = parse_vector_file(text.as_bytes()).unwrap();
/// assert_eq!(file.cases[0].index, 5);
/// assert!(matches!(parse_vector_file(b"{"), Err(VectorError::Json { .. })));
/// assert!(matches!(parse_vector_file(b"{\"format\": 1}"), Err(VectorError::Json { .. })));
/// ```
pub fn parse_vector_file(bytes: &[u8]) -> Result<VectorFile, VectorError> {
    let text = std::str::from_utf8(bytes).map_err(|_| VectorError::NotUtf8 { line: None })?;
    let json = |e: serde_json::Error| VectorError::Json {
        line: None,
        message: e.to_string(),
    };
    let value: serde_json::Value = serde_json::from_str(text).map_err(json)?;
    // serde would also read a struct from an array; the schema says objects.
    let cases_are_objects = match value.get("cases") {
        Some(serde_json::Value::Array(cases)) => cases.iter().all(|c| c.is_object()),
        _ => true, // missing or not an array: from_value says so
    };
    if !value.is_object() || !cases_are_objects {
        return Err(VectorError::Schema(
            "expected a JSON object whose \"cases\" are objects".into(),
        ));
    }
    let file: VectorFile = serde_json::from_value(value).map_err(json)?;
    if file.format != FORMAT {
        return Err(VectorError::Schema(format!(
            "format is {:?}, expected {FORMAT:?}",
            file.format
        )));
    }
    if file.version != VERSION {
        return Err(VectorError::Schema(format!(
            "version {} is not supported (this reader knows version {VERSION})",
            file.version
        )));
    }
    let mut ids = BTreeSet::new();
    for case in &file.cases {
        if !ids.insert(case.id) {
            return Err(VectorError::DuplicateId {
                id: case.id,
                line: None,
            });
        }
        if Level::new(case.level).is_err() {
            return Err(VectorError::Schema(format!(
                "case {}: level {} is above {}",
                case.id,
                case.level,
                Level::MAX
            )));
        }
        for (name, text) in [("u", &case.u), ("v", &case.v)] {
            Value::parse(text)
                .map_err(|e| VectorError::Schema(format!("case {}: {name}: {e}", case.id)))?;
        }
    }
    Ok(file)
}

#[derive(Deserialize)]
struct AnswerLine {
    id: u64,
    #[serde(default)]
    index: Option<u64>,
    #[serde(default)]
    error: Option<String>,
}

/// Reads answers: JSON lines `{"id": N, "index": I}` (or
/// `{"id": N, "error": "..."}` for a refused input), extra fields allowed,
/// blank lines skipped, `\r\n` accepted. A repeated id is an error. Never
/// panics, whatever the bytes.
///
/// ```
/// use micromap_index_verify::vectors::{parse_answers, Answer, VectorError};
/// let answers = parse_answers(b"{\"id\": 1, \"index\": 5, \"ms\": 0.1}\n\n{\"id\": 2, \"index\": 0}\n").unwrap();
/// assert_eq!(answers.by_id[&1], Answer::Index(5));
/// assert_eq!(
///     parse_answers(b"{\"id\": 1, \"index\": 5}\n{\"id\": 1, \"index\": 6}"),
///     Err(VectorError::DuplicateId { id: 1, line: Some(2) })
/// );
/// assert!(parse_answers(b"{\"id\": 1}").is_err());
/// ```
pub fn parse_answers(bytes: &[u8]) -> Result<Answers, VectorError> {
    let mut answers = Answers::default();
    for (number, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_number = number + 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let text = std::str::from_utf8(line).map_err(|_| VectorError::NotUtf8 {
            line: Some(line_number),
        })?;
        let json = |e: serde_json::Error| VectorError::Json {
            line: Some(line_number),
            message: e.to_string(),
        };
        // An object, not any JSON serde could read a struct from (an array).
        let object: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(text).map_err(json)?;
        let parsed: AnswerLine =
            serde_json::from_value(serde_json::Value::Object(object)).map_err(json)?;
        let answer = match (parsed.index, parsed.error) {
            (Some(index), None) => Answer::Index(index),
            (None, Some(message)) => Answer::Refused(message),
            (Some(_), Some(_)) => {
                return Err(VectorError::BadAnswer {
                    line: line_number,
                    message: "has both \"index\" and \"error\"".into(),
                })
            }
            (None, None) => {
                return Err(VectorError::BadAnswer {
                    line: line_number,
                    message: "needs \"index\" (a non-negative integer) or \"error\"".into(),
                })
            }
        };
        if answers.by_id.insert(parsed.id, answer).is_some() {
            return Err(VectorError::DuplicateId {
                id: parsed.id,
                line: Some(line_number),
            });
        }
    }
    Ok(answers)
}
