//! [`MicromapBuffersBuilder`]: micromaps in, deduplicated, with one index
//! buffer per geometry; [`BuildOptions`] say how special indices are
//! used.

use super::buffers::{Geometry, MicromapBuffers};
use super::index::{BufferError, IndexWidth, MicromapIndex};
use super::map::Micromap;
use super::opacity::TriangleOpacity;
use super::records::{TriangleRecord, UsageCount};
use super::state::{Format, State};
use crate::Level;
use alloc::collections::BTreeMap;
use alloc::vec::Vec;

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
