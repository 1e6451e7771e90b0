//! [`Micromap`]: one triangle's micro-triangle states, packed as the APIs
//! read them.

use super::map_error::MicromapError;
use super::map_rules::{MergeRule, UnknownPolicy};
use super::state::{Format, State};
use crate::{spec, Level, SpecLevel};
use alloc::vec::Vec;
use core::fmt;

/// One triangle's opacity micromap: a subdivision level, a format and the
/// `4^level` micro-triangle states in curve order, packed exactly as Vulkan,
/// DXR and glTF read them.
///
/// # Layout
///
/// Least-significant bit first: in a 2-state map micro-triangle `i` is bit
/// `i & 7` of byte `i >> 3`; in a 4-state map it is bits `2 * (i & 3)` and
/// `2 * (i & 3) + 1` of byte `i >> 2`. The data is
/// [`byte_len`](Micromap::byte_len) `= max(1, 4^level * bits / 8)` bytes;
/// bits past the last micro-triangle (level-0 and level-1 2-state maps,
/// level-0 4-state maps) are zero.
///
/// # Guarantees
///
/// - The packed bytes are always valid for the level and format: every
///   state fits the format and unused bits are zero, so [`Micromap::as_bytes`]
///   can go into an API buffer as is, and two micromaps are equal exactly
///   when their level, format and bytes are equal.
/// - Levels `0..=`[`MAX_LEVEL`](Micromap::MAX_LEVEL) (16, the highest level
///   the Vulkan reference indexes correctly; DXR stops at 12, Vulkan devices
///   report their own limit of at least 3). A level-16 4-state map is 1 GiB;
///   constructors ask the allocator with `try_reserve` and return
///   [`MicromapError::AllocationFailed`] instead of aborting.
/// - No function panics; bad input is a [`MicromapError`].
///
/// ```
/// use micromap_index::micromap::{Format, Micromap, State};
/// use micromap_index::Level;
///
/// let level = Level::new(1).unwrap();
/// let mut map = Micromap::new(level, Format::FourState).unwrap();
/// map.set(2, State::Opaque).unwrap();
/// map.set(3, State::UnknownOpaque).unwrap();
/// // States 0, 0, 1, 3 at bit pairs 0, 2, 4, 6 of one byte.
/// assert_eq!(map.as_bytes(), &[0b11_01_00_00]);
/// assert_eq!(map.get(3), Some(State::UnknownOpaque));
/// assert_eq!(map.get(4), None);
/// // The hit (u, v) = (0.7, 0.1) is in micro-triangle 2 (the Right corner).
/// assert_eq!(map.state_at(0.7, 0.1), State::Opaque);
/// ```
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Micromap {
    level: Level,
    format: Format,
    data: Vec<u8>,
}

// `state_at` relies on the reference accepting every micromap level.
const _: () = assert!(Micromap::MAX_LEVEL <= spec::MAX_LEVEL);

impl Micromap {
    /// The highest level a [`Micromap`] can have: 16, the highest level at
    /// which the Vulkan reference index (and so [`state_at`](Self::state_at))
    /// is valid. A level-16 4-state map's 1 GiB still fits the APIs' 32-bit
    /// data offsets.
    pub const MAX_LEVEL: u32 = 16;

    /// The level if it is at most [`MAX_LEVEL`](Self::MAX_LEVEL).
    fn check_level(level: Level) -> Result<Level, MicromapError> {
        if level.get() > Self::MAX_LEVEL {
            Err(MicromapError::LevelTooHigh {
                level: level.get(),
                max: Self::MAX_LEVEL,
            })
        } else {
            Ok(level)
        }
    }

    /// The number of bytes a micromap of this level and format takes:
    /// `max(1, ceil(4^level * bits / 8))` (at most 2^31 for levels up to 16;
    /// the value saturates at `usize::MAX` for levels the type cannot hold).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap};
    /// use micromap_index::Level;
    /// let l = |n| Level::new(n).unwrap();
    /// assert_eq!(Micromap::byte_len(l(0), Format::TwoState), 1);
    /// assert_eq!(Micromap::byte_len(l(1), Format::TwoState), 1);
    /// assert_eq!(Micromap::byte_len(l(2), Format::TwoState), 2);
    /// assert_eq!(Micromap::byte_len(l(2), Format::FourState), 4);
    /// assert_eq!(Micromap::byte_len(l(12), Format::FourState), 1 << 22);
    /// ```
    #[inline]
    #[must_use]
    pub const fn byte_len(level: Level, format: Format) -> usize {
        // 4^level * bits / 8 = 2^(2 level + log2 bits - 3).
        let log2_bits = 2 * level.get() + format.bits_per_state() - 1;
        if log2_bits <= 3 {
            1
        } else if log2_bits - 3 >= usize::BITS {
            usize::MAX
        } else {
            1 << (log2_bits - 3)
        }
    }

    /// Zeroed data of `len` bytes, or [`MicromapError::AllocationFailed`].
    fn zeroed(len: usize) -> Result<Vec<u8>, MicromapError> {
        let mut data = Vec::new();
        data.try_reserve_exact(len)
            .map_err(|_| MicromapError::AllocationFailed { bytes: len })?;
        data.resize(len, 0);
        Ok(data)
    }

    /// A micromap with every micro-triangle transparent (all bytes zero).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MicromapError, State};
    /// use micromap_index::Level;
    /// let map = Micromap::new(Level::new(3).unwrap(), Format::TwoState).unwrap();
    /// assert_eq!(map.len(), 64);
    /// assert_eq!(map.uniform(), Some(State::Transparent));
    /// assert_eq!(
    ///     Micromap::new(Level::new(17).unwrap(), Format::TwoState),
    ///     Err(MicromapError::LevelTooHigh { level: 17, max: 16 })
    /// );
    /// ```
    pub fn new(level: Level, format: Format) -> Result<Micromap, MicromapError> {
        let level = Self::check_level(level)?;
        let data = Self::zeroed(Self::byte_len(level, format))?;
        Ok(Micromap {
            level,
            format,
            data,
        })
    }

    /// A micromap of `level` and `format` with every micro-triangle `state`.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let map = Micromap::uniform_map(Level::new(2).unwrap(), Format::FourState, State::UnknownOpaque).unwrap();
    /// assert_eq!(map.as_bytes(), &[0xff; 4]);
    /// ```
    pub fn uniform_map(
        level: Level,
        format: Format,
        state: State,
    ) -> Result<Micromap, MicromapError> {
        if !format.holds(state) {
            return Err(MicromapError::StateNotInFormat { state, format });
        }
        let mut map = Self::new(level, format)?;
        let byte = repeat_state(format, state);
        map.data.fill(byte);
        map.clear_unused_bits();
        Ok(map)
    }

    /// A micromap from its `4^level` states in curve order: exactly that
    /// many, each one the format holds.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MicromapError, State};
    /// use micromap_index::Level;
    /// let level = Level::new(1).unwrap();
    /// let states = [State::Opaque, State::Transparent, State::Opaque, State::Opaque];
    /// let map = Micromap::from_states(level, Format::TwoState, states).unwrap();
    /// assert_eq!(map.as_bytes(), &[0b1101]);
    /// assert!(map.states().eq(states));
    /// assert_eq!(
    ///     Micromap::from_states(level, Format::TwoState, states[..3].iter().copied()),
    ///     Err(MicromapError::TooFewStates { expected: 4, got: 3 })
    /// );
    /// ```
    pub fn from_states(
        level: Level,
        format: Format,
        states: impl IntoIterator<Item = State>,
    ) -> Result<Micromap, MicromapError> {
        let mut map = Self::new(level, format)?;
        let expected = map.len();
        let mut states = states.into_iter();
        for index in 0..expected {
            let Some(state) = states.next() else {
                return Err(MicromapError::TooFewStates {
                    expected,
                    got: index,
                });
            };
            map.set(index, state)?;
        }
        if states.next().is_some() {
            return Err(MicromapError::TooManyStates { expected });
        }
        Ok(map)
    }

    /// A micromap whose state at each index is `state(index)`, called once
    /// per index in increasing order.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let map = Micromap::from_index_fn(Level::new(2).unwrap(), Format::TwoState, |i| {
    ///     if i % 2 == 0 { State::Opaque } else { State::Transparent }
    /// }).unwrap();
    /// assert_eq!(map.as_bytes(), &[0x55, 0x55]);
    /// ```
    pub fn from_index_fn(
        level: Level,
        format: Format,
        mut state: impl FnMut(u64) -> State,
    ) -> Result<Micromap, MicromapError> {
        let mut map = Self::new(level, format)?;
        for index in 0..map.len() {
            map.set(index, state(index))?;
        }
        Ok(map)
    }

    /// A micromap whose state at each micro-triangle is
    /// `state(index, vertices)`, where `vertices` are the micro-triangle's
    /// exact corners as `(u, v)` numerators over `2^level`
    /// ([`MicroTriangle::vertices_scaled`], in the walk's local order),
    /// called once per index in increasing order.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// // Opaque where the whole micro-triangle is in u <= 1/2.
    /// let level = Level::new(3).unwrap();
    /// let half = 1u64 << (level.get() - 1);
    /// let map = Micromap::from_micro_triangles(level, Format::TwoState, |_, vertices| {
    ///     if vertices.iter().all(|&(u, _)| u <= half) { State::Opaque } else { State::Transparent }
    /// }).unwrap();
    /// assert_eq!(map.state_at(0.1, 0.2), State::Opaque);
    /// assert_eq!(map.state_at(0.9, 0.05), State::Transparent);
    /// ```
    ///
    /// [`MicroTriangle::vertices_scaled`]: crate::inverse::MicroTriangle::vertices_scaled
    pub fn from_micro_triangles(
        level: Level,
        format: Format,
        mut state: impl FnMut(u64, [(u64, u64); 3]) -> State,
    ) -> Result<Micromap, MicromapError> {
        let mut map = Self::new(level, format)?;
        let len = map.len();
        for index in 0..len {
            let triangle = crate::inverse::micro_triangle(level, index)
                .map_err(|_| MicromapError::IndexOutOfRange { index, len })?;
            map.set(index, state(index, triangle.vertices_scaled()))?;
        }
        Ok(map)
    }

    /// A micromap from packed bytes as the APIs read them: exactly
    /// [`byte_len`](Self::byte_len) bytes, with the unused bits of a one-byte
    /// map zero ([`MicromapError::UnusedBitsSet`] otherwise; see
    /// [`from_bytes_ignoring_unused_bits`](Self::from_bytes_ignoring_unused_bits)).
    /// A 2-state map can hold any bytes; every 4-state value is a state.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MicromapError, State};
    /// use micromap_index::Level;
    /// let level = Level::new(1).unwrap();
    /// let map = Micromap::from_bytes(level, Format::TwoState, &[0b0100]).unwrap();
    /// assert_eq!(map.get(2), Some(State::Opaque));
    /// assert_eq!(
    ///     Micromap::from_bytes(level, Format::TwoState, &[0b1_0100]),
    ///     Err(MicromapError::UnusedBitsSet { byte: 0b1_0100 })
    /// );
    /// ```
    pub fn from_bytes(
        level: Level,
        format: Format,
        bytes: &[u8],
    ) -> Result<Micromap, MicromapError> {
        let map = Self::from_bytes_ignoring_unused_bits(level, format, bytes)?;
        match bytes {
            [byte] if *byte != map.data[0] => Err(MicromapError::UnusedBitsSet { byte: *byte }),
            _ => Ok(map),
        }
    }

    /// Like [`from_bytes`](Self::from_bytes), but bits past the last
    /// micro-triangle are cleared instead of refused: readers ignore them
    /// (the glTF draft: they "MUST be ignored").
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let map = Micromap::from_bytes_ignoring_unused_bits(Level::new(0).unwrap(), Format::FourState, &[0xfe]).unwrap();
    /// assert_eq!(map.as_bytes(), &[0x02]);
    /// assert_eq!(map.uniform(), Some(State::UnknownTransparent));
    /// ```
    pub fn from_bytes_ignoring_unused_bits(
        level: Level,
        format: Format,
        bytes: &[u8],
    ) -> Result<Micromap, MicromapError> {
        let level = Self::check_level(level)?;
        let expected = Self::byte_len(level, format);
        if bytes.len() != expected {
            return Err(MicromapError::WrongByteLength {
                expected,
                got: bytes.len(),
            });
        }
        let mut data = Vec::new();
        data.try_reserve_exact(expected)
            .map_err(|_| MicromapError::AllocationFailed { bytes: expected })?;
        data.extend_from_slice(bytes);
        let mut map = Micromap {
            level,
            format,
            data,
        };
        map.clear_unused_bits();
        Ok(map)
    }

    /// Zeroes the bits past the last micro-triangle (one-byte maps only).
    fn clear_unused_bits(&mut self) {
        let used_bits = self.len() * u64::from(self.format.bits_per_state());
        if used_bits < 8 {
            if let Some(byte) = self.data.first_mut() {
                *byte &= (1u8 << used_bits) - 1;
            }
        }
    }

    /// The subdivision level.
    #[inline]
    #[must_use]
    pub fn level(&self) -> Level {
        self.level
    }

    /// The format.
    #[inline]
    #[must_use]
    pub fn format(&self) -> Format {
        self.format
    }

    /// The number of micro-triangles, `4^level`.
    #[inline]
    #[must_use]
    #[allow(clippy::len_without_is_empty)] // never empty: 4^level >= 1
    pub fn len(&self) -> u64 {
        1 << (2 * self.level.get())
    }

    /// The packed data, [`byte_len`](Self::byte_len) bytes, as the APIs
    /// read it (see [Layout](Self#layout)).
    #[inline]
    #[must_use]
    pub fn as_bytes(&self) -> &[u8] {
        &self.data
    }

    /// The byte and shift of micro-triangle `index` (which must be below
    /// [`len`](Self::len)).
    #[inline]
    fn position(&self, index: u64) -> (usize, u32) {
        let bits = self.format.bits_per_state();
        let per_byte_log2 = 4 - bits; // 8 states per byte (3) or 4 (2)
                                      // index < 4^16, so the byte index fits usize on 32-bit targets.
        let byte = (index >> per_byte_log2) as usize;
        let shift = (index as u32 & ((1 << per_byte_log2) - 1)) * bits;
        (byte, shift)
    }

    /// The state of micro-triangle `index`, or `None` if `index >= 4^level`.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let map = Micromap::from_bytes(Level::new(2).unwrap(), Format::TwoState, &[0, 0b10]).unwrap();
    /// assert_eq!(map.get(9), Some(State::Opaque));
    /// assert_eq!(map.get(8), Some(State::Transparent));
    /// assert_eq!(map.get(16), None);
    /// ```
    #[inline]
    #[must_use]
    pub fn get(&self, index: u64) -> Option<State> {
        if index >= self.len() {
            return None;
        }
        let (byte, shift) = self.position(index);
        let mask = (1u8 << self.format.bits_per_state()) - 1;
        State::from_bits((self.data.get(byte)? >> shift) & mask)
    }

    /// Sets micro-triangle `index` to `state`: an index `>= 4^level` is
    /// [`MicromapError::IndexOutOfRange`], an unknown state in a 2-state
    /// map [`MicromapError::StateNotInFormat`] (convert it first, e.g. with
    /// [`UnknownPolicy::resolve`]); the map is unchanged on error.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MicromapError, State};
    /// use micromap_index::Level;
    /// let mut map = Micromap::new(Level::new(0).unwrap(), Format::TwoState).unwrap();
    /// map.set(0, State::Opaque).unwrap();
    /// assert_eq!(map.as_bytes(), &[1]);
    /// assert_eq!(
    ///     map.set(0, State::UnknownOpaque),
    ///     Err(MicromapError::StateNotInFormat { state: State::UnknownOpaque, format: Format::TwoState })
    /// );
    /// assert_eq!(map.set(1, State::Opaque), Err(MicromapError::IndexOutOfRange { index: 1, len: 1 }));
    /// ```
    #[inline]
    pub fn set(&mut self, index: u64, state: State) -> Result<(), MicromapError> {
        let len = self.len();
        if index >= len {
            return Err(MicromapError::IndexOutOfRange { index, len });
        }
        if !self.format.holds(state) {
            return Err(MicromapError::StateNotInFormat {
                state,
                format: self.format,
            });
        }
        let (byte, shift) = self.position(index);
        let mask = (1u8 << self.format.bits_per_state()) - 1;
        if let Some(slot) = self.data.get_mut(byte) {
            *slot = (*slot & !(mask << shift)) | (state.bits() << shift);
        }
        Ok(())
    }

    /// Copies `part`, a map of the same format and a lower level, over the
    /// states from `first` (its states are `first..first + part.len()`):
    /// how a map baked in parts is put together. `first` and `part` must
    /// start and end on byte boundaries (a part of level 2 or more, at a
    /// multiple of its length, does).
    pub(crate) fn copy_aligned(
        &mut self,
        first: u64,
        part: &Micromap,
    ) -> Result<(), MicromapError> {
        let len = self.len();
        let bits = u64::from(self.format.bits_per_state());
        let end = first.checked_add(part.len()).filter(|&e| e <= len);
        let aligned = (first * bits) % 8 == 0 && (part.len() * bits) % 8 == 0;
        let (Some(_), true, true) = (end, aligned, part.format == self.format) else {
            return Err(MicromapError::IndexOutOfRange {
                index: first.saturating_add(part.len()),
                len,
            });
        };
        let start = (first * bits / 8) as usize;
        if let Some(bytes) = self.data.get_mut(start..start + part.data.len()) {
            bytes.copy_from_slice(&part.data);
        }
        Ok(())
    }

    /// Sets micro-triangles `start..start + count` to `state`: the
    /// descendants of one micro-triangle of a coarser level are such a range
    /// (children of `i` are `4i..4i + 3`). Whole bytes are written at once.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let mut map = Micromap::new(Level::new(3).unwrap(), Format::FourState).unwrap();
    /// // Micro-triangle 1 of level 1 is 16..32 at level 3.
    /// map.fill(16, 16, State::Opaque).unwrap();
    /// assert!((0..64).all(|i| map.get(i) == Some(if (16..32).contains(&i) { State::Opaque } else { State::Transparent })));
    /// assert!(map.fill(60, 5, State::Opaque).is_err());
    /// ```
    pub fn fill(&mut self, start: u64, count: u64, state: State) -> Result<(), MicromapError> {
        let len = self.len();
        let end = start.checked_add(count).filter(|&e| e <= len);
        let Some(end) = end else {
            return Err(MicromapError::IndexOutOfRange {
                index: start.saturating_add(count),
                len,
            });
        };
        if !self.format.holds(state) {
            return Err(MicromapError::StateNotInFormat {
                state,
                format: self.format,
            });
        }
        let pattern = match self.format {
            Format::TwoState => 0u8.wrapping_sub(state.bits() & 1),
            Format::FourState => state.bits() * 0b0101_0101,
        };
        if count == 0 {
            return Ok(());
        }
        // The range is the bits [first_bit, end_bit) of the data (states
        // low bits first): a partial first and last byte, whole bytes
        // between, each written once (a bake fills many short ranges).
        let bits = u64::from(self.format.bits_per_state());
        let (first_bit, end_bit) = (start * bits, end * bits);
        let (first, last) = (first_bit >> 3, (end_bit - 1) >> 3);
        // The bits of byte `k` (first <= k <= last) in the range.
        let mask = |k: u64| {
            let low = first_bit.saturating_sub(8 * k);
            let high = (end_bit - 8 * k).min(8);
            ((0xffu16 << low) & (0xffu16 >> (8 - high))) as u8
        };
        let blend = |byte: &mut u8, mask: u8| *byte = (*byte & !mask) | (pattern & mask);
        // end <= 4^16 states: the byte indices fit usize on 32-bit targets.
        match self.data.get_mut(first as usize..=last as usize) {
            Some([only]) => blend(only, mask(first)),
            Some([head, middle @ .., tail]) => {
                blend(head, mask(first));
                middle.fill(pattern);
                blend(tail, mask(last));
            }
            _ => {}
        }
        Ok(())
    }

    /// The states in curve order, `4^level` of them.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let map = Micromap::from_bytes(Level::new(1).unwrap(), Format::FourState, &[0b10_01_11_00]).unwrap();
    /// let states: Vec<State> = map.states().collect();
    /// assert_eq!(states, [State::Transparent, State::UnknownOpaque, State::Opaque, State::UnknownTransparent]);
    /// ```
    pub fn states(&self) -> impl Iterator<Item = State> + '_ {
        let bits = self.format.bits_per_state();
        let mask = (1u8 << bits) - 1;
        let per_byte = 8 / bits as usize;
        let len = self.len();
        self.data
            .iter()
            .flat_map(move |&byte| (0..per_byte).map(move |k| (byte >> (k as u32 * bits)) & mask))
            // Only a one-byte map has slots past the last state; 4^16 would
            // not fit a 32-bit usize, but then no slot is cut.
            .take(usize::try_from(len).unwrap_or(usize::MAX))
            // Every 1- or 2-bit value is a state.
            .filter_map(State::from_bits)
    }

    /// The state a GPU reads for a hit at barycentrics `(u, v)`: the
    /// micro-triangle the Vulkan reference `BarycentricsToSpaceFillingCurveIndex`
    /// picks in binary32 ([`spec::index_f32`]), for every pair of
    /// `f32` (NaN and points outside the triangle are clamped as the
    /// reference clamps them).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let map = Micromap::from_index_fn(Level::new(1).unwrap(), Format::FourState, |i| State::ALL[i as usize]).unwrap();
    /// assert_eq!(map.state_at(0.1, 0.1), State::Transparent); // Left corner, index 0
    /// assert_eq!(map.state_at(0.3, 0.3), State::Opaque); // the middle, index 1
    /// assert_eq!(map.state_at(0.1, 0.8), State::UnknownOpaque); // Top corner, index 3
    /// assert_eq!(map.state_at(f32::NAN, 2.0), State::UnknownOpaque); // clamped to (0, 1)
    /// ```
    #[must_use]
    pub fn state_at(&self, u: f32, v: f32) -> State {
        match SpecLevel::try_from(self.level) {
            // The index is below 4^level, so `get` answers.
            Ok(level) => self
                .get(u64::from(spec::index_f32(u, v, level)))
                .unwrap_or(State::Transparent),
            // Unreachable: the const assertion above keeps micromap levels
            // within the reference's levels.
            Err(_) => State::Transparent,
        }
    }

    /// The state of every micro-triangle if they are all equal.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let mut map = Micromap::uniform_map(Level::new(4).unwrap(), Format::TwoState, State::Opaque).unwrap();
    /// assert_eq!(map.uniform(), Some(State::Opaque));
    /// map.set(200, State::Transparent).unwrap();
    /// assert_eq!(map.uniform(), None);
    /// ```
    #[must_use]
    pub fn uniform(&self) -> Option<State> {
        let first = self.get(0)?;
        let full = repeat_state(self.format, first);
        match self.data.as_slice() {
            // One byte with unused (zero) bits: compare state by state.
            [_] => self.states().all(|state| state == first).then_some(first),
            bytes => bytes.iter().all(|&b| b == full).then_some(first),
        }
    }

    /// The special index that replaces this micromap if it is uniform
    /// (`-1` transparent ... `-4` unknown-opaque, see
    /// [`State::special_index`]): a triangle with it reads the same state at
    /// every hit as with the micromap.
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let map = Micromap::uniform_map(Level::new(3).unwrap(), Format::FourState, State::UnknownTransparent).unwrap();
    /// assert_eq!(map.special_index(), Some(-3));
    /// ```
    #[must_use]
    pub fn special_index(&self) -> Option<i32> {
        self.uniform().map(State::special_index)
    }

    /// This micromap in `format`: 2 → 4 states keeps every state; 4 → 2
    /// states resolves each unknown state with `policy` (known states stay).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, State, UnknownPolicy};
    /// use micromap_index::Level;
    /// let level = Level::new(1).unwrap();
    /// let four = Micromap::from_states(level, Format::FourState, State::ALL).unwrap();
    /// let two = four.to_format(Format::TwoState, UnknownPolicy::Fallback).unwrap();
    /// assert!(two.states().eq([State::Transparent, State::Opaque, State::Transparent, State::Opaque]));
    /// let back = two.to_format(Format::FourState, UnknownPolicy::Fallback).unwrap();
    /// assert_eq!(back.as_bytes(), &[0b01_00_01_00]);
    /// ```
    pub fn to_format(
        &self,
        format: Format,
        policy: UnknownPolicy,
    ) -> Result<Micromap, MicromapError> {
        if format == self.format {
            return Ok(self.clone());
        }
        Self::from_states(
            self.level,
            format,
            self.states().map(|state| policy.resolve(state)),
        )
    }

    /// The micromap one level coarser: parent `i` merges children
    /// `4i..4i+3` (the curve is hierarchical: they tile it) with `rule`.
    /// Four equal children keep their state. In a 2-state map the rule's
    /// unknown state falls back to a known one ([`State::to_two_state`]), so
    /// under either rule a parent with any opaque child is opaque. Level 0
    /// has no coarser level ([`MicromapError::NoCoarserLevel`]).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MergeRule, State};
    /// use micromap_index::Level;
    /// let level = Level::new(1).unwrap();
    /// let map = Micromap::from_states(level, Format::FourState,
    ///     [State::Transparent, State::Transparent, State::Opaque, State::Transparent]).unwrap();
    /// let parent = map.merge_one_level(MergeRule::Conservative).unwrap();
    /// assert_eq!(parent.level().get(), 0);
    /// assert_eq!(parent.get(0), Some(State::UnknownOpaque));
    /// let two = map.to_format(Format::TwoState, Default::default()).unwrap();
    /// assert_eq!(two.merge_one_level(MergeRule::Conservative).unwrap().get(0), Some(State::Opaque));
    /// ```
    pub fn merge_one_level(&self, rule: MergeRule) -> Result<Micromap, MicromapError> {
        let Some(coarser) = self.level.get().checked_sub(1) else {
            return Err(MicromapError::NoCoarserLevel);
        };
        let level = Level::new(coarser).map_err(|_| MicromapError::NoCoarserLevel)?;
        let mut children = self.states();
        let parents = core::iter::from_fn(|| {
            let quad = [
                children.next()?,
                children.next()?,
                children.next()?,
                children.next()?,
            ];
            let merged = rule.merge(quad);
            Some(if self.format.holds(merged) {
                merged
            } else {
                merged.to_two_state()
            })
        });
        Self::from_states(level, self.format, parents)
    }

    /// The micromap one level finer: children `4i..4i+3` each get parent
    /// `i`'s state, so every hit reads the same state as before. Level 16
    /// has no finer micromap ([`MicromapError::LevelTooHigh`]).
    ///
    /// ```
    /// use micromap_index::micromap::{Format, Micromap, MergeRule, State};
    /// use micromap_index::Level;
    /// let map = Micromap::from_states(Level::new(1).unwrap(), Format::TwoState,
    ///     [State::Opaque, State::Transparent, State::Transparent, State::Opaque]).unwrap();
    /// let fine = map.upsample_one_level().unwrap();
    /// assert_eq!(fine.as_bytes(), &[0x0f, 0xf0]);
    /// assert_eq!(fine.merge_one_level(MergeRule::Conservative).unwrap(), map);
    /// ```
    pub fn upsample_one_level(&self) -> Result<Micromap, MicromapError> {
        let finer = self.level.get() + 1;
        let level = Level::new(finer)
            .ok()
            .filter(|l| l.get() <= Self::MAX_LEVEL)
            .ok_or(MicromapError::LevelTooHigh {
                level: finer,
                max: Self::MAX_LEVEL,
            })?;
        Self::from_states(
            level,
            self.format,
            self.states().flat_map(|state| [state; 4]),
        )
    }
}

/// A byte whose every state slot holds `state` (in `format`'s width).
#[inline]
const fn repeat_state(format: Format, state: State) -> u8 {
    match format {
        Format::TwoState => 0xff * (state.bits() & 1),
        Format::FourState => 0x55 * state.bits(),
    }
}

impl fmt::Debug for Micromap {
    /// Level, format and the bytes in hex (the first 32 and the length for
    /// longer maps, so a failing test on a level-12 map stays readable).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "Micromap {{ level: {}, format: {}, bytes ({}): ",
            self.level,
            self.format,
            self.data.len()
        )?;
        for byte in self.data.iter().take(32) {
            write!(f, "{byte:02x}")?;
        }
        if self.data.len() > 32 {
            f.write_str("...")?;
        }
        f.write_str(" }")
    }
}
