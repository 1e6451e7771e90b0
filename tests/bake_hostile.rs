//! The baker and verifier under hostile sizes (issue 26): bounded-memory
//! verification, fallible allocation, level choice at the limits.

use micromap_index::bake::{
    levels_within_budget, useful_level, AlphaTexture, Baker, Cutoff, Sampler, TextureError,
    Unorm8Texture,
};
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

/// A texture of any size whose texels are all one alpha (nothing stored).
struct Uniform {
    width: u32,
    height: u32,
}

impl AlphaTexture for Uniform {
    fn width(&self) -> u32 {
        self.width
    }
    fn height(&self) -> u32 {
        self.height
    }
    fn alpha(&self, _: u32, _: u32) -> f64 {
        1.0
    }
}

/// Textures that pass the size check (`w h < 2^32`) but whose tables do not
/// fit the caller's limit are a typed error naming the bytes, at once (no
/// texel is read, nothing is allocated): 65535 x 65535 needs 12.9 GB,
/// 2^31 x 1 10.7 GB. At the limit exactly, a small texture is accepted;
/// one byte less is refused.
#[test]
fn baker_tables_past_the_limit_are_an_error_not_an_abort() {
    let limit = 1 << 30;
    for (width, height) in [(65535, 65535), (1 << 31, 1), (1, 1 << 31)] {
        let texture = Uniform { width, height };
        let bytes = u64::from(width) * u64::from(height)
            + 2 * (u64::from(width) + 1) * (u64::from(height) + 1);
        match Baker::new_within(&texture, Sampler::default(), Cutoff::default(), limit) {
            Err(TextureError::AllocationFailed { bytes: b, limit: l }) => {
                assert_eq!((b, l), (bytes, limit));
            }
            other => panic!("{width}x{height}: {other:?}"),
        }
        let message = TextureError::AllocationFailed { bytes, limit }.to_string();
        assert!(
            message.contains("over the limit of 1073741824 bytes"),
            "{message}"
        );
    }
    let small = Uniform {
        width: 30,
        height: 20,
    };
    let exact = 30 * 20 + 2 * 31 * 21;
    assert!(Baker::new_within(&small, Sampler::default(), Cutoff::default(), exact).is_ok());
    assert!(matches!(
        Baker::new_within(&small, Sampler::default(), Cutoff::default(), exact - 1),
        Err(TextureError::AllocationFailed { .. })
    ));
    // 2^32 texels is still the size check's error, before any limit.
    let too_large = Uniform {
        width: 1 << 16,
        height: 1 << 16,
    };
    assert!(matches!(
        Baker::new_within(&too_large, Sampler::default(), Cutoff::default(), u64::MAX),
        Err(TextureError::TooLarge { .. })
    ));
}

/// Levels at the top of `Level`'s range: `levels_within_budget` neither
/// overflows (it panicked in debug builds and answered level 32 for a
/// 100-byte budget in release) nor answers above 16, and `useful_level`
/// never answers above the 16 the baker bakes.
#[test]
fn level_choice_stays_within_what_the_baker_bakes() {
    let l = |n| Level::new(n).unwrap();
    for top in [16, 17, 31, 32] {
        let wanted = vec![l(top); 1000];
        // Even level 0 (1 byte each) does not fit 100 bytes: all level 0.
        let levels = levels_within_budget(&wanted, Format::FourState, 100);
        assert!(levels.iter().all(|&x| x == l(0)), "{top}: {:?}", levels[0]);
        // 1000 level-2 maps (8 bytes each) fit 8000 bytes; level 3 does not.
        let levels = levels_within_budget(&wanted, Format::FourState, 8000);
        assert_eq!(levels[0], l(2), "{top}");
        let levels = levels_within_budget(&wanted, Format::FourState, u64::MAX);
        assert_eq!(levels[0], l(16), "{top}");
    }
    let huge = [[0.0, 0.0], [1.0e9, 0.0], [0.0, 1.0e9]];
    assert_eq!(useful_level(&huge, (65535, 65535), l(32)), l(16));
    assert_eq!(useful_level(&huge, (65535, 65535), l(12)), l(12));
}
