//! Reading API buffers back from untrusted bytes: every inconsistency is a
//! [`ReadError`], never a panic.

use super::records::record_shape;
use super::{
    Format, IndexWidth, Micromap, MicromapError, MicromapIndex, TriangleRecord, UsageCount,
};
use crate::Level;
use alloc::collections::BTreeMap;
use alloc::vec::Vec;
use core::fmt;

/// The bytes of one micromap array and, optionally, one geometry's index
/// buffer, as an API or a glTF file would hold them (little-endian, tight
/// strides).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BufferBytes<'a> {
    /// The triangle records, 8 bytes each.
    pub records: &'a [u8],
    /// The packed micromap data the records point into.
    pub data: &'a [u8],
    /// The array's usage counts, 12 bytes each, if they are to be checked
    /// against the records.
    pub usage_counts: Option<&'a [u8]>,
    /// One geometry's per-triangle index buffer and its width, if any.
    pub indices: Option<(&'a [u8], IndexWidth)>,
}

/// Whether records may point at overlapping data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Overlap {
    /// Blocks must not overlap (the glTF draft: "regions MUST NOT
    /// overlap"). Every byte is then decoded at most once, so the micromaps
    /// returned take no more memory than the data given.
    Forbid,
    /// Blocks may overlap or be shared (no rule against it was found in the
    /// Vulkan or DXR text, see `docs/micromaps.md`), as long as the decoded micromaps take at most
    /// `max_decoded_bytes` in total (many records on one large block would
    /// otherwise multiply the memory).
    Allow {
        /// The limit on the sum of the records' block sizes.
        max_decoded_bytes: u64,
    },
}

/// Options for [`read_buffers`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ReadOptions {
    /// Whether blocks may overlap (default [`Overlap::Forbid`]).
    pub overlap: Overlap,
    /// The highest level accepted (default and at most
    /// [`Micromap::MAX_LEVEL`], 16; 12 for DXR).
    pub max_level: u32,
    /// Added to every regular index of the index buffer, as Vulkan's
    /// `baseTriangle`, DXR's `OpacityMicromapBaseLocation` and glTF's
    /// `micromapBaseTriangle` (default 0).
    pub base_triangle: u32,
    /// Bytes from one triangle record to the next (default 8, packed):
    /// Vulkan's `triangleArrayStride`, at least 8 and a multiple of 4; the
    /// bytes between records are ignored. The record buffer holds either
    /// whole strides or ends right after its last record.
    pub record_stride: usize,
    /// Bytes from one index to the next (default `None`: the index width,
    /// packed): Vulkan's `indexStride` and glTF's `byteStride`, a multiple
    /// of the width; the bytes between indices are ignored. The index
    /// buffer holds either whole strides or ends right after its last index.
    pub index_stride: Option<usize>,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            overlap: Overlap::Forbid,
            max_level: Micromap::MAX_LEVEL,
            base_triangle: 0,
            record_stride: TriangleRecord::SIZE,
            index_stride: None,
        }
    }
}

impl ReadOptions {
    /// Checks [`record_stride`](Self::record_stride) and, for an index
    /// buffer of `width`, [`index_stride`](Self::index_stride), as
    /// [`read_buffers`] does before it reads anything: the record stride at
    /// least 8 and a multiple of 4 ([`ReadError::RecordStride`]), the index
    /// stride a positive multiple of the width ([`ReadError::IndexStride`]).
    /// Without an index buffer (`width` `None`) the index stride is not
    /// looked at.
    ///
    /// ```
    /// use micromap_index::micromap::{IndexWidth, ReadError, ReadOptions};
    ///
    /// let options = ReadOptions { record_stride: 12, index_stride: Some(6), ..ReadOptions::default() };
    /// assert_eq!(options.check_strides(Some(IndexWidth::U16)), Ok(()));
    /// assert_eq!(
    ///     options.check_strides(Some(IndexWidth::U32)),
    ///     Err(ReadError::IndexStride { stride: 6, width: IndexWidth::U32 })
    /// );
    /// let options = ReadOptions { record_stride: 10, ..ReadOptions::default() };
    /// assert_eq!(options.check_strides(None), Err(ReadError::RecordStride { stride: 10 }));
    /// ```
    pub fn check_strides(&self, width: Option<IndexWidth>) -> Result<(), ReadError> {
        let stride = self.record_stride;
        if stride < TriangleRecord::SIZE || stride % 4 != 0 {
            return Err(ReadError::RecordStride { stride });
        }
        if let Some(width) = width {
            let stride = self.index_stride.unwrap_or(width.bytes());
            if stride == 0 || stride % width.bytes() != 0 {
                return Err(ReadError::IndexStride { stride, width });
            }
        }
        Ok(())
    }
}

/// Splits `bytes` into `element`-byte elements `stride` bytes apart
/// (`stride >= element`): `None` unless the bytes are whole strides or
/// end right after the last element (one reading only, as the two counts
/// differ unless `stride == element`).
fn strided(bytes: &[u8], stride: usize, element: usize) -> Option<impl Iterator<Item = &[u8]>> {
    let rem = bytes.len() % stride;
    let count = bytes.len() / stride + usize::from(rem != 0);
    (rem == 0 || rem == element)
        .then(|| (0..count).map(move |i| &bytes[i * stride..i * stride + element]))
}

/// What [`read_buffers`] found wrong. Record, entry and triangle numbers
/// count from 0.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ReadError {
    /// The record bytes are not a whole number of 8-byte records.
    RecordsLength {
        /// The length given.
        len: usize,
    },
    /// [`ReadOptions::record_stride`] is below 8 or not a multiple of 4.
    RecordStride {
        /// The stride given.
        stride: usize,
    },
    /// [`ReadOptions::index_stride`] is not a positive multiple of the
    /// index width.
    IndexStride {
        /// The stride given.
        stride: usize,
        /// The index width.
        width: IndexWidth,
    },
    /// A strided buffer neither holds whole strides nor ends right after
    /// its last element.
    StridedLength {
        /// The buffer's length.
        len: usize,
        /// The stride.
        stride: usize,
        /// The element's size.
        element: usize,
    },
    /// More records than 32-bit indices can address.
    TooManyRecords {
        /// How many.
        count: usize,
    },
    /// A record's format is neither 1 nor 2.
    InvalidFormat {
        /// The record.
        record: usize,
        /// Its format field.
        format: u16,
    },
    /// A record's level is above [`ReadOptions::max_level`].
    LevelTooHigh {
        /// The record.
        record: usize,
        /// Its level field.
        level: u16,
        /// The highest level accepted.
        max: u32,
    },
    /// A record's block does not lie inside the data.
    BlockOutOfBounds {
        /// The record.
        record: usize,
        /// Its data offset.
        offset: u32,
        /// Its block size.
        len: usize,
        /// The data's length.
        data_len: usize,
    },
    /// Two records' blocks overlap under [`Overlap::Forbid`].
    Overlap {
        /// The record whose block starts first (or the lower number on a tie).
        first: usize,
        /// The record whose block starts inside it.
        second: usize,
    },
    /// The blocks add up to more than [`Overlap::Allow`]'s limit.
    DecodedTooLarge {
        /// The limit.
        limit: u64,
    },
    /// The usage-count bytes are not a whole number of 12-byte entries.
    UsageCountsLength {
        /// The length given.
        len: usize,
    },
    /// A usage count's format is neither 1 nor 2.
    UsageInvalidFormat {
        /// The entry.
        entry: usize,
        /// Its format field.
        format: u32,
    },
    /// A usage count is zero (glTF: every count "MUST be greater than or
    /// equal to 1").
    UsageZeroCount {
        /// The entry.
        entry: usize,
    },
    /// The usage counts for a level and format (summed over duplicate
    /// entries, as glTF asks) differ from the number of records with them.
    UsageMismatch {
        /// The level.
        level: u32,
        /// The format.
        format: u32,
        /// The sum of the usage counts.
        declared: u64,
        /// The number of records.
        actual: u64,
    },
    /// The index bytes are not a whole number of indices.
    IndexBufferLength {
        /// The length given.
        len: usize,
        /// The index width.
        width: IndexWidth,
    },
    /// A regular index (plus the base triangle) names no record.
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The index plus the base triangle.
        index: u64,
        /// The number of records.
        records: usize,
    },
    /// An index is the reserved pattern of -5 (see
    /// [`IndexWidth::max_regular`]).
    ReservedIndex {
        /// The triangle.
        triangle: usize,
        /// The raw value.
        raw: u32,
    },
    /// A micromap could not be made (only [`MicromapError::AllocationFailed`]
    /// is possible after the checks above).
    Micromap {
        /// The record.
        record: usize,
        /// What failed.
        error: MicromapError,
    },
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::RecordsLength { len } => {
                write!(f, "{len} bytes of triangle records are not a multiple of 8")
            }
            ReadError::RecordStride { stride } => write!(
                f,
                "record stride {stride}: Vulkan's triangleArrayStride is at least 8 and a multiple of 4"
            ),
            ReadError::IndexStride { stride, width } => write!(
                f,
                "index stride {stride} is not a positive multiple of the {width} index size"
            ),
            ReadError::StridedLength { len, stride, element } => write!(
                f,
                "{len} bytes are neither whole {stride}-byte strides nor end right after a {element}-byte element"
            ),
            ReadError::TooManyRecords { count } => {
                write!(f, "{count} triangle records are more than 32-bit indices address")
            }
            ReadError::InvalidFormat { record, format } => {
                write!(f, "record {record}: format {format} is neither 1 nor 2")
            }
            ReadError::LevelTooHigh { record, level, max } => {
                write!(f, "record {record}: subdivision level {level} is above {max}")
            }
            ReadError::BlockOutOfBounds {
                record,
                offset,
                len,
                data_len,
            } => write!(
                f,
                "record {record}: {len} bytes at offset {offset} pass the end of {data_len} bytes of data"
            ),
            ReadError::Overlap { first, second } => {
                write!(f, "records {first} and {second} have overlapping data")
            }
            ReadError::DecodedTooLarge { limit } => {
                write!(f, "the micromaps would take more than {limit} bytes")
            }
            ReadError::UsageCountsLength { len } => {
                write!(f, "{len} bytes of usage counts are not a multiple of 12")
            }
            ReadError::UsageInvalidFormat { entry, format } => {
                write!(f, "usage count {entry}: format {format} is neither 1 nor 2")
            }
            ReadError::UsageZeroCount { entry } => write!(f, "usage count {entry} is zero"),
            ReadError::UsageMismatch {
                level,
                format,
                declared,
                actual,
            } => write!(
                f,
                "usage counts declare {declared} micromaps of level {level} format {format}, the records have {actual}"
            ),
            ReadError::IndexBufferLength { len, width } => {
                write!(f, "{len} bytes are not a whole number of {width} indices")
            }
            ReadError::IndexOutOfRange {
                triangle,
                index,
                records,
            } => write!(
                f,
                "triangle {triangle}: micromap index {index} is past the {records} records"
            ),
            ReadError::ReservedIndex { triangle, raw } => {
                write!(f, "triangle {triangle}: index {raw:#x} is the reserved special index -5")
            }
            ReadError::Micromap { record, error } => write!(f, "record {record}: {error}"),
        }
    }
}

impl core::error::Error for ReadError {}

/// What [`read_buffers`] returns.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ReadBuffers {
    /// The triangle records as read.
    pub records: Vec<TriangleRecord>,
    /// The micromap of each record, in record order. Bits past the last
    /// micro-triangle of a one-byte block are cleared (readers ignore them:
    /// the glTF draft says so).
    pub micromaps: Vec<Micromap>,
    /// The geometry's per-triangle indices with the base triangle added,
    /// if an index buffer was given; every [`MicromapIndex::Record`] names
    /// an entry of `micromaps`.
    pub indices: Option<Vec<MicromapIndex>>,
}

/// Reads a micromap array (and optionally usage counts and one geometry's
/// index buffer) from untrusted bytes, checking everything the APIs
/// require and the micromaps need:
///
/// 1. the strides ([`ReadOptions::check_strides`]); record bytes a
///    multiple of 8 (whole strides, or ending right after the last
///    record), at most `2^32 - 5` records;
/// 2. each record's format 1 or 2 and level at most
///    [`ReadOptions::max_level`];
/// 3. each block (`ceil(4^level * bits / 8)` bytes at `data_offset`) inside
///    the data;
/// 4. blocks disjoint under [`Overlap::Forbid`] (sharing is overlap too),
///    or their total within the limit under [`Overlap::Allow`];
/// 5. usage counts, if given: a multiple of 12 bytes, formats 1 or 2,
///    counts at least 1, and for every level and format the sum of the
///    counts equal to the number of records (so their total is the record
///    count, as glTF requires);
/// 6. indices, if given: a whole number of indices (or strides); each a special index
///    (-1..-4 as two's complement at the width), or a regular index whose
///    sum with the base triangle names a record; the pattern of -5 is
///    refused.
///
/// Blocks need not be aligned (the APIs call offsets "byte aligned").
/// Never panics; the first problem found is returned (in the order above).
///
/// ```
/// use micromap_index::micromap::{read_buffers, BufferBytes, ReadError, State};
///
/// // One level-1 2-state record at offset 0, data 0b1010.
/// let records = [0, 0, 0, 0, 1, 0, 1, 0];
/// let read = read_buffers(&BufferBytes { records: &records, data: &[0b1010], ..Default::default() }, &Default::default()).unwrap();
/// assert!(read.micromaps[0].states().eq([State::Transparent, State::Opaque, State::Transparent, State::Opaque]));
///
/// // The same record with level 2 needs two bytes.
/// let records = [0, 0, 0, 0, 2, 0, 1, 0];
/// assert_eq!(
///     read_buffers(&BufferBytes { records: &records, data: &[0b1010], ..Default::default() }, &Default::default()),
///     Err(ReadError::BlockOutOfBounds { record: 0, offset: 0, len: 2, data_len: 1 })
/// );
/// ```
pub fn read_buffers(
    input: &BufferBytes<'_>,
    options: &ReadOptions,
) -> Result<ReadBuffers, ReadError> {
    options.check_strides(input.indices.map(|(_, width)| width))?;
    let records = read_records(input.records, options.record_stride)?;
    // Check every record and compute its block before decoding any.
    let max_level = options.max_level.min(Micromap::MAX_LEVEL);
    let mut blocks = Vec::new();
    reserve(&mut blocks, records.len())?;
    for (record, &r) in records.iter().enumerate() {
        let Some(format) = Format::from_raw(r.format) else {
            return Err(ReadError::InvalidFormat {
                record,
                format: r.format,
            });
        };
        let shape = record_shape(r).filter(|(level, _)| level.get() <= max_level);
        let Some((level, _)) = shape else {
            return Err(ReadError::LevelTooHigh {
                record,
                level: r.subdivision_level,
                max: max_level,
            });
        };
        let len = Micromap::byte_len(level, format);
        let start = r.data_offset as usize;
        match start.checked_add(len) {
            Some(end) if end <= input.data.len() => blocks.push((start, end, level, format)),
            _ => {
                return Err(ReadError::BlockOutOfBounds {
                    record,
                    offset: r.data_offset,
                    len,
                    data_len: input.data.len(),
                })
            }
        }
    }
    check_overlap(&blocks, options.overlap)?;
    if let Some(usage) = input.usage_counts {
        check_usage(usage, &records)?;
    }
    let indices = match input.indices {
        Some((bytes, width)) => Some(read_indices(
            bytes,
            width,
            options.index_stride.unwrap_or(width.bytes()),
            records.len(),
            options.base_triangle,
        )?),
        None => None,
    };
    let mut micromaps = Vec::new();
    reserve(&mut micromaps, blocks.len())?;
    for (record, &(start, end, level, format)) in blocks.iter().enumerate() {
        let bytes = input.data.get(start..end).unwrap_or_default();
        let map = Micromap::from_bytes_ignoring_unused_bits(level, format, bytes)
            .map_err(|error| ReadError::Micromap { record, error })?;
        micromaps.push(map);
    }
    Ok(ReadBuffers {
        records,
        micromaps,
        indices,
    })
}

/// A record's block: start and end in the data, level and format.
type Block = (usize, usize, Level, Format);

/// Room for `count` more items, or the allocation failure (as record 0's:
/// a list per record cannot be had).
fn reserve<T>(list: &mut Vec<T>, count: usize) -> Result<(), ReadError> {
    list.try_reserve_exact(count)
        .map_err(|_| ReadError::Micromap {
            record: 0,
            error: MicromapError::AllocationFailed {
                bytes: count.saturating_mul(core::mem::size_of::<T>()),
            },
        })
}

/// The records of `bytes` (a multiple of 8, fewer than `2^32 - 5`).
fn read_records(bytes: &[u8], stride: usize) -> Result<Vec<TriangleRecord>, ReadError> {
    if stride < TriangleRecord::SIZE || stride % 4 != 0 {
        return Err(ReadError::RecordStride { stride });
    }
    let Some(chunks) = strided(bytes, stride, TriangleRecord::SIZE) else {
        return Err(if stride == TriangleRecord::SIZE {
            ReadError::RecordsLength { len: bytes.len() }
        } else {
            ReadError::StridedLength {
                len: bytes.len(),
                stride,
                element: TriangleRecord::SIZE,
            }
        });
    };
    let count = bytes.len().div_ceil(stride);
    if count as u64 > u64::from(IndexWidth::U32.max_regular()) + 1 {
        return Err(ReadError::TooManyRecords { count });
    }
    Ok(chunks
        .map(|chunk| {
            let mut record = [0u8; 8];
            record.copy_from_slice(chunk);
            TriangleRecord::from_le_bytes(record)
        })
        .collect())
}

/// Rule 4 of [`read_buffers`]: `blocks` are `(start, end, ..)` per record.
fn check_overlap(blocks: &[Block], overlap: Overlap) -> Result<(), ReadError> {
    match overlap {
        Overlap::Allow { max_decoded_bytes } => {
            let total: u64 = blocks.iter().map(|b| (b.1 - b.0) as u64).sum();
            if total > max_decoded_bytes {
                return Err(ReadError::DecodedTooLarge {
                    limit: max_decoded_bytes,
                });
            }
        }
        Overlap::Forbid => {
            let mut order: Vec<usize> = (0..blocks.len()).collect();
            order.sort_by_key(|&i| (blocks[i].0, i));
            for pair in order.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                // Sorted by start: b overlaps a exactly when it starts
                // before a ends (every block is at least one byte).
                if blocks[b].0 < blocks[a].1 {
                    return Err(ReadError::Overlap {
                        first: a,
                        second: b,
                    });
                }
            }
        }
    }
    Ok(())
}

/// Rule 5 of [`read_buffers`].
fn check_usage(bytes: &[u8], records: &[TriangleRecord]) -> Result<(), ReadError> {
    let chunks = bytes.chunks_exact(UsageCount::SIZE);
    if !chunks.remainder().is_empty() {
        return Err(ReadError::UsageCountsLength { len: bytes.len() });
    }
    // (format, level) -> (declared, actual)
    let mut sums: BTreeMap<(u32, u32), (u64, u64)> = BTreeMap::new();
    for (entry, chunk) in chunks.enumerate() {
        let mut raw = [0u8; 12];
        raw.copy_from_slice(chunk);
        let usage = UsageCount::from_le_bytes(raw);
        if !(1..=2).contains(&usage.format) {
            return Err(ReadError::UsageInvalidFormat {
                entry,
                format: usage.format,
            });
        }
        if usage.count == 0 {
            return Err(ReadError::UsageZeroCount { entry });
        }
        sums.entry((usage.format, usage.subdivision_level))
            .or_default()
            .0 += u64::from(usage.count);
    }
    for r in records {
        sums.entry((u32::from(r.format), u32::from(r.subdivision_level)))
            .or_default()
            .1 += 1;
    }
    match sums
        .into_iter()
        .find(|(_, (declared, actual))| declared != actual)
    {
        Some(((format, level), (declared, actual))) => Err(ReadError::UsageMismatch {
            level,
            format,
            declared,
            actual,
        }),
        None => Ok(()),
    }
}

/// Rule 6 of [`read_buffers`].
fn read_indices(
    bytes: &[u8],
    width: IndexWidth,
    stride: usize,
    records: usize,
    base_triangle: u32,
) -> Result<Vec<MicromapIndex>, ReadError> {
    if stride == 0 || stride % width.bytes() != 0 {
        return Err(ReadError::IndexStride { stride, width });
    }
    let Some(chunks) = strided(bytes, stride, width.bytes()) else {
        return Err(if stride == width.bytes() {
            ReadError::IndexBufferLength {
                len: bytes.len(),
                width,
            }
        } else {
            ReadError::StridedLength {
                len: bytes.len(),
                stride,
                element: width.bytes(),
            }
        });
    };
    chunks
        .enumerate()
        .map(|(triangle, chunk)| {
            let mut raw = [0u8; 4];
            raw[..chunk.len()].copy_from_slice(chunk);
            let raw = u32::from_le_bytes(raw);
            match MicromapIndex::decode(raw, width) {
                None => Err(ReadError::ReservedIndex { triangle, raw }),
                Some(MicromapIndex::Special(state)) => Ok(MicromapIndex::Special(state)),
                Some(MicromapIndex::Record(r)) => {
                    let index = u64::from(r) + u64::from(base_triangle);
                    match u32::try_from(index) {
                        Ok(i) if (i as usize) < records => Ok(MicromapIndex::Record(i)),
                        _ => Err(ReadError::IndexOutOfRange {
                            triangle,
                            index,
                            records,
                        }),
                    }
                }
            }
        })
        .collect()
}
