//! NVIDIA Opacity Micromap SDK 1.9.2 CPU baker through `nvidia-omm` 0.1.0
//! (features `omm` / `omm-native`). UNTESTED here: the crate's native
//! backend needs NVIDIA's prebuilt `libomm-lib.so.1.9.2`, which its build
//! script downloads (or takes from `OMM_SDK`), and this machine reaches no
//! download host. Without `omm-native` the crate's stub backend is linked
//! and every bake returns its "native nvidia omm is unavailable" error.

use nvidia_omm::{AlphaMip, BakeConfig, BakeInput, Baker as OmmBaker};

use super::{Baked, Baker, Conventions, Request};
use crate::output::{Format, Micromaps, Record};

/// `--baker nvidia-omm`.
pub struct NvidiaOmm;

const REFERENCES: &[&str] = &[
    "nvidia-omm-0.1.0/native/omm.cpp:262-268 texture: UNORM8, alphaCutoff 0.5",
    "nvidia-omm-0.1.0/native/omm.cpp:301-325 bake desc: Force32BitIndices, Wrap, Linear, AlphaMode Test, \
     alphaCutoff 0.5, LessEqual -> Transparent, Greater -> Opaque, OC1_4_State only, \
     unknownStatePromotion ForceOpaque, unresolvedTriState -4, nearDuplicateDeduplicationFactor 0",
    "nvidia-omm-0.1.0/src/lib.rs:83-107 BakeConfig (dynamic_subdivision_scale must be > 0)",
    "nvidia-omm-0.1.0/src/lib.rs:246-254 BakeOutput (array_data, descriptors = VkMicromapTriangleEXT, indices i32)",
    "nvidia-omm-0.1.0/build.rs:38 (SDK resolve: OMM_SDK, NVIDIA_SDK_ROOT, cache, else download), 64-75 (Linux: bridge omm.cpp + prebuilt lib/libomm-lib.so.1.9.2; SDK sources are built only on macOS, l.94-)",
    "OMM SDK (not available here): bake_cpu_impl.cpp ResampleFine, bake_kernels_cpu.h, util/texture.h l.46 (wrap)",
];

impl Baker for NvidiaOmm {
    fn name(&self) -> &'static str {
        "nvidia-omm"
    }

    fn version(&self) -> &'static str {
        "nvidia-omm 0.1.0 (FFI to the NVIDIA Opacity Micromap SDK 1.9.2 CPU baker)"
    }

    fn conventions(&self) -> Conventions {
        Conventions {
            filter: "linear (bilinear), fixed by the wrapper (ommTextureFilterMode_Linear)",
            address_mode: "wrap (ommTextureAddressMode_Wrap), fixed by the wrapper; the SDK wraps \
                texel indices by `uint2(texCoord) % texSize` (util/texture.h l.46), wrong for -1 \
                on non-power-of-two sizes",
            texel_centres:
                "texel (i, j) at ((i + 0.5) / W, (j + 0.5) / H) (bilinear raster offset \
                -0.5); v = 0 is row 0 of the data",
            sample_position_precision: "f32 throughout (no sub-texel quantisation)",
            cutoff: 0.5,
            comparison:
                "opaque iff alpha > 0.5 (alphaCutoffGreater = Opaque, alphaCutoffLessEqual \
                = Transparent)",
            classification:
                "conservative rasterisation of each micro-triangle over the texel grid; \
                bilinear: the level set alpha = cutoff in each touched cell tested against the \
                micro-triangle's edges, plus texel centres inside and one sample at a vertex; \
                float with epsilons (see shared/micromap-landscape.md section 3)",
            level_control: "NOT forceable through nvidia-omm 0.1.0: the level is the SDK's area \
                heuristic capped at maxSubdivisionLevel, and the wrapper rejects \
                dynamic_subdivision_scale <= 0. The tool sets max_subdivision_level = L and a \
                scale small enough that the heuristic exceeds L for every triangle \
                (scale = sqrt(min texel area / 4^(L+1))), so every record should have level L; \
                summary.json lists the levels actually used",
            pipeline: "SDK pipeline with default flags: duplicate detection (hash of UVs and \
                states), special indices, array data sorted by level then Morton order; 4-state \
                only in this wrapper; unknown states promoted ForceOpaque (4-state keeps UO/UT)",
            order: "the SDK's own bird-curve order (GetMicroTriangle); untested here",
            references: REFERENCES,
        }
    }

    fn bake(&self, request: &Request<'_>) -> Result<Baked, String> {
        let Request {
            texture,
            triangles,
            level,
            format,
        } = *request;
        if format != Format::FourState {
            return Err("nvidia-omm 0.1.0 bakes the 4-state format only".into());
        }
        let library = OmmBaker::bundled_backend_path().ok_or_else(|| {
            "nvidia-omm was built without its native backend (feature omm-native)".to_string()
        })?;
        let baker = OmmBaker::new(library).map_err(|e| format!("{e:#}"))?;
        let omm_texture = baker
            .create_texture(&[AlphaMip {
                width: texture.width,
                height: texture.height,
                row_pitch: 0,
                data: &texture.alpha,
            }])
            .map_err(|e| format!("{e:#}"))?;
        let uvs: Vec<[f32; 2]> = triangles.iter().flatten().copied().collect();
        let indices: Vec<u32> = (0..uvs.len() as u32).collect();
        let (w, h) = (texture.width as f32, texture.height as f32);
        let min_area = triangles
            .iter()
            .map(|t| {
                let a = [(t[1][0] - t[0][0]) * w, (t[1][1] - t[0][1]) * h];
                let b = [(t[2][0] - t[0][0]) * w, (t[2][1] - t[0][1]) * h];
                0.5 * (a[0] * b[1] - a[1] * b[0]).abs()
            })
            .fold(f32::INFINITY, f32::min)
            .max(1e-3);
        let scale = (min_area / 4f32.powi(i32::from(level) + 1)).sqrt();
        let output = baker
            .bake(
                &omm_texture,
                BakeInput {
                    texture_coordinates: &uvs,
                    indices: &indices,
                    config: BakeConfig {
                        dynamic_subdivision_scale: scale,
                        max_subdivision_level: level,
                        internal_threads: false,
                        validation: false,
                        ..BakeConfig::default()
                    },
                },
            )
            .map_err(|e| format!("{e:#}"))?;
        // The SDK's descriptors are VkMicromapTriangleEXT already, and with
        // Force32BitIndices its index buffer is i32 with -1..-4 specials.
        let records: Vec<Record> = output
            .descriptors
            .iter()
            .map(|d| Record {
                data_offset: d.data_offset,
                level: d.subdivision_level,
                format: d.format,
            })
            .collect();
        // The SDK deduplicates internally; count what the input asked for.
        let micro_triangles_baked = triangles.len() as u64 * (1u64 << (2 * level));
        Ok(Baked {
            maps: Micromaps {
                data: output.array_data.into_vec(),
                records,
                indices: output.indices.into_vec(),
            },
            micro_triangles_baked,
        })
    }
}
