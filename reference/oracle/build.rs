//! Compiles `reference/c/spec_reference.c` into a static library.

use std::env;
use std::path::PathBuf;

fn main() {
    let manifest_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let c_dir = manifest_dir.join("..").join("c");
    let source = c_dir.join("spec_reference.c");
    let header = c_dir.join("spec_reference.h");
    println!("cargo:rerun-if-changed={}", source.display());
    println!("cargo:rerun-if-changed={}", header.display());

    let mut build = cc::Build::new();
    build
        .file(&source)
        .include(&c_dir)
        .warnings(true)
        // Fixed rather than taken from the profile, so the oracle is the same
        // code in every profile. The flags below are GCC/Clang spellings and
        // added unconditionally: a compiler that rejects them should fail the
        // build, not silently drop a flag the results depend on.
        .opt_level(2)
        // The reference rounds `uf + vf` on its own before the compare; an
        // FMA contraction (GCC's default in GNU C mode on targets with FMA)
        // would skip a rounding.
        .flag("-ffp-contract=off")
        // Fast math would let the compiler ignore NaN, which the clamp relies
        // on. CFLAGS from the environment come later on cc's command line and
        // win, so the C file also refuses to compile under fast math.
        .flag("-fno-fast-math");
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    if arch == "x86_64" || arch == "x86" {
        // Binary32 in SSE registers, never the x87 stack: x87 keeps excess
        // precision and would change rounding (x86_64's default already, but
        // a 32-bit x86 target defaults to x87). The C file refuses to compile
        // unless FLT_EVAL_METHOD == 0.
        build.flag("-msse2").flag("-mfpmath=sse");
    }
    build.compile("micromap_spec_reference");
}
