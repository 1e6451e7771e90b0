//! Reading an asset's files from disk: the glTF itself within the byte
//! limit ([`read_file`]) and the files its relative URIs name, beside it
//! ([`resolve_beside`]), within [`Limits::uri_scope`], for the reader and
//! the writer alike.
//!
//! Contracts: an absolute path is refused under every scope; a FIFO or a
//! socket is refused before it is opened (opening or reading one could block
//! forever); under [`UriScope::AssetFolder`] a URI is refused when its `..`
//! components climb above the asset's folder (lexically, as written), when
//! its canonical path (symbolic links followed) does not lie under the
//! folder's canonical path, or when it is not a regular file, and the file
//! read is the canonical path checked.

use crate::error::AssetError;
use crate::limits::{check_limit, Limits, UriScope};
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// The `resolve` of a glTF in directory `base`: a relative URI's file
/// there, within [`Limits::max_bytes`] and [`Limits::uri_scope`] (the
/// module's contracts); an absolute path is refused.
pub(super) fn resolve_beside<'a>(
    base: &'a Path,
    limits: &'a Limits,
) -> impl FnMut(&str) -> Result<Vec<u8>, AssetError> + 'a {
    move |uri: &str| {
        let refuse = |message: &str| AssetError::Uri {
            uri: uri.to_string(),
            message: message.to_string(),
        };
        if uri.starts_with(['/', '\\']) || Path::new(uri).is_absolute() {
            return Err(refuse(
                "absolute paths are not supported; use a path relative to the glTF",
            ));
        }
        let path = base.join(uri);
        match limits.uri_scope {
            UriScope::Anywhere => read_file(&path, limits.max_bytes),
            UriScope::AssetFolder => {
                if climbs_above(uri) {
                    return Err(refuse(OUTSIDE));
                }
                let inside = canonical_inside(base, &path)?.ok_or_else(|| refuse(OUTSIDE))?;
                // A FIFO or socket: the same I/O error as under `Anywhere`.
                refuse_blocking(&inside).map_err(|e| AssetError::Io {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })?;
                if !std::fs::metadata(&inside).is_ok_and(|m| m.is_file()) {
                    return Err(refuse(
                        "not a regular file (URIs are confined to the asset's folder)",
                    ));
                }
                read_file_as(&inside, &path, limits.max_bytes)
            }
        }
    }
}

/// The refusal of a URI outside the asset's folder.
const OUTSIDE: &str = "names a file outside the asset's folder (URIs are confined to it)";

/// Whether the relative path `uri`'s `..` components climb above its
/// starting folder at any point (`../a`, `a/../../b`; not `a/../b`).
fn climbs_above(uri: &str) -> bool {
    let mut depth = 0i64;
    for component in Path::new(uri).components() {
        match component {
            Component::Normal(_) => depth += 1,
            Component::ParentDir => {
                depth -= 1;
                if depth < 0 {
                    return true;
                }
            }
            Component::CurDir => {}
            Component::RootDir | Component::Prefix(_) => return true,
        }
    }
    false
}

/// `path`'s canonical path if it lies under `base`'s canonical path (the
/// current directory for an empty `base`), `None` if it does not; an I/O
/// error (a missing file) names `path`.
fn canonical_inside(base: &Path, path: &Path) -> Result<Option<PathBuf>, AssetError> {
    let io = |shown: &Path, e: std::io::Error| AssetError::Io {
        path: shown.display().to_string(),
        message: e.to_string(),
    };
    let base = if base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base
    };
    let folder = std::fs::canonicalize(base).map_err(|e| io(base, e))?;
    let file = std::fs::canonicalize(path).map_err(|e| io(path, e))?;
    Ok(file.starts_with(&folder).then_some(file))
}

/// The whole file, if it is at most `max_bytes` long; a FIFO or a socket
/// refused before it is opened.
pub(super) fn read_file(path: &Path, max_bytes: u64) -> Result<Vec<u8>, AssetError> {
    read_file_as(path, path, max_bytes)
}

/// [`read_file`] of `path`, its errors naming `shown`.
fn read_file_as(path: &Path, shown: &Path, max_bytes: u64) -> Result<Vec<u8>, AssetError> {
    let io = |e: std::io::Error| AssetError::Io {
        path: shown.display().to_string(),
        message: e.to_string(),
    };
    refuse_blocking(path).map_err(io)?;
    let file = std::fs::File::open(path).map_err(io)?;
    let length = file.metadata().map_err(io)?.len();
    check_limit(|| format!("file {}", shown.display()), length, max_bytes)?;
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(usize::try_from(length).unwrap_or(0))
        .map_err(|_| {
            io(std::io::Error::new(
                std::io::ErrorKind::OutOfMemory,
                format!("cannot allocate {length} bytes"),
            ))
        })?;
    // `take`: a file that grows while being read stays within the limit.
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    check_limit(
        || format!("file {}", shown.display()),
        bytes.len() as u64,
        max_bytes,
    )?;
    Ok(bytes)
}

/// Refuses a FIFO (opening one without a writer blocks) or a socket.
fn refuse_blocking(path: &Path) -> std::io::Result<()> {
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
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    format!("{what}, not a regular file (reading it could block forever)"),
                ));
            }
        }
    }
    #[cfg(not(unix))]
    let _ = path;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn climbing_is_lexical() {
        for uri in ["../a.png", "a/../../b.png", "./../a", ".."] {
            assert!(climbs_above(uri), "{uri}");
        }
        for uri in ["a.png", "a/../b.png", "./a/b/../c", "a/b/../../c"] {
            assert!(!climbs_above(uri), "{uri}");
        }
    }
}
