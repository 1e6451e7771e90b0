//! The committed SPIR-V of both tracers, built from `shaders/` by
//! `shaders/compile.sh` (`tests/spirv.rs` checks it is current): the ray
//! query tracer's compute shader and the ray tracing pipeline's four
//! stages, as the words Vulkan takes, and the sampler lookup's variants of
//! the two that decide candidates.

/// Little-endian words of SPIR-V bytes (`include_bytes!` gives no
/// alignment).
fn words(spv: &[u8]) -> Vec<u32> {
    spv.chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// `shaders/render_query.comp`.
pub(crate) fn query() -> Vec<u32> {
    words(include_bytes!("../shaders/render_query.spv"))
}

/// `shaders/render_query.comp` with `MMI_SAMPLER_LOOKUP`: the alpha test
/// through a combined image sampler per mesh.
pub(crate) fn query_sampler() -> Vec<u32> {
    words(include_bytes!("../shaders/render_query_sampler.spv"))
}

/// `shaders/render_pipeline.rahit` with `MMI_SAMPLER_LOOKUP`.
pub(crate) fn any_hit_sampler() -> Vec<u32> {
    words(include_bytes!(
        "../shaders/render_pipeline_rahit_sampler.spv"
    ))
}

/// `shaders/render_pipeline.{rgen,rmiss,rchit,rahit}`.
pub(crate) fn pipeline() -> [Vec<u32>; 4] {
    [
        words(include_bytes!("../shaders/render_pipeline_rgen.spv")),
        words(include_bytes!("../shaders/render_pipeline_rmiss.spv")),
        words(include_bytes!("../shaders/render_pipeline_rchit.spv")),
        words(include_bytes!("../shaders/render_pipeline_rahit.spv")),
    ]
}
