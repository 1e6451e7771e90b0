//! The committed SPIR-V of both tracers (`shaders/render_query.spv`, the
//! ray tracing pipeline's `shaders/render_pipeline_{rgen,rahit,rchit,rmiss}.spv`)
//! is what `shaders/compile.sh` makes from their GLSL, `render_common.glsl`
//! and the shader library they include (`shaders/glsl`): a changed include
//! or tracer without a regenerated SPIR-V fails here.
//!
//! Without `glslangValidator`/`spirv-val` on `PATH` the test prints
//! `SKIPPED: ...` and passes, unless `MICROMAP_REQUIRE_VULKAN=1` (the CI
//! tier, which installs them), where it fails.

use std::path::Path;
use std::process::Command;

#[test]
fn committed_spirv_is_current() {
    let tools = ["glslangValidator", "spirv-val"].iter().all(|t| {
        Command::new(t)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    });
    if !tools {
        assert!(
            std::env::var("MICROMAP_REQUIRE_VULKAN").as_deref() != Ok("1"),
            "MICROMAP_REQUIRE_VULKAN=1 but glslangValidator or spirv-val is missing"
        );
        println!(
            "SKIPPED: no glslangValidator/spirv-val on PATH (Debian: glslang-tools spirv-tools)"
        );
        return;
    }
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    if !here.join("../../shaders/glsl/micromap_state.glsl").exists() {
        // The published package has the SPIR-V, not the repository's library.
        println!("SKIPPED: shaders/glsl is not here (outside the repository)");
        return;
    }
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("render-spirv");
    std::fs::create_dir_all(&out).unwrap();
    let status = Command::new("sh")
        .arg(here.join("shaders/compile.sh"))
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success(), "shaders/compile.sh failed");
    for name in [
        "render_query.spv",
        "render_pipeline_rgen.spv",
        "render_pipeline_rahit.spv",
        "render_pipeline_rchit.spv",
        "render_pipeline_rmiss.spv",
        "render_query_sampler.spv",
        "render_pipeline_rahit_sampler.spv",
    ] {
        let fresh = std::fs::read(out.join(name)).unwrap();
        let committed = std::fs::read(here.join("shaders").join(name)).unwrap();
        assert!(
            fresh == committed,
            "shaders/{name} is stale: run crates/render/shaders/compile.sh ({} bytes fresh, {} committed)",
            fresh.len(),
            committed.len()
        );
    }
}
