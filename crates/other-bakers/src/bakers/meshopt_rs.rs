//! `meshoptimizer-rs` 0.2.17: a pure-Rust port of meshoptimizer 1.3
//! (`src/opacity.rs`), with checked errors instead of assertions.

use meshoptimizer_rs::{
    opacity_map_compact, opacity_map_entry_size, opacity_map_measure, opacity_map_rasterize_into,
    Workspace,
};

use super::baker::{Baked, Baker, Conventions, Request};
use super::meshopt_common::{meshopt_baked, meshopt_conventions, meshopt_sampler};

/// `--baker meshopt-rs`.
pub struct MeshoptRs;

const REFERENCES: &[&str] = &[
    "meshoptimizer-rs-0.2.17/UPSTREAM.md (port of meshoptimizer 1.3 @ 4c203430, byte-identical by its claim)",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:22-27 opacity_map_entry_size",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:75-77 quantize (dedup key: 1/4 texel)",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:241-336 measure_triangles (level = max_level unless target_edge > 0, l.281-291)",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:548-567 special_index, 578-703 opacity_map_compact",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:706-744 sample (wrap l.715-724, 16.8 fixed point l.725-727, clamp l.725-733, integer bilinear l.740-743)",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:747-760 edge (alpha >= 0.5)",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:784-820 emit (coverage l.793-800, 2-state l.801-804, 4-state known l.805-806, unknown l.807, edge check l.813-818, packing l.819)",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:824-872 raster_setup (edgeres l.864-865)",
    "meshoptimizer-rs-0.2.17/src/opacity.rs:1087-1180 raster_state_core (level-1 children l.1121-1158, recursion children 4i+k l.1160-1178)",
];

impl Baker for MeshoptRs {
    fn name(&self) -> &'static str {
        "meshopt-rs"
    }

    fn version(&self) -> &'static str {
        "meshoptimizer-rs 0.2.17 (pure-Rust port of meshoptimizer 1.3)"
    }

    fn conventions(&self) -> Conventions {
        meshopt_conventions(REFERENCES)
    }

    fn bake(&self, request: &Request<'_>) -> Result<Baked, String> {
        let Request {
            texture,
            triangles,
            level,
            format,
            sampler,
        } = *request;
        meshopt_sampler(sampler)?;
        let states = format.states();
        fn e(what: &'static str) -> impl Fn(meshoptimizer_rs::Error) -> String {
            move |err| format!("{what}: {err}")
        }
        let mut workspace = Workspace::default();
        let uvs: Vec<f32> = triangles.iter().flatten().flatten().copied().collect();
        let indices: Vec<u32> = (0..(uvs.len() / 2) as u32).collect();
        let measure = opacity_map_measure(
            &indices,
            &uvs,
            uvs.len() / 2,
            2,
            texture.width,
            texture.height,
            level,
            0.0,
            &mut workspace,
        )
        .map_err(e("opacity_map_measure"))?;
        let mut levels = measure.levels;
        let mut offsets = Vec::with_capacity(levels.len());
        let mut size = 0usize;
        for &l in &levels {
            offsets.push(u32::try_from(size).map_err(|_| "data over 4 GiB".to_string())?);
            size += opacity_map_entry_size(l, states).map_err(e("opacity_map_entry_size"))?;
        }
        let mut data = vec![0u8; size];
        let mut micro_triangles_baked = 0u64;
        for (k, &source) in measure.sources.iter().enumerate() {
            opacity_map_rasterize_into(
                &mut data[offsets[k] as usize..],
                levels[k],
                states,
                triangles[source as usize],
                &texture.alpha,
                1,
                texture.width as usize,
                texture.width,
                texture.height,
                &mut workspace,
            )
            .map_err(e("opacity_map_rasterize_into"))?;
            micro_triangles_baked += 1u64 << (2 * levels[k]);
        }
        let mut omm_indices = measure.omm_indices;
        let (count, bytes) = opacity_map_compact(
            &mut data,
            &mut levels,
            &mut offsets,
            &mut omm_indices,
            states,
            &mut workspace,
        )
        .map_err(e("opacity_map_compact"))?;
        data.truncate(bytes);
        Ok(meshopt_baked(
            &offsets[..count],
            &levels[..count],
            format,
            data,
            omm_indices,
            micro_triangles_baked,
        ))
    }
}
