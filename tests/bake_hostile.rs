//! The baker and verifier under hostile sizes (issue 26): bounded-memory
//! verification, fallible allocation, level choice at the limits.

use micromap_index::bake::{Baker, Cutoff, Sampler, Unorm8Texture};
use micromap_index::micromap::{Format, Micromap, State, TriangleOpacity};
use micromap_index::Level;

/// Left column opaque, right column transparent.
const TEXELS: [u8; 4] = [255, 0, 255, 0];

/// A map that calls every micro-triangle of a triangle across both columns
/// opaque: about half of them are contradictions.
fn all_opaque(level: u32) -> Micromap {
    let level = Level::new(level).unwrap();
    let mut map = Micromap::new(level, Format::FourState).unwrap();
    for i in 0..map.len() {
        map.set(i, State::Opaque).unwrap();
    }
    map
}

/// `verify_each` counts every contradiction `verify` collects, hands each
/// to the callback (which may keep only a few), and a cap on the known
/// micro-triangles checked is reported as `unchecked`, never dropped.
#[test]
fn verify_each_counts_everything_keeps_what_the_caller_keeps_and_reports_its_cap() {
    let texture = Unorm8Texture::new(2, 2, &TEXELS).unwrap();
    let baker = Baker::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
    let across = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let map = all_opaque(5);
    let opacity = TriangleOpacity::Micromap(&map);
    let full = baker.verify(&across, &opacity);
    assert!(
        full.contradictions.len() > 100,
        "{}",
        full.contradictions.len()
    );

    let mut kept = Vec::new();
    let counts = baker.verify_each(&across, &opacity, u64::MAX, |c| {
        if kept.len() < 3 {
            kept.push(c);
        }
    });
    assert_eq!(counts.contradictions, full.contradictions.len() as u64);
    assert_eq!(kept, full.contradictions[..3]);
    assert_eq!((counts.known, counts.unchecked), (1024, 0));
    assert_eq!(counts.unknown, full.unknown);

    let capped = baker.verify_each(&across, &opacity, 100, |_| {});
    assert_eq!((capped.known, capped.unchecked), (100, 924));
    assert!(capped.contradictions <= counts.contradictions);
    assert!(capped.checked);
}
