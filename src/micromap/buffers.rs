//! API build inputs made from many micromaps: packed data, triangle records,
//! usage counts and per-triangle index buffers (Vulkan
//! `VK_EXT_opacity_micromap` / `VK_KHR_opacity_micromap`, DXR 1.2, glTF
//! `EXT_mesh_opacity_micromap`). `docs/micromaps.md` cites the spec rule
//! behind each choice.

use super::index::{Api, BufferError, IndexWidth, MicromapIndex};
use super::map::Micromap;
use super::opacity::BakedOpacity;
use super::records::{record_shape, records_to_le_bytes, TriangleRecord, UsageCount};
use super::state::Format;
use crate::Level;
use alloc::vec::Vec;

/// One geometry's per-triangle indices and usage counts.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) struct Geometry {
    pub(super) indices: Vec<MicromapIndex>,
    pub(super) usage: Vec<UsageCount>,
}

/// The build inputs for one micromap array and the geometries that use it
/// (from [`MicromapBuffersBuilder::finish`](super::MicromapBuffersBuilder::finish)).
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
    pub(super) data: Vec<u8>,
    pub(super) records: Vec<TriangleRecord>,
    pub(super) usage: Vec<UsageCount>,
    pub(super) geometries: Vec<Geometry>,
}

impl MicromapBuffers {
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
    /// allowed). Never true under [`BuildOptions::no_mixed_special_indices`](super::BuildOptions::no_mixed_special_indices).
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
