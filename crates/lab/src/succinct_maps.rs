//! Micromaps for the succinct-tree tests, the size example and the
//! benchmark: synthetic ones and ones sampled from the Crytek Sponza alpha
//! textures in `assets/crytek-sponza/` (read from the repository, so for
//! the lab's tests, benches and examples only).

use micromap_index::inverse::micro_triangle;
use micromap_index::micromap::{Format, State};
use micromap_index::Level;
use micromap_index_test_support::SplitMix64;

/// `4^level`.
#[must_use]
pub fn count(level: u32) -> usize {
    1 << (2 * level)
}

fn level(level: u32) -> Level {
    Level::new(level).expect("levels up to 32")
}

/// Every micro-triangle in `state`.
#[must_use]
pub fn uniform(level: u32, state: State) -> Vec<State> {
    vec![state; count(level)]
}

/// The paper's worst case: states alternate along the curve
/// (transparent, opaque, ... or all four states in turn), so no quadrant
/// is uniform at any level.
#[must_use]
pub fn alternating(level: u32, format: Format) -> Vec<State> {
    let period = format.bits_per_state() as usize * 2;
    (0..count(level)).map(|i| State::ALL[i % period]).collect()
}

/// Opaque inside the disc of radius 0.3 around the centroid `(1/3, 1/3)`
/// of the base triangle, transparent outside. A 2-state map asks about the
/// micro-triangle's centroid; a 4-state map about its three vertices: all
/// inside opaque, all outside transparent, otherwise unknown-opaque.
#[must_use]
pub fn disc(level_n: u32, format: Format) -> Vec<State> {
    let inside = |(u, v): (f64, f64)| {
        let (du, dv) = (u - 1.0 / 3.0, v - 1.0 / 3.0);
        du * du + dv * dv <= 0.09
    };
    (0..count(level_n) as u64)
        .map(|i| {
            let t = micro_triangle(level(level_n), i).expect("index in range");
            match format {
                Format::TwoState => State::ALL[usize::from(inside(t.centroid_f64()))],
                Format::FourState => {
                    let n = t.vertices_f64().into_iter().filter(|&p| inside(p)).count();
                    match n {
                        0 => State::Transparent,
                        3 => State::Opaque,
                        _ => State::UnknownOpaque,
                    }
                }
            }
        })
        .collect()
}

/// Independent states: opaque with probability `density` (per mille),
/// otherwise transparent; in a 4-state map a further 1 in 16 of the
/// micro-triangles is unknown-opaque.
#[must_use]
pub fn noise(level: u32, format: Format, density_per_mille: u64, seed: u64) -> Vec<State> {
    let mut rng = SplitMix64::new(seed);
    (0..count(level))
        .map(|_| {
            let r = rng.next_u64();
            if format == Format::FourState && r % 16 == 0 {
                State::UnknownOpaque
            } else if (r >> 8) % 1000 < density_per_mille {
                State::Opaque
            } else {
                State::Transparent
            }
        })
        .collect()
}

/// `states` with micro-triangle `index` changed to the next state the
/// format holds.
#[must_use]
pub fn with_one_change(states: &[State], format: Format, index: usize) -> Vec<State> {
    let mut out = states.to_vec();
    let bits = out[index].bits() + 1;
    out[index] = State::ALL[(bits % (2 * format.bits_per_state() as u8)) as usize];
    out
}

/// An alpha texture: width, height, alpha bytes row by row (row 0 first).
pub struct AlphaTexture {
    /// The file name under `assets/crytek-sponza/`.
    pub name: &'static str,
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` alpha bytes, row 0 first.
    pub alpha: Vec<u8>,
}

/// Reads `assets/crytek-sponza/<file>` (an RGBA or grey+alpha PNG).
///
/// # Panics
///
/// If the file cannot be read or has no alpha channel.
#[must_use]
pub fn sponza_texture(file: &'static str) -> AlphaTexture {
    let path =
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/crytek-sponza/").to_string() + file;
    let reader = std::fs::File::open(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut decoder = png::Decoder::new(std::io::BufReader::new(reader));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder
        .read_info()
        .unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut buf = vec![0; reader.output_buffer_size().expect("image size fits")];
    let info = reader
        .next_frame(&mut buf)
        .unwrap_or_else(|e| panic!("{path}: {e}"));
    let channels = info.color_type.samples();
    assert!(
        info.color_type == png::ColorType::Rgba
            || info.color_type == png::ColorType::GrayscaleAlpha,
        "{path}: no alpha channel ({:?})",
        info.color_type
    );
    let alpha = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|px| px[channels - 1])
        .collect();
    AlphaTexture {
        name: file,
        width: info.width as usize,
        height: info.height as usize,
        alpha,
    }
}

impl AlphaTexture {
    /// Whether the texel nearest to texture coordinate `(s, t)` (in
    /// `[0, 1]`, clamped) has alpha at least 128.
    #[must_use]
    pub fn opaque_at(&self, (s, t): (f64, f64)) -> bool {
        let x = ((s * self.width as f64) as usize).min(self.width - 1);
        let y = ((t * self.height as f64) as usize).min(self.height - 1);
        self.alpha[y * self.width + x] >= 128
    }

    /// The micromap of one of the two triangles that cover the texture
    /// (`half` 0: texture corners (0,0), (1,0), (0,1) as vertices 0, 1, 2;
    /// `half` 1: (1,1), (0,1), (1,0)), sampled with the nearest texel: a
    /// 2-state map at each micro-triangle's centroid; a 4-state map at its
    /// centroid and three vertices (all opaque: opaque, none: transparent,
    /// otherwise unknown, opaque or transparent as the centroid). A sampler,
    /// not a conservative baker: texels between the samples are not seen.
    #[must_use]
    pub fn micromap(&self, level_n: u32, format: Format, half: usize) -> Vec<State> {
        let corners = [
            [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)],
            [(1.0, 1.0), (0.0, 1.0), (1.0, 0.0)],
        ][half % 2];
        let texcoord = |(u, v): (f64, f64)| {
            let w = 1.0 - u - v;
            (
                w * corners[0].0 + u * corners[1].0 + v * corners[2].0,
                w * corners[0].1 + u * corners[1].1 + v * corners[2].1,
            )
        };
        (0..count(level_n) as u64)
            .map(|i| {
                let t = micro_triangle(level(level_n), i).expect("index in range");
                let centre = self.opaque_at(texcoord(t.centroid_f64()));
                match format {
                    Format::TwoState => State::ALL[usize::from(centre)],
                    Format::FourState => {
                        let corners = t
                            .vertices_f64()
                            .into_iter()
                            .filter(|&p| self.opaque_at(texcoord(p)))
                            .count();
                        match (corners, centre) {
                            (3, true) => State::Opaque,
                            (0, false) => State::Transparent,
                            (_, true) => State::UnknownOpaque,
                            (_, false) => State::UnknownTransparent,
                        }
                    }
                }
            })
            .collect()
    }
}
