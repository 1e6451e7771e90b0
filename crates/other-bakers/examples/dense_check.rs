//! How often meshoptimizer's known states disagree with its OWN sampler
//! inside the micro-triangle: reads an `other-bake` output directory, samples
//! every known micro-triangle on a barycentric grid of `n` steps per edge
//! (closed triangle) with meshoptimizer's sampler, and counts known-opaque
//! micro-triangles with a sample < 0.5 and known-transparent ones with a
//! sample >= 0.5. A quick preview, not the verifier: the grid can miss a
//! violation, and meshoptimizer's sampler is not the exact bilinear field.
//!
//! cargo run --release --example dense_check -- OUT_DIR TEXTURE.png TRIS.json [n]

use std::path::Path;

use micromap_index::inverse::micro_triangle;
use micromap_index::Level;
use other_bakers::bakers::meshopt_sample;
use other_bakers::input::{parse_triangles, read_png_alpha};
use other_bakers::output::{Micromaps, Record};

fn read_maps(dir: &Path) -> Micromaps {
    let data = std::fs::read(dir.join("micromap-data.bin")).unwrap();
    let records = std::fs::read(dir.join("micromap-triangles.bin"))
        .unwrap()
        .chunks_exact(8)
        .map(|r| Record {
            data_offset: u32::from_le_bytes(r[0..4].try_into().unwrap()),
            level: u16::from_le_bytes(r[4..6].try_into().unwrap()),
            format: u16::from_le_bytes(r[6..8].try_into().unwrap()),
        })
        .collect();
    let indices = std::fs::read(dir.join("micromap-indices.bin"))
        .unwrap()
        .chunks_exact(4)
        .map(|b| i32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    Micromaps {
        data,
        records,
        indices,
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = Path::new(&args[0]);
    let texture = read_png_alpha(Path::new(&args[1])).unwrap();
    let tris = parse_triangles(&std::fs::read_to_string(&args[2]).unwrap()).unwrap();
    let n: u32 = args.get(3).map_or(16, |s| s.parse().unwrap());
    let maps = read_maps(dir);
    maps.validate(tris.len()).unwrap();
    let (mut known, mut bad_opaque, mut bad_transparent) = (0u64, 0u64, 0u64);
    for (t, tri) in tris.iter().enumerate() {
        let level = match maps.indices[t] {
            i if i < 0 => {
                let summary: serde_json::Value = serde_json::from_str(
                    &std::fs::read_to_string(dir.join("summary.json")).unwrap(),
                )
                .unwrap();
                summary["level"].as_u64().unwrap() as u8
            }
            i => maps.records[i as usize].level as u8,
        };
        for i in 0..1u64 << (2 * level) {
            let state = maps.state(t, i as usize);
            if state >= 2 {
                continue;
            }
            known += 1;
            let m = micro_triangle(Level::new(level.into()).unwrap(), i).unwrap();
            let p = m.vertices_f64().map(|(u, v)| {
                let w = 1.0 - u - v;
                [0, 1].map(|k| {
                    w * f64::from(tri[0][k]) + u * f64::from(tri[1][k]) + v * f64::from(tri[2][k])
                })
            });
            let mut violated = false;
            'grid: for a in 0..=n {
                for b in 0..=n - a {
                    let (s, r) = (f64::from(a) / f64::from(n), f64::from(b) / f64::from(n));
                    let q = [0, 1].map(|k| (1.0 - s - r) * p[0][k] + s * p[1][k] + r * p[2][k]);
                    let alpha = meshopt_sample(&texture, q[0] as f32, q[1] as f32);
                    if (state == 1 && alpha < 0.5) || (state == 0 && alpha >= 0.5) {
                        violated = true;
                        break 'grid;
                    }
                }
            }
            if violated {
                if state == 1 {
                    bad_opaque += 1;
                } else {
                    bad_transparent += 1;
                }
            }
        }
    }
    println!(
        "{}: {known} known micro-triangles; {bad_opaque} known-opaque with a sample < 0.5, \
         {bad_transparent} known-transparent with a sample >= 0.5 ({n} steps per edge)",
        dir.display()
    );
}
