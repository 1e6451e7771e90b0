//! Reading an asset's files from disk: the glTF itself within the byte
//! limit ([`read_file`]) and the files its relative URIs name, beside it
//! ([`resolve_beside`]), for the reader and the writer alike.

use crate::error::AssetError;
use crate::limits::{check_limit, Limits};
use std::io::Read;
use std::path::Path;

/// The `resolve` of a glTF in directory `base`: a relative URI's file
/// there, within [`Limits::max_bytes`]; an absolute path is refused.
pub(super) fn resolve_beside<'a>(
    base: &'a Path,
    limits: &'a Limits,
) -> impl FnMut(&str) -> Result<Vec<u8>, AssetError> + 'a {
    move |uri: &str| {
        if uri.starts_with(['/', '\\']) || Path::new(uri).is_absolute() {
            return Err(AssetError::Uri {
                uri: uri.to_string(),
                message: "absolute paths are not supported; use a path relative to the glTF"
                    .to_string(),
            });
        }
        read_file(&base.join(uri), limits.max_bytes)
    }
}

/// The whole file, if it is at most `max_bytes` long.
pub(super) fn read_file(path: &Path, max_bytes: u64) -> Result<Vec<u8>, AssetError> {
    let io = |e: std::io::Error| AssetError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let length = file.metadata().map_err(io)?.len();
    check_limit(|| format!("file {}", path.display()), length, max_bytes)?;
    let mut bytes = Vec::with_capacity(usize::try_from(length).unwrap_or(0));
    // `take`: a file that grows while being read stays within the limit.
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    check_limit(
        || format!("file {}", path.display()),
        bytes.len() as u64,
        max_bytes,
    )?;
    Ok(bytes)
}
