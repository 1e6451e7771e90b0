//! The body of the fuzz target `inverse_round_trip`, replayed on stable by
//! `crates/lab/tests/fuzz_corpus.rs`.

#[allow(clippy::wildcard_imports)]
use super::*;

/// The point `(x, y) / 2^scale_log2` as exact rationals.
fn dyadic(x: u64, y: u64, scale_log2: u32) -> (BigRational, BigRational) {
    let denominator = BigInt::from(1u8) << scale_log2;
    (
        BigRational::new(x.into(), denominator.clone()),
        BigRational::new(y.into(), denominator),
    )
}

/// Every index the crate's exact implementations give the dyadic point
/// `(x, y) / 2^scale_log2` at `level`, checked equal (the slow all-BigRational
/// walk only `with_ref`); `what` names the point in messages. Returns the
/// walk's index.
fn index_of_dyadic(
    x: u64,
    y: u64,
    scale_log2: u32,
    level: Level,
    what: &str,
    with_ref: bool,
) -> u64 {
    let (u, v) = dyadic(x, y, scale_log2);
    let at = || format!("{what} ({u}, {v}) at level {level}");
    let walk = uv2index::index_real(&u, &v, level);
    if with_ref {
        let walk_ref = micromap_index::internals::index_real_ref(&u, &v, level);
        assert_eq!(
            walk,
            walk_ref,
            "uv2index::index_real = {walk:?} but index_real_ref = {walk_ref:?} at {}",
            at()
        );
    }
    let Ok(walk) = walk else {
        panic!("{} is not in the triangle: {walk:?}", at());
    };
    // Numerators have at most 35 bits: exact in binary64.
    let scale = 1.0 / (1u64 << scale_log2) as f64;
    let (uf, vf) = (x as f64 * scale, y as f64 * scale);
    let by_fixed = uv2index::exact_index_f64(uf, vf, level);
    assert_eq!(
        by_fixed,
        Ok(walk),
        "uv2index::exact_index_f64 = {by_fixed:?} but the walk says {walk} at {}",
        at()
    );
    if let Ok(spec_level) = SpecLevel::try_from(level) {
        let by_spec = u64::from(spec::index_real(&u, &v, spec_level));
        let by_dyadic = spec::index_dyadic(x, y, scale_log2, spec_level).map(u64::from);
        assert_eq!(
            (by_spec, by_dyadic),
            (walk, Ok(walk)),
            "spec::index_real / index_dyadic disagree with the walk ({walk}) at {}",
            at()
        );
    } else {
        let wide = spec::wide_index_real(&u, &v, level);
        let wide_dyadic = spec::wide_index_dyadic(x, y, scale_log2, level);
        assert_eq!(
            (wide, wide_dyadic),
            (walk, Ok(walk)),
            "spec::wide_index_real / wide_index_dyadic disagree with the walk ({walk}) at {}",
            at()
        );
    }
    walk
}

/// The vertex set of a micro-triangle, sorted.
fn vertex_set(triangle: &MicroTriangle) -> [(u64, u64); 3] {
    let mut vertices = triangle.vertices_scaled();
    vertices.sort_unstable();
    vertices
}

/// Round trip: index → [`inverse::micro_triangle`](micromap_index::inverse::micro_triangle) → points → the walk.
///
/// Decoding: byte `0`: level `= byte % 33`; bytes `1..9`: the index
/// (little-endian `u64`) reduced modulo `4^level`; byte `9`: which vertex
/// (`byte % 3`) gets weight 2 in the interior point.
///
/// Checks, with `V0, V1, V2` the micro-triangle's vertices:
///
/// * the interior point `(2 Va + Vb + Vc) / 4` and the centroid map back to
///   the index under the exact walk (`BigRational` and fast path; for the
///   centroid the fast path), the
///   fixed-point walk, and the reference over the reals (32-bit words up to
///   level 16, 64-bit words above; rational and dyadic versions); up to
///   level 16 also under the reference in binary32 and its integer mirror;
/// * the vertices have the shape `upright()` claims (`(a, b), (a+1, b),
///   (a, b+1)` or `(a+1, b), (a, b+1), (a+1, b+1)`, each a lattice point of
///   the closed triangle) and wind counter-clockwise exactly when upright;
/// * each vertex maps, under every exact implementation alike (but the
///   slow all-BigRational walk), to a micro-triangle that has it as a
///   vertex;
/// * each neighbour is `None` exactly for edges on the base triangle's
///   boundary, otherwise another valid index whose micro-triangle shares
///   the edge; each edge midpoint maps to this index or that neighbour.
///
/// ```
/// use micromap_index_lab::fuzzing::inverse_round_trip;
/// // Level 3, index 42, weight 2 on vertex 1.
/// inverse_round_trip(&[3, 42, 0, 0, 0, 0, 0, 0, 0, 1]);
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn inverse_round_trip(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let Ok(level) = Level::new(u32::from(bytes.byte()) % 33) else {
        return;
    };
    let index = (u128::from(bytes.u64()) % level.micro_triangle_count()) as u64;
    let heavy = usize::from(bytes.byte() % 3);
    let triangle = match micro_triangle(level, index) {
        Ok(triangle) => triangle,
        Err(e) => panic!("micro_triangle(level {level}, index {index}) failed: {e}"),
    };
    assert_eq!(
        (triangle.level(), triangle.index()),
        (level, index),
        "micro_triangle(level {level}, index {index}) reports another level or index"
    );
    let vertices = triangle.vertices_scaled();
    let side = 1u64 << level.get();

    // Shape and orientation.
    let [p, q, r] = vertices;
    let corner = (
        vertices.iter().map(|v| v.0).min().unwrap_or(0),
        vertices.iter().map(|v| v.1).min().unwrap_or(0),
    );
    let (a, b) = corner;
    let mut expected = if triangle.upright() {
        [(a, b), (a + 1, b), (a, b + 1)]
    } else {
        [(a + 1, b), (a, b + 1), (a + 1, b + 1)]
    };
    expected.sort_unstable();
    assert_eq!(
        vertex_set(&triangle),
        expected,
        "level {level} index {index}: vertices {vertices:?} do not have the shape upright() = {} claims",
        triangle.upright()
    );
    for (x, y) in vertices {
        assert!(
            x + y <= side,
            "level {level} index {index}: vertex ({x}, {y}) / 2^{level} is outside the triangle"
        );
    }
    let cross = |o: (u64, u64), s: (u64, u64), t: (u64, u64)| {
        let d = |m: (u64, u64)| {
            (
                i128::from(m.0) - i128::from(o.0),
                i128::from(m.1) - i128::from(o.1),
            )
        };
        let (s, t) = (d(s), d(t));
        s.0 * t.1 - s.1 * t.0
    };
    assert_eq!(
        cross(p, q, r) > 0,
        triangle.upright(),
        "level {level} index {index}: vertices {vertices:?} wind against upright() = {}",
        triangle.upright()
    );

    // Interior points map back.
    let (b1, b2) = ((heavy + 1) % 3, (heavy + 2) % 3);
    let x = 2 * vertices[heavy].0 + vertices[b1].0 + vertices[b2].0;
    let y = 2 * vertices[heavy].1 + vertices[b1].1 + vertices[b2].1;
    let back = index_of_dyadic(x, y, level.get() + 2, level, "interior point", true);
    assert_eq!(
        back,
        index,
        "level {level} index {index}: interior point ({x}, {y}) / 2^{} walks to {back}",
        level.get() + 2
    );
    let (cu, cv) = triangle.centroid_rational();
    let by_centroid = uv2index::index_real(&cu, &cv, level);
    assert_eq!(
        by_centroid,
        Ok(index),
        "level {level} index {index}: centroid ({cu}, {cv}) walks to {by_centroid:?}"
    );
    if level.get() <= spec::MAX_LEVEL {
        // (x, y) / 2^(level + 2) has at most 19 significant bits: exact in
        // binary32, and its fractions are multiples of 1/4, far from where
        // binary32 rounds the reference's diagonal test.
        let scale = 1.0 / (1u64 << (level.get() + 2)) as f32;
        let (uf, vf) = (x as f32 * scale, y as f32 * scale);
        let by_f32 = spec::reference_bits_f32(uf, vf, level.get());
        let by_mirror = spec::reference_bits_f32_by_integers(uf, vf, level.get());
        assert_eq!(
            (u64::from(by_f32), u64::from(by_mirror)),
            (index, index),
            "level {level} index {index}: spec::index_f32 / index_mirror_f32 at (0x{:08x}, 0x{:08x})",
            uf.to_bits(),
            vf.to_bits()
        );
    }

    // Vertices map to a micro-triangle having them as a vertex.
    for (i, &(vx, vy)) in vertices.iter().enumerate() {
        let owner = index_of_dyadic(vx, vy, level.get(), level, "vertex", false);
        let owner_vertices = match micro_triangle(level, owner) {
            Ok(t) => t.vertices_scaled(),
            Err(e) => panic!("level {level}: vertex {i} walks to {owner}, which fails: {e}"),
        };
        assert!(
            owner_vertices.contains(&(vx, vy)),
            "level {level} index {index}: vertex {i} ({vx}, {vy}) / 2^{level} walks to {owner} with vertices {owner_vertices:?}"
        );
    }

    // Neighbours and edge midpoints.
    let neighbours = triangle.neighbours();
    for (i, neighbour) in neighbours.into_iter().enumerate() {
        let (s, t) = (vertices[(i + 1) % 3], vertices[(i + 2) % 3]);
        let on_boundary = (s.0 == 0 && t.0 == 0)
            || (s.1 == 0 && t.1 == 0)
            || (s.0 + s.1 == side && t.0 + t.1 == side);
        assert_eq!(
            neighbour.is_none(),
            on_boundary,
            "level {level} index {index}: neighbour {i} is {neighbour:?} for edge {s:?}-{t:?}"
        );
        if let Some(n) = neighbour {
            let shared = match micro_triangle(level, n) {
                Ok(other) => other.vertices_scaled(),
                Err(e) => panic!("level {level} index {index}: neighbour {i} = {n} fails: {e}"),
            };
            assert!(
                n != index && shared.contains(&s) && shared.contains(&t),
                "level {level} index {index}: neighbour {i} = {n} (vertices {shared:?}) does not share edge {s:?}-{t:?}"
            );
        }
        let midpoint = index_of_dyadic(
            s.0 + t.0,
            s.1 + t.1,
            level.get() + 1,
            level,
            "midpoint",
            false,
        );
        assert!(
            midpoint == index || Some(midpoint) == neighbour,
            "level {level} index {index}: midpoint of edge {i} walks to {midpoint}, neither this nor neighbour {neighbour:?}"
        );
    }
}
