//! Reading vector files and answers, never panicking: [`parse_vector_file`],
//! [`parse_answers`] and their [`VectorError`].

use super::{Answer, Answers, Case, VectorFile, FORMAT, VERSION};
use crate::eval::Variant;
use crate::value::Value;
use micromap_index::Level;
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use std::fmt;
use std::io::Read;

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
        /// `serde_json`'s message (with its own line and column for a vector file).
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
    /// An answers line with none or more than one of `index`, `error` and
    /// `"unsupported": true`.
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

/// A vector file's fields other than its cases, as [`read_vector_file`]
/// returns them after streaming the cases.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VectorHeader {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`].
    pub version: u64,
    /// The function the expected indices are of: an `eval` variant name
    /// (or its legacy name).
    pub function: String,
    /// The `description` field (empty if absent).
    pub description: String,
    /// How many cases the file holds (at least one).
    pub cases: usize,
}

/// Reads a vector file from `reader` one case at a time, handing each case
/// to `on_case` as soon as it is read and checked, so the memory used is
/// one case, not the file. The checks: the JSON object's `format` is
/// [`FORMAT`], its `version` [`VERSION`], its `function` names an `eval`
/// variant ([`Variant::from_name`]); it has at least one case; case ids
/// strictly increase; every level is `0..=32`, every expected index
/// `< 4^level`, every coordinate in the value syntax. Unknown fields are
/// ignored. Never panics, whatever the bytes; on an error `on_case` may
/// already have seen the cases before it.
///
/// ```
/// use micromap_index_conformance::vectors::read_vector_file;
/// let text = r#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32",
///   "cases": [{"id": 7, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#;
/// let mut indices = vec![];
/// let header = read_vector_file(text.as_bytes(), |case| indices.push(case.index)).unwrap();
/// assert_eq!((header.function.as_str(), header.cases, indices), ("spec-f32", 1, vec![5]));
/// ```
pub fn read_vector_file<R: Read, F: FnMut(Case)>(
    reader: R,
    mut on_case: F,
) -> Result<VectorHeader, VectorError> {
    let mut failure = None;
    let mut deserializer = serde_json::Deserializer::from_reader(reader);
    let visitor = FileVisitor {
        on_case: &mut on_case,
        failure: &mut failure,
    };
    let result = deserializer
        .deserialize_map(visitor)
        .and_then(|header| deserializer.end().map(|()| header));
    match result {
        Ok(header) => Ok(header),
        Err(error) => Err(failure.unwrap_or_else(|| VectorError::Json {
            line: None,
            message: error.to_string(),
        })),
    }
}

/// Reads a whole vector file from bytes: [`read_vector_file`]'s checks,
/// the cases collected. Never panics, whatever the bytes.
///
/// ```
/// use micromap_index_conformance::vectors::{parse_vector_file, VectorError};
/// let text = r#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32",
///   "cases": [{"id": 7, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#;
/// let file = parse_vector_file(text.as_bytes()).unwrap();
/// assert_eq!(file.cases[0].index, 5);
/// assert!(matches!(parse_vector_file(b"{"), Err(VectorError::Json { .. })));
/// assert!(matches!(parse_vector_file(b"{\"format\": 1}"), Err(VectorError::Json { .. })));
/// // An expected index >= 4^level, or no case at all, is a malformed file.
/// let too_big = text.replace("\"index\": 5", "\"index\": 16");
/// assert!(matches!(parse_vector_file(too_big.as_bytes()), Err(VectorError::Schema(_))));
/// let empty = r#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32", "cases": []}"#;
/// assert!(matches!(parse_vector_file(empty.as_bytes()), Err(VectorError::Schema(_))));
/// ```
pub fn parse_vector_file(bytes: &[u8]) -> Result<VectorFile, VectorError> {
    std::str::from_utf8(bytes).map_err(|_| VectorError::NotUtf8 { line: None })?;
    let mut cases = Vec::new();
    let header = read_vector_file(bytes, |case| cases.push(case))?;
    Ok(VectorFile {
        format: header.format,
        version: header.version,
        function: header.function,
        description: header.description,
        cases,
    })
}

/// Records `error` for the caller and returns serde's form of it (which
/// [`read_vector_file`] replaces by the recorded one).
fn fail<E: de::Error>(failure: &mut Option<VectorError>, error: VectorError) -> E {
    let message = error.to_string();
    *failure = Some(error);
    E::custom(message)
}

struct FileVisitor<'a, F> {
    on_case: &'a mut F,
    failure: &'a mut Option<VectorError>,
}

impl<'de, F: FnMut(Case)> Visitor<'de> for FileVisitor<'_, F> {
    type Value = VectorHeader;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a vector file (a JSON object)")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<VectorHeader, A::Error> {
        let (mut format, mut version, mut function, mut description, mut cases) =
            (None, None, None, None, None);
        while let Some(key) = map.next_key::<String>()? {
            let seen = match key.as_str() {
                "format" => {
                    let value: String = map.next_value()?;
                    if value != FORMAT {
                        let message = format!("format is {value:?}, expected {FORMAT:?}");
                        return Err(fail(self.failure, VectorError::Schema(message)));
                    }
                    format.replace(value).is_some()
                }
                "version" => {
                    let value: u64 = map.next_value()?;
                    if value != VERSION {
                        let message = format!(
                            "version {value} is not supported (this reader knows version {VERSION})"
                        );
                        return Err(fail(self.failure, VectorError::Schema(message)));
                    }
                    version.replace(value).is_some()
                }
                "function" => {
                    let value: String = map.next_value()?;
                    if Variant::from_name(&value).is_none() {
                        let message = format!(
                            "function {value:?} is not a function this checker knows (an eval \
                             variant: spec-f32, spec-exact, uv2index-exact, ...)"
                        );
                        return Err(fail(self.failure, VectorError::Schema(message)));
                    }
                    function.replace(value).is_some()
                }
                "description" => description.replace(map.next_value::<String>()?).is_some(),
                "cases" => {
                    let seed = CasesSeed {
                        on_case: &mut *self.on_case,
                        failure: &mut *self.failure,
                    };
                    cases.replace(map.next_value_seed(seed)?).is_some()
                }
                _ => {
                    map.next_value::<de::IgnoredAny>()?;
                    false
                }
            };
            if seen {
                return Err(de::Error::custom(format_args!("duplicate field `{key}`")));
            }
        }
        let missing = |name: &str| {
            let message = format!("missing field \"{name}\"");
            VectorError::Schema(message)
        };
        let name = [
            ("format", format.is_none()),
            ("version", version.is_none()),
            ("function", function.is_none()),
            ("cases", cases.is_none()),
        ]
        .into_iter()
        .find_map(|(name, absent)| absent.then_some(name));
        if let Some(name) = name {
            return Err(fail(self.failure, missing(name)));
        }
        let (Some(format), Some(version), Some(function), Some(cases)) =
            (format, version, function, cases)
        else {
            return Err(fail(self.failure, missing("format")));
        };
        if cases == 0 {
            let message = "the file has no cases: nothing could be checked".to_owned();
            return Err(fail(self.failure, VectorError::Schema(message)));
        }
        Ok(VectorHeader {
            format,
            version,
            function,
            description: description.unwrap_or_default(),
            cases,
        })
    }
}

/// The `cases` array, read one case at a time.
struct CasesSeed<'a, F> {
    on_case: &'a mut F,
    failure: &'a mut Option<VectorError>,
}

impl<'de, F: FnMut(Case)> DeserializeSeed<'de> for CasesSeed<'_, F> {
    type Value = usize;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<usize, D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de, F: FnMut(Case)> Visitor<'de> for CasesSeed<'_, F> {
    type Value = usize;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of case objects")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<usize, A::Error> {
        let mut count = 0;
        let mut previous_id: Option<u64> = None;
        // An object, not any JSON serde could read a struct from (an array).
        while let Some(object) = seq.next_element::<serde_json::Map<String, serde_json::Value>>()? {
            let case: Case = match serde_json::from_value(serde_json::Value::Object(object)) {
                Ok(case) => case,
                Err(e) => {
                    let message = format!("case {}: {e}", count + 1);
                    return Err(fail(self.failure, VectorError::Schema(message)));
                }
            };
            if let Err(error) = check_case(&case, previous_id) {
                return Err(fail(self.failure, error));
            }
            previous_id = Some(case.id);
            count += 1;
            (self.on_case)(case);
        }
        Ok(count)
    }
}

/// One case's checks: ids strictly increase, level, index and coordinates.
fn check_case(case: &Case, previous_id: Option<u64>) -> Result<(), VectorError> {
    match previous_id {
        Some(previous) if case.id == previous => {
            return Err(VectorError::DuplicateId {
                id: case.id,
                line: None,
            })
        }
        Some(previous) if case.id < previous => {
            return Err(VectorError::Schema(format!(
                "case ids must increase: id {} after id {previous}",
                case.id
            )))
        }
        _ => {}
    }
    let Ok(level) = Level::new(case.level) else {
        return Err(VectorError::Schema(format!(
            "case {}: level {} is above {}",
            case.id,
            case.level,
            Level::MAX
        )));
    };
    if u128::from(case.index) >= level.micro_triangle_count() {
        return Err(VectorError::Schema(format!(
            "case {}: expected index {} is not below 4^{} (the file is wrong, not the implementation)",
            case.id, case.index, case.level
        )));
    }
    for (name, text) in [("u", &case.u), ("v", &case.v)] {
        Value::parse(text)
            .map_err(|e| VectorError::Schema(format!("case {}: {name}: {e}", case.id)))?;
    }
    Ok(())
}

#[derive(Deserialize)]
struct AnswerLine {
    id: u64,
    #[serde(default)]
    index: Option<u64>,
    #[serde(default)]
    error: Option<String>,
    #[serde(default)]
    unsupported: Option<bool>,
}

/// Reads answers: JSON lines `{"id": N, "index": I}` (or
/// `{"id": N, "error": "..."}` for a refused input), extra fields allowed,
/// blank lines skipped, `\r\n` accepted. A repeated id is an error. Never
/// panics, whatever the bytes.
///
/// ```
/// use micromap_index_conformance::vectors::{parse_answers, Answer, VectorError};
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
        let unsupported = parsed.unsupported == Some(true);
        let answer = match (parsed.index, parsed.error, unsupported) {
            (Some(index), None, false) => Answer::Index(index),
            (None, Some(message), false) => Answer::Refused(message),
            (None, None, true) => Answer::Unsupported,
            (None, None, false) => return Err(VectorError::BadAnswer {
                line: line_number,
                message:
                    "needs \"index\" (a non-negative integer), \"error\" or \"unsupported\": true"
                        .into(),
            }),
            _ => {
                return Err(VectorError::BadAnswer {
                    line: line_number,
                    message: "has more than one of \"index\", \"error\" and \"unsupported\": true"
                        .into(),
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
