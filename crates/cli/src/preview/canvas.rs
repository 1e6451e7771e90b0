//! The picture a preview is drawn on: an RGB canvas that blends colours
//! into its pixels, and the colours of the four states (shared by the
//! tiles and the legend).

/// Colours by state value: transparent blue, opaque green, unknown-
/// transparent red, unknown-opaque yellow.
pub(super) const COLOURS: [[u8; 3]; 4] =
    [[40, 90, 255], [40, 200, 60], [235, 60, 40], [250, 210, 30]];

/// An RGB picture, row-major, 3 bytes a pixel.
pub(super) struct Canvas {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) rgb: Vec<u8>,
}

impl Canvas {
    /// Mixes `colour` into pixel `(x, y)` with `weight` in `[0, 1]`;
    /// pixels outside the canvas are ignored.
    pub(super) fn blend(&mut self, x: i64, y: i64, colour: [u8; 3], weight: f32) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return;
        }
        let at = (y as usize * self.width as usize + x as usize) * 3;
        // In fixed point (weight in 256ths, rounded): no float rounding
        // call per channel; weight 1 copies the colour exactly.
        let w = (weight.clamp(0.0, 1.0) * 256.0 + 0.5) as u32;
        for (slot, &c) in self.rgb[at..at + 3].iter_mut().zip(&colour) {
            *slot = ((u32::from(*slot) * (256 - w) + u32::from(c) * w + 128) >> 8) as u8;
        }
    }
}
