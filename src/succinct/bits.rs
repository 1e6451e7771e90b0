//! Bit vectors for the trees: a plain growable one, one with a rank
//! directory, and a packed vector of states.
//!
//! Bits are numbered least-significant first inside `u64` words, like the
//! APIs number micromap bits inside bytes.

use crate::micromap::{Format, State};
use alloc::vec::Vec;

/// A growable bit vector: bit `i` is bit `i % 64` of word `i / 64`; the bits
/// of the last word past `len` are zero.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub(crate) struct BitVec {
    words: Vec<u64>,
    len: usize,
}

impl BitVec {
    pub(crate) fn new() -> Self {
        BitVec::default()
    }

    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    #[inline]
    pub(crate) fn push(&mut self, bit: bool) {
        if self.len % 64 == 0 {
            self.words.push(0);
        }
        if bit {
            self.words[self.len / 64] |= 1 << (self.len % 64);
        }
        self.len += 1;
    }

    /// Bit `i`; `false` past the end (the trees never read there once
    /// validated, and a read past the end must not panic).
    #[inline]
    pub(crate) fn get(&self, i: usize) -> bool {
        i < self.len && (self.words[i / 64] >> (i % 64)) & 1 == 1
    }

    pub(crate) fn words(&self) -> &[u64] {
        &self.words
    }

    /// The bits as bytes, least-significant bit first, `ceil(len / 8)`
    /// bytes, unused bits zero.
    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        let mut bytes: Vec<u8> = self.words.iter().flat_map(|w| w.to_le_bytes()).collect();
        bytes.truncate(self.len.div_ceil(8));
        bytes
    }

    /// `len` bits from `bytes` (least-significant bit first); `None` unless
    /// `bytes` has exactly `ceil(len / 8)` bytes with the unused bits zero.
    pub(crate) fn from_bytes(bytes: &[u8], len: usize) -> Option<BitVec> {
        if bytes.len() != len.div_ceil(8) {
            return None;
        }
        if len % 8 != 0 && bytes[bytes.len() - 1] >> (len % 8) != 0 {
            return None;
        }
        let words = bytes
            .chunks(8)
            .map(|chunk| {
                let mut word = [0u8; 8];
                word[..chunk.len()].copy_from_slice(chunk);
                u64::from_le_bytes(word)
            })
            .collect();
        Some(BitVec { words, len })
    }
}

/// Bits per rank block: one `u64` of the directory per 512 bits (8 words),
/// 12.5% of the bits.
pub(crate) const RANK_BLOCK_BITS: usize = 512;
const RANK_BLOCK_WORDS: usize = RANK_BLOCK_BITS / 64;
/// Bits of one relative count in a directory entry (a count of at most 384).
const REL_BITS: u32 = 9;

/// A bit vector with a rank directory of one `u64` per 512-bit block: the
/// ones before the block in the high 32 bits, and in the low 27 bits, 9 bits
/// each, the ones in the block's words `0..2`, `0..4` and `0..6`. A rank is
/// then the entry, the count before the word pair (a shift), and at most two
/// popcounts (the pair's first word, and the word itself below `p`): no loop
/// and no branch. A vector of at most 128 bits needs no entry (its one word
/// pair starts at 0) and has an empty directory.
///
/// Why this shape: per level of a tree lookup the rank is on the critical
/// path, and a loop over up to seven words (the plain 512-bit directory)
/// costs a mispredicted branch and, without hardware `popcnt`, seven
/// software popcounts. Per-word counts (rank9, 18.75%) would save one more
/// popcount but push the level-order tree past 1.1x the paper's bits.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct RankBits {
    bits: BitVec,
    blocks: Vec<u64>,
    ones: usize,
}

impl RankBits {
    /// The directory for `bits`. The bits are limited to `u32::MAX` ones by
    /// the trees' level limit.
    pub(crate) fn new(bits: BitVec) -> Self {
        let words = bits.words();
        let mut blocks = Vec::new();
        let mut ones = 0usize;
        let needs_directory = bits.len() > 128;
        for block in words.chunks(RANK_BLOCK_WORDS) {
            let mut entry = (ones as u64) << 32;
            let mut in_block = 0u64;
            for (i, w) in block.iter().enumerate() {
                if i % 2 == 0 && i > 0 {
                    entry |= in_block << (REL_BITS * (i as u32 / 2 - 1));
                }
                in_block += u64::from(w.count_ones());
            }
            // At most (4^16 - 1) / 3 < 2^32 tree bits.
            ones += in_block as usize;
            if needs_directory {
                blocks.push(entry);
            }
        }
        RankBits { bits, blocks, ones }
    }

    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.bits.len()
    }

    #[inline]
    pub(crate) fn bits(&self) -> &BitVec {
        &self.bits
    }

    /// The number of ones in the whole vector.
    #[inline]
    pub(crate) fn count_ones(&self) -> usize {
        self.ones
    }

    /// Bits the directory takes.
    pub(crate) fn directory_bits(&self) -> u64 {
        64 * self.blocks.len() as u64
    }

    /// Bits the directory of a `len`-bit vector takes (what
    /// [`directory_bits`](Self::directory_bits) gives once it is built):
    /// one entry per started block, none up to 128 bits.
    pub(crate) fn directory_bits_for(len: u64) -> u64 {
        if len > 128 {
            64 * len.div_ceil(RANK_BLOCK_BITS as u64)
        } else {
            0
        }
    }

    /// Bit `p` and the number of ones before it (`rank1(p)`), from one
    /// directory entry and two words of one pair. `p` must be below
    /// `len()`; past the end the answer is `(false, count_ones())`.
    #[inline]
    pub(crate) fn bit_and_rank(&self, p: usize) -> (bool, usize) {
        let words = self.bits.words();
        let w = p / 64;
        let Some(&word) = words.get(w) else {
            return (false, self.ones);
        };
        // Absent only for a vector of at most two words: all counts 0.
        let entry = self.blocks.get(w / RANK_BLOCK_WORDS).copied().unwrap_or(0);
        let pair = (w % RANK_BLOCK_WORDS / 2) as u32;
        // Shifting the entry up by one field puts a zero field at pair 0.
        let before_pair = ((entry << REL_BITS) >> (REL_BITS * pair)) & ((1 << REL_BITS) - 1);
        // The pair's first word counts only when `w` is its second.
        let odd = 0u64.wrapping_sub((w & 1) as u64);
        let first = words[w & !1] & odd;
        let below = word & ((1u64 << (p % 64)) - 1);
        let rank = (entry >> 32) + before_pair + u64::from(first.count_ones() + below.count_ones());
        ((word >> (p % 64)) & 1 == 1, rank as usize)
    }
    /// `rank1(p)`: the ones in bits `0..p`, for any `p` (all ones past the
    /// end).
    #[inline]
    pub(crate) fn rank1(&self, p: usize) -> usize {
        if p >= self.len() {
            self.ones
        } else {
            self.bit_and_rank(p).1
        }
    }
}

/// States packed at the format's width (1 or 2 bits each), first state in
/// the lowest bits, like the APIs pack micromap data.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PackedStates {
    bits: BitVec,
    format: Format,
}

impl PackedStates {
    pub(crate) fn new(format: Format) -> Self {
        PackedStates {
            bits: BitVec::new(),
            format,
        }
    }

    /// Appends `state`; the caller has checked `format.holds(state)` (a
    /// 2-state vector stores only the low bit).
    #[inline]
    pub(crate) fn push(&mut self, state: State) {
        debug_assert!(self.format.holds(state));
        self.bits.push(state.bits() & 1 == 1);
        if self.format == Format::FourState {
            self.bits.push(state.bits() & 2 == 2);
        }
    }

    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.bits.len() / self.format.bits_per_state() as usize
    }

    /// State `i`, or `None` past the end.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> Option<State> {
        let words = self.bits.words();
        match self.format {
            Format::TwoState => {
                if i >= self.bits.len() {
                    return None;
                }
                let bit = (words[i / 64] >> (i % 64)) & 1;
                State::from_bits(bit as u8)
            }
            Format::FourState => {
                if i >= self.bits.len() / 2 {
                    return None;
                }
                let pair = (words[i / 32] >> (2 * (i % 32))) & 3;
                State::from_bits(pair as u8)
            }
        }
    }

    pub(crate) fn bit_len(&self) -> usize {
        self.bits.len()
    }

    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        self.bits.to_bytes()
    }

    /// `count` states from `bytes`; `None` unless the length is exactly
    /// right and the unused bits are zero.
    pub(crate) fn from_bytes(bytes: &[u8], count: usize, format: Format) -> Option<Self> {
        let len = count.checked_mul(format.bits_per_state() as usize)?;
        BitVec::from_bytes(bytes, len).map(|bits| PackedStates { bits, format })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use micromap_index_test_support::SplitMix64;

    /// rank1 against a count over the bits, around every block and word
    /// boundary of 2000- and 3000-bit vectors: an irregular pattern, all
    /// ones (the largest count every directory field holds), and dense.
    #[test]
    fn rank_equals_counting_the_bits() {
        for (len, pattern) in [(2000usize, 0), (3000, 1), (3000, 2)] {
            let mut bits = BitVec::new();
            let mut rng = SplitMix64::new(0x9e37_79b9_7f4a_7c15);
            let mut plain = Vec::new();
            for _ in 0..len {
                let x = rng.next_u64();
                let bit = match pattern {
                    0 => x % 3 == 0,
                    1 => true,
                    _ => x % 7 != 0,
                };
                bits.push(bit);
                plain.push(bit);
            }
            let ranked = RankBits::new(bits);
            assert_eq!(ranked.directory_bits(), 64 * len.div_ceil(512) as u64);
            let mut ones = 0;
            for (p, &bit) in plain.iter().enumerate() {
                assert_eq!(ranked.bit_and_rank(p), (bit, ones), "bit {p}");
                ones += usize::from(bit);
            }
            assert_eq!(ranked.count_ones(), ones);
            assert_eq!(ranked.rank1(len), ones);
            assert_eq!(ranked.bit_and_rank(5000), (false, ones));
        }
    }

    #[test]
    fn small_vectors_have_an_empty_directory() {
        let mut bits = BitVec::new();
        for i in 0..128 {
            bits.push(i % 5 == 0);
        }
        assert_eq!(RankBits::new(bits.clone()).directory_bits(), 0);
        bits.push(true);
        assert_eq!(RankBits::new(bits).directory_bits(), 64);
    }

    #[test]
    fn bytes_round_trip_and_reject_unused_bits() {
        let mut bits = BitVec::new();
        for i in 0..13 {
            bits.push(i % 3 == 1);
        }
        let bytes = bits.to_bytes();
        assert_eq!(bytes, [0b1001_0010, 0b0000_0100]);
        assert_eq!(BitVec::from_bytes(&bytes, 13), Some(bits));
        assert_eq!(BitVec::from_bytes(&[0b1001_0010, 0b0010_0100], 13), None);
        assert_eq!(BitVec::from_bytes(&bytes, 17), None);
        assert_eq!(BitVec::from_bytes(&bytes, 8), None);
    }

    #[test]
    fn packed_states_store_the_api_layout() {
        let mut four = PackedStates::new(Format::FourState);
        for state in [State::UnknownOpaque, State::Transparent, State::Opaque] {
            four.push(state);
        }
        assert_eq!(four.to_bytes(), [0b01_00_11]);
        assert_eq!(four.get(0), Some(State::UnknownOpaque));
        assert_eq!(four.get(2), Some(State::Opaque));
        assert_eq!(four.get(3), None);
        let mut two = PackedStates::new(Format::TwoState);
        two.push(State::Opaque);
        two.push(State::Transparent);
        assert_eq!(two.len(), 2);
        assert_eq!(two.get(0), Some(State::Opaque));
        assert_eq!(two.get(2), None);
    }
}
