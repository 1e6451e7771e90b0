//! `docs/cli.md` shows each command's usage exactly as the binary renders
//! it from the command's flag table, and no usage that is not a command's
//! (`micromap-lab`'s: `crates/lab/tests/lab_docs.rs`).

mod common;

#[test]
fn docs_cli_md_shows_every_table_rendered_usage() {
    common::CLI.docs_show_the_usage(
        "micromap-index",
        &[
            "eval",
            "locate",
            "check",
            "tree",
            "bake",
            "verify-bake",
            "render",
        ],
    );
}
