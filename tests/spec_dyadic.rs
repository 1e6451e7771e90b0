//! `spec::cell_dyadic` (the integer first half the face-by-face proof feeds
//! the reference) against `spec::cell_real_ref` (the reference's first half
//! over the rationals, `BigRational` only) on the points where a first half
//! can go wrong: fractions summing to exactly 1 (on a cell's diagonal), one
//! unit of the point's scale either side of it, cell corners, and
//! coordinates clamped at 0 and 1, at every level 0..=32 and at scales from
//! the level's own to `MAX_SCALE_LOG2`. (Issue 36: a mutant of
//! `cell_dyadic`'s diagonal test at levels >= 21 survived every other test.)

use micromap_index::spec::{cell_dyadic, cell_real_ref, MAX_SCALE_LOG2};
use micromap_index::Level;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::One;

fn dyadic(numerator: u64, scale_log2: u32) -> BigRational {
    BigRational::new(numerator.into(), BigInt::one() << scale_log2)
}

#[test]
fn cell_dyadic_equals_the_rational_reference_on_and_around_diagonals() {
    let mut checked = 0u64;
    for level in 0..=32u32 {
        let l = Level::new(level).unwrap();
        let mut scales = vec![level, level + 1, level + 3, 40, 52, MAX_SCALE_LOG2];
        scales.retain(|&s| s >= level && s <= MAX_SCALE_LOG2);
        scales.dedup();
        for &scale in &scales {
            let one = 1u64 << scale;
            // One cell is `2^(scale - level)` units of the point's scale.
            let cell = 1u64 << (scale - level);
            let cells = 1u64 << level;
            // Cells near both ends of a row and in the middle.
            let picks = [0, 1, cells / 2, cells.saturating_sub(2), cells - 1];
            for &iu in &picks {
                for &iv in &picks {
                    if iu + iv >= cells {
                        continue;
                    }
                    let (u0, v0) = (iu * cell, iv * cell);
                    // Fractions (in units) summing to cell - 1, cell, cell + 1,
                    // split three ways, and the cell's corner.
                    let mut points = vec![(u0, v0)];
                    for sum in [cell.saturating_sub(1), cell, cell + 1] {
                        for fu in [0, 1, sum / 2, sum.saturating_sub(1), sum] {
                            let fu = fu.min(sum);
                            let fv = sum - fu;
                            if fu < cell && fv < cell {
                                points.push((u0 + fu, v0 + fv));
                            }
                        }
                    }
                    for (u, v) in points {
                        let got = cell_dyadic(u, v, scale, l).unwrap();
                        let want = cell_real_ref(&dyadic(u, scale), &dyadic(v, scale), l);
                        assert_eq!(got, want, "cell_dyadic({u}, {v}, {scale}, level {level})");
                        checked += 1;
                    }
                }
            }
            // Clamping: coordinates at and above 1 (numerators up to 2^62).
            for (u, v) in [(one, 0), (0, one), (one, one), (one - 1, 1), (1 << 62, 3)] {
                if u > 1 << 62 || v > 1 << 62 {
                    continue;
                }
                let got = cell_dyadic(u, v, scale, l).unwrap();
                let want = cell_real_ref(&dyadic(u, scale), &dyadic(v, scale), l);
                assert_eq!(got, want, "cell_dyadic({u}, {v}, {scale}, level {level})");
                checked += 1;
            }
        }
    }
    assert!(checked > 10_000, "{checked} points");
}

/// The issue's witness: `(1, 2) / 2^23` at level 21 lies below the diagonal
/// of cell (0, 0) (fractions 1/4 + 1/2 of a cell), micro-triangle 0.
#[test]
fn the_issue_witness_is_below_the_diagonal() {
    let level = Level::new(21).unwrap();
    assert_eq!(
        micromap_index::spec::wide_index_dyadic(1, 2, 23, level),
        Ok(0)
    );
}
