//! NVIDIA's Opacity-MicroMap-SDK CPU baker (`ommCpuBake`, SDK 1.7.1),
//! called through its C API from the user's own build (`OMM_SDK_LIB`, see
//! README.md; its licence allows no vendoring, so nothing of it is here).
//! Settings: UNORM8 texture, one mip, the cutoff 0.5 embedded in the
//! texture (which enables the SDK's summed-area-table coarse pass), the
//! requested sampler (default clamp-to-edge, linear), alpha test, every
//! triangle at the requested level (`dynamicSubdivisionScale = 0`), opaque
//! iff alpha > 0.5, the requested format, defaults otherwise. Its output is
//! already the Vulkan layout, copied as it is.

mod ffi;
pub mod library;

use std::collections::HashSet;

use micromap_index::bake::{AddressMode, Filter};

use crate::bakers::baker::{Baked, Baker, Conventions, Request};
use crate::output::{Micromaps, Record};

/// `--baker omm-sdk`.
pub struct OmmSdk;

/// The cutoff every baker of this tool uses.
const CUTOFF: f32 = 0.5;

const REFERENCES: &[&str] = &[
    "OMM SDK 1.7.1 (github NVIDIAGameWorks/Opacity-MicroMap-SDK, tag v1.7.1), libraries/omm-lib:",
    "include/omm.h: ommCpuBakeInputDesc (dynamicSubdivisionScale <= 0: maxSubdivisionLevel for every triangle; \
     texture = alphaCutoff > cutoff ? alphaCutoffGreater : alphaCutoffLessEqual)",
    "src/texture_impl.h: UNORM8 texel c read as float(c) * (1.f / 255.f)",
    "src/texture_impl.cpp: SAT of (texel > alphaCutoff) built when the texture has an alpha cutoff",
    "src/bake_cpu_impl.cpp ResampleCoarse: per micro-triangle inside one UV period, the SAT over the texels \
     of its float AABB's bilinear footprint: none above -> alphaCutoffLessEqual, all above -> alphaCutoffGreater",
    "src/bake_cpu_impl.cpp ResampleFine: remaining micro-triangles: conservative raster over texel cells \
     (offset -0.5), LevelLineIntersectionKernel per cell, plus one bilinear sample at the micro-triangle's \
     first vertex",
    "src/bake_kernels_cpu.h LevelLineIntersectionKernel: cell corners inside the micro-triangle, then the \
     bilinear level line alpha = cutoff intersected with the micro-triangle's edges in float (epsilons 1e-6, 1e-5)",
    "src/util/bird.h GetMicroTriangle: micro-triangle corners computed in float from the float UV triangle",
];

impl Baker for OmmSdk {
    fn name(&self) -> &'static str {
        "omm-sdk"
    }

    fn version(&self) -> &'static str {
        "NVIDIA Opacity-MicroMap-SDK 1.7.1 CPU baker (ommCpuBake), the user's build named by OMM_SDK_LIB"
    }

    fn conventions(&self) -> Conventions {
        Conventions {
            filter: "as requested (--filter; default linear): ommTextureFilterMode_Linear or _Nearest; \
                one mip",
            address_mode: "as requested (--address; default clamp-to-edge): repeat -> Wrap, \
                mirrored-repeat -> Mirror, clamp-to-edge -> Clamp, clamp-to-border -> Border \
                (border alpha 0), mirror-clamp-to-edge -> MirrorOnce",
            texel_centres: "texel (i, j) at ((i + 0.5) / W, (j + 0.5) / H): the linear raster grid is \
                offset by -0.5 texel so that each cell's corners are 4 texel centres; v = 0 is row 0 \
                of the data",
            sample_position_precision: "binary32 throughout: micro-triangle corners interpolated in \
                float from the float UVs, no sub-texel quantisation",
            cutoff: CUTOFF,
            comparison: "opaque iff alpha > 0.5 (alphaCutoffGreater = Opaque, alphaCutoffLessEqual = \
                Transparent; the cutoff is also embedded in the texture); UNORM8 texel c is \
                float(c) * (1.f / 255.f)",
            classification: "linear: by the bilinear VALUE, not the footprint. A coarse pass (the \
                texture's summed-area table of texel > cutoff) decides micro-triangles whose whole \
                bilinear footprint is one class; the rest are rasterized conservatively over texel \
                cells, and in each cell the level line alpha = cutoff is intersected with the \
                micro-triangle's edges (binary32, epsilons 1e-6 / 1e-5), cell corners inside count \
                as samples, plus one bilinear sample at the first vertex; a micro-triangle is known \
                when every test saw one side. Nearest: every texel the conservative raster touches. \
                Not conservative where the float corners or the epsilons miss (README.md)",
            level_control: "forced: dynamicSubdivisionScale = 0 and maxSubdivisionLevel = L put every \
                triangle at level L",
            pipeline: "SDK defaults otherwise: equal UV triangles classified once, uniform micromaps \
                become special indices, exact duplicates merged, no near-duplicate merging, unknown \
                states ForceOpaque (4-state: unknown-opaque; 2-state: opaque), unresolvable UV \
                triangles -4; micromaps sorted by level then spatially; Force32BitIndices",
            order: "the Vulkan space-filling (bird) curve and bit packing (omm.h: the output is the \
                DX/VK build input); checked by this crate's tests and by verify-bake",
            references: REFERENCES,
        }
    }

    fn bake(&self, request: &Request<'_>) -> Result<Baked, String> {
        let Request {
            texture,
            triangles,
            level,
            format,
            sampler,
        } = *request;
        let sdk = library::sdk()?;
        let index_count = u32::try_from(triangles.len() * 3)
            .map_err(|_| format!("{} triangles: too many for 32-bit indices", triangles.len()))?;
        let baker = library::Baker::new(sdk)?;
        let omm_texture = baker.texture(texture.width, texture.height, &texture.alpha, CUTOFF)?;
        let uvs: Vec<[f32; 2]> = triangles.iter().flatten().copied().collect();
        let indices: Vec<u32> = (0..index_count).collect();
        let threads = std::env::var("OTHER_BAKE_THREADS")
            .ok()
            .and_then(|t| t.parse::<usize>().ok())
            .unwrap_or(1);
        let mut flags = ffi::BAKE_FLAG_FORCE_32BIT_INDICES;
        if threads > 1 {
            // OpenMP's threads: OMP_NUM_THREADS, else every core.
            flags |= ffi::BAKE_FLAG_INTERNAL_THREADS;
        }
        let desc = ffi::BakeInputDesc {
            bake_flags: flags,
            texture: omm_texture.handle,
            runtime_sampler: ffi::SamplerDesc {
                address_mode: address_mode(sampler.address),
                filter: match sampler.filter {
                    Filter::Nearest => ffi::filter::NEAREST,
                    Filter::Linear => ffi::filter::LINEAR,
                },
                border_alpha: 0.0,
            },
            alpha_mode: ffi::ALPHA_MODE_TEST,
            tex_coord_format: ffi::TEX_COORD_UV32_FLOAT,
            tex_coords: uvs.as_ptr().cast(),
            tex_coord_stride: 0,
            index_format: ffi::INDEX_FORMAT_UINT_32,
            index_buffer: indices.as_ptr().cast(),
            index_count,
            dynamic_subdivision_scale: 0.0,
            rejection_threshold: 0.0,
            alpha_cutoff: CUTOFF,
            // Used only with EnableNearDuplicateDetection (not set).
            near_duplicate_deduplication_factor: 0.15,
            alpha_cutoff_less_equal: ffi::STATE_TRANSPARENT,
            alpha_cutoff_greater: ffi::STATE_OPAQUE,
            format: u32::from(format.vk()),
            formats: std::ptr::null(),
            unknown_state_promotion: ffi::PROMOTION_FORCE_OPAQUE,
            unresolved_tri_state: ffi::SPECIAL_FULLY_UNKNOWN_OPAQUE,
            max_subdivision_level: level,
            max_array_data_size: u32::MAX,
            subdivision_levels: std::ptr::null(),
            max_workload_size: u64::MAX,
        };
        let result = baker.bake(&desc)?;
        let view = result.view()?;
        let maps = Micromaps {
            data: view.data.to_vec(),
            records: view
                .records
                .iter()
                .map(|d| Record {
                    data_offset: d.offset,
                    level: d.subdivision_level,
                    format: d.format,
                })
                .collect(),
            indices: view.indices.to_vec(),
        };
        // What it classified: each distinct UV triangle once.
        let distinct: HashSet<[u32; 6]> = triangles
            .iter()
            .map(|t| [t[0][0], t[0][1], t[1][0], t[1][1], t[2][0], t[2][1]].map(f32::to_bits))
            .collect();
        Ok(Baked {
            maps,
            micro_triangles_baked: distinct.len() as u64 * (1u64 << (2 * level)),
        })
    }
}

fn address_mode(mode: AddressMode) -> u32 {
    match mode {
        AddressMode::Repeat => ffi::address::WRAP,
        AddressMode::MirroredRepeat => ffi::address::MIRROR,
        AddressMode::ClampToEdge => ffi::address::CLAMP,
        AddressMode::ClampToBorder => ffi::address::BORDER,
        AddressMode::MirrorClampToEdge => ffi::address::MIRROR_ONCE,
    }
}
