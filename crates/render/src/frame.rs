//! What one traced frame holds: the committed hit of every pixel, the
//! [`Counters`] and the first [`Contradiction`]s, as the shaders wrote
//! them (the word layouts are the shaders' `COUNTERS` and `RECORD_WORDS`).

use crate::method::{Lookup, Method, Tracer};

/// Most pixels of a frame (the pixel buffer's words stay below 2^31).
pub const MAX_PIXELS: u64 = 1 << 22;

/// Words per pixel (shader `PIXEL_WORDS`): committed triangle + 1, t's
/// bits, contradicted candidates.
pub(crate) const PIXEL_WORDS: usize = 3;
/// Counter words before the contradiction records (shader `COUNTERS`).
pub(crate) const COUNTER_WORDS: usize = 8;
/// Words per contradiction record (shader `RECORD_WORDS`).
pub(crate) const RECORD_WORDS: usize = 8;

/// What one frame counted, over all its rays. The device counts in 32
/// bits: a frame would need 2^32 candidates to wrap, far above the
/// [`MAX_PIXELS`] frames with tens of candidates per ray seen here.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Primary rays (one per pixel).
    pub rays: u64,
    /// Candidate hits the traversal reported to the shader.
    pub candidates: u64,
    /// Alpha tests the method ran (texture fetches; a bilinear fetch reads
    /// four texels and counts once).
    pub texture_fetches: u64,
    /// Candidates decided by a known state.
    pub known: u64,
    /// Candidates whose state was unknown (decided by the alpha test).
    pub unknown: u64,
    /// Known decisions the alpha test contradicts.
    pub contradicted: u64,
    /// Lookups that returned the shader library's invalid state (a
    /// malformed buffer; never expected after the host's checks).
    pub invalid: u64,
}

/// A candidate whose known state the alpha test contradicted, as the
/// shader recorded it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contradiction {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// The triangle (the scene's order, the BLAS's primitive index).
    pub triangle: u32,
    /// The micro-triangle the shader looked up (0 for a special index).
    pub micro_triangle: u32,
    /// The hit's barycentric `b1` (weight of vertex 1), binary32 bits.
    pub b1_bits: u32,
    /// `b2`, binary32 bits.
    pub b2_bits: u32,
    /// The known state the method decided by (0 transparent, 1 opaque).
    pub state: u32,
    /// The alpha the alpha test compared with the cutoff (the filtered
    /// alpha times the alpha factor, binary32 bits), as the lookup read it.
    pub alpha_bits: u32,
}

/// One traced frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The tracer that traced it.
    pub tracer: Tracer,
    /// What read the texture for its alpha tests.
    pub lookup: Lookup,
    /// The method it was traced with.
    pub method: Method,
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Per pixel (row-major, row 0 at the top): the committed triangle + 1
    /// (0: no hit) and the hit distance's binary32 bits.
    pub hits: Vec<[u32; 2]>,
    /// The counters.
    pub counters: Counters,
    /// The first contradictions in pixel order (row-major; within a pixel
    /// by triangle and barycentrics), at most the `max_records` asked for:
    /// the same records whatever order the device ran the candidates in.
    pub contradictions: Vec<Contradiction>,
    /// Process CPU seconds of the dispatch (the CPU device's threads are
    /// the process's), where the platform has a process clock.
    pub cpu_seconds: Option<f64>,
    /// Wall-clock seconds of the dispatch.
    pub wall_seconds: f64,
    /// Seconds between the device's timestamps around the dispatch, where
    /// its queue writes timestamps (the frame time on a GPU).
    pub device_seconds: Option<f64>,
}

impl Frame {
    /// The fraction of pixels whose ray committed a hit.
    #[must_use]
    pub fn hit_fraction(&self) -> f64 {
        if self.hits.is_empty() {
            return 0.0;
        }
        self.hits.iter().filter(|h| h[0] != 0).count() as f64 / self.hits.len() as f64
    }
}

/// The counters of the shader's counter words.
pub(crate) fn counters_from_words(c: &[u32]) -> Counters {
    Counters {
        rays: u64::from(c[0]),
        candidates: u64::from(c[1]),
        texture_fetches: u64::from(c[2]),
        known: u64::from(c[3]),
        unknown: u64::from(c[4]),
        contradicted: u64::from(c[5]),
        invalid: u64::from(c[6]),
    }
}

/// The contradiction records of the shader's counter words (at most
/// `max_records`), for a frame `width` pixels wide, ordered by pixel (then
/// triangle, barycentrics, state, micro-triangle): the order does not
/// depend on the order the device ran the candidates in.
pub(crate) fn records_from_words(c: &[u32], max_records: u32, width: u32) -> Vec<Contradiction> {
    let recorded = (c[7] as usize).min(max_records as usize);
    let mut records: Vec<(u32, Contradiction)> = (0..recorded)
        .map(|r| {
            let w = &c[COUNTER_WORDS + RECORD_WORDS * r..][..RECORD_WORDS];
            let record = Contradiction {
                x: w[0] % width,
                y: w[0] / width,
                triangle: w[1],
                micro_triangle: w[2],
                b1_bits: w[3],
                b2_bits: w[4],
                state: w[5],
                alpha_bits: w[7],
            };
            (w[0], record)
        })
        .collect();
    records.sort_by_key(|(pixel, r)| {
        (
            *pixel,
            r.triangle,
            r.b1_bits,
            r.b2_bits,
            r.state,
            r.micro_triangle,
        )
    });
    records.into_iter().map(|(_, r)| r).collect()
}
