//! The walk's fold: `uv2index::index_unchecked` (and `index`, which checks
//! the point and calls it) must be, token for token, the composition the
//! transducer proof models: `Walk::new(u, v)`, then `level` calls of
//! `Walk::step`, the digits concatenated most significant first.
//!
//! The product proof (`crate::prove_all_levels`) runs the crate's own
//! `Walk::new` and `Walk::step` on symbolic numbers, and its output for a
//! point at level `L` is the first `L` digits the walk transducer emits.
//! What binds that to the function users call is the fold around the step;
//! it is not run symbolically (a run per level would not merge states), so
//! it is checked the way `crates/lab/certificates/lemmas.py` checks the
//! reference's integer half: the functions are cut from the source the lab
//! was built with (`include_str!`) by brace matching, split into tokens
//! (comments and whitespace dropped, string and character literals one
//! token each) and compared with the model's tokens exactly. An inserted,
//! deleted, reordered or changed token is refused with the line where the
//! source departs from the model, until the model (and this proof's
//! argument, `docs/verification.md` 10.12) is updated.

use std::fmt;

/// The source of `src/uv2index/mod.rs` this lab was built with.
const UV2INDEX_SOURCE: &str = include_str!("../../../../src/uv2index/mod.rs");

/// The modelled functions: name and the whole function as the model reads
/// it (signature and body).
const MODELLED: [(&str, &str); 2] = [
    (
        "index_unchecked",
        "pub fn index_unchecked<T: WalkNumber>(u: T, v: T, level: Level) -> u64 {
            let mut walk = Walk::new(u, v);
            (0..level.get()).fold(0u64, |index, _| (index << 2) | u64::from(walk.step()))
        }",
    ),
    (
        "index",
        "pub fn index<T: WalkNumber>(u: T, v: T, level: Level) -> Result<u64, Error> {
            T::check_point(&u, &v)?;
            Ok(index_unchecked(u, v, level))
        }",
    ),
];

/// Where the source departs from the model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FoldMismatch {
    /// The modelled function.
    pub function: &'static str,
    /// The source line (1-based) of the first differing token, or of the
    /// function's end when the source is shorter; 0 when the function is
    /// missing or cannot be cut out.
    pub line: usize,
    /// What was expected and what was found there.
    pub detail: String,
}

impl fmt::Display for FoldMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "uv2index::{} is not the modelled fold of Walk::step (src/uv2index/mod.rs line {}): {}",
            self.function, self.line, self.detail
        )
    }
}

/// What was checked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FoldProof {
    /// The functions checked, in order.
    pub functions: Vec<&'static str>,
    /// Their tokens in all.
    pub tokens: usize,
}

/// Checks the source this lab was built with (module comment).
///
/// # Errors
/// The first function whose tokens differ from the model's.
pub fn prove_walk_fold() -> Result<FoldProof, FoldMismatch> {
    check_walk_fold(UV2INDEX_SOURCE)
}

/// [`prove_walk_fold`] on a given source text: how the tests check that
/// changed folds are refused.
///
/// # Errors
/// The first function whose tokens differ from the model's.
pub fn check_walk_fold(source: &str) -> Result<FoldProof, FoldMismatch> {
    let tokens = tokenize(source).map_err(|(line, why)| FoldMismatch {
        function: MODELLED[0].0,
        line,
        detail: format!("the source cannot be split into tokens: {why}"),
    })?;
    let mut proof = FoldProof {
        functions: Vec::new(),
        tokens: 0,
    };
    for (name, model) in MODELLED {
        let expected = tokenize(model).expect("the model tokenizes");
        let found = cut_function(&tokens, name).map_err(|detail| FoldMismatch {
            function: name,
            line: 0,
            detail,
        })?;
        compare(name, &expected, found)?;
        proof.functions.push(name);
        proof.tokens += found.len();
    }
    Ok(proof)
}

/// Token by token; the first difference is the error.
fn compare(name: &'static str, expected: &[Token], found: &[Token]) -> Result<(), FoldMismatch> {
    match first_difference(expected, found) {
        Some((line, detail)) => Err(FoldMismatch {
            function: name,
            line,
            detail,
        }),
        None => Ok(()),
    }
}

/// The first token where `found` departs from `expected`: the source line
/// there (of the last found token when `found` is shorter; 0 when it is
/// empty) and "expected X, found Y". `None`: the same tokens.
pub(super) fn first_difference(expected: &[Token], found: &[Token]) -> Option<(usize, String)> {
    let show =
        |token: Option<&Token>| token.map_or("the end".to_owned(), |t| format!("{:?}", t.text));
    (0..expected.len().max(found.len())).find_map(|i| {
        let (want, got) = (expected.get(i), found.get(i));
        (want.map(|t| &t.text) != got.map(|t| &t.text)).then(|| {
            let line = got.or(found.last()).map_or(0, |t| t.line);
            (
                line,
                format!("expected {}, found {}", show(want), show(got)),
            )
        })
    })
}

/// Where the token texts `needle` start in `tokens`, in order.
pub(super) fn occurrences(tokens: &[Token], needle: &[&str]) -> Vec<usize> {
    tokens
        .windows(needle.len())
        .enumerate()
        .filter(|(_, window)| window.iter().zip(needle).all(|(t, n)| t.text == *n))
        .map(|(i, _)| i)
        .collect()
}

/// One token and the line it starts on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Token {
    pub(super) text: String,
    pub(super) line: usize,
}

/// Splits Rust source into tokens: identifiers and numbers (with their
/// suffixes), string, raw-string and character literals (each one token),
/// lifetimes, the two-character operators `::`, `->`, `=>`, `<<`, `>>`,
/// `==`, `!=`, `<=`, `>=`, `&&`, `||`, `..` and single punctuation.
/// Comments (line, block, nested) and whitespace are dropped. Errors: an
/// unterminated comment or literal, with its line.
pub(super) fn tokenize(source: &str) -> Result<Vec<Token>, (usize, &'static str)> {
    let chars: Vec<char> = source.chars().collect();
    let mut tokens = Vec::new();
    let (mut i, mut line) = (0, 1);
    let at = |i: usize| chars.get(i).copied();
    while let Some(c) = at(i) {
        let start_line = line;
        let start = i;
        if c == '\n' {
            line += 1;
            i += 1;
            continue;
        }
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c == '/' && at(i + 1) == Some('/') {
            while at(i).is_some_and(|c| c != '\n') {
                i += 1;
            }
            continue;
        }
        if c == '/' && at(i + 1) == Some('*') {
            let mut depth = 0usize;
            loop {
                match (at(i), at(i + 1)) {
                    (Some('/'), Some('*')) => {
                        depth += 1;
                        i += 2;
                    }
                    (Some('*'), Some('/')) => {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    }
                    (Some(c), _) => {
                        line += usize::from(c == '\n');
                        i += 1;
                    }
                    (None, _) => return Err((start_line, "an unterminated block comment")),
                }
            }
            continue;
        }
        if c == 'r' && matches!(at(i + 1), Some('"' | '#')) {
            // A raw string: r"..." or r#"..."#, any number of #.
            let mut j = i + 1;
            while at(j) == Some('#') {
                j += 1;
            }
            if at(j) == Some('"') {
                let hashes = j - i - 1;
                j += 1;
                loop {
                    match at(j) {
                        None => return Err((start_line, "an unterminated raw string")),
                        Some('"') if (1..=hashes).all(|k| at(j + k) == Some('#')) => {
                            j += 1 + hashes;
                            break;
                        }
                        Some(c) => {
                            line += usize::from(c == '\n');
                            j += 1;
                        }
                    }
                }
                push(&mut tokens, &chars[start..j], start_line);
                i = j;
                continue;
            }
        }
        if c == '"' {
            i += 1;
            loop {
                match at(i) {
                    None => return Err((start_line, "an unterminated string")),
                    Some('\\') => {
                        // An escape; a line continuation still ends a line.
                        line += usize::from(at(i + 1) == Some('\n'));
                        i += 2;
                    }
                    Some('"') => {
                        i += 1;
                        break;
                    }
                    Some(c) => {
                        line += usize::from(c == '\n');
                        i += 1;
                    }
                }
            }
            push(&mut tokens, &chars[start..i], start_line);
            continue;
        }
        if c == '\'' {
            // A character literal ('x', '\n', '\u{..}') or a lifetime ('a).
            let literal_end = if at(i + 1) == Some('\\') {
                (i + 2..chars.len().min(i + 12)).find(|&j| at(j) == Some('\''))
            } else if at(i + 2) == Some('\'') {
                Some(i + 2)
            } else {
                None
            };
            i = if let Some(end) = literal_end {
                end + 1
            } else {
                let mut j = i + 1;
                while at(j).is_some_and(|c| c.is_alphanumeric() || c == '_') {
                    j += 1;
                }
                j
            };
            push(&mut tokens, &chars[start..i], start_line);
            continue;
        }
        if c.is_alphanumeric() || c == '_' {
            while at(i).is_some_and(|c| c.is_alphanumeric() || c == '_') {
                i += 1;
            }
            push(&mut tokens, &chars[start..i], start_line);
            continue;
        }
        let pair: String = chars[i..chars.len().min(i + 2)].iter().collect();
        let width = if [
            "::", "->", "=>", "<<", ">>", "==", "!=", "<=", ">=", "&&", "||", "..",
        ]
        .contains(&pair.as_str())
        {
            2
        } else {
            1
        };
        i += width;
        push(&mut tokens, &chars[start..i], start_line);
    }
    Ok(tokens)
}

fn push(tokens: &mut Vec<Token>, text: &[char], line: usize) {
    tokens.push(Token {
        text: text.iter().collect(),
        line,
    });
}

/// The tokens of `fn NAME` from its `pub` through the brace closing its
/// body (the first `{` after the name opens it). Exactly one such function
/// must exist.
pub(super) fn cut_function<'a>(tokens: &'a [Token], name: &str) -> Result<&'a [Token], String> {
    let starts: Vec<usize> = (1..tokens.len())
        .filter(|&i| tokens[i - 1].text == "fn" && tokens[i].text == name)
        .collect();
    let &[at] = starts.as_slice() else {
        return Err(format!(
            "{} definitions of fn {name} found, expected 1",
            starts.len()
        ));
    };
    let begin = if at >= 2 && tokens[at - 2].text == "pub" {
        at - 2
    } else {
        at - 1
    };
    let open = (at..tokens.len())
        .find(|&i| tokens[i].text == "{")
        .ok_or_else(|| format!("fn {name} has no body"))?;
    let mut depth = 0usize;
    for (i, token) in tokens.iter().enumerate().skip(open) {
        match token.text.as_str() {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if depth == 0 {
                    return Ok(&tokens[begin..=i]);
                }
            }
            _ => {}
        }
    }
    Err(format!("fn {name}'s body is not closed"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_source_is_the_model() {
        let proof = prove_walk_fold().unwrap();
        assert_eq!(proof.functions, ["index_unchecked", "index"]);
        assert!(proof.tokens > 60, "{proof:?}");
    }

    /// Replaces `from` inside the modelled functions of the real source
    /// (from `fn index_unchecked` on: the first occurrence there).
    fn changed(from: &str, to: &str) -> String {
        let start = UV2INDEX_SOURCE.find("pub fn index_unchecked").unwrap();
        let (before, after) = UV2INDEX_SOURCE.split_at(start);
        assert!(after.contains(from), "{from}");
        format!("{before}{}", after.replacen(from, to, 1))
    }

    const FOLD: &str =
        "(0..level.get()).fold(0u64, |index, _| (index << 2) | u64::from(walk.step()))";

    #[test]
    fn layout_and_comments_are_free() {
        for source in [
            changed(FOLD, "(0..level.get())\n  .fold(0u64, |index, _| /* } */ (index << 2) | u64::from(walk.step())) // }"),
            changed("let mut walk = Walk::new(u, v);", "let mut walk =\n    Walk::new(u, v); /* a { comment */"),
        ] {
            check_walk_fold(&source).unwrap();
        }
    }

    #[test]
    fn changed_folds_are_refused() {
        let cases = [
            // The issue's mutation: the last step by version 1 at levels >= 25.
            changed(
                FOLD,
                "(0..level.get()).fold(0u64, |index, i| (index << 2) | u64::from(if level.get() >= 25 && i + 1 == level.get() { walk.step_version1() } else { walk.step() }))",
            ),
            changed(FOLD, "(0..level.get()).fold(0u64, |index, _| (index << 2) ^ u64::from(walk.step()))"),
            changed(FOLD, "(1..level.get()).fold(0u64, |index, _| (index << 2) | u64::from(walk.step()))"),
            changed("let mut walk = Walk::new(u, v);", "let mut walk = Walk::new(v, u);"),
            changed("let mut walk = Walk::new(u, v);", "let mut walk = Walk::new(u, v);\n    let _ = walk.step();"),
            changed("    Ok(index_unchecked(u, v, level))\n", "    Ok(index_unchecked(u, v, level) & !1)\n"),
            changed("    T::check_point(&u, &v)?;\n", ""),
        ];
        for source in &cases {
            let error = check_walk_fold(source).unwrap_err();
            assert!(error.line > 0, "{error}");
        }
        // A second definition is refused too: which one runs is not known.
        let twice = format!("{UV2INDEX_SOURCE}\nmod again {{ pub fn index() {{}} }}\n");
        assert!(check_walk_fold(&twice)
            .unwrap_err()
            .detail
            .contains("2 definitions"));
    }

    #[test]
    fn literals_and_lifetimes_are_tokens() {
        let tokens =
            tokenize("fn f<'a>(x: &'a str) -> char { let _ = \"}\"; let _ = r#\"{\"#; '}' }")
                .unwrap();
        let texts: Vec<&str> = tokens.iter().map(|t| t.text.as_str()).collect();
        assert!(
            texts.contains(&"'a") && texts.contains(&"\"}\"") && texts.contains(&"'}'"),
            "{texts:?}"
        );
        assert_eq!(
            cut_function(&tokens, "f").unwrap().last().unwrap().text,
            "}"
        );
        assert!(tokenize("/* open").is_err() && tokenize("\"open").is_err());
        // A string's line continuation still ends a line.
        let tokens = tokenize("f(\"a \\\n b\");\ng").unwrap();
        assert_eq!(
            tokens.last().map(|t| (t.text.as_str(), t.line)),
            Some(("g", 3))
        );
    }
}
