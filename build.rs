//! Build probe: `#[target_feature(enable = "avx512f")]` is stable from Rust
//! 1.89 on, above this crate's minimum supported version. When the compiler
//! accepts it, the cfg `micromap_avx512` turns on the AVX-512 backend of
//! `batch` (its loops in `src/arch/x86_64.rs`); older compilers build every
//! other backend.

use std::env;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=RUSTC");
    println!("cargo::rustc-check-cfg=cfg(micromap_avx512)");
    let rustc = env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let minor = Command::new(rustc)
        .arg("--version")
        .output()
        .ok()
        .and_then(|output| String::from_utf8(output.stdout).ok())
        .and_then(|version| {
            // "rustc 1.95.0 (59807616e 2026-04-14)"
            let number = version.split_whitespace().nth(1)?.to_owned();
            number.split('.').nth(1)?.parse::<u32>().ok()
        });
    if minor.is_some_and(|minor| minor >= 89) {
        println!("cargo:rustc-cfg=micromap_avx512");
    }
}
