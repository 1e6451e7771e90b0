//! `preview.png` of a bake: one tile per material (the jobs that share an
//! image and a caption, e.g. `material 3, cutoff 0.3`; side by side, in
//! rows when there are many), each its texture in grey under the caption,
//! every triangle of its jobs tinted by the states of its micro-triangles,
//! the mesh triangles' edges in white, and under the tiles a legend of the
//! colours and the model ([`legend`]). Jobs of different materials on one
//! texture get tiles of their own, so each material's result can be read.
//!
//! The picture is drawn at its own resolution, not per micro-triangle:
//! each pixel whose centre lies in a triangle takes the state of the
//! micro-triangle under that centre, found by the library's index function
//! (`micromap_index::index` of the centre's barycentrics, as a GPU finds a
//! hit's micro-triangle). The cost is the pixels the triangles cover, not
//! `4^level` per triangle, so a level-8 bake's preview costs what a level-2
//! one does; micro-triangles smaller than a pixel are sampled, not
//! averaged.

mod canvas;
mod legend;

use canvas::{Canvas, COLOURS};

use micromap_index::bake::mesh::MeshBake;
use micromap_index::bake::{AddressMode, Model, Sampler, UvTriangle};
use micromap_index::micromap::State;
use micromap_index::SpecLevel;
use micromap_index_assets::{AlphaImage, AlphaTexels};

/// The largest side of the picture we aim for.
const TARGET: u32 = 1024;

/// The most pixels the triangles of one preview may cover in total (their
/// bounding boxes: 2^27, about a second of drawing). Past it the rest are
/// not drawn and their micro-triangles are counted in [`Drawn::skipped`],
/// so a bake of 10^6 overlapping triangles cannot make the preview take
/// hours.
pub(crate) const PIXEL_BUDGET: u64 = 1 << 27;

/// What [`render`] drew.
pub(crate) struct Drawn {
    /// The PNG bytes.
    pub(crate) png: Vec<u8>,
    /// Micro-triangles of the triangles drawn (each pixel shows the one
    /// under its centre).
    pub(crate) micro_triangles: u64,
    /// Micro-triangles not drawn: past [`PIXEL_BUDGET`], or of a triangle
    /// already drawn (the same UVs in the same job bake the same way).
    pub(crate) skipped: u64,
}

/// The most pixels a preview may have (an 8192 x 8192 picture).
const MAX_PIXELS: u64 = 1 << 26;

/// One tile: the image it shows and its caption. Jobs with the same image
/// and caption are drawn on the same tile.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct TileSpec {
    /// Index into the images.
    pub(crate) image: usize,
    /// Drawn above the tile (the legend's font: lower case, digits,
    /// `-:,.` and spaces).
    pub(crate) caption: String,
}

/// The tiles of `jobs` (each job's image and caption), in order of first
/// use, and each job's tile.
pub(crate) fn tiles_of(jobs: impl Iterator<Item = TileSpec>) -> (Vec<TileSpec>, Vec<usize>) {
    let mut tiles: Vec<TileSpec> = Vec::new();
    let mut of_job = Vec::new();
    for job in jobs {
        let at = if let Some(at) = tiles.iter().position(|t| *t == job) {
            at
        } else {
            tiles.push(job);
            tiles.len() - 1
        };
        of_job.push(at);
    }
    (tiles, of_job)
}

/// Where the tiles go and how large the picture is.
struct Layout {
    /// Texels to pixels (1..=8).
    scale: u32,
    /// Each tile's top-left corner (its caption's; the image starts
    /// [`legend::caption_height`] below).
    corners: Vec<(u32, u32)>,
    width: u32,
    height: u32,
    /// The tiles' height (the legend is under it).
    tiles_height: u32,
}

/// The picture's layout for `tiles` of `images` and the legend of `model`,
/// or why it is refused (over [`MAX_PIXELS`]): known before the bake, so a
/// preview too large to draw is refused before any micro-triangle is
/// baked. Tiles go left to right in rows of `ceil(sqrt(n))`, each as wide
/// as its image or its caption, each row as tall as its tallest tile.
fn layout(images: &[AlphaImage], tiles: &[TileSpec], model: Model) -> Result<Layout, String> {
    let max_side = tiles
        .iter()
        .map(|t| images[t.image].width.max(images[t.image].height))
        .max()
        .unwrap_or(1);
    let scale = (TARGET / max_side.max(1)).clamp(1, 8);
    // ceil(sqrt(n)) columns (at least 1), so the picture stays near square.
    let columns = (1..=tiles.len().max(1))
        .find(|c| c * c >= tiles.len())
        .unwrap_or(1);
    let caption = legend::caption_height();
    let mut corners = Vec::new();
    let (mut width, mut height) = (0u32, 0u32);
    for row in tiles.chunks(columns) {
        let (mut x, mut row_height) = (0u32, 0u32);
        for (k, tile) in row.iter().enumerate() {
            let image = &images[tile.image];
            // A gap between tiles, none after the row's last.
            if k > 0 {
                x = x.saturating_add(legend::GAP);
            }
            corners.push((x, height));
            let tile_width =
                (image.width.saturating_mul(scale)).max(legend::caption_width(&tile.caption));
            x = x.saturating_add(tile_width);
            row_height = row_height.max(image.height.saturating_mul(scale).saturating_add(caption));
        }
        width = width.max(x);
        height = height.saturating_add(row_height);
    }
    let tiles_height = height;
    let (legend_width, legend_height) = legend::size(model);
    let width = width.max(legend_width);
    let height = height.saturating_add(legend_height);
    if u64::from(width) * u64::from(height) > MAX_PIXELS {
        return Err(format!(
            "the preview would be {width}x{height} pixels, over the limit of {MAX_PIXELS}: \
             use --no-preview; nothing written"
        ));
    }
    Ok(Layout {
        scale,
        corners,
        width,
        height,
        tiles_height,
    })
}

/// Why the preview of `tiles` of `images` under `model` would be refused,
/// checked before the bake.
pub(crate) fn check_size(
    images: &[AlphaImage],
    tiles: &[TileSpec],
    model: Model,
) -> Result<(), String> {
    layout(images, tiles, model).map(drop)
}

/// The picture as PNG bytes. `tiles` as [`tiles_of`] gives them; `jobs`:
/// (tile index, sampler, triangles), job `j` being mesh `j` of `baked`,
/// baked under `model` (named in the legend); `progress` is told how many
/// triangles (of all jobs together) have been drawn or skipped.
pub(crate) fn render<'a>(
    images: &[AlphaImage],
    tiles: &[TileSpec],
    model: Model,
    jobs: impl Iterator<Item = (usize, Sampler, &'a [UvTriangle])>,
    baked: &MeshBake,
    progress: &mut dyn FnMut(usize),
) -> Result<Drawn, String> {
    let Layout {
        scale,
        corners,
        width,
        height,
        tiles_height,
    } = layout(images, tiles, model)?;
    let mut canvas = Canvas {
        width: width.max(1),
        height: height.max(1),
        rgb: vec![0; width.max(1) as usize * height.max(1) as usize * 3],
    };
    let caption = legend::caption_height();
    for (tile, &(x0, y0)) in tiles.iter().zip(&corners) {
        let image = &images[tile.image];
        legend::caption(&mut canvas, x0, y0, &tile.caption);
        for y in 0..image.height * scale {
            for x in 0..image.width * scale {
                let i = (y / scale) as usize * image.width as usize + (x / scale) as usize;
                let alpha = match &image.texels {
                    AlphaTexels::Unorm8(t) => f32::from(t[i]) / 255.0,
                    AlphaTexels::Unorm16(t) => f32::from(t[i]) / 65535.0,
                    AlphaTexels::Float(t) => t[i].clamp(0.0, 1.0),
                };
                let grey = (40.0 + 180.0 * alpha) as u8;
                canvas.blend(
                    i64::from(x0 + x),
                    i64::from(y0 + caption + y),
                    [grey; 3],
                    1.0,
                );
            }
        }
    }
    let mut pixels_left = PIXEL_BUDGET;
    let (mut drawn, mut skipped) = (0u64, 0u64);
    let mut done = 0;
    for (job, (tile_index, sampler, triangles)) in jobs.enumerate() {
        let image = &images[tiles[tile_index].image];
        let (x0, y0) = corners[tile_index];
        let tile = Tile {
            x0,
            y0: y0 + caption,
            width: image.width * scale,
            height: image.height * scale,
            address: [sampler.address_u, sampler.address_v],
        };
        let mut seen = std::collections::HashSet::new();
        for (t, uv) in triangles.iter().enumerate() {
            done += 1;
            progress(done);
            let Some(b) = baked.triangle(job, t) else {
                continue;
            };
            let count = 1u64 << (2 * b.level.get());
            if !seen.insert(uv.map(|c| c.map(f32::to_bits))) {
                skipped += count;
                continue;
            }
            if uv
                .iter()
                .flatten()
                .any(|c| !c.is_finite() || c.abs() > 64.0)
            {
                continue;
            }
            let corners = uv.map(|c| {
                (
                    f64::from(c[0]) * f64::from(tile.width),
                    f64::from(c[1]) * f64::from(tile.height),
                )
            });
            let (Some(opacity), Ok(level)) = (baked.opacity(job, t), SpecLevel::new(b.level.get()))
            else {
                continue;
            };
            let area = bounding_pixels(&corners);
            if area > pixels_left {
                skipped += count;
                continue;
            }
            pixels_left -= area;
            drawn += count;
            // Each pixel whose centre lies in the triangle takes the state
            // of the micro-triangle under that centre, found as a GPU finds
            // it: the library's index of the centre's barycentrics.
            tile.fill(&mut canvas, corners, |u, v| {
                let state = opacity
                    .state(u64::from(micromap_index::index(u, v, level)))
                    .unwrap_or(State::UnknownOpaque);
                (COLOURS[state.bits() as usize], 0.55)
            });
            for k in 0..3 {
                tile.line(&mut canvas, corners[k], corners[(k + 1) % 3]);
            }
        }
    }
    legend::draw(&mut canvas, tiles_height, model);
    let png = encode(&canvas)?;
    Ok(Drawn {
        png,
        micro_triangles: drawn,
        skipped,
    })
}

/// The pixels of `p`'s bounding box (what `fill` visits), at least 1.
fn bounding_pixels(p: &[(f64, f64); 3]) -> u64 {
    let span = |k: fn(&(f64, f64)) -> f64| {
        let lo = p.iter().map(k).fold(f64::INFINITY, f64::min).floor();
        let hi = p.iter().map(k).fold(f64::NEG_INFINITY, f64::max).ceil();
        (hi - lo).max(1.0)
    };
    let area = span(|q| q.0) * span(|q| q.1);
    if area.is_finite() && area < 1e18 {
        area as u64
    } else {
        u64::MAX
    }
}

/// Where a pixel `i` of a `size`-pixel axis lands in the tile under `mode`:
/// where the sampler reads it (`AddressMode::wrap`) on the periods the
/// texture is repeated on, `None` elsewhere (clamped axes draw only the
/// tile itself, mirror-clamp-to-edge the tile and its one mirror image).
fn wrap(mode: AddressMode, i: i64, size: u32) -> Option<i64> {
    let period = i.div_euclid(i64::from(size.max(1)));
    let repeated = match mode {
        AddressMode::Repeat | AddressMode::MirroredRepeat => true,
        AddressMode::MirrorClampToEdge => period == 0 || period == -1,
        // Clamp-to-edge, clamp-to-border and modes added later: only the
        // tile itself.
        _ => period == 0,
    };
    if repeated {
        mode.wrap(i, size).map(i64::from)
    } else {
        None
    }
}

struct Tile {
    /// Where the image's top-left texel is drawn.
    x0: u32,
    y0: u32,
    width: u32,
    height: u32,
    /// The job's address modes (u, v): a triangle past the unit square is
    /// drawn where the sampler reads it.
    address: [AddressMode; 2],
}

impl Tile {
    /// Blends a pixel given in tile coordinates, wrapped into the tile with
    /// the job's address modes (dropped where a clamped axis does not
    /// repeat the texture).
    fn put(&self, canvas: &mut Canvas, x: i64, y: i64, colour: [u8; 3], weight: f32) {
        let (Some(x), Some(y)) = (
            wrap(self.address[0], x, self.width),
            wrap(self.address[1], y, self.height),
        ) else {
            return;
        };
        canvas.blend(
            i64::from(self.x0) + x,
            i64::from(self.y0) + y,
            colour,
            weight,
        );
    }

    /// Blends the pixels whose centres lie in the triangle `p` (edges
    /// included), each with the colour and weight `paint` gives for the
    /// centre's barycentrics `(u, v)`: the weights of `p[1]` and `p[2]`, in
    /// binary32 (the corners' order is the triangle's; either winding).
    /// A triangle whose bounding box exceeds 2^22 pixels, or with no area,
    /// is not drawn.
    fn fill(
        &self,
        canvas: &mut Canvas,
        p: [(f64, f64); 3],
        mut paint: impl FnMut(f32, f32) -> ([u8; 3], f32),
    ) {
        let min_x = p.iter().map(|q| q.0).fold(f64::INFINITY, f64::min).floor() as i64;
        let max_x = p
            .iter()
            .map(|q| q.0)
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil() as i64;
        let min_y = p.iter().map(|q| q.1).fold(f64::INFINITY, f64::min).floor() as i64;
        let max_y = p
            .iter()
            .map(|q| q.1)
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil() as i64;
        if (max_x - min_x) * (max_y - min_y) > 1 << 22 {
            return;
        }
        let area = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[1].1 - p[0].1) * (p[2].0 - p[0].0);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        // The weight of corner `k` at `c` is the edge function of the edge
        // opposite `k` over the area: affine in `c`, `dx * c.0 + dy * c.1 + at0`.
        let weight = |k: usize| {
            let (a, b) = (p[(k + 1) % 3], p[(k + 2) % 3]);
            let (dx, dy) = (-(b.1 - a.1) / area, (b.0 - a.0) / area);
            (dx, dy, -(dx * a.0 + dy * a.1))
        };
        let w = [weight(0), weight(1), weight(2)];
        for y in min_y..=max_y {
            let cy = y as f64 + 0.5;
            let row = w.map(|(_, dy, at0)| dy * cy + at0);
            for x in min_x..=max_x {
                let cx = x as f64 + 0.5;
                let (w0, w1, w2) = (
                    w[0].0 * cx + row[0],
                    w[1].0 * cx + row[1],
                    w[2].0 * cx + row[2],
                );
                if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
                    let (colour, weight) = paint(w1 as f32, w2 as f32);
                    self.put(canvas, x, y, colour, weight);
                }
            }
        }
    }

    fn line(&self, canvas: &mut Canvas, a: (f64, f64), b: (f64, f64)) {
        let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as i64).clamp(1, 1 << 16);
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let x = (a.0 + (b.0 - a.0) * t).floor() as i64;
            let y = (a.1 + (b.1 - a.1) * t).floor() as i64;
            self.put(canvas, x, y, [255, 255, 255], 0.8);
        }
    }
}

fn encode(canvas: &Canvas) -> Result<Vec<u8>, String> {
    encode_rgb(canvas.width, canvas.height, &canvas.rgb).map_err(|e| format!("preview: {e}"))
}

/// An 8-bit RGB PNG of `rgb` (`3 * width * height` bytes, row-major).
pub(crate) fn encode_rgb(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        // A preview, not an archive: fast compression keeps encoding well
        // under the bake's time.
        encoder.set_compression(png::Compression::Fast);
        let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
        writer.write_image_data(rgb).map_err(|e| e.to_string())?;
    }
    Ok(bytes)
}

/// Keeps `State` in scope for the colour table's order.
const _: () = assert!(State::Opaque as usize == 1);

#[cfg(test)]
mod tests {
    use super::*;

    /// The picture is the tiles with the legend under them (wide enough
    /// for the legend even over a tiny texture), and the legend names the
    /// model: the two models' pictures differ only there.
    #[test]
    fn the_picture_ends_in_a_legend_naming_the_model() {
        let image = AlphaImage {
            width: 2,
            height: 2,
            texels: AlphaTexels::Unorm8(vec![255, 0, 0, 255]),
        };
        let decode = |png: &[u8]| {
            let decoder = png::Decoder::new(std::io::Cursor::new(png.to_vec()));
            let mut reader = decoder.read_info().unwrap();
            let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
            let info = reader.next_frame(&mut rgb).unwrap();
            (info.width, info.height, rgb)
        };
        let draw = |model| {
            let nothing = micromap_index::bake::mesh::bake_meshes(
                &[],
                &micromap_index::bake::mesh::MeshOptions::default(),
                &mut |_, _| {},
            )
            .unwrap();
            let tiles = [TileSpec {
                image: 0,
                caption: "cutoff 0.5".into(),
            }];
            let drawn = render(
                std::slice::from_ref(&image),
                &tiles,
                model,
                std::iter::empty(),
                &nothing,
                &mut |_| {},
            )
            .unwrap();
            decode(&drawn.png)
        };
        let (width, height, gpu) = draw(Model::GpuBinary32);
        let (legend_width, legend_height) = legend::size(Model::GpuBinary32);
        // 2 texels at the largest scale, 8: a 16-pixel tile under its
        // caption.
        let tiles_height = legend::caption_height() + 16;
        assert_eq!(
            (width, height),
            (legend_width.max(16), tiles_height + legend_height)
        );
        let (_, exact_height, exact) = draw(Model::Exact);
        assert_eq!(exact_height, height);
        let (w, h) = (width as usize, height as usize);
        let first_difference =
            (0..w * h).find(|&i| gpu[3 * i..3 * i + 3] != exact[3 * i..3 * i + 3]);
        let row = first_difference.expect("the model line differs") / w;
        assert!(row >= tiles_height as usize, "row {row}: above the legend");
    }

    /// Two materials on one texture get a tile each, with its caption:
    /// alpha 0.5 everywhere is opaque under cutoff 0.4 and transparent
    /// under 0.6, and each tile shows its own material's state.
    #[test]
    fn each_material_gets_its_own_captioned_tile() {
        use micromap_index::bake::mesh::{
            bake_meshes, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
        };
        use micromap_index::bake::{Cutoff, Unorm8Texture};
        let image = AlphaImage {
            width: 4,
            height: 4,
            texels: AlphaTexels::Unorm8(vec![128; 16]),
        };
        let texture = Unorm8Texture::new(4, 4, &[128; 16]).unwrap();
        let triangle = [[[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]]];
        let mesh = |cutoff: f32| Mesh {
            triangles: MeshTriangles::Uv(&triangle),
            texture: &texture,
            material: Material {
                cutoff: Cutoff::new(cutoff, micromap_index::bake::Comparison::default()).unwrap(),
                ..Material::default()
            },
            vertex_alpha: None,
        };
        let options = MeshOptions {
            levels: LevelRule::Fixed(micromap_index::Level::new(0).unwrap()),
            ..MeshOptions::default()
        };
        let baked = bake_meshes(&[mesh(0.4), mesh(0.6)], &options, &mut |_, _| {}).unwrap();
        let specs = ["material 0, cutoff 0.4", "material 1, cutoff 0.6"].map(|c| TileSpec {
            image: 0,
            caption: c.into(),
        });
        let (tiles, of_job) = tiles_of(specs.iter().cloned());
        assert_eq!((tiles.len(), of_job.as_slice()), (2, &[0, 1][..]));
        // The same image and caption twice: one tile.
        assert_eq!(
            tiles_of([specs[0].clone(), specs[0].clone()].into_iter())
                .0
                .len(),
            1
        );
        let model = Model::GpuBinary32;
        let drawn = render(
            std::slice::from_ref(&image),
            &tiles,
            model,
            of_job
                .iter()
                .map(|&t| (t, Sampler::default(), &triangle[..])),
            &baked,
            &mut |_| {},
        )
        .unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(drawn.png));
        let mut reader = decoder.read_info().unwrap();
        let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut rgb).unwrap();
        let layout = layout(std::slice::from_ref(&image), &tiles, model).unwrap();
        let pixel = |x: u32, y: u32| {
            let at = ((y * info.width + x) * 3) as usize;
            [rgb[at], rgb[at + 1], rgb[at + 2]]
        };
        let caption = legend::caption_height();
        let inside = |t: usize| {
            let (x0, y0) = layout.corners[t];
            pixel(x0 + layout.scale, y0 + caption + layout.scale)
        };
        // Opaque is green, transparent blue (blended over the grey).
        let (opaque, transparent) = (inside(0), inside(1));
        assert!(opaque[1] > opaque[2], "{opaque:?}");
        assert!(transparent[2] > transparent[1], "{transparent:?}");
        // Side by side, each under a caption with text in it.
        assert_eq!(layout.corners[0].1, layout.corners[1].1);
        assert!(layout.corners[1].0 >= 4 * layout.scale);
        for &(x0, y0) in &layout.corners {
            let text = (y0..y0 + caption)
                .flat_map(|y| (x0..x0 + 60).map(move |x| (x, y)))
                .filter(|&(x, y)| pixel(x, y) == [235, 235, 235])
                .count();
            assert!(text > 20, "caption at ({x0}, {y0}): {text} text pixels");
        }
    }

    /// Each pixel takes the state of the micro-triangle under its centre:
    /// a level-3 map drawn over a 256-pixel right triangle, every
    /// micro-triangle its own colour; every pixel centre off the
    /// micro-triangles' edges has the colour of the micro-triangle
    /// (`inverse::micro_triangle`, exact vertices) that contains it.
    #[test]
    fn each_pixel_shows_the_micro_triangle_under_its_centre() {
        let level = SpecLevel::new(3).unwrap();
        let size = 256u32;
        let mut canvas = Canvas {
            width: size,
            height: size,
            rgb: vec![0; (size * size * 3) as usize],
        };
        let tile = Tile {
            x0: 0,
            y0: 0,
            width: size,
            height: size,
            address: [AddressMode::ClampToEdge; 2],
        };
        let s = f64::from(size);
        tile.fill(&mut canvas, [(0.0, 0.0), (s, 0.0), (0.0, s)], |u, v| {
            let i = micromap_index::index(u, v, level);
            ([1 + i as u8, 7, 7], 1.0)
        });
        let n = 8; // 2^level micro-triangle edges per side
        let mut checked = 0;
        for y in 0..size {
            for x in 0..size {
                let at = ((y * size + x) * 3) as usize;
                let inside = x + y < size;
                if !inside {
                    assert_eq!(canvas.rgb[at], 0, "({x}, {y}) is outside");
                    continue;
                }
                // Centres on a diagonal edge (u + v = m / 8) belong to either side.
                if (x + y + 1) % (size / n) == 0 {
                    continue;
                }
                let (u, v) = ((f64::from(x) + 0.5) / s, (f64::from(y) + 0.5) / s);
                let containing = (0..64u64)
                    .find(|&i| {
                        let t = micromap_index::inverse::micro_triangle(level.level(), i).unwrap();
                        let p = t
                            .vertices_scaled()
                            .map(|(a, b)| (a as f64 / f64::from(n), b as f64 / f64::from(n)));
                        let edge = |a: (f64, f64), b: (f64, f64)| {
                            (b.0 - a.0) * (v - a.1) - (b.1 - a.1) * (u - a.0)
                        };
                        let e = [edge(p[0], p[1]), edge(p[1], p[2]), edge(p[2], p[0])];
                        e.iter().all(|&e| e >= 0.0) || e.iter().all(|&e| e <= 0.0)
                    })
                    .unwrap();
                assert_eq!(
                    canvas.rgb[at],
                    1 + containing as u8,
                    "pixel ({x}, {y}) at ({u}, {v})"
                );
                checked += 1;
            }
        }
        assert!(checked > 30_000, "{checked}");
    }

    /// Pixels past the tile land where the sampler reads them: repeat
    /// wraps, mirrored-repeat reflects every other period, mirror-clamp
    /// reflects once, the clamps draw only the tile (they drew at
    /// repeat-wrapped positions before).
    #[test]
    fn pixels_wrap_with_the_jobs_address_modes() {
        let size = 4;
        let at = |mode| (-5..9).map(|i| wrap(mode, i, size)).collect::<Vec<_>>();
        let s = Some;
        assert_eq!(
            at(AddressMode::Repeat),
            [
                s(3),
                s(0),
                s(1),
                s(2),
                s(3),
                s(0),
                s(1),
                s(2),
                s(3),
                s(0),
                s(1),
                s(2),
                s(3),
                s(0)
            ]
        );
        assert_eq!(
            at(AddressMode::MirroredRepeat),
            [
                s(3),
                s(3),
                s(2),
                s(1),
                s(0),
                s(0),
                s(1),
                s(2),
                s(3),
                s(3),
                s(2),
                s(1),
                s(0),
                s(0)
            ]
        );
        assert_eq!(
            at(AddressMode::MirrorClampToEdge),
            // Mirrored once, then clamped: past the tile only the edge.
            [
                None,
                s(3),
                s(2),
                s(1),
                s(0),
                s(0),
                s(1),
                s(2),
                s(3),
                None,
                None,
                None,
                None,
                None
            ]
        );
        for mode in [AddressMode::ClampToEdge, AddressMode::ClampToBorder] {
            let expected: Vec<_> = (-5..9).map(|i| (0..4).contains(&i).then_some(i)).collect();
            assert_eq!(at(mode), expected);
        }
    }
}
