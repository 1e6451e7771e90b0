//! meshoptimizer 1.3 (C++), through the `meshopt` 0.7.0 FFI crate, which
//! vendors it and builds `vendor/src/opacitymap.cpp` with `cc`.

use meshopt::{AlphaTexture, OpacityStates};

use super::baker::{Baked, Baker, Conventions, Request};
use super::meshopt_common::{meshopt_baked, meshopt_conventions, meshopt_sampler};
use crate::output::Format;

/// `--baker meshopt-cpp`.
pub struct MeshoptCpp;

const REFERENCES: &[&str] = &[
    "meshopt-0.7.0/vendor/src/meshoptimizer.h:15 (MESHOPTIMIZER_VERSION 1030 = 1.3)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:11-14 (bird order, Vulkan micromap-subd figure)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:29-69 sampleTexture (wrap l.32-33, 16.8 fixed point l.35-37, clamp l.39-41 and l.53-56, integer bilinear l.63-68)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:193-196 quantizeSubpixel (dedup key: 1/4 texel)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:198-219 rasterizeEdge (edge samples, a >= 0.5f)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:222-261 rasterizeOpacity0 (coverage l.226-235, 2-state l.237-241, 4-state known < 0.5 / > 0.5 l.243-244, unknown l.248, edge check l.251-258, packing l.260)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:264-304 rasterizeOpacity1 (level-1 children)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:307-349 rasterizeOpacityRec (children 4i+0..3 l.345-348)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:351-375 getSpecialIndex",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:377-451 meshopt_opacityMapMeasure (level = max_level unless target_edge > 0, l.414-425)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:461-491 meshopt_opacityMapRasterize (edgeres l.476-484)",
    "meshopt-0.7.0/vendor/src/opacitymap.cpp:493- meshopt_opacityMapCompact",
    "meshopt-0.7.0/src/opacity.rs (safe wrappers opacity_map_measure/_layout/_rasterize/_compact)",
];

impl Baker for MeshoptCpp {
    fn name(&self) -> &'static str {
        "meshopt-cpp"
    }

    fn version(&self) -> &'static str {
        "meshopt 0.7.0 (FFI crate) vendoring meshoptimizer 1.3 C++ (MESHOPTIMIZER_VERSION 1030)"
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
        if level > 12 {
            return Err(format!("level {level} > 12"));
        }
        let states = match format {
            Format::TwoState => OpacityStates::Two,
            Format::FourState => OpacityStates::Four,
        };
        let uvs: Vec<[f32; 2]> = triangles.iter().flatten().copied().collect();
        let indices: Vec<u32> = (0..uvs.len() as u32).collect();
        let measure =
            meshopt::opacity_map_measure(&indices, &uvs, texture.width, texture.height, level, 0.0);
        let mut levels = measure.levels;
        let (mut offsets, size) = meshopt::opacity_map_layout(&levels, states);
        let mut data = vec![0u8; size];
        let alpha = AlphaTexture {
            data: &texture.alpha,
            stride: 1,
            pitch: texture.width as usize,
            width: texture.width,
            height: texture.height,
        };
        let mut micro_triangles_baked = 0u64;
        for (k, &source) in measure.sources.iter().enumerate() {
            meshopt::opacity_map_rasterize(
                &mut data[offsets[k] as usize..],
                levels[k],
                states,
                &triangles[source as usize],
                &alpha,
            );
            micro_triangles_baked += 1u64 << (2 * levels[k]);
        }
        let mut omm_indices = measure.indices;
        meshopt::opacity_map_compact(
            &mut data,
            &mut levels,
            &mut offsets,
            &mut omm_indices,
            states,
        );
        Ok(meshopt_baked(
            &offsets,
            &levels,
            format,
            data,
            omm_indices,
            micro_triangles_baked,
        ))
    }
}
