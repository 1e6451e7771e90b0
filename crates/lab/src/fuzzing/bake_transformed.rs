//! Fuzz body for bakes of transformed texture coordinates (issue 34):
//! `Baker::with_uv_transform` never panics, and what it bakes known holds
//! for the shader's binary32 transform by `uv_transform_oracle`.

use crate::uv_transform_oracle::{judge, Case};
use micromap_index::bake::{
    AddressMode, Baker, Cutoff, Filter, Sampler, TriangleStatus, Unorm8Texture, UvTransform,
    UvTransformError, MAX_ROTATION,
};
use micromap_index::micromap::{BakedOpacity, Format, State, UnknownPolicy};
use micromap_index::Level;

/// A transformed bake: never panics; [`UvTransform::new`] refuses exactly
/// non-finite parameters and rotations beyond [`MAX_ROTATION`]; a bake
/// placed on its grid has no known micro-triangle the oracle contradicts
/// (hits judged where every form's coordinate stays within `2^20`).
///
/// Input: width, height (1..=8 each), `w h` texel codes (opaque at 128 and
/// above), the address mode per axis (one byte each), level (0..=4), the
/// transform's offset, rotation and scale (5 `f32` bits, little endian),
/// then the triangle (6 `f32` bits).
///
/// ```
/// micromap_index_lab::fuzzing::bake_transformed(&[2, 1, 255, 0, 0, 0, 2]);
/// ```
pub fn bake_transformed(data: &[u8]) {
    let mut at = 0usize;
    let mut byte = || {
        let b = data.get(at).copied().unwrap_or(0);
        at += 1;
        b
    };
    let (w, h) = (u32::from(byte() % 8) + 1, u32::from(byte() % 8) + 1);
    let texels: Vec<u8> = (0..w * h).map(|_| byte()).collect();
    let address = |b: u8| AddressMode::ALL[usize::from(b) % AddressMode::ALL.len()];
    let sampler = Sampler {
        filter: Filter::Nearest,
        address_u: address(byte()),
        address_v: address(byte()),
        ..Sampler::default()
    };
    let level = u32::from(byte() % 5);
    let mut float = || f32::from_bits(u32::from_le_bytes([byte(), byte(), byte(), byte()]));
    let (offset, rotation, scale) = ([float(), float()], float(), [float(), float()]);
    let uv = [[float(), float()], [float(), float()], [float(), float()]];
    let transform = match UvTransform::new(offset, rotation, scale) {
        Ok(t) => t,
        Err(e) => {
            let finite = offset.iter().chain(&scale).all(|x| x.is_finite()) && rotation.is_finite();
            let expected = if finite {
                assert!(rotation.abs() > MAX_ROTATION, "refused {rotation}: {e}");
                UvTransformError::Rotation(rotation)
            } else {
                UvTransformError::NotFinite
            };
            assert_eq!(e, expected);
            return;
        }
    };
    let texture = Unorm8Texture::new(w, h, &texels).expect("w h texels");
    let baker = Baker::new(&texture, sampler, Cutoff::default())
        .expect("a small texture")
        .with_uv_transform(transform);
    let level = Level::new(level).expect("level <= 4");
    let baked = baker
        .bake(&uv, level, Format::FourState, UnknownPolicy::default())
        .unwrap_or_else(|e| panic!("bake failed: {e} ({data:02x?})"));
    let count = level.micro_triangle_count() as u64;
    let states: Vec<State> = match &baked.opacity {
        BakedOpacity::Map(map) => (0..count)
            .map(|i| map.get(i).expect("index in range"))
            .collect(),
        BakedOpacity::Special(s) => {
            assert!(
                matches!(
                    baked.status,
                    TriangleStatus::NotFinite | TriangleStatus::OutOfExactRange
                ),
                "a special index with status {:?}",
                baked.status
            );
            vec![*s; count as usize]
        }
    };
    let case = Case {
        texels: &texels,
        width: w,
        height: h,
        sampler,
        uv,
        transform: (offset, rotation, scale),
    };
    let (known, wrong, first) = judge(&case, &states, level.get());
    assert_eq!(
        wrong, 0,
        "{wrong} of {known} known micro-triangles contradicted, first (index, b1, b2) {first:?} ({data:02x?})"
    );
}
