//! The legend under `preview.png`'s tiles: a swatch and a name for each
//! colour, and the model the bake used, and each tile's caption, in a
//! 5 x 7 pixel font with descenders (drawn here: the CLI takes no font
//! dependency).

use super::canvas::{Canvas, COLOURS};
use micromap_index::bake::Model;
use micromap_index::micromap::State;

/// Font pixels per glyph pixel.
const SCALE: u32 = 2;
/// A glyph cell: 5 x 9 pixels (descenders included) plus one column and
/// one row of spacing.
const CELL_W: u32 = 6 * SCALE;
const LINE_H: u32 = 10 * SCALE;
/// The margin around the legend and the swatch's side.
const MARGIN: u32 = 4 * SCALE;
const SWATCH: u32 = 7 * SCALE;

/// The legend's background and text colours.
const BACKGROUND: [u8; 3] = [24, 24, 24];
const TEXT: [u8; 3] = [235, 235, 235];

/// The legend's lines: a swatch colour (none for the model line) and text.
fn lines(model: Model) -> Vec<(Option<[u8; 3]>, String)> {
    let colour = |state: State| Some(COLOURS[state.bits() as usize]);
    vec![
        (colour(State::Opaque), "opaque".into()),
        (colour(State::Transparent), "transparent".into()),
        (colour(State::UnknownOpaque), "unknown-opaque".into()),
        (
            colour(State::UnknownTransparent),
            "unknown-transparent".into(),
        ),
        (
            Some([130, 130, 130]),
            "outside: no micro-triangle, texture alpha as grey".into(),
        ),
        (Some([255, 255, 255]), "mesh triangle edges".into()),
        (None, format!("model: {}", model.name())),
    ]
}

/// The legend's size in pixels for `model`.
pub(super) fn size(model: Model) -> (u32, u32) {
    let lines = lines(model);
    let longest = lines.iter().map(|(_, t)| t.len() as u32).max().unwrap_or(0);
    (
        2 * MARGIN + SWATCH + MARGIN + longest * CELL_W,
        2 * MARGIN + lines.len() as u32 * LINE_H,
    )
}

/// The pixels between two tiles.
pub(super) const GAP: u32 = MARGIN;

/// The height of a tile's caption strip (one line with its margins).
pub(super) fn caption_height() -> u32 {
    2 * MARGIN + LINE_H
}

/// The width of `text` as a caption (with its margins).
pub(super) fn caption_width(text: &str) -> u32 {
    2 * MARGIN + text.chars().count() as u32 * CELL_W
}

/// Draws the caption strip `text` with its top-left corner at `(x0, y0)`:
/// the legend's background, the text in its colour.
pub(super) fn caption(canvas: &mut Canvas, x0: u32, y0: u32, text: &str) {
    fill_rect(
        canvas,
        x0,
        y0,
        caption_width(text),
        caption_height(),
        BACKGROUND,
    );
    let mut x = x0 + MARGIN;
    for c in text.chars() {
        glyph(canvas, x, y0 + MARGIN, c);
        x += CELL_W;
    }
}

/// Draws the legend with its top-left corner at `(0, top)`.
pub(super) fn draw(canvas: &mut Canvas, top: u32, model: Model) {
    let (width, height) = size(model);
    fill_rect(canvas, 0, top, width.max(canvas.width), height, BACKGROUND);
    for (k, (swatch, text)) in lines(model).iter().enumerate() {
        let y = top + MARGIN + k as u32 * LINE_H;
        if let Some(colour) = swatch {
            fill_rect(canvas, MARGIN, y, SWATCH, SWATCH, *colour);
        }
        let mut x = 2 * MARGIN + SWATCH;
        for c in text.chars() {
            glyph(canvas, x, y, c);
            x += CELL_W;
        }
    }
}

fn fill_rect(canvas: &mut Canvas, x0: u32, y0: u32, w: u32, h: u32, colour: [u8; 3]) {
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            canvas.blend(i64::from(x), i64::from(y), colour, 1.0);
        }
    }
}

fn glyph(canvas: &mut Canvas, x0: u32, y0: u32, c: char) {
    let Some(rows) = rows(c) else {
        return;
    };
    for (r, row) in rows.iter().enumerate() {
        for (col, pixel) in row.bytes().enumerate() {
            if pixel != b'#' {
                continue;
            }
            let (x, y) = (x0 + col as u32 * SCALE, y0 + r as u32 * SCALE);
            fill_rect(canvas, x, y, SCALE, SCALE, TEXT);
        }
    }
}

/// The glyph of `c` (lower case, digits, a little punctuation): 5 pixels
/// wide, 7 rows from the ascender line to the baseline, and 2 more below it
/// for descenders (g, j, p, q, y and the comma); `None` for a space or a
/// character it has no glyph for.
fn rows(c: char) -> Option<&'static [&'static str]> {
    Some(match c {
        'a' => &[
            ".....", ".....", ".###.", "....#", ".####", "#...#", ".####",
        ],
        'b' => &[
            "#....", "#....", "####.", "#...#", "#...#", "#...#", "####.",
        ],
        'c' => &[
            ".....", ".....", ".###.", "#....", "#....", "#...#", ".###.",
        ],
        'd' => &[
            "....#", "....#", ".####", "#...#", "#...#", "#...#", ".####",
        ],
        'e' => &[
            ".....", ".....", ".###.", "#...#", "#####", "#....", ".###.",
        ],
        'f' => &[
            "..##.", ".#..#", ".#...", "###..", ".#...", ".#...", ".#...",
        ],
        'g' => &[
            ".....", ".....", ".####", "#...#", "#...#", "#...#", ".####", "....#", ".###.",
        ],
        'h' => &[
            "#....", "#....", "#.##.", "##..#", "#...#", "#...#", "#...#",
        ],
        'i' => &[
            "..#..", ".....", ".##..", "..#..", "..#..", "..#..", ".###.",
        ],
        'j' => &[
            "...#.", ".....", "..##.", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##..",
        ],
        'k' => &[
            "#....", "#....", "#..#.", "#.#..", "##...", "#.#..", "#..#.",
        ],
        'l' => &[
            ".##..", "..#..", "..#..", "..#..", "..#..", "..#..", ".###.",
        ],
        'm' => &[
            ".....", ".....", "##.#.", "#.#.#", "#.#.#", "#.#.#", "#.#.#",
        ],
        'n' => &[
            ".....", ".....", "#.##.", "##..#", "#...#", "#...#", "#...#",
        ],
        'o' => &[
            ".....", ".....", ".###.", "#...#", "#...#", "#...#", ".###.",
        ],
        'p' => &[
            ".....", ".....", "####.", "#...#", "#...#", "#...#", "####.", "#....", "#....",
        ],
        'q' => &[
            ".....", ".....", ".####", "#...#", "#...#", "#...#", ".####", "....#", "....#",
        ],
        'r' => &[
            ".....", ".....", "#.##.", "##..#", "#....", "#....", "#....",
        ],
        's' => &[
            ".....", ".....", ".####", "#....", ".###.", "....#", "####.",
        ],
        't' => &[
            ".#...", ".#...", "###..", ".#...", ".#...", ".#..#", "..##.",
        ],
        'u' => &[
            ".....", ".....", "#...#", "#...#", "#...#", "#..##", ".##.#",
        ],
        'v' => &[
            ".....", ".....", "#...#", "#...#", "#...#", ".#.#.", "..#..",
        ],
        'w' => &[
            ".....", ".....", "#...#", "#...#", "#.#.#", "#.#.#", ".#.#.",
        ],
        'x' => &[
            ".....", ".....", "#...#", ".#.#.", "..#..", ".#.#.", "#...#",
        ],
        'y' => &[
            ".....", ".....", "#...#", "#...#", "#...#", "#...#", ".####", "....#", ".###.",
        ],
        'z' => &[
            ".....", ".....", "#####", "...#.", "..#..", ".#...", "#####",
        ],
        '0' => &[
            ".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###.",
        ],
        '1' => &[
            "..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###.",
        ],
        '2' => &[
            ".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####",
        ],
        '3' => &[
            "#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###.",
        ],
        '4' => &[
            "...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#.",
        ],
        '5' => &[
            "#####", "#....", "####.", "....#", "....#", "#...#", ".###.",
        ],
        '6' => &[
            "..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###.",
        ],
        '7' => &[
            "#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#...",
        ],
        '8' => &[
            ".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###.",
        ],
        '9' => &[
            ".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##..",
        ],
        '-' => &[
            ".....", ".....", ".....", "#####", ".....", ".....", ".....",
        ],
        ':' => &[
            ".....", ".##..", ".##..", ".....", ".##..", ".##..", ".....",
        ],
        ',' => &[
            ".....", ".....", ".....", ".....", ".....", ".##..", ".##..", "..#..", ".#...",
        ],
        '.' => &[
            ".....", ".....", ".....", ".....", ".....", ".##..", ".##..",
        ],
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every character of every legend line has a glyph (or is a space),
    /// each glyph is 5 wide and 7 rows (9 with a descender) of `#` and `.`,
    /// and no two glyphs are the same.
    #[test]
    fn every_legend_character_has_a_distinct_well_formed_glyph() {
        for model in [Model::GpuBinary32, Model::Exact] {
            for (_, text) in lines(model) {
                for c in text.chars() {
                    assert!(c == ' ' || rows(c).is_some(), "{c:?} in {text:?}");
                }
            }
        }
        let all: Vec<char> = ('a'..='z').chain('0'..='9').chain("-:,.".chars()).collect();
        let glyphs: Vec<_> = all.iter().map(|&c| rows(c).unwrap()).collect();
        for (c, g) in all.iter().zip(&glyphs) {
            assert!(
                (g.len() == 7 || g.len() == 9)
                    && g.iter()
                        .all(|r| r.len() == 5 && r.bytes().all(|b| b == b'#' || b == b'.')),
                "{c:?}"
            );
        }
        for i in 0..glyphs.len() {
            for j in i + 1..glyphs.len() {
                assert_ne!(glyphs[i], glyphs[j], "{:?} and {:?}", all[i], all[j]);
            }
        }
    }

    /// The legend shows each state's colour as a swatch, in the order of
    /// its lines, on its background.
    #[test]
    fn the_legend_draws_each_states_swatch() {
        let model = Model::GpuBinary32;
        let (width, height) = size(model);
        let mut canvas = Canvas {
            width,
            height,
            rgb: vec![0; (width * height * 3) as usize],
        };
        draw(&mut canvas, 0, model);
        let pixel = |x: u32, y: u32| {
            let at = ((y * width + x) * 3) as usize;
            [canvas.rgb[at], canvas.rgb[at + 1], canvas.rgb[at + 2]]
        };
        assert_eq!(pixel(1, 1), BACKGROUND);
        let states = [
            State::Opaque,
            State::Transparent,
            State::UnknownOpaque,
            State::UnknownTransparent,
        ];
        for (k, state) in states.iter().enumerate() {
            let y = MARGIN + k as u32 * LINE_H + SWATCH / 2;
            assert_eq!(
                pixel(MARGIN + SWATCH / 2, y),
                COLOURS[state.bits() as usize]
            );
        }
        // Some text pixels.
        let text = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .filter(|&(x, y)| pixel(x, y) == TEXT)
            .count();
        assert!(text > 500, "{text}");
    }
}
