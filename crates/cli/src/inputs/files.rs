//! Input files read under a size limit: the `--texture` and `--triangles`
//! files and bake's buffer files; and the limits a glTF asset is read and
//! written back under ([`asset_limits`]), with its errors' exit codes
//! ([`asset_failure`]).

use cli_support::args::Parsed;
use cli_support::input::refuse_blocking;
use cli_support::output::Failure;
use micromap_index_assets::{AssetError, Limits, UriScope};
use std::path::Path;

/// The most bytes `--texture` and `--triangles` may hold (the 1 GiB the glTF
/// reader allows a whole asset).
pub(super) const INPUT_FILE_LIMIT: u64 = 1 << 30;
/// The most bytes `micromap-data.bin` may hold: every block lies below a
/// 32-bit offset plus one level-16 4-state block (1 GiB).
pub(crate) const DATA_FILE_LIMIT: u64 = (1 << 32) + (1 << 30);
/// The most bytes `micromap-triangles.bin` and `micromap-indices.bin` may
/// hold (2^27 records or 2^28 32-bit indices).
const RECORD_FILE_LIMIT: u64 = 1 << 30;

/// `path`'s bytes, refused past `limit` bytes (read at most `limit + 1`, so
/// `/dev/zero` or an endless pipe cannot exhaust memory): exit 2 with a
/// message naming the limit; unreadable: exit 3.
pub(crate) fn read_file(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>, Failure> {
    use std::io::Read as _;
    let io = |e: std::io::Error| Failure::Io(format!("cannot read {}: {e}", path.display()));
    refuse_blocking(path).map_err(io)?;
    let file = std::fs::File::open(path).map_err(io)?;
    let too_large = || {
        Failure::Malformed(format!(
            "{}: over the limit of {limit} bytes for {what}",
            path.display()
        ))
    };
    // A regular file's size is known at once; a pipe or a device is read
    // up to the limit.
    if file
        .metadata()
        .is_ok_and(|m| m.is_file() && m.len() > limit)
    {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_large());
    }
    Ok(bytes)
}

/// The buffer files in bake's layout, each read under its limit.
pub(crate) struct BufferFiles {
    /// `micromap-data.bin`.
    pub(crate) data: Vec<u8>,
    /// `micromap-triangles.bin`.
    pub(crate) records: Vec<u8>,
    /// `micromap-indices.bin`.
    pub(crate) indices: Vec<u8>,
}

/// `dir`'s data, records and indices (in that order: the first that
/// fails is reported), as [`read_file`] reads each.
pub(crate) fn read_buffer_files(dir: &Path) -> Result<BufferFiles, Failure> {
    Ok(BufferFiles {
        data: read_file(
            &dir.join("micromap-data.bin"),
            DATA_FILE_LIMIT,
            "micromap data",
        )?,
        records: read_file(
            &dir.join("micromap-triangles.bin"),
            RECORD_FILE_LIMIT,
            "triangle records",
        )?,
        indices: read_file(
            &dir.join("micromap-indices.bin"),
            RECORD_FILE_LIMIT,
            "indices",
        )?,
    })
}

/// The limits of the glTF readers and writer: the defaults, the asset's
/// URIs confined to its folder with `--confine-uris` (which goes with
/// `--gltf`: exit 2 without it).
pub(crate) fn asset_limits(p: &Parsed<'_>) -> Result<Limits, Failure> {
    if !p.flag("--confine-uris") {
        return Ok(Limits::default());
    }
    if p.get("--gltf").is_none() {
        return Err(Failure::Usage(
            "--confine-uris confines a glTF asset's URIs: it goes with --gltf".into(),
        ));
    }
    Ok(Limits {
        uri_scope: UriScope::AssetFolder,
        ..Limits::default()
    })
}

/// A glTF reader's or writer's error about `asset`: unreadable (exit 3) or
/// malformed (exit 2); `suffix` is added to the message.
pub(crate) fn asset_failure(error: &AssetError, suffix: &str) -> Failure {
    let message = format!("{error}{suffix}");
    if matches!(error.root(), AssetError::Io { .. }) {
        Failure::Io(message)
    } else {
        Failure::Malformed(message)
    }
}
