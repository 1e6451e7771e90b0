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

/// Bits per rank block: one `u32` of the directory per 512 bits (8 words),
/// 6.25% of the bits.
pub(crate) const RANK_BLOCK_BITS: usize = 512;
const RANK_BLOCK_WORDS: usize = RANK_BLOCK_BITS / 64;

/// A bit vector with a rank directory: `blocks[b]` holds the number of ones
/// in blocks `0..=b`, for every block but the last (the first block needs no
/// entry, its count before is 0), so a vector of at most 512 bits has an
/// empty directory.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct RankBits {
    bits: BitVec,
    blocks: Vec<u32>,
    ones: usize,
}

impl RankBits {
    /// The directory for `bits`. The bits are limited to `u32::MAX` ones by
    /// the trees' level limit.
    pub(crate) fn new(bits: BitVec) -> Self {
        let words = bits.words();
        let block_count = words.len().div_ceil(RANK_BLOCK_WORDS);
        let mut blocks = Vec::with_capacity(block_count.saturating_sub(1));
        let mut ones = 0usize;
        for (b, block) in words.chunks(RANK_BLOCK_WORDS).enumerate() {
            ones += block.iter().map(|w| w.count_ones() as usize).sum::<usize>();
            if b + 1 < block_count {
                // At most (4^16 - 1) / 3 < 2^32 tree bits.
                blocks.push(ones as u32);
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
        32 * self.blocks.len() as u64
    }

    /// Bit `p` and the number of ones before it (`rank1(p)`), from one word
    /// read and one directory entry. `p` must be below `len()`; past the end
    /// the answer is `(false, count_ones())`.
    #[inline]
    pub(crate) fn bit_and_rank(&self, p: usize) -> (bool, usize) {
        let words = self.bits.words();
        let w = p / 64;
        let Some(&word) = words.get(w) else {
            return (false, self.ones);
        };
        let block = w / RANK_BLOCK_WORDS;
        let before_block = match block.checked_sub(1) {
            Some(b) => self.blocks[b] as usize,
            None => 0,
        };
        // The words of the block before `w`, then `w`'s bits below `p`: a
        // plain loop (at most 7 words; LLVM's vectorized form of a slice sum
        // costs more than it saves at this length).
        let mut in_block = (word & ((1u64 << (p % 64)) - 1)).count_ones();
        let mut i = block * RANK_BLOCK_WORDS;
        while i < w {
            in_block += words[i].count_ones();
            i += 1;
        }
        (
            (word >> (p % 64)) & 1 == 1,
            before_block + in_block as usize,
        )
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

    /// rank1 against a count over the bits, around every block and word
    /// boundary of a 2000-bit vector with an irregular pattern.
    #[test]
    fn rank_equals_counting_the_bits() {
        let mut bits = BitVec::new();
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut plain = Vec::new();
        for _ in 0..2000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let bit = x % 3 == 0;
            bits.push(bit);
            plain.push(bit);
        }
        let ranked = RankBits::new(bits);
        assert_eq!(ranked.directory_bits(), 32 * 3); // 4 blocks, 3 entries
        let mut ones = 0;
        for (p, &bit) in plain.iter().enumerate() {
            assert_eq!(ranked.bit_and_rank(p), (bit, ones), "bit {p}");
            ones += usize::from(bit);
        }
        assert_eq!(ranked.count_ones(), ones);
        assert_eq!(ranked.rank1(2000), ones);
        assert_eq!(ranked.bit_and_rank(5000), (false, ones));
    }

    #[test]
    fn small_vectors_have_an_empty_directory() {
        let mut bits = BitVec::new();
        for i in 0..512 {
            bits.push(i % 5 == 0);
        }
        assert_eq!(RankBits::new(bits.clone()).directory_bits(), 0);
        bits.push(true);
        assert_eq!(RankBits::new(bits).directory_bits(), 32);
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
