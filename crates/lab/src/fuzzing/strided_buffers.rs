//! The body of the `strided_buffers` fuzz target, replayed on stable by
//! `tests/fuzz_corpus.rs`.

use super::micromap_buffers::{decode, hex};
use micromap_index::micromap::{read_buffers, BufferBytes, ReadError, ReadOptions};

/// The elements a strided read of `bytes` takes: `element` bytes at every
/// multiple of `stride` (`None` if one is cut short).
fn gather(bytes: &[u8], stride: usize, element: usize) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(bytes.len());
    for start in (0..bytes.len()).step_by(stride) {
        out.extend_from_slice(bytes.get(start..start.checked_add(element)?)?);
    }
    Some(out)
}

/// `element`-byte elements of `bytes` laid `stride` bytes apart, the gaps
/// filled with `junk + k`, ending with a whole stride or right after the
/// last element.
fn spread(bytes: &[u8], element: usize, stride: usize, junk: u8, whole: bool) -> Vec<u8> {
    let mut out = Vec::with_capacity(bytes.len() / element * stride);
    for chunk in bytes.chunks_exact(element) {
        out.extend_from_slice(chunk);
        out.extend((element..stride).map(|k| junk.wrapping_add(k as u8)));
    }
    if !whole && !out.is_empty() {
        out.truncate(out.len() - (stride - element));
    }
    out
}

/// `micromap::read_buffers` at record and index strides from the input.
/// Splits `data` as: byte 0 a record stride, byte 1 an index stride (each
/// 0..=255, allowed or not; index stride 0 means the width, tight), byte 2 the junk between elements, byte 3 bit
/// 0 set when the strided buffers end with a whole stride; the rest is a
/// [`micromap_buffers`](super::micromap_buffers) input (flags, lengths,
/// records, usage counts, indices, data). Checks that
///
/// 1. the input's bytes read at the raw strides never panic; a stride is
///    refused (`RecordStride` / `IndexStride`) exactly when
///    `ReadOptions::check_strides` refuses it, and what is accepted equals
///    the tight read of the elements the strides pick;
/// 2. when the bytes read tightly, the same records and indices laid out
///    again at allowed strides derived from bytes 0 and 1 (record stride
///    `8 + 4 (b0 % 8)`, index stride the width times `1 + b1 % 4`), junk in
///    the gaps, read back equal to the tight read.
///
/// Panics only when one of these fails, printing the input in hex.
///
/// ```
/// use micromap_index_lab::fuzzing::strided_buffers;
/// for data in [&[][..], &[0xff; 40][..], &[12, 4, 0xee, 1, 2, 8, 0, 0, 0, 2, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0x5a]] {
///     strided_buffers(data);
/// }
/// ```
pub fn strided_buffers(data: &[u8]) {
    let byte = |i: usize| data.get(i).copied().unwrap_or(0);
    let (raw_record, raw_index) = (usize::from(byte(0)), usize::from(byte(1)));
    let (junk, whole) = (byte(2), byte(3) & 1 != 0);
    let input = decode(data.get(4..).unwrap_or_default());
    let fail = |what: &str| -> ! { panic!("strided_buffers: {what}; input {}", hex(data)) };
    let width = input.bytes.indices.map(|(_, width)| width);

    // 1. The raw strides.
    let raw = ReadOptions {
        record_stride: raw_record,
        index_stride: (raw_index != 0).then_some(raw_index),
        ..input.options
    };
    let allowed = raw.check_strides(width);
    let read = read_buffers(&input.bytes, &raw);
    match (&allowed, &read) {
        (Err(refused), read) if read.as_ref().err() != Some(refused) => {
            fail(&format!(
                "check_strides refused ({refused}) but read_buffers said {read:?}"
            ));
        }
        (Ok(()), Err(e @ (ReadError::RecordStride { .. } | ReadError::IndexStride { .. }))) => {
            fail(&format!(
                "check_strides allowed the strides but read_buffers refused: {e}"
            ));
        }
        _ => {}
    }
    if let Ok(read) = &read {
        let records = gather(input.bytes.records, raw_record, 8)
            .unwrap_or_else(|| fail("accepted records cut short"));
        let indices = input.bytes.indices.map(|(bytes, width)| {
            let stride = if raw_index == 0 {
                width.bytes()
            } else {
                raw_index
            };
            let gathered = gather(bytes, stride, width.bytes())
                .unwrap_or_else(|| fail("accepted indices cut short"));
            (gathered, width)
        });
        let tight = read_buffers(
            &BufferBytes {
                records: &records,
                indices: indices.as_ref().map(|(bytes, width)| (&bytes[..], *width)),
                ..input.bytes
            },
            &input.options,
        );
        if tight.as_ref() != Ok(read) {
            fail(&format!(
                "the strided read differs from the tight read of its elements: {tight:?}"
            ));
        }
    }

    // 2. Re-laid at allowed strides.
    let Ok(tight) = read_buffers(&input.bytes, &input.options) else {
        return;
    };
    let record_stride = 8 + 4 * (raw_record % 8);
    let index_multiple = 1 + raw_index % 4;
    let index_stride = width.map(|width| width.bytes() * index_multiple);
    let records = spread(input.bytes.records, 8, record_stride, junk, whole);
    let indices = input.bytes.indices.map(|(bytes, width)| {
        let stride = width.bytes() * index_multiple;
        (spread(bytes, width.bytes(), stride, junk, whole), width)
    });
    let again = read_buffers(
        &BufferBytes {
            records: &records,
            indices: indices.as_ref().map(|(bytes, width)| (&bytes[..], *width)),
            ..input.bytes
        },
        &ReadOptions {
            record_stride,
            index_stride,
            ..input.options
        },
    );
    if again.as_ref() != Ok(&tight) {
        fail(&format!(
            "re-laid at strides {record_stride} and {index_stride:?} the buffers read {again:?}"
        ));
    }
}
