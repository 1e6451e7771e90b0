//! API build inputs made from many micromaps: packed data, triangle records,
//! usage counts and per-triangle index buffers (Vulkan
//! `VK_EXT_opacity_micromap` / `VK_KHR_opacity_micromap`, DXR 1.2, glTF
//! `EXT_mesh_opacity_micromap`). `docs/micromaps.md` cites the spec rule
//! behind each choice.

use super::map::Micromap;
use super::opacity::{BakedOpacity, TriangleOpacity};
use super::state::{Format, State};
use crate::Level;
use alloc::collections::BTreeMap;
use alloc::vec::Vec;
use core::fmt;
use core::mem::{offset_of, size_of};

/// One micromap's entry in the triangle array: where its data starts in the
/// data buffer, its level and its format. The same 8 bytes as Vulkan's
/// `VkMicromapTriangleEXT` / `VkMicromapTriangleKHR`, DXR's
/// `D3D12_RAYTRACING_OPACITY_MICROMAP_DESC` and a glTF
/// `EXT_mesh_opacity_micromap` triangle record (little-endian on disk).
///
/// ```
/// use micromap_index::micromap::TriangleRecord;
/// let record = TriangleRecord { data_offset: 0x0102_0304, subdivision_level: 5, format: 2 };
/// assert_eq!(record.to_le_bytes(), [4, 3, 2, 1, 5, 0, 2, 0]);
/// assert_eq!(TriangleRecord::from_le_bytes(record.to_le_bytes()), record);
/// ```
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TriangleRecord {
    /// Byte offset of the micromap's data in the data buffer.
    pub data_offset: u32,
    /// The subdivision level.
    pub subdivision_level: u16,
    /// The format: 1 (2-state) or 2 (4-state), see [`Format::raw`].
    pub format: u16,
}

const _: () = {
    assert!(size_of::<TriangleRecord>() == 8);
    assert!(offset_of!(TriangleRecord, data_offset) == 0);
    assert!(offset_of!(TriangleRecord, subdivision_level) == 4);
    assert!(offset_of!(TriangleRecord, format) == 6);
};

impl TriangleRecord {
    /// The size of a record in bytes (the tight stride).
    pub const SIZE: usize = 8;

    /// The record in little-endian bytes, as the APIs and glTF read it.
    #[inline]
    #[must_use]
    pub const fn to_le_bytes(self) -> [u8; 8] {
        let o = self.data_offset.to_le_bytes();
        let l = self.subdivision_level.to_le_bytes();
        let f = self.format.to_le_bytes();
        [o[0], o[1], o[2], o[3], l[0], l[1], f[0], f[1]]
    }

    /// The record from little-endian bytes (any bytes; validation is the
    /// reader's job, see [`read_buffers`](super::read_buffers)).
    #[inline]
    #[must_use]
    pub const fn from_le_bytes(b: [u8; 8]) -> TriangleRecord {
        TriangleRecord {
            data_offset: u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            subdivision_level: u16::from_le_bytes([b[4], b[5]]),
            format: u16::from_le_bytes([b[6], b[7]]),
        }
    }
}

/// How many micromaps (or triangles) have one level and format: the same
/// 12 bytes as Vulkan's `VkMicromapUsageEXT` (and `VkMicromapUsageKHR`),
/// DXR's `D3D12_RAYTRACING_OPACITY_MICROMAP_HISTOGRAM_ENTRY` and one entry of
/// glTF's parallel `usageCounts` / `usageLevels` / `usageFormats` arrays.
///
/// ```
/// use micromap_index::micromap::UsageCount;
/// let usage = UsageCount { count: 3, subdivision_level: 4, format: 1 };
/// assert_eq!(usage.to_le_bytes(), [3, 0, 0, 0, 4, 0, 0, 0, 1, 0, 0, 0]);
/// assert_eq!(UsageCount::from_le_bytes(usage.to_le_bytes()), usage);
/// ```
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct UsageCount {
    /// How many.
    pub count: u32,
    /// The subdivision level.
    pub subdivision_level: u32,
    /// The format: 1 (2-state) or 2 (4-state).
    pub format: u32,
}

const _: () = {
    assert!(size_of::<UsageCount>() == 12);
    assert!(offset_of!(UsageCount, count) == 0);
    assert!(offset_of!(UsageCount, subdivision_level) == 4);
    assert!(offset_of!(UsageCount, format) == 8);
};

impl UsageCount {
    /// The size of a usage count in bytes.
    pub const SIZE: usize = 12;

    /// The usage count in little-endian bytes.
    #[inline]
    #[must_use]
    pub const fn to_le_bytes(self) -> [u8; 12] {
        let c = self.count.to_le_bytes();
        let l = self.subdivision_level.to_le_bytes();
        let f = self.format.to_le_bytes();
        [
            c[0], c[1], c[2], c[3], l[0], l[1], l[2], l[3], f[0], f[1], f[2], f[3],
        ]
    }

    /// The usage count from little-endian bytes (any bytes).
    #[inline]
    #[must_use]
    pub const fn from_le_bytes(b: [u8; 12]) -> UsageCount {
        UsageCount {
            count: u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            subdivision_level: u32::from_le_bytes([b[4], b[5], b[6], b[7]]),
            format: u32::from_le_bytes([b[8], b[9], b[10], b[11]]),
        }
    }
}

/// Records as consecutive little-endian bytes (stride 8).
///
/// ```
/// use micromap_index::micromap::{records_to_le_bytes, TriangleRecord};
/// let records = [TriangleRecord { data_offset: 8, subdivision_level: 1, format: 1 }; 2];
/// assert_eq!(records_to_le_bytes(&records).len(), 16);
/// ```
#[must_use]
pub fn records_to_le_bytes(records: &[TriangleRecord]) -> Vec<u8> {
    records.iter().flat_map(|r| r.to_le_bytes()).collect()
}

/// Usage counts as consecutive little-endian bytes (stride 12).
///
/// ```
/// use micromap_index::micromap::{usage_counts_to_le_bytes, UsageCount};
/// let usage = [UsageCount { count: 1, subdivision_level: 0, format: 2 }];
/// assert_eq!(usage_counts_to_le_bytes(&usage), [1, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0]);
/// ```
#[must_use]
pub fn usage_counts_to_le_bytes(usage: &[UsageCount]) -> Vec<u8> {
    usage.iter().flat_map(|u| u.to_le_bytes()).collect()
}

/// The width of a per-triangle micromap index buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum IndexWidth {
    /// 8-bit indices: Vulkan KHR (only on Vulkan 1.4 or with
    /// `VK_KHR_index_type_uint8` / `VK_EXT_index_type_uint8`), DXR and glTF;
    /// never Vulkan EXT.
    U8,
    /// 16-bit indices.
    U16,
    /// 32-bit indices.
    U32,
}

impl IndexWidth {
    /// Every width, narrowest first.
    pub const ALL: [IndexWidth; 3] = [IndexWidth::U8, IndexWidth::U16, IndexWidth::U32];

    /// Bytes per index.
    #[inline]
    #[must_use]
    pub const fn bytes(self) -> usize {
        match self {
            IndexWidth::U8 => 1,
            IndexWidth::U16 => 2,
            IndexWidth::U32 => 4,
        }
    }

    /// `2^bits - 1`, the pattern of -1 at this width.
    #[inline]
    #[must_use]
    pub const fn all_ones(self) -> u32 {
        match self {
            IndexWidth::U8 => 0xff,
            IndexWidth::U16 => 0xffff,
            IndexWidth::U32 => 0xffff_ffff,
        }
    }

    /// The largest regular (non-special) index this crate writes or accepts
    /// at this width: `2^bits - 6`. The top four patterns are the special
    /// indices -1..-4, and -5 (`2^bits - 5`) is kept out too because
    /// cluster acceleration structures give it a meaning (Vulkan
    /// `VK_OPACITY_MICROMAP_SPECIAL_INDEX_CLUSTER_GEOMETRY_DISABLE_OPACITY_MICROMAP_NV`,
    /// D3D12 `..._CLUSTER_SKIP_OMM`).
    ///
    /// ```
    /// use micromap_index::micromap::IndexWidth;
    /// assert_eq!(IndexWidth::U8.max_regular(), 250);
    /// assert_eq!(IndexWidth::U16.max_regular(), 65530);
    /// ```
    #[inline]
    #[must_use]
    pub const fn max_regular(self) -> u32 {
        self.all_ones() - 5
    }

    /// The narrowest width whose [`max_regular`](Self::max_regular) is at
    /// least `max_index` and that `api` accepts (`None` when no index is
    /// regular: then every width fits and the narrowest allowed one is
    /// chosen).
    ///
    /// ```
    /// use micromap_index::micromap::{Api, IndexWidth};
    /// assert_eq!(IndexWidth::narrowest(Some(250), Api::Dxr), IndexWidth::U8);
    /// assert_eq!(IndexWidth::narrowest(Some(251), Api::Dxr), IndexWidth::U16);
    /// assert_eq!(IndexWidth::narrowest(Some(3), Api::VulkanExt), IndexWidth::U16);
    /// assert_eq!(IndexWidth::narrowest(None, Api::VulkanKhr), IndexWidth::U8);
    /// ```
    #[must_use]
    pub fn narrowest(max_index: Option<u32>, api: Api) -> IndexWidth {
        let need = max_index.unwrap_or(0);
        IndexWidth::ALL
            .into_iter()
            .find(|&w| api.allows_index_width(w) && need <= w.max_regular())
            // Every API accepts 32-bit indices and record counts stay
            // below 2^32 - 5 (the builder checks it).
            .unwrap_or(IndexWidth::U32)
    }
}

impl fmt::Display for IndexWidth {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            IndexWidth::U8 => "u8",
            IndexWidth::U16 => "u16",
            IndexWidth::U32 => "u32",
        })
    }
}

/// The API (or file format) that will read the buffers; its rules differ in
/// the details this crate checks or documents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Api {
    /// Vulkan `VK_EXT_opacity_micromap` (`vkCmdBuildMicromapsEXT`).
    VulkanExt,
    /// Vulkan `VK_KHR_opacity_micromap` (micromaps built as acceleration
    /// structures).
    VulkanKhr,
    /// DirectX Raytracing 1.2 opacity micromap arrays.
    Dxr,
    /// The glTF `EXT_mesh_opacity_micromap` draft.
    Gltf,
}

impl Api {
    /// The alignment the API demands of the data and triangle-array base
    /// addresses: 256 for Vulkan EXT (VUID-vkCmdBuildMicromapsEXT-pInfos-07515),
    /// 128 for Vulkan KHR (VUID-vkCmdBuildAccelerationStructuresKHR-micromap-11552)
    /// and for DXR (`InputBuffer` "must be 128-byte aligned",
    /// `D3D12_RAYTRACING_OPACITY_MICROMAP_ARRAY_BYTE_ALIGNMENT`; DXR asks
    /// only 4 of the descriptor array); `None` for glTF, which sets no rule
    /// of its own (the uploader must meet the target API's).
    ///
    /// ```
    /// use micromap_index::micromap::Api;
    /// assert_eq!(Api::VulkanExt.base_alignment(), Some(256));
    /// assert_eq!(Api::Dxr.base_alignment(), Some(128));
    /// ```
    #[inline]
    #[must_use]
    pub const fn base_alignment(self) -> Option<u64> {
        match self {
            Api::VulkanExt => Some(256),
            Api::VulkanKhr | Api::Dxr => Some(128),
            Api::Gltf => None,
        }
    }

    /// Whether the API accepts index buffers of `width`: Vulkan EXT takes
    /// 16 and 32 bits only (VUID-VkAccelerationStructureTrianglesOpacityMicromapEXT-indexType-10719);
    /// DXR (`DXGI_FORMAT_R8_UINT` etc.) and glTF (`UNSIGNED_BYTE`) also
    /// take 8 bits, and so does Vulkan KHR (…KHR-indexType-11570) on a
    /// device with Vulkan 1.4 or `VK_KHR_index_type_uint8` /
    /// `VK_EXT_index_type_uint8` (the caller's to know; `true` here).
    #[inline]
    #[must_use]
    pub const fn allows_index_width(self, width: IndexWidth) -> bool {
        !matches!((self, width), (Api::VulkanExt, IndexWidth::U8))
    }

    /// The highest subdivision level the API accepts whatever the device:
    /// 12 for DXR (`D3D12_RAYTRACING_OPACITY_MICROMAP_OC1_MAX_SUBDIVISION_LEVEL`)
    /// and for glTF (the `EXT_mesh_opacity_micromap` draft at 4b95e4d3:
    /// records and `usageLevels` in `[0, 12]`, schema `maximum: 12`);
    /// `None` for Vulkan (a device limit, `maxOpacity2StateSubdivisionLevel` /
    /// `maxOpacity4StateSubdivisionLevel`, and for KHR lossy builds
    /// `maxOpacityLossy4StateSubdivisionLevel`, each required to be only at
    /// least 3).
    ///
    /// ```
    /// use micromap_index::micromap::Api;
    /// assert_eq!(Api::Gltf.max_level(), Some(12));
    /// assert_eq!(Api::VulkanKhr.max_level(), None);
    /// ```
    #[inline]
    #[must_use]
    pub const fn max_level(self) -> Option<u32> {
        match self {
            Api::Dxr | Api::Gltf => Some(12),
            Api::VulkanExt | Api::VulkanKhr => None,
        }
    }

    /// Whether the API also wants per-geometry usage counts (of the
    /// triangles that reference each level and format, special indices
    /// skipped): only Vulkan EXT, in
    /// `VkAccelerationStructureTrianglesOpacityMicromapEXT::pUsageCounts`.
    #[inline]
    #[must_use]
    pub const fn needs_geometry_usage_counts(self) -> bool {
        matches!(self, Api::VulkanExt)
    }
}

impl fmt::Display for Api {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Api::VulkanExt => "Vulkan VK_EXT_opacity_micromap",
            Api::VulkanKhr => "Vulkan VK_KHR_opacity_micromap",
            Api::Dxr => "DXR 1.2",
            Api::Gltf => "glTF EXT_mesh_opacity_micromap",
        })
    }
}

/// What one triangle's entry in a per-triangle index buffer says: a
/// micromap (an index into the triangle records) or a special index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum MicromapIndex {
    /// The triangle uses the micromap of this record.
    Record(u32),
    /// The whole triangle has this state (special index `-(state + 1)`).
    Special(State),
}

impl MicromapIndex {
    /// The index as the signed value the APIs define: the record number, or
    /// -1..-4 for a special index.
    ///
    /// ```
    /// use micromap_index::micromap::{MicromapIndex, State};
    /// assert_eq!(MicromapIndex::Record(7).signed(), 7);
    /// assert_eq!(MicromapIndex::Special(State::Opaque).signed(), -2);
    /// ```
    #[inline]
    #[must_use]
    pub const fn signed(self) -> i64 {
        match self {
            MicromapIndex::Record(r) => r as i64,
            MicromapIndex::Special(s) => s.special_index() as i64,
        }
    }

    /// The raw value at `width`: a record number up to
    /// [`IndexWidth::max_regular`], or the two's-complement pattern of the
    /// special index (0xFFFF is -1 at 16 bits). A record number that does
    /// not fit is [`BufferError::IndexDoesNotFit`].
    ///
    /// ```
    /// use micromap_index::micromap::{BufferError, IndexWidth, MicromapIndex, State};
    /// assert_eq!(MicromapIndex::Special(State::Transparent).encode(IndexWidth::U16), Ok(0xffff));
    /// assert_eq!(MicromapIndex::Special(State::UnknownOpaque).encode(IndexWidth::U8), Ok(0xfc));
    /// assert_eq!(
    ///     MicromapIndex::Record(251).encode(IndexWidth::U8),
    ///     Err(BufferError::IndexDoesNotFit { index: 251, width: IndexWidth::U8 })
    /// );
    /// ```
    #[inline]
    pub const fn encode(self, width: IndexWidth) -> Result<u32, BufferError> {
        match self {
            MicromapIndex::Record(r) if r <= width.max_regular() => Ok(r),
            MicromapIndex::Record(r) => Err(BufferError::IndexDoesNotFit { index: r, width }),
            // -(state + 1) in two's complement at the width: all ones - state.
            MicromapIndex::Special(s) => Ok(width.all_ones() - s.bits() as u32),
        }
    }

    /// The index a raw value at `width` stands for, or `None` for the
    /// reserved pattern of -5 (see [`IndexWidth::max_regular`]); a value
    /// wider than `width` is read modulo `2^bits`. Whether a record number
    /// exists is the reader's check.
    ///
    /// ```
    /// use micromap_index::micromap::{IndexWidth, MicromapIndex, State};
    /// assert_eq!(MicromapIndex::decode(0xfffe, IndexWidth::U16), Some(MicromapIndex::Special(State::Opaque)));
    /// assert_eq!(MicromapIndex::decode(0xfffb, IndexWidth::U16), None);
    /// assert_eq!(MicromapIndex::decode(0xfffa, IndexWidth::U16), Some(MicromapIndex::Record(0xfffa)));
    /// ```
    #[inline]
    #[must_use]
    pub const fn decode(raw: u32, width: IndexWidth) -> Option<MicromapIndex> {
        let raw = raw & width.all_ones();
        let from_top = width.all_ones() - raw; // 0 for -1, 3 for -4, 4 for -5
        if from_top <= 3 {
            match State::from_bits(from_top as u8) {
                Some(state) => Some(MicromapIndex::Special(state)),
                None => None,
            }
        } else if from_top == 4 {
            None
        } else {
            Some(MicromapIndex::Record(raw))
        }
    }
}

/// What went wrong building buffers or writing an index buffer.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum BufferError {
    /// The data buffer would pass 4 GiB, beyond the records' 32-bit offsets.
    DataTooLarge {
        /// The size it would have, in bytes.
        bytes: u64,
    },
    /// More distinct micromaps than a 32-bit index buffer can address
    /// ([`IndexWidth::max_regular`] of [`IndexWidth::U32`]).
    TooManyMicromaps {
        /// How many there were.
        count: u64,
    },
    /// A record number does not fit the index width.
    IndexDoesNotFit {
        /// The record number.
        index: u32,
        /// The width asked for.
        width: IndexWidth,
    },
    /// The API does not accept this index width.
    IndexWidthNotAllowed {
        /// The width asked for.
        width: IndexWidth,
        /// The API.
        api: Api,
    },
    /// A micromap's level is above what the API accepts.
    LevelNotAllowed {
        /// The level.
        level: u32,
        /// The API's highest level.
        max: u32,
        /// The API.
        api: Api,
    },
    /// A record is 2-state where only 4-state is accepted (Vulkan KHR
    /// lossy builds, [`MicromapBuffers::check_for_khr_lossy`]).
    FormatNotAllowed {
        /// The record.
        record: usize,
        /// Its format (raw API value).
        format: u16,
    },
    /// There is no geometry with this number.
    NoSuchGeometry {
        /// The geometry asked for.
        geometry: usize,
        /// How many there are.
        count: usize,
    },
    /// The allocator refused the buffers.
    AllocationFailed,
    /// A [`TriangleEntry`] names a micromap this builder does not hold
    /// (it came from another builder).
    NoSuchEntry {
        /// The distinct micromap it names.
        entry: u32,
        /// How many this builder holds.
        count: usize,
    },
}

impl fmt::Display for BufferError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BufferError::DataTooLarge { bytes } => write!(
                f,
                "the micromap data would take {bytes} bytes, more than 32-bit offsets address"
            ),
            BufferError::TooManyMicromaps { count } => {
                write!(
                    f,
                    "{count} distinct micromaps are more than 32-bit indices address"
                )
            }
            BufferError::IndexDoesNotFit { index, width } => write!(
                f,
                "micromap index {index} does not fit a {width} index buffer (at most {})",
                width.max_regular()
            ),
            BufferError::IndexWidthNotAllowed { width, api } => {
                write!(f, "{api} does not accept {width} micromap index buffers")
            }
            BufferError::LevelNotAllowed { level, max, api } => write!(
                f,
                "subdivision level {level} is above {api}'s highest level {max}"
            ),
            BufferError::FormatNotAllowed { record, format } => write!(
                f,
                "record {record} has format {format}: a Vulkan KHR lossy build takes 4-state (2) micromaps only"
            ),
            BufferError::NoSuchGeometry { geometry, count } => {
                write!(f, "geometry {geometry} does not exist: there are {count}")
            }
            BufferError::AllocationFailed => f.write_str("could not allocate the buffers"),
            BufferError::NoSuchEntry { entry, count } => write!(
                f,
                "entry {entry} names no micromap of this builder (it holds {count})"
            ),
        }
    }
}

impl core::error::Error for BufferError {}

/// Options for [`MicromapBuffersBuilder`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BuildOptions {
    /// Replace every uniform micromap by its special index (default
    /// `true`): a triangle then reads the same state at every hit, and the
    /// micromap takes no data. DXR recommends it ("it is preferable to
    /// signal this explicitly").
    pub uniform_to_special: bool,
    /// Never mix special indices with records in one geometry (default
    /// `false`): in a geometry that references any record, each special
    /// index is replaced by a shared level-0 record of its state (at most
    /// four extra records of one byte, deduplicated with equal maps). A
    /// geometry of special indices only keeps them. For Vulkan KHR
    /// pipelines created with
    /// `VK_PIPELINE_CREATE_2_OPACITY_MICROMAP_DISALLOW_MIXED_SPECIAL_INDEX_BIT_KHR`
    /// (VUID-{cmd}-micromap-11638); [`MicromapBuffers::is_mixed`] checks it.
    /// The shared records are 4-state for the unknown states or when the
    /// builder holds any 4-state map, else 2-state, so a single-format
    /// bake stays single-format.
    pub no_mixed_special_indices: bool,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            uniform_to_special: true,
            no_mixed_special_indices: false,
        }
    }
}

/// A triangle's entry before the final order is known.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Entry {
    /// Index into the builder's distinct micromaps.
    Unique(u32),
    Special(State),
}

/// A triangle's opacity as a [`MicromapBuffersBuilder`] holds it: a
/// distinct micromap it stores, or a special index
/// ([`MicromapBuffersBuilder::add_micromap`],
/// [`MicromapBuffersBuilder::special`]), meaningful for the builder that
/// made it (another builder's entry may name another map, or none:
/// [`BufferError::NoSuchEntry`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleEntry(Entry);

/// Collects the micromaps of one or more geometries, deduplicates them by
/// content and lays out the API buffers ([`finish`](Self::finish)).
///
/// ```
/// use micromap_index::micromap::{
///     Format, Micromap, MicromapBuffersBuilder, MicromapIndex, State, TriangleOpacity,
/// };
/// use micromap_index::Level;
///
/// let level = Level::new(2).unwrap();
/// let mut half = Micromap::new(level, Format::TwoState).unwrap();
/// for i in 0..8 {
///     half.set(i, State::Opaque).unwrap();
/// }
/// let full = Micromap::uniform_map(level, Format::TwoState, State::Opaque).unwrap();
///
/// let mut builder = MicromapBuffersBuilder::new(Default::default());
/// builder.add_geometry([
///     TriangleOpacity::Micromap(&half),
///     TriangleOpacity::Micromap(&full), // uniform: becomes special index -2
///     TriangleOpacity::Micromap(&half.clone()), // same content: same record
///     TriangleOpacity::Special(State::Transparent),
/// ]).unwrap();
/// let buffers = builder.finish().unwrap();
/// assert_eq!(buffers.data(), &[0xff, 0x00]);
/// assert_eq!(buffers.records().len(), 1);
/// assert_eq!(
///     buffers.geometry_indices(0).unwrap(),
///     &[
///         MicromapIndex::Record(0),
///         MicromapIndex::Special(State::Opaque),
///         MicromapIndex::Record(0),
///         MicromapIndex::Special(State::Transparent),
///     ]
/// );
/// // Vulkan EXT's per-geometry counts: two triangles reference a level-2 2-state map.
/// let usage = buffers.geometry_usage_counts(0).unwrap();
/// assert_eq!((usage[0].count, usage[0].subdivision_level, usage[0].format), (2, 2, 1));
/// ```
#[derive(Clone, Debug, Default)]
pub struct MicromapBuffersBuilder {
    options: BuildOptions,
    /// Distinct micromaps in order of first appearance: their level,
    /// format and place in `arenas`.
    unique: Vec<Stored>,
    /// The distinct maps' bytes, one arena per byte length, each in order
    /// of first appearance: the data buffer in pieces (`finish` joins them
    /// without copying the largest).
    arenas: BTreeMap<usize, Vec<u8>>,
    /// Content hash → the last index into `unique` with that hash (the
    /// others follow its `same_hash` chain).
    buckets: BTreeMap<u64, u32>,
    geometries: Vec<Vec<Entry>>,
}

/// Where the builder keeps one distinct micromap.
#[derive(Clone, Copy, Debug)]
struct Stored {
    level: Level,
    format: Format,
    /// Its byte length (its arena).
    len: usize,
    /// Its position in the arena, in maps.
    slot: usize,
    /// The map stored before it with the same content hash.
    same_hash: Option<u32>,
}

/// A hash of level, format and bytes, 8 bytes a step (a multiply and a
/// shift each): it only buckets candidates, equality is always checked on
/// the bytes, so any mix does. (Byte by byte, a level-8 map's 16 KiB took
/// a dependent multiply per byte.)
fn content_hash(map: &Micromap) -> u64 {
    let mix = |hash: u64, word: u64| {
        let h = (hash ^ word).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        h ^ (h >> 29)
    };
    let head = (u64::from(map.level().get()) << 8) | u64::from(map.format().raw());
    let mut hash = mix(0xcbf2_9ce4_8422_2325, head);
    let mut words = map.as_bytes().chunks_exact(8);
    for word in &mut words {
        let mut w = [0u8; 8];
        w.copy_from_slice(word);
        hash = mix(hash, u64::from_le_bytes(w));
    }
    let rest = words.remainder();
    if !rest.is_empty() {
        let mut w = [0u8; 8];
        w[..rest.len()].copy_from_slice(rest);
        hash = mix(hash, u64::from_le_bytes(w));
    }
    hash
}

impl MicromapBuffersBuilder {
    /// An empty builder.
    #[must_use]
    pub fn new(options: BuildOptions) -> Self {
        MicromapBuffersBuilder {
            options,
            ..Default::default()
        }
    }

    /// The bytes of a stored map.
    fn bytes(&self, stored: Stored) -> &[u8] {
        let start = stored.slot * stored.len;
        &self.arenas[&stored.len][start..start + stored.len]
    }

    /// The distinct micromap equal to `map` (`hash` its content hash).
    fn find(&self, map: &Micromap, hash: u64) -> Option<u32> {
        let mut candidate = self.buckets.get(&hash).copied();
        while let Some(i) = candidate {
            let stored = self.unique[i as usize];
            if stored.level == map.level()
                && stored.format == map.format()
                && self.bytes(stored) == map.as_bytes()
            {
                return Some(i);
            }
            candidate = stored.same_hash;
        }
        None
    }

    /// Stores a copy of `map`'s bytes, known to be new (`hash` its content
    /// hash).
    fn store(&mut self, map: &Micromap, hash: u64) -> Result<u32, BufferError> {
        let id = self.unique.len() as u64;
        if id > u64::from(IndexWidth::U32.max_regular()) {
            return Err(BufferError::TooManyMicromaps { count: id + 1 });
        }
        let bytes = map.as_bytes();
        let arena = self.arenas.entry(bytes.len()).or_default();
        // Amortised growth (a large arena grows in place where the
        // allocator can remap it).
        arena
            .try_reserve(bytes.len())
            .map_err(|_| BufferError::AllocationFailed)?;
        self.unique
            .try_reserve(1)
            .map_err(|_| BufferError::AllocationFailed)?;
        let slot = arena.len() / bytes.len().max(1);
        arena.extend_from_slice(bytes);
        let same_hash = self.buckets.insert(hash, id as u32);
        self.unique.push(Stored {
            level: map.level(),
            format: map.format(),
            len: bytes.len(),
            slot,
            same_hash,
        });
        Ok(id as u32)
    }

    /// The special index a uniform `map` becomes, if the options say so.
    fn as_special(&self, map: &Micromap) -> Option<State> {
        map.uniform().filter(|_| self.options.uniform_to_special)
    }

    /// Adds one triangle's micromap: its bytes join the builder's data
    /// once per content (a map equal to one already added adds nothing, a
    /// uniform one becomes its special index), and returns the entry to
    /// name it by in [`add_geometry_entries`](Self::add_geometry_entries).
    /// This is how a baker streams its maps in as it makes them, freeing
    /// each once added: the builder holds each distinct map's bytes once,
    /// and [`finish`](Self::finish) makes them the data buffer.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MicromapBuffersBuilder, MicromapIndex, State};
    /// use micromap_index::Level;
    /// let mut half = Micromap::new(Level::new(1).unwrap(), Format::TwoState).unwrap();
    /// half.set(0, State::Opaque).unwrap();
    /// let mut builder = MicromapBuffersBuilder::new(Default::default());
    /// let a = builder.add_micromap(&half).unwrap();
    /// let b = builder.add_micromap(&half.clone()).unwrap(); // equal: the same record
    /// let c = MicromapBuffersBuilder::special(State::Opaque);
    /// builder.add_geometry_entries([a, b, c, a]).unwrap();
    /// let buffers = builder.finish().unwrap();
    /// assert_eq!(buffers.records().len(), 1);
    /// let indices = buffers.geometry_indices(0).unwrap();
    /// assert_eq!((indices[1], indices[2]), (MicromapIndex::Record(0), MicromapIndex::Special(State::Opaque)));
    /// ```
    pub fn add_micromap(&mut self, map: &Micromap) -> Result<TriangleEntry, BufferError> {
        if let Some(state) = self.as_special(map) {
            return Ok(TriangleEntry(Entry::Special(state)));
        }
        let hash = content_hash(map);
        let id = match self.find(map, hash) {
            Some(id) => id,
            None => self.store(map, hash)?,
        };
        Ok(TriangleEntry(Entry::Unique(id)))
    }

    /// The entry of a triangle with one state, a special index (for
    /// [`add_geometry_entries`](Self::add_geometry_entries)).
    #[must_use]
    pub const fn special(state: State) -> TriangleEntry {
        TriangleEntry(Entry::Special(state))
    }

    /// Adds a geometry from entries ([`add_micromap`](Self::add_micromap),
    /// [`special`](Self::special)) of this builder, one per triangle in
    /// triangle order; an entry may serve any number of triangles and
    /// geometries. Returns the geometry's number. The buffers are those
    /// [`add_geometry`](Self::add_geometry) gives for the maps in the order
    /// they were added.
    pub fn add_geometry_entries(
        &mut self,
        entries: impl IntoIterator<Item = TriangleEntry>,
    ) -> Result<usize, BufferError> {
        let mut list = Vec::new();
        for TriangleEntry(entry) in entries {
            if let Entry::Unique(id) = entry {
                if id as usize >= self.unique.len() {
                    return Err(BufferError::NoSuchEntry {
                        entry: id,
                        count: self.unique.len(),
                    });
                }
            }
            list.try_reserve(1)
                .map_err(|_| BufferError::AllocationFailed)?;
            list.push(entry);
        }
        self.geometries.push(list);
        Ok(self.geometries.len() - 1)
    }

    /// Adds a geometry: one opacity per triangle, in triangle order. Returns
    /// the geometry's number (0, 1, ...).
    pub fn add_geometry<'a>(
        &mut self,
        triangles: impl IntoIterator<Item = TriangleOpacity<'a>>,
    ) -> Result<usize, BufferError> {
        let mut entries = Vec::new();
        for triangle in triangles {
            let entry = match triangle {
                TriangleOpacity::Special(state) => Entry::Special(state),
                TriangleOpacity::Micromap(map) => self.add_micromap(map)?.0,
            };
            entries.push(entry);
        }
        self.geometries.push(entries);
        Ok(self.geometries.len() - 1)
    }

    /// Lays out the buffers. Distinct micromaps are ordered by decreasing
    /// data size (ties in order of first appearance) and packed without
    /// gaps, so every block starts at a multiple of its own size (sizes are
    /// powers of two): naturally aligned, and the data is as small as it can
    /// be. Records follow the same order; usage counts are sorted by format,
    /// then level.
    pub fn finish(mut self) -> Result<MicromapBuffers, BufferError> {
        if self.options.no_mixed_special_indices {
            self.unmix_special_indices()?;
        }
        // Record order: arenas by decreasing byte length, each in order of
        // first appearance (what a stable sort of the maps by decreasing
        // size gives).
        let mut first_record = BTreeMap::new();
        let mut records = Vec::new();
        records
            .try_reserve_exact(self.unique.len())
            .map_err(|_| BufferError::AllocationFailed)?;
        let mut offset: u64 = 0;
        for (&len, arena) in self.arenas.iter().rev() {
            first_record.insert(len, records.len() as u32);
            for slot in 0..arena.len() / len.max(1) {
                let data_offset = u32::try_from(offset + (slot * len) as u64)
                    .map_err(|_| BufferError::DataTooLarge { bytes: offset })?;
                // Placeholder level and format, set below from `unique`.
                records.push(TriangleRecord {
                    data_offset,
                    subdivision_level: 0,
                    format: 0,
                });
            }
            offset += arena.len() as u64;
        }
        if offset > u64::from(u32::MAX) + 1 {
            return Err(BufferError::DataTooLarge { bytes: offset });
        }
        let record_of: Vec<u32> = self
            .unique
            .iter()
            .map(|stored| first_record[&stored.len] + stored.slot as u32)
            .collect();
        for (stored, &record) in self.unique.iter().zip(&record_of) {
            let r = &mut records[record as usize];
            r.subdivision_level = stored.level.get() as u16;
            r.format = stored.format.raw();
        }
        // The data: the largest arena as it is (no copy), the others
        // appended in decreasing length, each freed once appended.
        let mut data = match self.arenas.pop_last() {
            Some((_, largest)) => largest,
            None => Vec::new(),
        };
        let len = usize::try_from(offset).map_err(|_| BufferError::AllocationFailed)?;
        data.try_reserve_exact(len - data.len())
            .map_err(|_| BufferError::AllocationFailed)?;
        while let Some((_, arena)) = self.arenas.pop_last() {
            data.extend_from_slice(&arena);
        }
        let usage = histogram(records.iter().map(|r| (r.subdivision_level, r.format)));
        let geometries = self
            .geometries
            .iter()
            .map(|entries| {
                let indices: Vec<MicromapIndex> = entries
                    .iter()
                    .map(|&entry| match entry {
                        Entry::Unique(id) => MicromapIndex::Record(record_of[id as usize]),
                        Entry::Special(state) => MicromapIndex::Special(state),
                    })
                    .collect();
                let usage = histogram(indices.iter().filter_map(|&index| match index {
                    MicromapIndex::Record(r) => {
                        let record = records[r as usize];
                        Some((record.subdivision_level, record.format))
                    }
                    MicromapIndex::Special(_) => None,
                }));
                Geometry { indices, usage }
            })
            .collect();
        Ok(MicromapBuffers {
            data,
            records,
            usage,
            geometries,
        })
    }
}

impl MicromapBuffersBuilder {
    /// [`BuildOptions::no_mixed_special_indices`]: the special entries of
    /// every geometry that also has records become shared level-0 records.
    fn unmix_special_indices(&mut self) -> Result<(), BufferError> {
        let any_four_state = self.unique.iter().any(|s| s.format == Format::FourState);
        // One record per state, made on first use (index: the state's
        // special index value + 4, 0..=3).
        let mut shared: [Option<u32>; 4] = [None; 4];
        for g in 0..self.geometries.len() {
            let entries = &self.geometries[g];
            let has_record = entries.iter().any(|e| matches!(e, Entry::Unique(_)));
            let has_special = entries.iter().any(|e| matches!(e, Entry::Special(_)));
            if !(has_record && has_special) {
                continue;
            }
            for t in 0..self.geometries[g].len() {
                let Entry::Special(state) = self.geometries[g][t] else {
                    continue;
                };
                let slot = (state.special_index() + 4) as usize;
                let id = if let Some(id) = shared[slot] {
                    id
                } else {
                    let format = if any_four_state || !state.is_known() {
                        Format::FourState
                    } else {
                        Format::TwoState
                    };
                    // Level 0 is valid and the format holds the state,
                    // so only the one-byte allocation can fail.
                    let map = Micromap::uniform_map(Level(0), format, state)
                        .map_err(|_| BufferError::AllocationFailed)?;
                    let hash = content_hash(&map);
                    let id = match self.find(&map, hash) {
                        Some(id) => id,
                        None => self.store(&map, hash)?,
                    };
                    shared[slot] = Some(id);
                    id
                };
                self.geometries[g][t] = Entry::Unique(id);
            }
        }
        Ok(())
    }
}

/// Usage counts of `(level, format)` pairs, sorted by format then level.
fn histogram(pairs: impl Iterator<Item = (u16, u16)>) -> Vec<UsageCount> {
    let mut counts: BTreeMap<(u16, u16), u32> = BTreeMap::new();
    for (level, format) in pairs {
        *counts.entry((format, level)).or_default() += 1;
    }
    counts
        .into_iter()
        .map(|((format, level), count)| UsageCount {
            count,
            subdivision_level: u32::from(level),
            format: u32::from(format),
        })
        .collect()
}

/// One geometry's per-triangle indices and usage counts.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Geometry {
    indices: Vec<MicromapIndex>,
    usage: Vec<UsageCount>,
}

/// The build inputs for one micromap array and the geometries that use it
/// (from [`MicromapBuffersBuilder::finish`]).
///
/// | API input | Vulkan EXT / KHR | DXR 1.2 | glTF draft | here |
/// |---|---|---|---|---|
/// | packed states | `data` | `InputBuffer` | `micromaps[].data` | [`data`](Self::data) |
/// | 8-byte records | `triangleArray` | `PerOmmDescs` | `micromaps[].triangles` | [`records`](Self::records), [`records_le_bytes`](Self::records_le_bytes) |
/// | array usage counts | `pUsageCounts` (build info) | `pOmmHistogram` | `usageCounts/Levels/Formats` | [`usage_counts`](Self::usage_counts) |
/// | per-geometry usage counts | `pUsageCounts` (EXT triangles only) | — | — | [`geometry_usage_counts`](Self::geometry_usage_counts) |
/// | per-triangle indices | `indexBuffer` | `OpacityMicromapIndexBuffer` | `micromapIndices` | [`index_bytes`](Self::index_bytes) |
///
/// # Guarantees
///
/// - Every record's block lies inside [`data`](Self::data), blocks do not
///   overlap, and each starts at a multiple of its own size.
/// - Equal micromaps (same level, format and bytes) share one record;
///   different ones never do (equality is decided on the bytes).
/// - Reading the bytes back with [`read_buffers`](super::read_buffers)
///   gives the same micromaps and indices.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct MicromapBuffers {
    data: Vec<u8>,
    records: Vec<TriangleRecord>,
    usage: Vec<UsageCount>,
    geometries: Vec<Geometry>,
}

impl MicromapBuffers {
    /// Builds the buffers of one geometry (see [`MicromapBuffersBuilder`]).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MicromapBuffers, State, TriangleOpacity};
    /// use micromap_index::Level;
    /// let map = Micromap::from_states(Level::new(1).unwrap(), Format::FourState, State::ALL).unwrap();
    /// let buffers = MicromapBuffers::build([TriangleOpacity::Micromap(&map)], Default::default()).unwrap();
    /// assert_eq!(buffers.data(), map.as_bytes());
    /// ```
    pub fn build<'a>(
        triangles: impl IntoIterator<Item = TriangleOpacity<'a>>,
        options: BuildOptions,
    ) -> Result<MicromapBuffers, BufferError> {
        let mut builder = MicromapBuffersBuilder::new(options);
        builder.add_geometry(triangles)?;
        builder.finish()
    }

    /// The packed data of every record's micromap.
    #[inline]
    #[must_use]
    pub fn data(&self) -> &[u8] {
        &self.data
    }

    /// The triangle records, one per distinct micromap.
    #[inline]
    #[must_use]
    pub fn records(&self) -> &[TriangleRecord] {
        &self.records
    }

    /// The records as little-endian bytes (stride 8).
    #[must_use]
    pub fn records_le_bytes(&self) -> Vec<u8> {
        records_to_le_bytes(&self.records)
    }

    /// A copy of the micromap record `record` describes (read from
    /// [`data`](Self::data)); `None` past the last record. The buffers
    /// keep each map only once, in the data.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MicromapBuffers, State, TriangleOpacity};
    /// use micromap_index::Level;
    /// let map = Micromap::from_states(Level::new(1).unwrap(), Format::FourState, State::ALL).unwrap();
    /// let buffers = MicromapBuffers::build([TriangleOpacity::Micromap(&map)], Default::default()).unwrap();
    /// assert_eq!(buffers.micromap(0), Some(map));
    /// assert_eq!(buffers.micromap(1), None);
    /// ```
    #[must_use]
    pub fn micromap(&self, record: u32) -> Option<Micromap> {
        let (level, format, bytes) = self.record_bytes(record)?;
        Micromap::from_bytes(level, format, bytes).ok()
    }

    /// A record's level, format and packed data, borrowed (`None` as for
    /// [`micromap`](Self::micromap)).
    pub(crate) fn record_bytes(&self, record: u32) -> Option<(Level, Format, &[u8])> {
        let r = *self.records.get(record as usize)?;
        let (level, format) = record_shape(r)?;
        let start = r.data_offset as usize;
        let bytes = self
            .data
            .get(start..start + Micromap::byte_len(level, format))?;
        Some((level, format, bytes))
    }

    /// Copies of the micromaps of every record, in record order, made one
    /// at a time ([`micromap`](Self::micromap)).
    pub fn micromaps(&self) -> impl Iterator<Item = Micromap> + '_ {
        (0..self.records.len() as u32).filter_map(|r| self.micromap(r))
    }

    /// The array's usage counts: how many records have each level and
    /// format (the micromap build's histogram), sorted by format, then
    /// level; no zero counts.
    #[inline]
    #[must_use]
    pub fn usage_counts(&self) -> &[UsageCount] {
        &self.usage
    }

    /// The number of geometries added.
    #[inline]
    #[must_use]
    pub fn geometry_count(&self) -> usize {
        self.geometries.len()
    }

    fn geometry(&self, geometry: usize) -> Result<&Geometry, BufferError> {
        self.geometries
            .get(geometry)
            .ok_or(BufferError::NoSuchGeometry {
                geometry,
                count: self.geometries.len(),
            })
    }

    /// The per-triangle indices of a geometry.
    pub fn geometry_indices(&self, geometry: usize) -> Result<&[MicromapIndex], BufferError> {
        Ok(&self.geometry(geometry)?.indices)
    }

    /// Vulkan EXT's per-geometry usage counts: how many triangles of the
    /// geometry reference a micromap of each level and format "after
    /// indirection and special index handling" (triangles with a special
    /// index are not counted), sorted by format, then level.
    pub fn geometry_usage_counts(&self, geometry: usize) -> Result<&[UsageCount], BufferError> {
        Ok(&self.geometry(geometry)?.usage)
    }

    /// Whether the geometry's index buffer holds both special indices and
    /// records: what a Vulkan KHR pipeline created with
    /// `VK_PIPELINE_CREATE_2_OPACITY_MICROMAP_DISALLOW_MIXED_SPECIAL_INDEX_BIT_KHR`
    /// must not trace (VUID-{cmd}-micromap-11638; all-special geometry is
    /// allowed). Never true under [`BuildOptions::no_mixed_special_indices`].
    ///
    /// ```
    /// use micromap_index::micromap::{
    ///     BuildOptions, Format, Micromap, MicromapBuffers, MicromapIndex, State, TriangleOpacity,
    /// };
    /// use micromap_index::Level;
    /// let map = Micromap::from_states(Level::new(1).unwrap(), Format::FourState, State::ALL).unwrap();
    /// let triangles = [TriangleOpacity::Micromap(&map), TriangleOpacity::Special(State::Opaque)];
    /// let mixed = MicromapBuffers::build(triangles, BuildOptions::default()).unwrap();
    /// assert!(mixed.is_mixed(0).unwrap());
    /// let options = BuildOptions { no_mixed_special_indices: true, ..BuildOptions::default() };
    /// let unmixed = MicromapBuffers::build(triangles, options).unwrap();
    /// assert!(!unmixed.is_mixed(0).unwrap());
    /// // The special index became a shared level-0 record of its state.
    /// assert_eq!(unmixed.geometry_indices(0).unwrap()[1], MicromapIndex::Record(1));
    /// assert_eq!(unmixed.micromap(1).unwrap().uniform(), Some(State::Opaque));
    /// ```
    pub fn is_mixed(&self, geometry: usize) -> Result<bool, BufferError> {
        let indices = &self.geometry(geometry)?.indices;
        let special = indices
            .iter()
            .any(|i| matches!(i, MicromapIndex::Special(_)));
        let record = indices
            .iter()
            .any(|i| matches!(i, MicromapIndex::Record(_)));
        Ok(special && record)
    }

    /// The largest record number any geometry's index buffer holds, or
    /// `None` if every index is special.
    #[must_use]
    pub fn max_record_index(&self) -> Option<u32> {
        self.geometries
            .iter()
            .flat_map(|g| &g.indices)
            .filter_map(|&index| match index {
                MicromapIndex::Record(r) => Some(r),
                MicromapIndex::Special(_) => None,
            })
            .max()
    }

    /// A geometry's index buffer at `width`, little-endian, special indices
    /// as two's-complement patterns. A record number above
    /// [`IndexWidth::max_regular`] is [`BufferError::IndexDoesNotFit`]
    /// (choose a width with [`IndexWidth::narrowest`] and
    /// [`max_record_index`](Self::max_record_index)).
    ///
    /// ```
    /// use micromap_index::micromap::{IndexWidth, MicromapBuffers, State, TriangleOpacity};
    /// let buffers = MicromapBuffers::build(
    ///     [TriangleOpacity::Special(State::Transparent), TriangleOpacity::Special(State::UnknownOpaque)],
    ///     Default::default(),
    /// ).unwrap();
    /// assert_eq!(buffers.index_bytes(0, IndexWidth::U16).unwrap(), [0xff, 0xff, 0xfc, 0xff]);
    /// ```
    pub fn index_bytes(&self, geometry: usize, width: IndexWidth) -> Result<Vec<u8>, BufferError> {
        let indices = &self.geometry(geometry)?.indices;
        let mut bytes = Vec::new();
        bytes
            .try_reserve_exact(indices.len() * width.bytes())
            .map_err(|_| BufferError::AllocationFailed)?;
        for index in indices {
            let raw = index.encode(width)?;
            bytes.extend_from_slice(&raw.to_le_bytes()[..width.bytes()]);
        }
        Ok(bytes)
    }

    /// Checks the buffers against `api`'s fixed rules: every level within
    /// [`Api::max_level`] and `width` one the API accepts, wide enough for
    /// every record number. (Device limits, such as Vulkan's maximum
    /// levels, are the caller's to check.)
    ///
    /// ```
    /// use micromap_index::micromap::{Api, BufferError, IndexWidth, MicromapBuffers, State, TriangleOpacity};
    /// let buffers = MicromapBuffers::build([TriangleOpacity::Special(State::Opaque)], Default::default()).unwrap();
    /// assert_eq!(buffers.check_for(Api::Dxr, IndexWidth::U8), Ok(()));
    /// assert_eq!(
    ///     buffers.check_for(Api::VulkanExt, IndexWidth::U8),
    ///     Err(BufferError::IndexWidthNotAllowed { width: IndexWidth::U8, api: Api::VulkanExt })
    /// );
    /// ```
    pub fn check_for(&self, api: Api, width: IndexWidth) -> Result<(), BufferError> {
        if !api.allows_index_width(width) {
            return Err(BufferError::IndexWidthNotAllowed { width, api });
        }
        if let Some(max) = api.max_level() {
            if let Some(r) = self
                .records
                .iter()
                .find(|r| u32::from(r.subdivision_level) > max)
            {
                return Err(BufferError::LevelNotAllowed {
                    level: u32::from(r.subdivision_level),
                    max,
                    api,
                });
            }
        }
        if let Some(max_index) = self.max_record_index() {
            MicromapIndex::Record(max_index).encode(width)?;
        }
        Ok(())
    }

    /// What a geometry's triangle resolves to: a copy of its micromap, or
    /// its special state; `None` past the end.
    #[must_use]
    pub fn resolve(&self, geometry: usize, triangle: usize) -> Option<BakedOpacity> {
        let index = *self.geometries.get(geometry)?.indices.get(triangle)?;
        Some(match index {
            MicromapIndex::Record(r) => BakedOpacity::Map(self.micromap(r)?),
            MicromapIndex::Special(state) => BakedOpacity::Special(state),
        })
    }
}

/// The record's level and format if both are valid for a [`Micromap`].
pub(crate) fn record_shape(record: TriangleRecord) -> Option<(Level, Format)> {
    let format = Format::from_raw(record.format)?;
    let level = Level::new(u32::from(record.subdivision_level)).ok()?;
    (level.get() <= Micromap::MAX_LEVEL).then_some((level, format))
}

#[cfg(feature = "ash")]
mod ash_conversions {
    //! `From` conversions to and from the `ash` 0.38 Vulkan types (feature
    //! `ash`). The EXT names exist in both ash 0.38 and later releases.

    use super::{TriangleRecord, UsageCount};
    use ash::vk;

    impl From<TriangleRecord> for vk::MicromapTriangleEXT {
        fn from(r: TriangleRecord) -> Self {
            vk::MicromapTriangleEXT {
                data_offset: r.data_offset,
                subdivision_level: r.subdivision_level,
                format: r.format,
            }
        }
    }

    impl From<vk::MicromapTriangleEXT> for TriangleRecord {
        fn from(t: vk::MicromapTriangleEXT) -> Self {
            TriangleRecord {
                data_offset: t.data_offset,
                subdivision_level: t.subdivision_level,
                format: t.format,
            }
        }
    }

    impl From<UsageCount> for vk::MicromapUsageEXT {
        fn from(u: UsageCount) -> Self {
            vk::MicromapUsageEXT {
                count: u.count,
                subdivision_level: u.subdivision_level,
                format: u.format,
            }
        }
    }

    impl From<vk::MicromapUsageEXT> for UsageCount {
        fn from(u: vk::MicromapUsageEXT) -> Self {
            UsageCount {
                count: u.count,
                subdivision_level: u.subdivision_level,
                format: u.format,
            }
        }
    }

    // The layouts agree, so a slice of either could be uploaded as the other.
    const _: () = {
        assert!(core::mem::size_of::<vk::MicromapTriangleEXT>() == TriangleRecord::SIZE);
        assert!(core::mem::size_of::<vk::MicromapUsageEXT>() == UsageCount::SIZE);
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Maps whose content hashes collide are all kept, each found by its
    /// own bytes along the chain of its hash, and a third is new.
    #[test]
    fn colliding_hashes_keep_every_map() {
        let level = Level::new(2).unwrap();
        let map = |states: [State; 2]| {
            Micromap::from_states(level, Format::FourState, (0..16).map(|i| states[i % 2])).unwrap()
        };
        let a = map([State::Opaque, State::Transparent]);
        let b = map([State::Transparent, State::Opaque]);
        let c = map([State::UnknownOpaque, State::Opaque]);
        let mut builder = MicromapBuffersBuilder::default();
        assert_eq!(builder.store(&a, 7), Ok(0));
        assert_eq!(builder.store(&b, 7), Ok(1));
        assert_eq!(builder.find(&a, 7), Some(0));
        assert_eq!(builder.find(&b, 7), Some(1));
        assert_eq!(builder.find(&c, 7), None);
        assert_eq!(builder.find(&a, 8), None);
    }
}
