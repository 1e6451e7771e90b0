//! The byte format shared by both layouts (described in the module docs of
//! `succinct`): a 24-byte header, the tree bits, the leaf states.

use super::bits::{BitVec, PackedStates};
use super::{Layout, Section, TreeError, MAX_TREE_LEVEL};
use crate::micromap::Format;
use alloc::vec::Vec;

pub(super) const MAGIC: [u8; 4] = *b"SOMT";
pub(super) const VERSION: u8 = 1;
pub(super) const HEADER_LEN: usize = 24;

pub(super) fn write(
    layout: Layout,
    level: u32,
    format: Format,
    tree: &BitVec,
    data: &PackedStates,
) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_LEN + tree.len() / 8 + data.bit_len() / 8 + 2);
    out.extend_from_slice(&MAGIC);
    out.push(VERSION);
    out.push(layout as u8);
    // Levels are at most 16 and formats 1 or 2: both fit a byte.
    out.push(level as u8);
    out.push(format.raw() as u8);
    out.extend_from_slice(&(tree.len() as u64).to_le_bytes());
    out.extend_from_slice(&(data.len() as u64).to_le_bytes());
    out.extend_from_slice(&tree.to_bytes());
    out.extend_from_slice(&data.to_bytes());
    out
}

/// The header's fields and the two sections, checked for everything but the
/// tree's shape (the layout's own check does that): magic, version, layout,
/// level, format, lengths, unused bits.
pub(super) fn read(
    layout: Layout,
    bytes: &[u8],
) -> Result<(u32, Format, BitVec, PackedStates), TreeError> {
    let available = bytes.len() as u64;
    let Some(header) = bytes.get(..HEADER_LEN) else {
        return Err(TreeError::Truncated {
            needed: HEADER_LEN as u64,
            available,
        });
    };
    if header[..4] != MAGIC {
        return Err(TreeError::BadMagic);
    }
    if header[4] != VERSION {
        return Err(TreeError::UnsupportedVersion { version: header[4] });
    }
    if header[5] != layout as u8 {
        return Err(TreeError::WrongLayout {
            expected: layout,
            found: header[5],
        });
    }
    let level = u32::from(header[6]);
    if level > MAX_TREE_LEVEL {
        return Err(TreeError::LevelTooHigh {
            level,
            max: MAX_TREE_LEVEL,
        });
    }
    let format =
        Format::from_raw(u16::from(header[7])).ok_or(TreeError::BadFormat { raw: header[7] })?;
    let word = |at: usize| {
        let mut le = [0u8; 8];
        le.copy_from_slice(&header[at..at + 8]);
        u64::from_le_bytes(le)
    };
    let (tree_bits, leaves) = (word(8), word(16));
    // Sizes in u128: no header value can overflow them.
    let tree_len = u128::from(tree_bits).div_ceil(8);
    let data_len = (u128::from(leaves) * u128::from(format.bits_per_state())).div_ceil(8);
    let needed = HEADER_LEN as u128 + tree_len + data_len;
    if needed > u128::from(available) {
        return Err(TreeError::Truncated {
            needed: u64::try_from(needed).unwrap_or(u64::MAX),
            available,
        });
    }
    if needed < u128::from(available) {
        return Err(TreeError::TrailingBytes {
            expected: needed as u64,
            actual: available,
        });
    }
    // Both lengths fit in the bytes given, so in usize.
    let (tree_len, data_len) = (tree_len as usize, data_len as usize);
    let tree_bytes = &bytes[HEADER_LEN..HEADER_LEN + tree_len];
    let data_bytes = &bytes[HEADER_LEN + tree_len..];
    debug_assert_eq!(data_bytes.len(), data_len);
    let tree =
        BitVec::from_bytes(tree_bytes, tree_bits as usize).ok_or(TreeError::UnusedBitsSet {
            section: Section::Tree,
        })?;
    let data = PackedStates::from_bytes(data_bytes, leaves as usize, format).ok_or(
        TreeError::UnusedBitsSet {
            section: Section::Data,
        },
    )?;
    Ok((level, format, tree, data))
}
