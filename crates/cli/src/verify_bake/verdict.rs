//! The verdict and witness text every `verify-bake` report prints: the
//! verdict's word, and a contradiction's exact witness and texel.

use micromap_index::bake::TexelPoint;

/// The verdict's word: `sound`, `INCOMPLETE` (nothing contradicted, but not
/// everything checked) or `NOT SOUND`.
pub(crate) fn verdict(sound: bool, contradictions: u64) -> &'static str {
    if sound {
        "sound"
    } else if contradictions == 0 {
        "INCOMPLETE"
    } else {
        "NOT SOUND"
    }
}

/// A contradiction's exact witness in texel space, as the JSON reports give
/// it: (numerator, log2 denominator) per axis.
pub(crate) fn witness_texel_space(witness: Option<TexelPoint>) -> Option<[(String, u32); 2]> {
    witness.map(|w| [(w.x.to_string(), w.shift_x), (w.y.to_string(), w.shift_y)])
}

/// A contradiction's witness (as [`witness_texel_space`] gives it) and
/// texel, as the text reports name them.
pub(crate) fn witness_and_texel(
    witness: Option<&[(String, u32); 2]>,
    texel: Option<[u32; 2]>,
) -> (String, String) {
    let witness = match witness {
        Some([(x, sx), (y, sy)]) => format!("texel-space point ({x}/2^{sx}, {y}/2^{sy})"),
        None => "no exact point (block search)".into(),
    };
    let texel = match texel {
        Some([x, y]) => format!("texel ({x}, {y})"),
        None => "the border".into(),
    };
    (witness, texel)
}
