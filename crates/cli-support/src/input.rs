//! Reading input: files or stdin (`-`) with a message naming what failed
//! ([`read_bytes`], [`open`]), and lines with a bounded buffer: a line
//! longer than the cap is skipped (its bytes read and dropped as they come)
//! and reported, so one 200 MB line costs a bounded amount of memory, not
//! 200 MB.

use std::io::{self, BufRead, BufReader, Read};

/// The longest `eval` input line, in bytes (without the newline). A valid
/// line is far shorter: two values of at most 20,000 characters
/// (`micromap_index_conformance::value::MAX_VALUE_LEN`) and a level.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Refuses a named input whose opening or reading can block forever: a
/// FIFO (named pipe) with no writer blocks `open` itself, a socket its
/// reads. Regular files and devices (`/dev/zero`, read under a bound) pass.
/// Standard input (`-`) is read as it is, pipe or not.
///
/// # Errors
///
/// An `InvalidInput` error naming the kind of file.
pub fn refuse_blocking(path: &std::path::Path) -> io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if let Ok(metadata) = std::fs::metadata(path) {
            let kind = metadata.file_type();
            let what = if kind.is_fifo() {
                Some("a FIFO (named pipe)")
            } else if kind.is_socket() {
                Some("a socket")
            } else {
                None
            };
            if let Some(what) = what {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("{what}, not a regular file (reading it could block forever)"),
                ));
            }
        }
    }
    #[cfg(not(unix))]
    let _ = path;
    Ok(())
}

/// The file (`-`: stdin) as a buffered reader, or a message naming it.
pub fn open(path: &str) -> Result<Box<dyn Read>, String> {
    if path == "-" {
        return Ok(Box::new(BufReader::new(io::stdin())));
    }
    refuse_blocking(path.as_ref()).map_err(|e| format!("cannot read {path}: {e}"))?;
    match std::fs::File::open(path) {
        Ok(file) => Ok(Box::new(BufReader::new(file))),
        Err(e) => Err(format!("cannot read {path}: {e}")),
    }
}

/// The file's bytes (`-`: stdin), or a message naming it.
pub fn read_bytes(path: &str) -> Result<Vec<u8>, String> {
    if path == "-" {
        let mut bytes = Vec::new();
        return io::stdin()
            .read_to_end(&mut bytes)
            .map(|_| bytes)
            .map_err(|e| format!("reading stdin: {e}"));
    }
    refuse_blocking(path.as_ref()).map_err(|e| format!("cannot read {path}: {e}"))?;
    std::fs::read(path).map_err(|e| format!("cannot read {path}: {e}"))
}

/// `path` as messages name it: `stdin` for `-`.
#[must_use]
pub fn shown_path(path: &str) -> &str {
    if path == "-" {
        "stdin"
    } else {
        path
    }
}

/// One input line.
#[derive(Debug, PartialEq, Eq)]
pub enum Line<'a> {
    /// The line's bytes, without the `\n` (a trailing `\r` is kept).
    Text(&'a [u8]),
    /// The line was longer than the cap; `bytes` is its length without the
    /// `\n`.
    TooLong {
        /// The line's length.
        bytes: u64,
    },
}

/// Lines of `reader`, each at most `max` bytes kept in memory.
pub struct BoundedLines<R> {
    reader: R,
    line: Vec<u8>,
    max: usize,
}

impl<R: BufRead> BoundedLines<R> {
    /// Lines of `reader`, each kept up to `max` bytes.
    pub fn new(reader: R, max: usize) -> Self {
        BoundedLines {
            reader,
            line: Vec::new(),
            max,
        }
    }

    /// The reader, to ask whether input is already buffered.
    pub fn reader(&self) -> &R {
        &self.reader
    }

    /// The next line, or `None` at the end of the input. A last line without
    /// a newline is still a line; an empty input has no lines.
    pub fn next_line(&mut self) -> io::Result<Option<Line<'_>>> {
        self.line.clear();
        let mut length: u64 = 0;
        let mut any = false;
        loop {
            let available = match self.reader.fill_buf() {
                Ok(available) => available,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if available.is_empty() {
                if !any {
                    return Ok(None);
                }
                break;
            }
            any = true;
            let (part, newline) = match available.iter().position(|&b| b == b'\n') {
                Some(at) => (&available[..at], true),
                None => (available, false),
            };
            length += part.len() as u64;
            if length <= self.max as u64 {
                self.line.extend_from_slice(part);
            }
            let used = part.len() + usize::from(newline);
            self.reader.consume(used);
            if newline {
                break;
            }
        }
        Ok(Some(if length > self.max as u64 {
            Line::TooLong { bytes: length }
        } else {
            Line::Text(&self.line)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// All lines of `input` read through a `capacity`-byte buffer.
    fn lines(input: &[u8], capacity: usize, max: usize) -> Vec<Result<Vec<u8>, u64>> {
        let reader = io::BufReader::with_capacity(capacity, input);
        let mut lines = BoundedLines::new(reader, max);
        let mut out = Vec::new();
        while let Some(line) = lines.next_line().unwrap() {
            out.push(match line {
                Line::Text(bytes) => Ok(bytes.to_vec()),
                Line::TooLong { bytes } => Err(bytes),
            });
        }
        out
    }

    #[test]
    fn splits_like_split_newline_and_caps_long_lines() {
        let input = b"ab\n\nabcdef\nabcde\r\nxyz";
        for capacity in [1, 2, 3, 7, 64] {
            assert_eq!(
                lines(input, capacity, 5),
                vec![
                    Ok(b"ab".to_vec()),
                    Ok(Vec::new()),
                    Err(6),
                    Err(6), // "abcde\r": the \r counts
                    Ok(b"xyz".to_vec()),
                ],
                "buffer of {capacity} bytes"
            );
        }
        // Exactly at the cap is kept.
        assert_eq!(lines(b"abcde\n", 2, 5), vec![Ok(b"abcde".to_vec())]);
        assert_eq!(lines(b"", 4, 5), Vec::<Result<Vec<u8>, u64>>::new());
        assert_eq!(lines(b"\n", 4, 5), vec![Ok(Vec::new())]);
    }
}
