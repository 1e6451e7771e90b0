//! The default work budgets (the unit: [bounded work](super#bounded-work)).

/// Work units ([bounded work](super#bounded-work)) one triangle may spend by
/// default: 2^26, about 4 per micro-triangle of a level-12 map; 3.4 s of
/// CPU at the costliest units measured ([bounded work](super#bounded-work)). The
/// bundled assets' bakes stay under a sixteenth of it per triangle
/// (`crates/cli/tests/cli_bake_work.rs`).
pub const DEFAULT_TRIANGLE_WORK_BUDGET: u64 = 1 << 26;

/// Work units a whole [`bake_meshes`](super::mesh::bake_meshes) may spend
/// by default: 2^34, about 4 per micro-triangle of the 1 GiB of 4-state
/// maps the CLI allows by default (`--max-bytes`).
pub const DEFAULT_BAKE_WORK_BUDGET: u64 = 1 << 34;
