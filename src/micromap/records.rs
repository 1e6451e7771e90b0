//! The 8-byte triangle records and 12-byte usage counts of the APIs, and
//! their little-endian bytes.

use super::map::Micromap;
use super::state::Format;
use crate::Level;
use alloc::vec::Vec;
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
