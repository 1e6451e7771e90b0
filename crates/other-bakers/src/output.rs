//! The Vulkan-layout result every baker is converted to, and its three files.

use std::fs;
use std::path::Path;

/// `VkOpacityMicromapFormatEXT`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `VK_OPACITY_MICROMAP_FORMAT_2_STATE_EXT` = 1: one bit per micro-triangle.
    TwoState = 1,
    /// `VK_OPACITY_MICROMAP_FORMAT_4_STATE_EXT` = 2: two bits per micro-triangle.
    FourState = 2,
}

impl Format {
    /// From the command line's `--format 2|4` (the number of states).
    pub fn from_states(states: u8) -> Option<Self> {
        match states {
            2 => Some(Self::TwoState),
            4 => Some(Self::FourState),
            _ => None,
        }
    }

    /// 2 or 4.
    pub fn states(self) -> u8 {
        match self {
            Self::TwoState => 2,
            Self::FourState => 4,
        }
    }

    /// Bits per micro-triangle.
    pub fn bits(self) -> usize {
        match self {
            Self::TwoState => 1,
            Self::FourState => 2,
        }
    }

    /// The Vulkan enum value written into the records.
    pub fn vk(self) -> u16 {
        self as u16
    }

    /// Bytes of one micromap: `ceil(4^level * bits / 8)`.
    pub fn bytes(self, level: u8) -> usize {
        ((1usize << (2 * level as usize)) * self.bits()).div_ceil(8)
    }
}

/// `VkMicromapTriangleEXT`: 8 bytes, little endian.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Record {
    /// Byte offset of the micromap in `micromap-data.bin`.
    pub data_offset: u32,
    /// Subdivision level.
    pub level: u16,
    /// [`Format::vk`].
    pub format: u16,
}

/// Special indices (`VkOpacityMicromapSpecialIndexEXT`): `-(state + 1)`.
pub const FULLY_TRANSPARENT: i32 = -1;
/// See [`FULLY_TRANSPARENT`].
pub const FULLY_OPAQUE: i32 = -2;
/// See [`FULLY_TRANSPARENT`].
pub const FULLY_UNKNOWN_TRANSPARENT: i32 = -3;
/// See [`FULLY_TRANSPARENT`].
pub const FULLY_UNKNOWN_OPAQUE: i32 = -4;

/// Micromap data, records and one index per input triangle, in the layout a
/// Vulkan micromap build and BLAS take.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Micromaps {
    /// Packed states, LSB first, micro-triangles in space-filling-curve order.
    pub data: Vec<u8>,
    /// One record per micromap.
    pub records: Vec<Record>,
    /// Per input triangle: a record index, or a special index -1..=-4.
    pub indices: Vec<i32>,
}

impl Micromaps {
    /// Checks that every record lies inside the data and every index is a
    /// record or a special index.
    pub fn validate(&self, triangles: usize) -> Result<(), String> {
        if self.indices.len() != triangles {
            return Err(format!(
                "{} indices for {triangles} triangles",
                self.indices.len()
            ));
        }
        for (k, r) in self.records.iter().enumerate() {
            let format = match r.format {
                1 => Format::TwoState,
                2 => Format::FourState,
                f => return Err(format!("record {k}: format {f}")),
            };
            if r.level > 12 {
                return Err(format!("record {k}: level {}", r.level));
            }
            let end = r.data_offset as usize + format.bytes(r.level as u8);
            if end > self.data.len() {
                return Err(format!(
                    "record {k}: bytes up to {end} of {}",
                    self.data.len()
                ));
            }
        }
        for (t, &i) in self.indices.iter().enumerate() {
            if !(-4..self.records.len() as i32).contains(&i) {
                return Err(format!("triangle {t}: index {i}"));
            }
        }
        Ok(())
    }

    /// The state (0 T, 1 O, 2 UT, 3 UO) of micro-triangle `micro` of input
    /// triangle `triangle`, reading the index, record and data as a GPU does
    /// (a special index gives its state to every micro-triangle).
    pub fn state(&self, triangle: usize, micro: usize) -> u8 {
        let i = self.indices[triangle];
        if i < 0 {
            return (-i - 1) as u8;
        }
        let r = self.records[i as usize];
        let base = r.data_offset as usize;
        if r.format == Format::TwoState.vk() {
            (self.data[base + (micro >> 3)] >> (micro & 7)) & 1
        } else {
            (self.data[base + (micro >> 2)] >> (2 * (micro & 3))) & 3
        }
    }

    /// Writes `micromap-data.bin`, `micromap-triangles.bin` and
    /// `micromap-indices.bin` into `dir`.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        fs::create_dir_all(dir)?;
        fs::write(dir.join("micromap-data.bin"), &self.data)?;
        let mut records = Vec::with_capacity(8 * self.records.len());
        for r in &self.records {
            records.extend_from_slice(&r.data_offset.to_le_bytes());
            records.extend_from_slice(&r.level.to_le_bytes());
            records.extend_from_slice(&r.format.to_le_bytes());
        }
        fs::write(dir.join("micromap-triangles.bin"), records)?;
        let indices: Vec<u8> = self.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        fs::write(dir.join("micromap-indices.bin"), indices)
    }

    /// Counts of micro-triangle states over all input triangles at `level`
    /// (special indices expanded): `[T, O, UT, UO]`.
    pub fn state_counts(&self, level: u8) -> [u64; 4] {
        let mut counts = [0u64; 4];
        let micro = 1usize << (2 * level as usize);
        for t in 0..self.indices.len() {
            let i = self.indices[t];
            if i < 0 {
                counts[(-i - 1) as usize] += micro as u64;
                continue;
            }
            let level = self.records[i as usize].level as u8;
            for m in 0..1usize << (2 * level as usize) {
                counts[self.state(t, m) as usize] += 1;
            }
        }
        counts
    }
}
