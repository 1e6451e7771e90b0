//! `micromap-geometry-usage.bin`: Vulkan EXT's per-geometry usage counts
//! (`VkAccelerationStructureTrianglesOpacityMicromapEXT::pUsageCounts`,
//! one list per BLAS geometry), as opposed to the micromap's own counts in
//! `micromap-usage.bin`. `bake` writes it, `verify-bake` checks it when
//! present. Layout (little endian), one block per geometry (bake: per job,
//! in `summary.json`'s job order):
//!
//! ```text
//! u32 n                       usage counts of this geometry
//! n x {u32 count, u32 level, u32 format}
//! ```
//!
//! A count is how many of the geometry's triangles reference a record of
//! that level and format (special indices count for nothing), sorted by
//! format, then level; no zero counts.

use cli_support::output::Failure;
use micromap_index::micromap::{MicromapBuffers, MicromapIndex, TriangleRecord, UsageCount};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The file's name in a bake's output directory.
pub(crate) const FILE: &str = "micromap-geometry-usage.bin";

/// One usage count as `summary.json` shows it.
#[derive(Serialize)]
pub(crate) struct UsageJson {
    count: u32,
    level: u32,
    format: u32,
}

/// `geometry`'s usage counts for `summary.json`.
pub(crate) fn to_json(
    buffers: &MicromapBuffers,
    geometry: usize,
) -> Result<Vec<UsageJson>, Failure> {
    Ok(buffers
        .geometry_usage_counts(geometry)
        .map_err(|e| Failure::Malformed(e.to_string()))?
        .iter()
        .map(|u| UsageJson {
            count: u.count,
            level: u.subdivision_level,
            format: u.format,
        })
        .collect())
}

/// The file's bytes: every geometry of `buffers`, in order.
pub(crate) fn to_le_bytes(buffers: &MicromapBuffers) -> Result<Vec<u8>, Failure> {
    let mut bytes = Vec::new();
    for g in 0..buffers.geometry_count() {
        let usage = buffers
            .geometry_usage_counts(g)
            .map_err(|e| Failure::Malformed(e.to_string()))?;
        // At most 2 formats x 13 levels entries: always fits a u32.
        bytes.extend((usage.len() as u32).to_le_bytes());
        bytes.extend(usage.iter().flat_map(|u| u.to_le_bytes()));
    }
    Ok(bytes)
}

/// The geometries of a file's bytes; an error names the byte where the
/// file stops making sense.
pub(crate) fn parse(bytes: &[u8]) -> Result<Vec<Vec<UsageCount>>, String> {
    let mut geometries = Vec::new();
    let mut at = 0usize;
    while at < bytes.len() {
        let head = bytes.get(at..at + 4).ok_or_else(|| {
            format!(
                "{} bytes left at byte {at}: a count needs 4",
                bytes.len() - at
            )
        })?;
        let n = u32::from_le_bytes([head[0], head[1], head[2], head[3]]) as usize;
        at += 4;
        let len = n
            .checked_mul(UsageCount::SIZE)
            .filter(|&len| len <= bytes.len() - at)
            .ok_or_else(|| {
                format!(
                    "geometry {} declares {n} usage counts at byte {}: only {} bytes follow",
                    geometries.len(),
                    at - 4,
                    bytes.len() - at
                )
            })?;
        let usage = bytes[at..at + len]
            .chunks_exact(UsageCount::SIZE)
            .map(|c| {
                let mut entry = [0u8; UsageCount::SIZE];
                entry.copy_from_slice(c);
                UsageCount::from_le_bytes(entry)
            })
            .collect();
        geometries.push(usage);
        at += len;
    }
    Ok(geometries)
}

/// Checks one geometry's usage counts against its indices: the same
/// multiset of (level, format) over the triangles that reference records
/// (order and zero counts aside, as Vulkan reads them).
pub(crate) fn check(
    usage: &[UsageCount],
    indices: &[MicromapIndex],
    records: &[TriangleRecord],
) -> Result<(), String> {
    let mut want: BTreeMap<(u32, u32), u64> = BTreeMap::new();
    for index in indices {
        if let MicromapIndex::Record(r) = *index {
            // read_buffers has checked every index names a record.
            if let Some(record) = records.get(r as usize) {
                *want
                    .entry((
                        u32::from(record.subdivision_level),
                        u32::from(record.format),
                    ))
                    .or_default() += 1;
            }
        }
    }
    let mut got: BTreeMap<(u32, u32), u64> = BTreeMap::new();
    for u in usage {
        *got.entry((u.subdivision_level, u.format)).or_default() += u64::from(u.count);
    }
    got.retain(|_, count| *count > 0);
    if got == want {
        return Ok(());
    }
    let first = want
        .keys()
        .chain(got.keys())
        .find(|k| want.get(k) != got.get(k))
        .copied()
        .unwrap_or_default();
    Err(format!(
        "the per-geometry usage counts say {} triangles of level {} format {}; the indices reference {}",
        got.get(&first).copied().unwrap_or(0),
        first.0,
        first.1,
        want.get(&first).copied().unwrap_or(0)
    ))
}

/// `verify-bake` on DIR: when DIR holds the file, its geometries' counts,
/// summed (verify-bake reads the jobs' indices as one buffer, in order),
/// must match `indices`. Returns whether the file was there.
pub(crate) fn verify_in(
    dir: &Path,
    indices: &[MicromapIndex],
    records: &[TriangleRecord],
) -> Result<bool, Failure> {
    let path = dir.join(FILE);
    if !path.exists() {
        return Ok(false);
    }
    // One geometry of at most 26 entries is 316 bytes; the limit leaves room
    // for thousands, and a wrong file is reported by what it holds.
    let bytes = crate::inputs::files::read_file(&path, 1 << 20, "per-geometry usage counts")?;
    let malformed = |message: String| Failure::Malformed(format!("{}: {message}", path.display()));
    let geometries = parse(&bytes).map_err(malformed)?;
    let all: Vec<UsageCount> = geometries.iter().flatten().copied().collect();
    check(&all, indices, records).map_err(malformed)?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_reads_what_to_le_bytes_writes_and_refuses_truncation() {
        let usage = UsageCount {
            count: 3,
            subdivision_level: 4,
            format: 2,
        };
        let mut bytes = 1u32.to_le_bytes().to_vec();
        bytes.extend(usage.to_le_bytes());
        bytes.extend(0u32.to_le_bytes());
        assert_eq!(parse(&bytes), Ok(vec![vec![usage], vec![]]));
        assert!(parse(&bytes[..bytes.len() - 1]).is_err());
        assert!(parse(&bytes[..15]).is_err());
        assert!(parse(&u32::MAX.to_le_bytes()).is_err());
    }

    #[test]
    fn check_compares_counts_with_the_indices() {
        let records = [TriangleRecord {
            data_offset: 0,
            subdivision_level: 4,
            format: 2,
        }];
        let indices = [
            MicromapIndex::Record(0),
            MicromapIndex::Record(0),
            MicromapIndex::Special(micromap_index::micromap::State::Opaque),
        ];
        let right = UsageCount {
            count: 2,
            subdivision_level: 4,
            format: 2,
        };
        assert_eq!(check(&[right], &indices, &records), Ok(()));
        let wrong = UsageCount { count: 3, ..right };
        let error = check(&[wrong], &indices, &records).unwrap_err();
        assert!(
            error.contains("say 3 triangles of level 4 format 2; the indices reference 2"),
            "{error}"
        );
        assert!(check(&[], &indices, &records).is_err());
    }
}
