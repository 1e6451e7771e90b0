//! Per-triangle indices: a record or a special index ([`MicromapIndex`]),
//! their widths ([`IndexWidth`]) and each API's rules ([`Api`]).

use super::state::State;
use core::fmt;

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
    /// lossy builds, [`MicromapBuffers::check_for_khr_lossy`](crate::micromap::MicromapBuffers::check_for_khr_lossy)).
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
    /// A [`TriangleEntry`](crate::micromap::TriangleEntry) names a micromap this builder does not hold
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
