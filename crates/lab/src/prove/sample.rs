//! Random faces, for levels too large to enumerate.

#[allow(clippy::wildcard_imports)]
use super::*;

/// Uniform integers in `0..bound` (`bound > 0`) without modulo bias
/// (Lemire's multiply-and-reject); the rejection threshold costs a
/// division, so it is computed once.
#[derive(Clone, Copy)]
pub(super) struct Below {
    pub(super) bound: u64,
    pub(super) threshold: u64,
}

impl Below {
    pub(super) fn new(bound: u64) -> Below {
        Below {
            bound,
            threshold: bound.wrapping_neg() % bound,
        }
    }

    pub(super) fn draw(self, rng: &mut SplitMix64) -> u64 {
        loop {
            let product = u128::from(rng.next_u64()) * u128::from(self.bound);
            if (product as u64) >= self.threshold {
                return (product >> 64) as u64;
            }
        }
    }
}

/// Draws faces uniformly among all faces of a level: a uniform anchor cell
/// `(a, b)` in `0..=2^level` squared and one of the six faces anchored
/// there (as [`lattice::faces`] anchors them), redrawn if outside the
/// triangle. Every face has exactly one anchor, so all are equally likely.
pub(super) struct FaceSampler {
    pub(super) level: Level,
    pub(super) anchor: Below,
    pub(super) kind: Below,
}

impl FaceSampler {
    pub(super) fn new(level: Level) -> FaceSampler {
        FaceSampler {
            level,
            anchor: Below::new((1u64 << level.get()) + 1),
            kind: Below::new(6),
        }
    }

    pub(super) fn draw(&self, rng: &mut SplitMix64) -> Face {
        let limit = 4 << self.level.get();
        loop {
            let a = self.anchor.draw(rng);
            let b = self.anchor.draw(rng);
            let (dx, dy, kind) = crate::lattice::FACE_OFFSETS[self.kind.draw(rng) as usize];
            let (x, y) = (4 * a + dx, 4 * b + dy);
            if x + y <= limit {
                return Face {
                    level: self.level,
                    x,
                    y,
                    kind,
                };
            }
        }
    }
}

/// Samples per unit of work.
pub(super) const SAMPLES_PER_UNIT: u64 = 1 << 20;

/// Compares the walk, run step by step on exact [`Fixed64`] points, with
/// the reference on `samples` uniformly random faces of the level. Not a
/// proof; for levels too large to enumerate. The same `seed` draws the
/// same faces, whatever the thread count.
///
/// ```
/// use micromap_index_lab::prove::{sample_level, Progress, Reference, Settings};
/// use micromap_index::Level;
/// let settings = Settings { reference: Reference::SpecWide, ..Settings::default() };
/// let report = sample_level(Level::new(32).unwrap(), 10_000, 7, &settings, &Progress::new()).unwrap();
/// assert_eq!((report.faces_checked, report.mismatches()), (10_000, 0));
/// ```
pub fn sample_level(
    level: Level,
    samples: u64,
    seed: u64,
    settings: &Settings,
    progress: &Progress,
) -> Result<LevelReport, ProveError> {
    let started = Instant::now();
    let level = checked_level(level, settings.reference)?;
    let units = samples.div_ceil(SAMPLES_PER_UNIT);
    let keep = settings.examples;
    let (walk, reference) = (settings.walk, settings.reference);
    let sampler = FaceSampler::new(level);
    let finished = run_units(units, thread_count(settings), progress, |i| {
        let first = i * SAMPLES_PER_UNIT;
        let count = SAMPLES_PER_UNIT.min(samples - first);
        // Each unit has its own stream, so results do not depend on the
        // thread count.
        let mut rng = SplitMix64::new(seed ^ i.wrapping_mul(0xd1b5_4a32_d192_ed03));
        rng.next_u64();
        let mut tally = Tally::default();
        for _ in 0..count {
            let face = sampler.draw(&mut rng);
            let (u, v) = face.to_fixed64();
            let by_walk = walk.index(u, v, level);
            let by_reference = reference.index(face.x, face.y, level);
            if by_walk != by_reference {
                tally.record_mismatch(level, face.x, face.y, by_walk, by_reference, keep);
            }
        }
        tally.faces = count;
        tally
    });
    Ok(merge(
        empty_report(
            level,
            settings,
            Method::Sampled { seed },
            u128::from(samples),
        ),
        finished,
        keep,
        started,
    ))
}
