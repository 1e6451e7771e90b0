//! Micromaps and their API buffers: the curve's hierarchy (children of `i`
//! are `4i..4i+3`, every micro-triangle of levels 0..=10), packing against a
//! bit-by-bit oracle, get/set against a `Vec<State>` model, merge and
//! upsample laws, deduplication, layout, round trips through bytes, and one
//! named test per [`ReadError`].

use micromap_index::inverse::micro_triangle;
use micromap_index::micromap::BakedOpacity;
use micromap_index::micromap::{
    read_buffers, records_to_le_bytes, usage_counts_to_le_bytes, Api, BufferBytes, BufferError,
    BuildOptions, Format, IndexWidth, MergeRule, Micromap, MicromapBuffers, MicromapBuffersBuilder,
    MicromapError, MicromapIndex, Overlap, ReadError, ReadOptions, State, TriangleOpacity,
    TriangleRecord, UnknownPolicy, UsageCount,
};
use micromap_index::{spec, Level, SpecLevel};
use proptest::prelude::*;
use std::collections::{BTreeSet, HashMap};

fn level(n: u32) -> Level {
    Level::new(n).unwrap()
}

type Point = (u64, u64);

/// The four triangles of the midpoint split of `parent` (vertices in units
/// of `2^-n`), as unordered vertex sets in units of `2^-(n+1)`.
fn midpoint_split(parent: [Point; 3]) -> BTreeSet<BTreeSet<Point>> {
    let [a, b, c] = parent.map(|(u, v)| (2 * u, 2 * v));
    let mid = |p: Point, q: Point| ((p.0 + q.0) / 2, (p.1 + q.1) / 2);
    let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
    [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        .into_iter()
        .map(|t| t.into_iter().collect())
        .collect()
}

/// The unordered vertex sets of micro-triangles `children` at `level`.
fn vertex_sets(level: Level, children: impl Iterator<Item = u64>) -> BTreeSet<BTreeSet<Point>> {
    children
        .map(|i| {
            micro_triangle(level, i)
                .unwrap()
                .vertices_scaled()
                .into_iter()
                .collect()
        })
        .collect()
}

/// Whether children `first..first + 4` at level `n + 1` tile parent `i` at
/// level `n` exactly (the four sets of its midpoint split).
fn children_tile_parent(n: u32, i: u64, first: u64) -> bool {
    let parent = micro_triangle(level(n), i).unwrap().vertices_scaled();
    vertex_sets(level(n + 1), first..first + 4) == midpoint_split(parent)
}

#[test]
fn children_of_i_are_4i_to_4i_plus_3_for_every_micro_triangle_of_levels_0_to_10() {
    let mut checked = 0u64;
    for n in 0..=10u32 {
        for i in 0..1u64 << (2 * n) {
            assert!(
                children_tile_parent(n, i, 4 * i),
                "level {n} index {i}: children {}..={} at level {} do not tile it",
                4 * i,
                4 * i + 3,
                n + 1
            );
            checked += 1;
        }
    }
    // 1 + 4 + ... + 4^10 parents.
    assert_eq!(checked, (4u64.pow(11) - 1) / 3);
}

#[test]
fn the_children_check_rejects_wrong_children() {
    // The check can fail: a neighbouring parent's children, or a window
    // shifted by one, do not tile the parent.
    assert!(!children_tile_parent(1, 1, 0));
    assert!(!children_tile_parent(2, 5, 21));
    assert!(!children_tile_parent(3, 17, 4 * 17 + 1));
}

#[test]
fn the_spec_index_of_every_child_centroid_names_its_parent_at_levels_0_to_10() {
    // Independent of the tiling: the reference at level n maps the (exact
    // binary32-rounded, still interior) centroid of child j at level n + 1
    // to j / 4.
    for n in 0..=9u32 {
        for j in 0..1u64 << (2 * (n + 1)) {
            let (u, v) = micro_triangle(level(n + 1), j).unwrap().centroid_f32();
            let parent = spec::index_f32(u, v, SpecLevel::new(n).unwrap());
            assert_eq!(
                u64::from(parent),
                j / 4,
                "child {j} at level {} (centroid {:#x}, {:#x})",
                n + 1,
                u.to_bits(),
                v.to_bits()
            );
        }
    }
}

#[test]
fn byte_len_matches_the_spec_formula_for_every_level() {
    for n in 0..=Micromap::MAX_LEVEL {
        for format in [Format::TwoState, Format::FourState] {
            let bits = 4u128.pow(n) * u128::from(format.bits_per_state());
            let want = bits.div_ceil(8) as usize;
            assert_eq!(
                Micromap::byte_len(level(n), format),
                want,
                "level {n} {format}"
            );
        }
    }
}

#[test]
fn levels_above_16_are_refused_without_allocating() {
    for n in 17..=32 {
        for format in [Format::TwoState, Format::FourState] {
            assert_eq!(
                Micromap::new(level(n), format),
                Err(MicromapError::LevelTooHigh { level: n, max: 16 })
            );
        }
    }
    assert_eq!(
        Micromap::new(level(0), Format::TwoState)
            .unwrap()
            .merge_one_level(MergeRule::Conservative),
        Err(MicromapError::NoCoarserLevel)
    );
}

#[test]
fn from_micro_triangles_passes_the_inverse_vertices() {
    let lvl = level(4);
    let mut seen = Vec::new();
    Micromap::from_micro_triangles(lvl, Format::TwoState, |i, vertices| {
        seen.push((i, vertices));
        State::Transparent
    })
    .unwrap();
    assert_eq!(seen.len(), 256);
    for (i, vertices) in seen {
        assert_eq!(vertices, micro_triangle(lvl, i).unwrap().vertices_scaled());
    }
}

// ---------------------------------------------------------------------------
// Strategies and oracles.

fn any_format() -> impl Strategy<Value = Format> {
    prop_oneof![Just(Format::TwoState), Just(Format::FourState)]
}

fn any_state_for(format: Format) -> BoxedStrategy<State> {
    match format {
        Format::TwoState => prop_oneof![Just(State::Transparent), Just(State::Opaque)].boxed(),
        Format::FourState => (0u8..4).prop_map(|b| State::from_bits(b).unwrap()).boxed(),
    }
}

/// A level, a format and `4^level` states the format holds; `alphabet`
/// limits the distinct states (1 makes uniform maps likely).
fn any_states(max_level: u32) -> impl Strategy<Value = (u32, Format, Vec<State>)> {
    (0..=max_level, any_format(), 1usize..=4).prop_flat_map(|(n, format, alphabet)| {
        let len = 1usize << (2 * n);
        let states = any_state_for(format);
        // Pick `alphabet` states, then fill with them.
        (
            Just(n),
            Just(format),
            proptest::collection::vec(states, alphabet).prop_flat_map(move |pool| {
                proptest::collection::vec(proptest::sample::select(pool), len)
            }),
        )
    })
}

fn any_map(max_level: u32) -> impl Strategy<Value = Micromap> {
    any_states(max_level)
        .prop_map(|(n, format, states)| Micromap::from_states(level(n), format, states).unwrap())
}

/// The packing written out bit by bit from the spec's words: state `i`'s
/// bit `k` is bit `(i * bits + k) % 8` of byte `(i * bits + k) / 8`.
fn pack_naive(n: u32, format: Format, states: &[State]) -> Vec<u8> {
    let bits = format.bits_per_state() as usize;
    let len = ((1usize << (2 * n)) * bits).div_ceil(8);
    let mut bytes = vec![0u8; len];
    for (i, state) in states.iter().enumerate() {
        for k in 0..bits {
            if state.bits() >> k & 1 == 1 {
                let bit = i * bits + k;
                bytes[bit / 8] |= 1 << (bit % 8);
            }
        }
    }
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn packing_matches_the_bitwise_oracle_and_unpacks((n, format, states) in any_states(6)) {
        let map = Micromap::from_states(level(n), format, states.iter().copied()).unwrap();
        let naive = pack_naive(n, format, &states);
        prop_assert_eq!(map.as_bytes(), naive.as_slice());
        prop_assert_eq!(map.states().collect::<Vec<_>>(), states.clone());
        for (i, &s) in states.iter().enumerate() {
            prop_assert_eq!(map.get(i as u64), Some(s));
        }
        prop_assert_eq!(map.get(map.len()), None);
        prop_assert_eq!(Micromap::from_bytes(level(n), format, map.as_bytes()), Ok(map.clone()));
        let uniform = states.iter().all(|&s| s == states[0]).then_some(states[0]);
        prop_assert_eq!(map.uniform(), uniform);
        prop_assert_eq!(map.special_index(), uniform.map(State::special_index));
    }

    #[test]
    fn set_and_get_follow_a_vec_model(
        (n, format) in (0u32..=5, any_format()),
        ops in proptest::collection::vec((any::<u64>(), 0u8..4), 0..200),
    ) {
        let mut map = Micromap::new(level(n), format).unwrap();
        let mut model = vec![State::Transparent; 1 << (2 * n)];
        for (raw_index, bits) in ops {
            // Mostly in range, sometimes just past it.
            let index = raw_index % (map.len() + 2);
            let state = State::from_bits(bits).unwrap();
            let result = map.set(index, state);
            if index >= map.len() {
                prop_assert_eq!(result, Err(MicromapError::IndexOutOfRange { index, len: map.len() }));
            } else if !format.holds(state) {
                prop_assert_eq!(result, Err(MicromapError::StateNotInFormat { state, format }));
            } else {
                prop_assert_eq!(result, Ok(()));
                model[index as usize] = state;
            }
            prop_assert_eq!(map.get(index), model.get(index as usize).copied());
        }
        let naive = pack_naive(n, format, &model);
        prop_assert_eq!(map.as_bytes(), naive.as_slice());
    }

    #[test]
    fn state_at_a_centroid_is_that_micro_triangles_state(map in any_map(6), pick in any::<u64>()) {
        let i = pick % map.len();
        let (u, v) = micro_triangle(map.level(), i).unwrap().centroid_f32();
        prop_assert_eq!(map.state_at(u, v), map.get(i).unwrap());
    }

    #[test]
    fn upsample_then_merge_is_the_identity(map in any_map(6)) {
        let fine = map.upsample_one_level().unwrap();
        prop_assert_eq!(fine.level().get(), map.level().get() + 1);
        for j in 0..fine.len() {
            prop_assert_eq!(fine.get(j), map.get(j / 4));
        }
        for rule in [MergeRule::Conservative, MergeRule::UnknownOpaque] {
            prop_assert_eq!(&fine.merge_one_level(rule).unwrap(), &map);
        }
    }

    #[test]
    fn merge_applies_the_rule_to_each_quad(map in any_map(6)) {
        prop_assume!(map.level().get() > 0);
        for rule in [MergeRule::Conservative, MergeRule::UnknownOpaque] {
            let parent = map.merge_one_level(rule).unwrap();
            prop_assert_eq!(parent.format(), map.format());
            for i in 0..parent.len() {
                let quad = [0, 1, 2, 3].map(|c| map.get(4 * i + c).unwrap());
                let merged = rule.merge(quad);
                let want = if map.format().holds(merged) { merged } else { merged.to_two_state() };
                prop_assert_eq!(parent.get(i), Some(want));
                // Equal children keep their state; mixed ones never become known
                // in a 4-state map.
                if quad.iter().all(|&s| s == quad[0]) {
                    prop_assert_eq!(parent.get(i), Some(quad[0]));
                } else if map.format() == Format::FourState {
                    prop_assert!(!parent.get(i).unwrap().is_known());
                }
            }
        }
    }

    #[test]
    fn merging_a_uniform_map_down_to_level_0_keeps_its_special_index(
        (n, format, state) in (0u32..=6, any_format(), 0u8..4),
    ) {
        let state = State::from_bits(state).unwrap();
        prop_assume!(format.holds(state));
        let mut map = Micromap::uniform_map(level(n), format, state).unwrap();
        while map.level().get() > 0 {
            map = map.merge_one_level(MergeRule::Conservative).unwrap();
            prop_assert_eq!(map.special_index(), Some(state.special_index()));
        }
        prop_assert_eq!(map.uniform(), Some(state));
    }

    #[test]
    fn format_conversion_resolves_unknowns_by_policy(map in any_map(5)) {
        let four = map.to_format(Format::FourState, UnknownPolicy::Fallback).unwrap();
        prop_assert!(four.states().eq(map.states()));
        for policy in [UnknownPolicy::Fallback, UnknownPolicy::Opaque, UnknownPolicy::Transparent] {
            let two = four.to_format(Format::TwoState, policy).unwrap();
            prop_assert!(two.states().eq(map.states().map(|s| policy.resolve(s))));
            // Fallback is the APIs' force-2-state reading.
            if policy == UnknownPolicy::Fallback {
                prop_assert!(two.states().eq(map.states().map(State::to_two_state)));
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Buffers.

/// Checks the layout promises of `buffers`: blocks inside the data,
/// disjoint, naturally aligned, gap-free, equal to their micromaps; usage
/// counts equal to naive histograms.
fn check_layout(buffers: &MicromapBuffers) {
    assert_eq!(buffers.micromaps().count(), buffers.records().len());
    let mut end = 0usize;
    for (record, map) in buffers.records().iter().zip(buffers.micromaps()) {
        let start = record.data_offset as usize;
        let len = map.as_bytes().len();
        assert_eq!(start, end, "blocks are packed without gaps: {record:?}");
        assert_eq!(start % len, 0, "block not naturally aligned: {record:?}");
        assert_eq!(&buffers.data()[start..start + len], map.as_bytes());
        assert_eq!(u32::from(record.subdivision_level), map.level().get());
        assert_eq!(record.format, map.format().raw());
        end = start + len;
    }
    assert_eq!(end, buffers.data().len());
    let mut naive: HashMap<(u32, u32), u32> = HashMap::new();
    for r in buffers.records() {
        *naive
            .entry((u32::from(r.subdivision_level), u32::from(r.format)))
            .or_default() += 1;
    }
    let got: HashMap<(u32, u32), u32> = buffers
        .usage_counts()
        .iter()
        .map(|u| ((u.subdivision_level, u.format), u.count))
        .collect();
    assert_eq!(got, naive);
    for g in 0..buffers.geometry_count() {
        let mut naive: HashMap<(u32, u32), u32> = HashMap::new();
        for index in buffers.geometry_indices(g).unwrap() {
            if let MicromapIndex::Record(r) = *index {
                let r = buffers.records()[r as usize];
                *naive
                    .entry((u32::from(r.subdivision_level), u32::from(r.format)))
                    .or_default() += 1;
            }
        }
        let got: HashMap<(u32, u32), u32> = buffers
            .geometry_usage_counts(g)
            .unwrap()
            .iter()
            .map(|u| ((u.subdivision_level, u.format), u.count))
            .collect();
        assert_eq!(got, naive, "geometry {g}");
    }
}

/// Triangles drawn from a small pool of maps (so duplicates are common) and
/// special indices.
fn any_geometry() -> impl Strategy<Value = (Vec<Micromap>, Vec<Option<(usize, u8)>>)> {
    proptest::collection::vec(any_map(4), 1..6).prop_flat_map(|pool| {
        let n = pool.len();
        (
            Just(pool),
            proptest::collection::vec(
                prop_oneof![
                    3 => (0..n, Just(0u8)).prop_map(Some),
                    1 => (Just(usize::MAX), 0u8..4).prop_map(Some),
                ],
                0..40,
            ),
        )
    })
}

fn opacities<'a>(pool: &'a [Micromap], picks: &[Option<(usize, u8)>]) -> Vec<TriangleOpacity<'a>> {
    picks
        .iter()
        .flatten()
        .map(|&(i, s)| match pool.get(i) {
            Some(map) => TriangleOpacity::Micromap(map),
            None => TriangleOpacity::Special(State::from_bits(s).unwrap()),
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn dedup_gives_equal_content_one_record_and_different_content_different_records(
        (pool, picks) in any_geometry(),
        uniform_to_special in any::<bool>(),
    ) {
        let triangles = opacities(&pool, &picks);
        let buffers = MicromapBuffers::build(triangles.iter().copied(), BuildOptions { uniform_to_special, ..BuildOptions::default() }).unwrap();
        check_layout(&buffers);
        let indices = buffers.geometry_indices(0).unwrap();
        prop_assert_eq!(indices.len(), triangles.len());
        for (a, ta) in triangles.iter().enumerate() {
            // Each triangle resolves to what it was given (or its uniform state).
            match (*ta, buffers.resolve(0, a).unwrap()) {
                (TriangleOpacity::Micromap(m), BakedOpacity::Map(got)) => {
                    prop_assert_eq!(m, &got);
                    prop_assert!(!(uniform_to_special && m.uniform().is_some()));
                }
                (TriangleOpacity::Micromap(m), BakedOpacity::Special(s)) => {
                    prop_assert!(uniform_to_special);
                    prop_assert_eq!(m.uniform(), Some(s));
                }
                (TriangleOpacity::Special(s), got) => prop_assert_eq!(got, BakedOpacity::Special(s)),
            }
            for (b, tb) in triangles.iter().enumerate() {
                if let (TriangleOpacity::Micromap(ma), TriangleOpacity::Micromap(mb),
                        MicromapIndex::Record(ra), MicromapIndex::Record(rb)) = (*ta, *tb, indices[a], indices[b]) {
                    prop_assert_eq!(ma == mb, ra == rb, "triangles {} and {}", a, b);
                    prop_assert_eq!(ma == mb, buffers.records()[ra as usize].data_offset == buffers.records()[rb as usize].data_offset);
                }
            }
        }
        // No two records hold equal micromaps.
        let distinct: BTreeSet<_> = buffers.micromaps().collect();
        prop_assert_eq!(distinct.len(), buffers.records().len());
    }

    #[test]
    fn buffers_round_trip_through_bytes(
        geometries in proptest::collection::vec(any_geometry(), 1..4),
        api in prop_oneof![Just(Api::VulkanExt), Just(Api::VulkanKhr), Just(Api::Dxr), Just(Api::Gltf)],
    ) {
        let mut builder = MicromapBuffersBuilder::new(BuildOptions::default());
        for (pool, picks) in &geometries {
            builder.add_geometry(opacities(pool, picks)).unwrap();
        }
        let buffers = builder.finish().unwrap();
        check_layout(&buffers);
        let width = IndexWidth::narrowest(buffers.max_record_index(), api);
        prop_assert_eq!(buffers.check_for(api, width), Ok(()));
        let records = buffers.records_le_bytes();
        let usage = usage_counts_to_le_bytes(buffers.usage_counts());
        for g in 0..buffers.geometry_count() {
            let index_bytes = buffers.index_bytes(g, width).unwrap();
            prop_assert_eq!(index_bytes.len(), buffers.geometry_indices(g).unwrap().len() * width.bytes());
            let read = read_buffers(
                &BufferBytes {
                    records: &records,
                    data: buffers.data(),
                    usage_counts: Some(&usage),
                    indices: Some((&index_bytes, width)),
                },
                &ReadOptions::default(),
            ).unwrap();
            prop_assert_eq!(read.records.as_slice(), buffers.records());
            prop_assert_eq!(read.micromaps, buffers.micromaps().collect::<Vec<_>>());
            prop_assert_eq!(read.indices.as_deref(), Some(buffers.geometry_indices(g).unwrap()));
        }
    }

    #[test]
    fn no_mixed_special_indices_unmixes_with_shared_level_zero_records_and_same_states(
        geometries in proptest::collection::vec(any_geometry(), 1..4),
        uniform_to_special in any::<bool>(),
    ) {
        let build = |no_mixed_special_indices| {
            let mut builder = MicromapBuffersBuilder::new(BuildOptions { uniform_to_special, no_mixed_special_indices });
            for (pool, picks) in &geometries {
                builder.add_geometry(opacities(pool, picks)).unwrap();
            }
            builder.finish().unwrap()
        };
        let (mixed, unmixed) = (build(false), build(true));
        check_layout(&unmixed);
        let four_state = mixed.records().iter().any(|r| r.format == Format::FourState.raw());
        let mut added = BTreeSet::new();
        for g in 0..mixed.geometry_count() {
            prop_assert!(!unmixed.is_mixed(g).unwrap(), "geometry {}", g);
            let before = mixed.geometry_indices(g).unwrap();
            let after = unmixed.geometry_indices(g).unwrap();
            prop_assert_eq!(before.len(), after.len());
            let all_special = before.iter().all(|i| matches!(i, MicromapIndex::Special(_)));
            prop_assert_eq!(mixed.is_mixed(g).unwrap(), !all_special
                && before.iter().any(|i| matches!(i, MicromapIndex::Special(_))));
            for (t, &index) in after.iter().enumerate() {
                // Every micro-triangle reads the same state as before.
                let (was, now) = (mixed.resolve(g, t).unwrap(), unmixed.resolve(g, t).unwrap());
                match (was, now, index) {
                    (BakedOpacity::Map(a), BakedOpacity::Map(b), _) => prop_assert_eq!(a, b),
                    (BakedOpacity::Special(a), BakedOpacity::Special(b), _) => {
                        prop_assert!(all_special);
                        prop_assert_eq!(a, b);
                    }
                    (BakedOpacity::Special(s), BakedOpacity::Map(m), MicromapIndex::Record(r)) => {
                        prop_assert!(!all_special);
                        prop_assert_eq!(m.level().get(), 0);
                        prop_assert_eq!(m.uniform(), Some(s));
                        let format = if four_state || !s.is_known() { Format::FourState } else { Format::TwoState };
                        prop_assert_eq!(m.format(), format);
                        added.insert((r, m));
                    }
                    other => prop_assert!(false, "triangle {} of geometry {}: {:?}", t, g, other),
                }
            }
        }
        // At most one shared record per state, and no more records than
        // those (fewer when an equal level-0 map was already there).
        let added: BTreeSet<Micromap> = added.into_iter().map(|(_, m)| m).collect();
        prop_assert!(added.len() <= 4);
        let before: BTreeSet<Micromap> = mixed.micromaps().collect();
        prop_assert_eq!(unmixed.records().len(), mixed.records().len() + added.difference(&before).count());
        let distinct: BTreeSet<_> = unmixed.micromaps().collect();
        prop_assert_eq!(distinct.len(), unmixed.records().len());
    }

    #[test]
    fn the_reader_never_panics_on_arbitrary_bytes(
        records in proptest::collection::vec(any::<u8>(), 0..64),
        data in proptest::collection::vec(any::<u8>(), 0..64),
        usage in proptest::option::of(proptest::collection::vec(any::<u8>(), 0..40)),
        indices in proptest::option::of((proptest::collection::vec(any::<u8>(), 0..16), 0usize..3)),
        allow in any::<bool>(),
        base_triangle in 0u32..4,
    ) {
        let input = BufferBytes {
            records: &records,
            data: &data,
            usage_counts: usage.as_deref(),
            indices: indices.as_ref().map(|(b, w)| (b.as_slice(), IndexWidth::ALL[*w])),
        };
        let options = ReadOptions {
            overlap: if allow { Overlap::Allow { max_decoded_bytes: 1 << 16 } } else { Overlap::Forbid },
            base_triangle,
            ..ReadOptions::default()
        };
        if let Ok(read) = read_buffers(&input, &options) {
            prop_assert_eq!(read.records.len(), records.len() / 8);
            prop_assert_eq!(read.micromaps.len(), read.records.len());
            for (r, m) in read.records.iter().zip(&read.micromaps) {
                prop_assert_eq!(u32::from(r.subdivision_level), m.level().get());
                prop_assert_eq!(r.format, m.format().raw());
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Index encoding, records, named errors.

#[test]
fn every_8_and_16_bit_index_value_decodes_and_re_encodes() {
    for width in [IndexWidth::U8, IndexWidth::U16] {
        for raw in 0..=width.all_ones() {
            match MicromapIndex::decode(raw, width) {
                Some(index) => {
                    assert_eq!(index.encode(width), Ok(raw), "{width} {raw:#x}");
                    // The signed value is the two's-complement reading for specials.
                    if let MicromapIndex::Special(s) = index {
                        let signed = i64::from(raw) - i64::from(width.all_ones()) - 1;
                        assert_eq!(signed, i64::from(s.special_index()));
                    }
                }
                None => assert_eq!(raw, width.all_ones() - 4, "only -5 is refused"),
            }
        }
    }
    for (raw, want) in [
        (
            0xffff_ffff,
            Some(MicromapIndex::Special(State::Transparent)),
        ),
        (
            0xffff_fffc,
            Some(MicromapIndex::Special(State::UnknownOpaque)),
        ),
        (0xffff_fffb, None),
        (0xffff_fffa, Some(MicromapIndex::Record(0xffff_fffa))),
    ] {
        assert_eq!(MicromapIndex::decode(raw, IndexWidth::U32), want);
    }
}

#[test]
fn records_and_usage_serialise_little_endian() {
    let records = [
        TriangleRecord {
            data_offset: 0x0403_0201,
            subdivision_level: 0x0605,
            format: 0x0807,
        },
        TriangleRecord {
            data_offset: 9,
            subdivision_level: 10,
            format: 1,
        },
    ];
    assert_eq!(
        records_to_le_bytes(&records),
        [1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 0, 0, 10, 0, 1, 0]
    );
    let usage = [UsageCount {
        count: 0x0403_0201,
        subdivision_level: 0x0807_0605,
        format: 0x0c0b_0a09,
    }];
    assert_eq!(
        usage_counts_to_le_bytes(&usage),
        [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]
    );
}

#[test]
fn blocks_are_sorted_by_decreasing_size_and_naturally_aligned() {
    // Sizes 1, 4, 2, 16 bytes in input order.
    let states = |n: u32, f: Format| {
        Micromap::from_index_fn(level(n), f, |i| {
            if i == 0 {
                State::Opaque
            } else {
                State::Transparent
            }
        })
        .unwrap()
    };
    let maps = [
        states(1, Format::TwoState),
        states(2, Format::FourState),
        states(2, Format::TwoState),
        states(3, Format::FourState),
    ];
    let buffers = MicromapBuffers::build(
        maps.iter().map(TriangleOpacity::Micromap),
        BuildOptions::default(),
    )
    .unwrap();
    let layout: Vec<(u32, usize)> = buffers
        .records()
        .iter()
        .zip(buffers.micromaps())
        .map(|(r, m)| (r.data_offset, m.as_bytes().len()))
        .collect();
    assert_eq!(layout, [(0, 16), (16, 4), (20, 2), (22, 1)]);
    assert_eq!(
        buffers.geometry_indices(0).unwrap(),
        [3, 1, 2, 0].map(MicromapIndex::Record)
    );
    check_layout(&buffers);
}

#[test]
fn index_widths_follow_the_api_and_refuse_overflow() {
    // 252 distinct level-2 2-state maps: record numbers up to 251 > 250.
    let maps: Vec<Micromap> = (0..252u64)
        .map(|k| {
            Micromap::from_index_fn(level(2), Format::TwoState, |i| {
                if (k + 1) >> i & 1 == 1 {
                    State::Opaque
                } else {
                    State::Transparent
                }
            })
            .unwrap()
        })
        .collect();
    let buffers = MicromapBuffers::build(
        maps.iter().map(TriangleOpacity::Micromap),
        BuildOptions::default(),
    )
    .unwrap();
    assert_eq!(buffers.records().len(), 252);
    assert_eq!(buffers.max_record_index(), Some(251));
    assert_eq!(
        buffers.index_bytes(0, IndexWidth::U8),
        Err(BufferError::IndexDoesNotFit {
            index: 251,
            width: IndexWidth::U8
        })
    );
    assert_eq!(IndexWidth::narrowest(Some(251), Api::Dxr), IndexWidth::U16);
    assert!(buffers.index_bytes(0, IndexWidth::U16).is_ok());
    assert_eq!(
        buffers.check_for(Api::VulkanExt, IndexWidth::U8),
        Err(BufferError::IndexWidthNotAllowed {
            width: IndexWidth::U8,
            api: Api::VulkanExt
        })
    );
    let deep = Micromap::from_index_fn(level(13), Format::TwoState, |i| {
        if i == 0 {
            State::Opaque
        } else {
            State::Transparent
        }
    })
    .unwrap();
    let buffers =
        MicromapBuffers::build([TriangleOpacity::Micromap(&deep)], BuildOptions::default())
            .unwrap();
    assert_eq!(
        buffers.check_for(Api::Dxr, IndexWidth::U16),
        Err(BufferError::LevelNotAllowed {
            level: 13,
            max: 12,
            api: Api::Dxr
        })
    );
    assert_eq!(buffers.check_for(Api::VulkanKhr, IndexWidth::U16), Ok(()));
    assert_eq!(
        buffers.geometry_indices(1),
        Err(BufferError::NoSuchGeometry {
            geometry: 1,
            count: 1
        })
    );
}

/// A record `{offset, level, format}` as bytes.
fn rec(offset: u32, level: u16, format: u16) -> [u8; 8] {
    TriangleRecord {
        data_offset: offset,
        subdivision_level: level,
        format,
    }
    .to_le_bytes()
}

fn read(records: &[u8], data: &[u8]) -> Result<micromap_index::micromap::ReadBuffers, ReadError> {
    read_buffers(
        &BufferBytes {
            records,
            data,
            ..Default::default()
        },
        &ReadOptions::default(),
    )
}

#[test]
fn read_error_records_length() {
    assert_eq!(
        read(&[0; 7], &[0]),
        Err(ReadError::RecordsLength { len: 7 })
    );
}

#[test]
fn read_error_invalid_format() {
    for format in [0, 3, 0xffff] {
        assert_eq!(
            read(&rec(0, 0, format), &[0]),
            Err(ReadError::InvalidFormat { record: 0, format })
        );
    }
}

#[test]
fn read_error_level_too_high() {
    assert_eq!(
        read(&rec(0, 17, 1), &[0]),
        Err(ReadError::LevelTooHigh {
            record: 0,
            level: 17,
            max: 16
        })
    );
    let dxr = ReadOptions {
        max_level: 12,
        ..ReadOptions::default()
    };
    assert_eq!(
        read_buffers(
            &BufferBytes {
                records: &rec(0, 13, 1),
                data: &[],
                ..Default::default()
            },
            &dxr
        ),
        Err(ReadError::LevelTooHigh {
            record: 0,
            level: 13,
            max: 12
        })
    );
}

#[test]
fn read_error_block_out_of_bounds() {
    let records = [rec(0, 2, 2), rec(u32::MAX, 0, 1)].concat();
    assert_eq!(
        read(&records, &[0; 4]),
        Err(ReadError::BlockOutOfBounds {
            record: 1,
            offset: u32::MAX,
            len: 1,
            data_len: 4
        })
    );
    assert_eq!(
        read(&rec(1, 2, 2), &[0; 4]),
        Err(ReadError::BlockOutOfBounds {
            record: 0,
            offset: 1,
            len: 4,
            data_len: 4
        })
    );
}

#[test]
fn read_error_overlap_unless_allowed() {
    // Record 1 (bytes 2..4) starts inside record 0 (bytes 0..4); record 2 is
    // a second reference to byte 4.
    let records = [rec(0, 2, 2), rec(2, 2, 1), rec(4, 0, 1), rec(4, 1, 1)].concat();
    let data = [0u8; 5];
    assert_eq!(
        read(&records, &data),
        Err(ReadError::Overlap {
            first: 0,
            second: 1
        })
    );
    let allow = |limit| ReadOptions {
        overlap: Overlap::Allow {
            max_decoded_bytes: limit,
        },
        ..ReadOptions::default()
    };
    let input = BufferBytes {
        records: &records,
        data: &data,
        ..Default::default()
    };
    assert_eq!(read_buffers(&input, &allow(8)).unwrap().micromaps.len(), 4);
    assert_eq!(
        read_buffers(&input, &allow(7)),
        Err(ReadError::DecodedTooLarge { limit: 7 })
    );
    // Adjacent blocks do not overlap; identical ones do.
    assert!(read(&[rec(0, 1, 1), rec(1, 1, 1)].concat(), &[0, 0]).is_ok());
    assert_eq!(
        read(&[rec(1, 1, 1), rec(1, 1, 1)].concat(), &[0, 0]),
        Err(ReadError::Overlap {
            first: 0,
            second: 1
        })
    );
}

#[test]
fn read_clears_unused_bits_as_the_apis_ignore_them() {
    let read = read(&rec(0, 1, 1), &[0xf5]).unwrap();
    assert_eq!(read.micromaps[0].as_bytes(), &[0x05]);
}

#[test]
fn read_error_usage_counts() {
    let records = [rec(0, 1, 1), rec(1, 1, 1), rec(2, 2, 2)].concat();
    let data = [0u8; 6];
    let with_usage = |usage: &[UsageCount]| {
        let bytes = usage_counts_to_le_bytes(usage);
        read_buffers(
            &BufferBytes {
                records: &records,
                data: &data,
                usage_counts: Some(&bytes),
                indices: None,
            },
            &ReadOptions::default(),
        )
        .map(|_| ())
    };
    let u = |count, subdivision_level, format| UsageCount {
        count,
        subdivision_level,
        format,
    };
    assert_eq!(with_usage(&[u(2, 1, 1), u(1, 2, 2)]), Ok(()));
    // Duplicate buckets are summed (glTF).
    assert_eq!(with_usage(&[u(1, 1, 1), u(1, 2, 2), u(1, 1, 1)]), Ok(()));
    assert_eq!(
        with_usage(&[u(1, 1, 1), u(1, 2, 2)]),
        Err(ReadError::UsageMismatch {
            level: 1,
            format: 1,
            declared: 1,
            actual: 2
        })
    );
    assert_eq!(
        with_usage(&[u(2, 1, 1), u(1, 2, 2), u(1, 5, 2)]),
        Err(ReadError::UsageMismatch {
            level: 5,
            format: 2,
            declared: 1,
            actual: 0
        })
    );
    assert_eq!(
        with_usage(&[u(2, 1, 1), u(0, 2, 2)]),
        Err(ReadError::UsageZeroCount { entry: 1 })
    );
    assert_eq!(
        with_usage(&[u(2, 1, 3)]),
        Err(ReadError::UsageInvalidFormat {
            entry: 0,
            format: 3
        })
    );
    let short = [0u8; 13];
    assert_eq!(
        read_buffers(
            &BufferBytes {
                records: &records,
                data: &data,
                usage_counts: Some(&short),
                indices: None
            },
            &ReadOptions::default(),
        ),
        Err(ReadError::UsageCountsLength { len: 13 })
    );
}

#[test]
fn read_error_indices() {
    let records = [rec(0, 1, 1), rec(1, 1, 1)].concat();
    let data = [0u8; 2];
    let with = |bytes: &[u8], width, base_triangle| {
        read_buffers(
            &BufferBytes {
                records: &records,
                data: &data,
                usage_counts: None,
                indices: Some((bytes, width)),
            },
            &ReadOptions {
                base_triangle,
                ..ReadOptions::default()
            },
        )
        .map(|r| r.indices.unwrap())
    };
    assert_eq!(
        with(&[1, 0, 0xfd, 0xff], IndexWidth::U16, 0),
        Ok(vec![
            MicromapIndex::Record(1),
            MicromapIndex::Special(State::UnknownTransparent)
        ])
    );
    assert_eq!(
        with(&[0, 0xff], IndexWidth::U8, 1),
        Ok(vec![
            MicromapIndex::Record(1),
            MicromapIndex::Special(State::Transparent)
        ])
    );
    assert_eq!(
        with(&[1], IndexWidth::U8, 1),
        Err(ReadError::IndexOutOfRange {
            triangle: 0,
            index: 2,
            records: 2
        })
    );
    assert_eq!(
        with(&[2, 0, 0, 0], IndexWidth::U32, 0),
        Err(ReadError::IndexOutOfRange {
            triangle: 0,
            index: 2,
            records: 2
        })
    );
    assert_eq!(
        with(&[0xfa, 0xff, 0xff, 0xff], IndexWidth::U32, u32::MAX),
        Err(ReadError::IndexOutOfRange {
            triangle: 0,
            index: 0xffff_fffa + 0xffff_ffff,
            records: 2
        })
    );
    assert_eq!(
        with(&[0, 0xfb], IndexWidth::U8, 0),
        Err(ReadError::ReservedIndex {
            triangle: 1,
            raw: 0xfb
        })
    );
    assert_eq!(
        with(&[0, 0, 0], IndexWidth::U16, 0),
        Err(ReadError::IndexBufferLength {
            len: 3,
            width: IndexWidth::U16
        })
    );
}

#[cfg(feature = "ash")]
#[test]
fn ash_types_convert_both_ways() {
    use ash::vk;
    let record = TriangleRecord {
        data_offset: 64,
        subdivision_level: 3,
        format: 2,
    };
    let vk_record: vk::MicromapTriangleEXT = record.into();
    assert_eq!(
        (
            vk_record.data_offset,
            vk_record.subdivision_level,
            vk_record.format
        ),
        (64, 3, 2)
    );
    assert_eq!(TriangleRecord::from(vk_record), record);
    let usage = UsageCount {
        count: 5,
        subdivision_level: 3,
        format: 1,
    };
    let vk_usage: vk::MicromapUsageEXT = usage.into();
    assert_eq!(
        (vk_usage.count, vk_usage.subdivision_level, vk_usage.format),
        (5, 3, 1)
    );
    assert_eq!(
        vk::OpacityMicromapFormatEXT::TYPE_4_STATE.as_raw() as u16,
        Format::FourState.raw()
    );
    assert_eq!(UsageCount::from(vk_usage), usage);
}

/// `fill` writes what `set` one index at a time writes, and nothing else:
/// every range of every map up to level 3, both formats, every state the
/// format holds, over a background of another state.
#[test]
fn fill_equals_setting_each_index() {
    for level in 0..=3 {
        let level = Level::new(level).unwrap();
        for format in [Format::TwoState, Format::FourState] {
            let states: Vec<State> = [
                State::Transparent,
                State::Opaque,
                State::UnknownTransparent,
                State::UnknownOpaque,
            ]
            .into_iter()
            .filter(|&s| format == Format::FourState || s.is_known())
            .collect();
            let len = 1u64 << (2 * level.get());
            for &background in &states {
                let mut base = Micromap::new(level, format).unwrap();
                base.fill(0, len, background).unwrap();
                assert!((0..len).all(|i| base.get(i) == Some(background)));
                for &state in &states {
                    for start in 0..=len {
                        for count in 0..=len - start {
                            let mut filled = base.clone();
                            filled.fill(start, count, state).unwrap();
                            let mut set = base.clone();
                            for i in start..start + count {
                                set.set(i, state).unwrap();
                            }
                            assert_eq!(filled, set, "{level:?} {format:?} {start} {count}");
                        }
                    }
                }
            }
        }
    }
}

/// `bytes` as `element`-byte elements `stride` bytes apart, the gaps filled
/// with `fill` (so a reader that looks at them gets them wrong), ending
/// with whole strides or right after the last element.
fn spread(bytes: &[u8], element: usize, stride: usize, fill: u8, whole: bool) -> Vec<u8> {
    let mut out = Vec::new();
    for chunk in bytes.chunks_exact(element) {
        out.extend_from_slice(chunk);
        out.resize(out.len() + stride - element, fill);
    }
    if !whole && !out.is_empty() {
        out.truncate(out.len() - (stride - element));
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn strided_records_and_indices_read_as_the_packed_buffers(
        (pool, picks) in any_geometry(),
        record_extra in 0usize..5,
        index_factor in 1usize..4,
        fill in any::<u8>(),
        whole in any::<bool>(),
        api in prop_oneof![Just(Api::VulkanKhr), Just(Api::Dxr)],
    ) {
        let buffers = MicromapBuffers::build(opacities(&pool, &picks), BuildOptions::default()).unwrap();
        let width = IndexWidth::narrowest(buffers.max_record_index(), api);
        let (records, indices) = (buffers.records_le_bytes(), buffers.index_bytes(0, width).unwrap());
        let usage = usage_counts_to_le_bytes(buffers.usage_counts());
        let read = |records: &[u8], indices: &[u8], options: &ReadOptions| read_buffers(
            &BufferBytes { records, data: buffers.data(), usage_counts: Some(&usage), indices: Some((indices, width)) },
            options,
        );
        let packed = read(&records, &indices, &ReadOptions::default()).unwrap();
        let (record_stride, index_stride) = (8 + 4 * record_extra, width.bytes() * index_factor);
        let options = ReadOptions { record_stride, index_stride: Some(index_stride), ..ReadOptions::default() };
        let strided_records = spread(&records, 8, record_stride, fill, whole);
        let strided_indices = spread(&indices, width.bytes(), index_stride, fill, whole);
        prop_assert_eq!(&read(&strided_records, &strided_indices, &options).unwrap(), &packed);
        // One byte too many or too few after the last element: refused
        // (a byte more with a tight stride is a partial element).
        if !strided_records.is_empty() {
            let short = &strided_records[..strided_records.len() - 1];
            prop_assert!(read(short, &strided_indices, &options).is_err());
        }
        if !strided_indices.is_empty() && index_stride > width.bytes() {
            let mut long = strided_indices.clone();
            long.push(fill);
            // Unless the byte completes one more 8-bit index or stride.
            let rem = long.len() % index_stride;
            if rem != 0 && rem != width.bytes() {
                prop_assert!(read(&strided_records, &long, &options).is_err());
            }
        }
    }
}

#[test]
fn read_options_refuse_strides_the_apis_do_not_allow() {
    let input = BufferBytes {
        records: &[0, 0, 0, 0, 0, 0, 1, 0],
        data: &[0xff],
        usage_counts: None,
        indices: Some((&[0, 0], IndexWidth::U16)),
    };
    let with = |record_stride, index_stride| {
        read_buffers(
            &input,
            &ReadOptions {
                record_stride,
                index_stride,
                ..ReadOptions::default()
            },
        )
    };
    assert!(with(8, None).is_ok());
    assert!(with(12, Some(4)).is_ok());
    for stride in [0, 4, 7, 9, 10, 14] {
        assert_eq!(
            with(stride, None),
            Err(ReadError::RecordStride { stride }),
            "{stride}"
        );
    }
    for stride in [0, 1, 3, 5] {
        assert_eq!(
            with(8, Some(stride)),
            Err(ReadError::IndexStride {
                stride,
                width: IndexWidth::U16
            }),
            "{stride}"
        );
    }
    // The strides are checked before any byte: a bad index stride is
    // reported even when the records are malformed too, and
    // `check_strides` answers the same.
    let mut broken = input;
    broken.records = &[0, 0, 0];
    let bad_index = ReadOptions {
        index_stride: Some(3),
        ..ReadOptions::default()
    };
    let expected = ReadError::IndexStride {
        stride: 3,
        width: IndexWidth::U16,
    };
    assert_eq!(read_buffers(&broken, &bad_index), Err(expected.clone()));
    assert_eq!(
        bad_index.check_strides(Some(IndexWidth::U16)),
        Err(expected)
    );
    // Without an index buffer the index stride is not looked at.
    broken.indices = None;
    assert_eq!(bad_index.check_strides(None), Ok(()));
    assert_eq!(
        read_buffers(&broken, &bad_index),
        Err(ReadError::RecordsLength { len: 3 })
    );
    // 12 bytes at stride 16: neither one whole stride nor one record.
    let mut twelve = input;
    twelve.records = &[0, 0, 0, 0, 0, 0, 1, 0, 9, 9, 9, 9];
    assert_eq!(
        read_buffers(
            &twelve,
            &ReadOptions {
                record_stride: 16,
                ..ReadOptions::default()
            }
        ),
        Err(ReadError::StridedLength {
            len: 12,
            stride: 16,
            element: 8
        })
    );
    assert_eq!(
        read_buffers(
            &twelve,
            &ReadOptions {
                record_stride: 12,
                ..ReadOptions::default()
            }
        )
        .unwrap()
        .records
        .len(),
        1
    );
}
