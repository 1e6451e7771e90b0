//! `docs/cli.md` shows `micromap-lab`'s usage exactly as the binary renders
//! it from the flag tables (as `crates/cli/tests/cli_docs.rs` does for
//! `micromap-index`).

mod common;

use common::cli;

#[test]
fn docs_cli_md_shows_every_table_rendered_usage() {
    cli::CLI.docs_show_the_usage("micromap-lab", &["prove", "vectors"]);
}
