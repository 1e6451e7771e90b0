//! The image of a range of texel coordinates under an address mode: what
//! a block reaching outside the texture reads.

use crate::bake::texture::AddressMode;

/// The image of `lo..=hi` under an address mode: at most two ranges of
/// `0..size`, and whether some coordinate reads the border.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisImage {
    pub(crate) ranges: [(u32, u32); 2],
    pub(crate) count: usize,
    pub(crate) border: bool,
}

impl AxisImage {
    fn one(lo: i128, hi: i128) -> AxisImage {
        AxisImage {
            ranges: [(lo as u32, hi as u32), (0, 0)],
            count: 1,
            border: false,
        }
    }
}

/// Does `lo..=hi` hold an integer `≡ r (mod m)`?
fn holds_residue(lo: i128, hi: i128, r: i128, m: i128) -> bool {
    lo + (r - lo).rem_euclid(m) <= hi
}

pub(crate) fn axis_image(mode: AddressMode, lo: i128, hi: i128, size: u32) -> AxisImage {
    let n = i128::from(size);
    // Every mode reads in-range coordinates as they are.
    if lo >= 0 && hi < n {
        return AxisImage::one(lo, hi);
    }
    let full = AxisImage::one(0, n - 1);
    // The wrapped value of one coordinate (the modes below never read the
    // border).
    let at = |i: i128| i128::from(mode.wrap_wide(i, size).unwrap_or(0));
    match mode {
        AddressMode::Repeat => {
            if hi - lo + 1 >= n {
                return full;
            }
            let a = lo.rem_euclid(n);
            let b = a + (hi - lo);
            if b < n {
                AxisImage::one(a, b)
            } else {
                AxisImage {
                    ranges: [(a as u32, (n - 1) as u32), (0, (b - n) as u32)],
                    count: 2,
                    border: false,
                }
            }
        }
        AddressMode::MirroredRepeat => {
            if hi - lo + 1 >= 2 * n {
                return full;
            }
            // Monotone between the folds at t = 0 | 2n - 1 (value 0) and
            // t = n - 1 | n (value n - 1).
            let min = if holds_residue(lo, hi, 0, 2 * n) || holds_residue(lo, hi, 2 * n - 1, 2 * n)
            {
                0
            } else {
                at(lo).min(at(hi))
            };
            let max = if holds_residue(lo, hi, n - 1, 2 * n) || holds_residue(lo, hi, n, 2 * n) {
                n - 1
            } else {
                at(lo).max(at(hi))
            };
            AxisImage::one(min, max)
        }
        AddressMode::ClampToEdge => AxisImage::one(lo.clamp(0, n - 1), hi.clamp(0, n - 1)),
        AddressMode::ClampToBorder => {
            let (a, b) = (lo.max(0), hi.min(n - 1));
            AxisImage {
                ranges: [(a.max(0) as u32, b.max(0) as u32), (0, 0)],
                count: usize::from(a <= b),
                border: lo < 0 || hi >= n,
            }
        }
        AddressMode::MirrorClampToEdge => {
            let min = if lo <= 0 && hi >= -1 {
                0
            } else {
                at(lo).min(at(hi))
            };
            AxisImage::one(min, at(lo).max(at(hi)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every address mode's image of every short range equals the set of
    /// wrapped values, computed one coordinate at a time.
    #[test]
    fn axis_images_match_wrapping_each_coordinate() {
        for size in 1..=5u32 {
            for mode in AddressMode::ALL {
                for lo in -13i128..13 {
                    for hi in lo..lo + 13 {
                        let image = axis_image(mode, lo, hi, size);
                        let mut expected = [false; 5];
                        let mut border = false;
                        for i in lo..=hi {
                            match mode.wrap(i as i64, size) {
                                Some(t) => expected[t as usize] = true,
                                None => border = true,
                            }
                        }
                        let mut got = [false; 5];
                        for &(a, b) in &image.ranges[..image.count] {
                            assert!(a <= b && b < size, "{mode:?} {lo}..={hi} size {size}");
                            for t in a..=b {
                                got[t as usize] = true;
                            }
                        }
                        assert_eq!(got, expected, "{mode:?} {lo}..={hi} size {size}");
                        assert_eq!(image.border, border, "{mode:?} {lo}..={hi} size {size}");
                    }
                }
            }
        }
    }
}
