//! The body of the `micromap_buffers` fuzz target, replayed on stable by
//! `tests/fuzz_corpus.rs`.

use micromap_index::micromap::{
    read_buffers, BufferBytes, BuildOptions, IndexWidth, MicromapBuffersBuilder, MicromapIndex,
    Overlap, ReadBuffers, ReadOptions, TriangleOpacity,
};

/// The decoded fuzz input: the four byte slices and the options.
pub(super) struct Input<'a> {
    pub(super) bytes: BufferBytes<'a>,
    pub(super) options: ReadOptions,
}

/// Splits `data` as: a flags byte (bits 0-1: index width none/u8/u16/u32;
/// bit 2: usage counts present; bit 3: [`Overlap::Allow`] with a 64 KiB
/// limit; bits 4-5: the base triangle), then three little-endian `u16`
/// lengths (records, usage counts, indices, each cut to what is left),
/// then those slices in that order; the rest is the data. Missing bytes
/// read as zero.
pub(super) fn decode(data: &[u8]) -> Input<'_> {
    let byte = |i: usize| data.get(i).copied().unwrap_or(0);
    let flags = byte(0);
    let len = |i: usize| usize::from(u16::from_le_bytes([byte(i), byte(i + 1)]));
    let mut rest = data.get(7..).unwrap_or_default();
    let mut take = |n: usize| {
        let (head, tail) = rest.split_at(n.min(rest.len()));
        rest = tail;
        head
    };
    let records = take(len(1));
    let usage = take(len(3));
    let indices = take(len(5));
    let width = match flags & 3 {
        1 => Some(IndexWidth::U8),
        2 => Some(IndexWidth::U16),
        3 => Some(IndexWidth::U32),
        _ => None,
    };
    Input {
        bytes: BufferBytes {
            records,
            data: rest,
            usage_counts: (flags & 4 != 0).then_some(usage),
            indices: width.map(|w| (indices, w)),
        },
        options: ReadOptions {
            overlap: if flags & 8 != 0 {
                Overlap::Allow {
                    max_decoded_bytes: 1 << 16,
                }
            } else {
                Overlap::Forbid
            },
            base_triangle: u32::from(flags >> 4 & 3),
            ..ReadOptions::default()
        },
    }
}

pub(super) fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write;
    bytes.iter().fold(String::new(), |mut hex, b| {
        let _ = write!(hex, "{b:02x}");
        hex
    })
}

/// [`read_buffers`] on arbitrary bytes never panics; what it accepts is
/// consistent (one micromap per record with the record's level and format,
/// each micro-triangle's state the bits the API reads at the record's
/// offset) and survives a rebuild: the micromaps the triangles reference,
/// written again by [`MicromapBuffersBuilder`] and read back, are the same.
/// Panics only when one of these fails, printing the input in hex.
///
/// ```
/// use micromap_index_lab::fuzzing::micromap_buffers;
/// for data in [&[][..], &[0xff; 40][..], &[2, 8, 0, 0, 0, 2, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0x5a]] {
///     micromap_buffers(data);
/// }
/// ```
pub fn micromap_buffers(data: &[u8]) {
    let input = decode(data);
    let Ok(read) = read_buffers(&input.bytes, &input.options) else {
        return;
    };
    let fail = |what: &str| -> ! { panic!("micromap_buffers: {what}; input {}", hex(data)) };
    check_against_bytes(&read, input.bytes.data).unwrap_or_else(|what| fail(&what));
    // The triangles: the index buffer's, else one per record.
    let triangles: Vec<MicromapIndex> = match &read.indices {
        Some(indices) => indices.clone(),
        None => (0..read.records.len() as u32)
            .map(MicromapIndex::Record)
            .collect(),
    };
    let opacity = |index: MicromapIndex| match index {
        MicromapIndex::Record(r) => read.micromaps.get(r as usize).map_or_else(
            || fail("an accepted index names no record"),
            TriangleOpacity::Micromap,
        ),
        MicromapIndex::Special(state) => TriangleOpacity::Special(state),
    };
    let mut builder = MicromapBuffersBuilder::new(BuildOptions {
        uniform_to_special: false,
        ..BuildOptions::default()
    });
    let rebuilt = builder
        .add_geometry(triangles.iter().map(|&t| opacity(t)))
        .and_then(|_| builder.finish())
        .unwrap_or_else(|e| fail(&format!("rebuild failed: {e}")));
    let width = IndexWidth::narrowest(
        rebuilt.max_record_index(),
        micromap_index::micromap::Api::Gltf,
    );
    let records = rebuilt.records_le_bytes();
    let usage = micromap_index::micromap::usage_counts_to_le_bytes(rebuilt.usage_counts());
    let index_bytes = rebuilt
        .index_bytes(0, width)
        .unwrap_or_else(|e| fail(&format!("index buffer failed: {e}")));
    let again = read_buffers(
        &BufferBytes {
            records: &records,
            data: rebuilt.data(),
            usage_counts: Some(&usage),
            indices: Some((&index_bytes, width)),
        },
        &ReadOptions::default(),
    )
    .unwrap_or_else(|e| fail(&format!("the rebuilt buffers do not read back: {e}")));
    let again_indices = again.indices.unwrap_or_default();
    if again_indices.len() != triangles.len() {
        fail("the rebuilt index buffer has another length");
    }
    for (t, (&before, &after)) in triangles.iter().zip(&again_indices).enumerate() {
        let same = match (opacity(before), after) {
            (TriangleOpacity::Special(a), MicromapIndex::Special(b)) => a == b,
            (TriangleOpacity::Micromap(a), MicromapIndex::Record(r)) => {
                again.micromaps.get(r as usize) == Some(a)
            }
            _ => false,
        };
        if !same {
            fail(&format!("triangle {t} changed in the rebuild"));
        }
    }
}

/// Every micromap has its record's level and format, and state `i` is the
/// `bits` bits at bit `i * bits` of the record's block.
fn check_against_bytes(read: &ReadBuffers, data: &[u8]) -> Result<(), String> {
    if read.micromaps.len() != read.records.len() {
        return Err(String::from("not one micromap per record"));
    }
    for (k, (record, map)) in read.records.iter().zip(&read.micromaps).enumerate() {
        if u32::from(record.subdivision_level) != map.level().get()
            || record.format != map.format().raw()
        {
            return Err(format!("record {k}: level or format differs"));
        }
        let bits = map.format().bits_per_state() as usize;
        let base = record.data_offset as usize * 8;
        for (i, state) in map.states().enumerate() {
            let mut value = 0u8;
            for b in 0..bits {
                let bit = base + i * bits + b;
                let byte = data.get(bit / 8).copied().unwrap_or(0);
                value |= (byte >> (bit % 8) & 1) << b;
            }
            if value != state.bits() {
                return Err(format!("record {k} micro-triangle {i}: state differs"));
            }
        }
    }
    Ok(())
}
