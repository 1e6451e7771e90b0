//! `micromap-index` itself (`micromap_index::bake`), run through the same
//! harness so its speed is measured in the same process, on the same input,
//! as the other bakers. Sampler: the requested one (default linear,
//! clamp-to-edge, as a glTF asset with these textures would use at run
//! time), cutoff 0.5 with glTF's `alpha >= cutoff`.

use micromap_index::bake::mesh::{
    bake_mesh, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{Cutoff, Sampler, Threads, Unorm8Texture};
use micromap_index::micromap::{Format as MmFormat, IndexWidth, UnknownPolicy};
use micromap_index::Level;

use super::baker::{Baked, Baker, Conventions, Request};
use crate::output::{Format, Micromaps, Record};

/// `--baker micromap-index`.
pub struct MicromapIndex;

impl Baker for MicromapIndex {
    fn name(&self) -> &'static str {
        "micromap-index"
    }

    fn version(&self) -> &'static str {
        "micromap-index (this repository), exact conservative classifier"
    }

    fn conventions(&self) -> Conventions {
        Conventions {
            filter: "as requested (--filter; default linear): the library's sampler model (docs/bake.md)",
            address_mode: "as requested (--address; default clamp-to-edge), both axes (Vulkan wrapping of integer texel coordinates)",
            texel_centres: "texel (i, j) covers [i/W, (i+1)/W) x [j/H, (j+1)/H); v = 0 is the top row",
            sample_position_precision: "exact (integer arithmetic on the exact micro-triangle vertices)",
            cutoff: 0.5,
            comparison: "opaque when alpha >= 0.5 (glTF MASK)",
            classification: "exact: a micro-triangle is known only if every point of it, closed, reads one class",
            level_control: "forced: every triangle at level L",
            pipeline: "bake::mesh: triangles with equal UVs classified once; uniform micromaps become special indices; identical micromaps are merged by content",
            order: "the Vulkan space-filling curve (micromap_index::inverse)",
            references: &["src/bake/ in this repository"],
        }
    }

    fn bake(&self, request: &Request<'_>) -> Result<Baked, String> {
        let texture = Unorm8Texture::new(
            request.texture.width,
            request.texture.height,
            &request.texture.alpha,
        )
        .map_err(|e| e.to_string())?;
        let sampler = Sampler {
            filter: request.sampler.filter,
            address_u: request.sampler.address,
            address_v: request.sampler.address,
            border_alpha: 0.0,
        };
        let level = Level::new(u32::from(request.level)).map_err(|e| e.to_string())?;
        let format = match request.format {
            Format::TwoState => MmFormat::TwoState,
            Format::FourState => MmFormat::FourState,
        };
        // The library's whole-mesh bake, as the CLI runs it: equal
        // triangles classified once, on OTHER_BAKE_THREADS threads
        // (default 1, serial).
        let threads = std::env::var("OTHER_BAKE_THREADS")
            .ok()
            .and_then(|t| t.parse::<usize>().ok())
            .unwrap_or(1);
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(request.triangles),
            texture: &texture,
            material: Material {
                sampler,
                cutoff: Cutoff::default(),
                alpha_factor: 1.0,
                uv_transform: micromap_index::bake::UvTransform::IDENTITY,
            },
            vertex_alpha: None,
        };
        let options = MeshOptions {
            levels: LevelRule::Fixed(level),
            format,
            unknown: UnknownPolicy::Fallback,
            threads: Threads::Exactly(threads),
            ..MeshOptions::default()
        };
        let buffers = bake_mesh(&mesh, &options)
            .map_err(|e| e.to_string())?
            .buffers;
        let indices = buffers
            .index_bytes(0, IndexWidth::U32)
            .map_err(|e| e.to_string())?
            .chunks_exact(4)
            .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        Ok(Baked {
            maps: Micromaps {
                data: buffers.data().to_vec(),
                records: buffers
                    .records()
                    .iter()
                    .map(|r| Record {
                        data_offset: r.data_offset,
                        level: r.subdivision_level,
                        format: r.format,
                    })
                    .collect(),
                indices,
            },
            micro_triangles_baked: request.triangles.len() as u64 * (1u64 << (2 * request.level)),
        })
    }
}
