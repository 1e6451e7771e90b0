//! The committed SPIR-V (`shaders/render_query.spv`) is what
//! `shaders/compile.sh` makes from `shaders/render_query.comp` and the
//! shader library it includes (`shaders/glsl`): a changed include or
//! tracer without a regenerated SPIR-V fails here.
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
    let fresh = std::fs::read(out.join("render_query.spv")).unwrap();
    let committed = std::fs::read(here.join("shaders/render_query.spv")).unwrap();
    assert!(
        fresh == committed,
        "shaders/render_query.spv is stale: run crates/render/shaders/compile.sh ({} bytes fresh, {} committed)",
        fresh.len(),
        committed.len()
    );
}
