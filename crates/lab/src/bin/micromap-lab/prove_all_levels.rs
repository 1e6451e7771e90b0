//! `micromap-lab prove --all-levels [--version1] [--json] [--list]
//! [--certificate FILE]`: the
//! walk against the reference at every level at once, by exploring the
//! product of two digit transducers (`micromap_index_lab::prove_all_levels`).

use crate::prove::{JSON, VERSION1};
use cli_support::args::{ArgError, Command, Flag};
use cli_support::output::{print_then, Exit, Program};
use cli_support::write_all_or_nothing::write_files;
use micromap_index_lab::entry_points::{
    prove_binary32_first_half, prove_binary64_first_half, prove_cell_dyadic,
    prove_fixed_arithmetic, prove_float_clamp, prove_float_first_half, prove_kernel_integer_halves,
    prove_literal_first_half, prove_rationals_source, prove_simd_lanes, prove_walk_fold,
    Binary32Counterexample, Binary32Proof, Binary64Counterexample, Binary64Proof,
    ClampCounterexample, ClampProof, DyadicCounterexample, DyadicProof, FixedMismatch, FixedProof,
    FloatCounterexample, FloatProof, FoldMismatch, FoldProof, KernelProof, KernelProofError,
    LanesError, LanesProof, LiteralCounterexample, LiteralProof, RationalsMismatch, RationalsProof,
};
use micromap_index_lab::prove::WalkVersion;
use micromap_index_lab::prove_all_levels::{prove_all_levels, AllLevelsReport, Verdict};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// The flag table of `prove --all-levels`: switches (each may be
/// repeated) and the certificate's file.
pub(crate) static ALL_LEVELS: Command = Command {
    name: "prove",
    forms: &[
        "--all-levels [--version1] [--json] [--list]",
        "--all-levels --certificate FILE [--json] [--list]",
    ],
    about: "  --all-levels proves the walk equal to the reference at every level at once
  by exploring the finite product of two digit transducers (under a second),
  then the kernel's integer halves and first halves on the bits,
  spec::cell_dyadic and exact_index_f64's first half (levels 0..=32) equal
  to the reference's code and definition at every input (decision
  diagrams), the kernel's float first half's two steps at every binary32
  input (exhaustion) and its clamp's two changes (diagrams), the literal
  port's first half (spec::cell_f32) at every binary32 input (exhaustion),
  index_unchecked, token for token, the fold of Walk::step the product
  models, Fixed64 / Fixed128's walk arithmetic and spec::cell_real's fast
  path, token for token, the code product.py's walk range and
  certificates/rationals.py prove exact, and the x86-64 SIMD lanes, token for token, the modelled
  intrinsics, whose readings are run on every backend this CPU has
  (docs/verification.md 10.12); exit 0 all proved, 1 not; with --version1
  it must fail and prints a face; --list prints every product state and
  transition; --certificate writes the proved product for
  crates/lab/certificates/product.py (docs/verification.md 10), exit 3 if
  it cannot.",
    flags: &[
        Flag::switch(
            "--all-levels",
            "every level at once (the transducer product)",
        )
        .repeatable(),
        VERSION1,
        JSON,
        Flag::switch("--list", "every product state and transition").repeatable(),
        Flag::value(
            "--certificate",
            "FILE",
            "write the proved product there (all or nothing)",
        ),
    ],
};

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    let parsed = match ALL_LEVELS.parse(options) {
        Ok(parsed) => parsed,
        Err(ArgError::Unknown(word) | ArgError::TakesNoValue(_, word)) => {
            return program.usage_error(&format!(
                "prove --all-levels: unknown option {word:?} (only --version1, --json, --list, --certificate)"
            ))
        }
        Err(other) => return program.usage_error(&other.message("prove --all-levels")),
    };
    let version = if parsed.flag("--version1") {
        WalkVersion::Version1
    } else {
        WalkVersion::Version2
    };
    let (json, list) = (parsed.flag("--json"), parsed.flag("--list"));
    let started = Instant::now();
    let report = match prove_all_levels(version) {
        Ok(report) => report,
        Err(e) => {
            program.report(format_args!("prove --all-levels: {e}"));
            return Exit::Failed;
        }
    };
    let seconds = started.elapsed().as_secs_f64();
    let confirmed = confirmed(&report);
    let entry_points = EntryPoints::prove();
    let mut text = String::new();
    if json {
        print_json(
            program,
            &mut text,
            &report,
            seconds,
            confirmed,
            &entry_points,
        );
    } else {
        print_text(&mut text, &report, seconds, confirmed);
        print_entry_points(&mut text, &entry_points);
    }
    if list {
        for line in report.listing() {
            let _ = writeln!(text, "{line}");
        }
    }
    let mut verdict = if report.is_proof() && entry_points.all_proved() {
        Exit::Success
    } else {
        Exit::Failed
    };
    if let Some(file) = parsed.get("--certificate") {
        match report.certificate() {
            Some(certificate) => {
                if let Err(e) = write_certificate(Path::new(file), certificate) {
                    program.report(format_args!("prove --all-levels: {e}"));
                    verdict = Exit::Io;
                }
            }
            None => {
                let _ = writeln!(text, "no certificate written to {file}: nothing was proved");
            }
        }
    }
    print_then(program, &text, verdict)
}

/// Writes the certificate to `file`: the whole file or (after an error)
/// nothing, the old content kept.
fn write_certificate(file: &Path, certificate: String) -> Result<(), String> {
    let name = file
        .file_name()
        .and_then(|name| name.to_str())
        .ok_or_else(|| format!("--certificate {}: not a file name", file.display()))?;
    let dir = match file.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    write_files(dir, &[(name.to_owned(), certificate.into_bytes())])
}

/// For a counterexample: whether the real functions differ at the face
/// and give the transducers' indices.
fn confirmed(report: &AllLevelsReport) -> Option<bool> {
    match &report.verdict {
        Verdict::Counterexample(example) => Some(example.real.is_some_and(|(walk, reference)| {
            walk != reference && (walk, reference) == (example.walk_index, example.reference_index)
        })),
        _ => None,
    }
}

fn print_text(out: &mut String, report: &AllLevelsReport, seconds: f64, confirmed: Option<bool>) {
    let name = report.walk.map_or("mutated walk", WalkVersion::name);
    let c = &report.counts;
    let _ = writeln!(
        out,
        "{name} vs the reference (exact first half, unbounded integer half), every level:"
    );
    let _ = writeln!(
        out,
        "  checker states (remainder sum, zero flags)  {:>8}",
        c.checker
    );
    let _ = writeln!(
        out,
        "  live (checker, reference guess) states      {:>8}",
        c.live_guesses
    );
    let _ = writeln!(
        out,
        "  start states                                {:>8}",
        c.starts
    );
    let _ = writeln!(
        out,
        "  walk transducer states reached              {:>8}",
        c.walk
    );
    let _ = writeln!(
        out,
        "  reference transducer states reached         {:>8}",
        c.reference
    );
    let _ = writeln!(
        out,
        "  product states reached                      {:>8}",
        c.product
    );
    let _ = writeln!(
        out,
        "  transitions compared                        {:>8}",
        c.transitions
    );
    match &report.verdict {
        Verdict::Proved => drop(writeln!(
            out,
            "proved in {seconds:.3} s: no reachable state emits two different digits, so the \
             walk equals the reference at every real point of every level"
        )),
        Verdict::Counterexample(example) => {
            let (u, v) = example.representative();
            let _ = writeln!(
                out,
                "NOT proved: at level {} the {} with representative (u, v) = ({u}, {v}) gets \
                 walk index {} and reference index {}",
                example.level.get(),
                example.face.kind.name(),
                example.walk_index,
                example.reference_index
            );
            match (example.real, confirmed) {
                (Some((walk, reference)), Some(true)) => drop(writeln!(
                    out,
                    "  confirmed by the real functions: {} = {walk}, \
                     spec::wide_index_dyadic = {reference}",
                    if report.walk == Some(WalkVersion::Version1) {
                        "internals::index_version1_unchecked"
                    } else {
                        "uv2index::index_unchecked"
                    }
                )),
                (Some((walk, reference)), _) => {
                    let _ = writeln!(out,
                    "  NOT confirmed by the real functions (walk {walk}, reference {reference}): \
                     the construction is wrong"
                );
                }
                (None, _) => {
                    let _ = writeln!(out, "  (no real walk to confirm it with)");
                }
            }
        }
        Verdict::Failed(e) => {
            let _ = writeln!(out, "NOT proved: the construction failed: {e}");
        }
    }
}

/// The entry points' proofs (`docs/verification.md` 10.12), each with its
/// seconds.
struct EntryPoints {
    kernels: (Result<KernelProof, KernelProofError>, f64),
    dyadic: (Result<DyadicProof, DyadicCounterexample>, f64),
    binary32: (Result<Binary32Proof, Binary32Counterexample>, f64),
    binary64: (Result<Binary64Proof, Binary64Counterexample>, f64),
    float: (Result<FloatProof, FloatCounterexample>, f64),
    clamp: (Result<ClampProof, ClampCounterexample>, f64),
    literal: (Result<LiteralProof, LiteralCounterexample>, f64),
    fold: (Result<FoldProof, FoldMismatch>, f64),
    rationals: (Result<RationalsProof, RationalsMismatch>, f64),
    fixed: (Result<FixedProof, FixedMismatch>, f64),
    lanes: (Result<LanesProof, LanesError>, f64),
}

impl EntryPoints {
    fn prove() -> Self {
        fn timed<T>(prove: impl FnOnce() -> T) -> (T, f64) {
            let started = Instant::now();
            let result = prove();
            (result, started.elapsed().as_secs_f64())
        }
        Self {
            kernels: timed(prove_kernel_integer_halves),
            dyadic: timed(prove_cell_dyadic),
            binary32: timed(prove_binary32_first_half),
            binary64: timed(prove_binary64_first_half),
            float: timed(prove_float_first_half),
            clamp: timed(prove_float_clamp),
            literal: timed(prove_literal_first_half),
            fold: timed(prove_walk_fold),
            rationals: timed(prove_rationals_source),
            fixed: timed(prove_fixed_arithmetic),
            lanes: timed(prove_simd_lanes),
        }
    }

    fn all_proved(&self) -> bool {
        self.kernels.0.is_ok()
            && self.dyadic.0.is_ok()
            && self.binary32.0.is_ok()
            && self.binary64.0.is_ok()
            && self.float.0.is_ok()
            && self.clamp.0.is_ok()
            && self.literal.0.is_ok()
            && self.fold.0.is_ok()
            && self.rationals.0.is_ok()
            && self.fixed.0.is_ok()
            && self.lanes.0.is_ok()
    }
}

/// One entry point's line: what `proved` says of its proof, or its
/// counterexample (`docs/verification.md` 10.12).
fn print_entry_point<P, E: std::fmt::Display>(
    out: &mut String,
    (result, seconds): &(Result<P, E>, f64),
    proved: impl Fn(&P, f64) -> String,
) {
    match result {
        Ok(proof) => drop(writeln!(out, "entry points: {}", proved(proof, *seconds))),
        Err(e) => drop(writeln!(out, "entry points: NOT proved: {e}")),
    }
}

/// Every entry point's lines: the kernel's integer halves against the
/// reference's generic code, `spec::cell_dyadic`, the kernel's binary32
/// and float and `exact_index_f64`'s first halves against the definition,
/// and the walk's fold against its model.
fn print_entry_points(out: &mut String, entry_points: &EntryPoints) {
    print_entry_point(out, &entry_points.kernels, |proof, seconds| {
        let mut text = format!(
            "the kernel's integer halves equal the reference's at every cell of every level \
             they serve ({} cases, {} reference paths, at most {} diagram nodes, \
             {seconds:.3} s):",
            proof.cases, proof.reference_paths, proof.peak_nodes
        );
        for (form, levels) in &proof.forms {
            let _ = write!(
                text,
                "\n  {:<44} levels {}..={}",
                form.name(),
                levels.start(),
                levels.end()
            );
        }
        text
    });
    print_entry_point(out, &entry_points.dyadic, |proof, seconds| {
        format!(
            "spec::cell_dyadic is the definition's cell and diagonal at every input, scale \
             0..=62 and level 0..=32 ({} cases, {} paths, at most {} diagram nodes, \
             {seconds:.3} s)",
            proof.cases, proof.paths, proof.peak_nodes
        )
    });
    print_entry_point(out, &entry_points.binary32, |proof, seconds| {
        format!(
            "the kernel's binary32 first half on the bits (wide, levels 0..=32; scalar narrow, \
             0..=16) is the definition's cell and fraction at every binary32 input ({} cases, \
             at most {} diagram nodes, {seconds:.3} s)",
            proof.cases, proof.peak_nodes
        )
    });
    print_entry_point(out, &entry_points.binary64, |proof, seconds| {
        format!(
            "exact_index_f64's first half (levels 0..=32) is the definition's cell and exact \
             diagonal at every binary64 input ({} cases, at most {} diagram nodes, \
             {seconds:.3} s)",
            proof.cases, proof.peak_nodes
        )
    });
    print_entry_point(out, &entry_points.float, |proof, seconds| {
        format!(
            "the kernel's float first half (clamp_flushed, truncate_float) holds its claims at \
             every binary32 input ({} inputs, {seconds:.3} s)",
            proof.inputs
        )
    });
    print_entry_point(out, &entry_points.clamp, |proof, seconds| {
        let forms: Vec<_> = proof.forms.iter().map(|form| form.name()).collect();
        format!(
            "the float clamp's flush below 2^-126 and stop at 1 - 2^-24 leave the index alone, \
             levels {}..={} (the stop's cell is the last, the flush's fraction at most 2^-110; \
             with a last cell {} do not read the diagonal; {seconds:.3} s)",
            proof.levels.start(),
            proof.levels.end(),
            forms.join(" and ")
        )
    });
    print_entry_point(out, &entry_points.literal, |proof, seconds| {
        format!(
            "the reference's literal port's first half (spec::cell_f32: clamp_unit, \
             truncate_scaled) holds its claims at every binary32 input ({} inputs, \
             {seconds:.3} s)",
            proof.inputs
        )
    });
    print_entry_point(out, &entry_points.fold, |proof, _| {
        format!(
            "uv2index::{} are, token for token, the fold of Walk::step the product models ({} \
             tokens of src/uv2index/mod.rs)",
            proof.functions.join(" and "),
            proof.tokens
        )
    });
    print_entry_point(out, &entry_points.rationals, |proof, _| {
        format!(
            "spec::cell_real's fast path ({}) is, token for token, the code \
             crates/lab/certificates/rationals.py proves with z3 ({} tokens)",
            proof.functions.join(", "),
            proof.tokens
        )
    });
    print_entry_point(out, &entry_points.fixed, |proof, _| {
        format!(
            "num::Fixed64 / Fixed128's walk arithmetic is, token for token, the modelled exact \
             integer steps ({} tokens of src/num/fixed.rs; exact: product.py's walk range keeps \
             every value in [0, 1])",
            proof.tokens
        )
    });
    print_entry_point(out, &entry_points.lanes, |proof, seconds| {
        let skipped = if proof.skipped.is_empty() {
            "none".to_owned()
        } else {
            format!(
                "{} (not run by this CPU or build: structure only)",
                proof.skipped.join(", ")
            )
        };
        format!(
            "the x86-64 SIMD lanes are, token for token, the modelled intrinsics ({} tokens of \
             src/arch/x86_64.rs), whose readings hold at every input the lanes give them \
             ({} lane inputs each, {seconds:.3} s): run {}; SKIPPED {skipped}",
            proof.tokens,
            proof.inputs,
            if proof.checked.is_empty() {
                "none".to_owned()
            } else {
                proof.checked.join(", ")
            }
        )
    });
}

#[derive(Serialize)]
struct JsonKernels {
    verdict: &'static str,
    cases: usize,
    detail: Option<String>,
}

#[derive(Serialize)]
struct JsonCounterexample {
    level: u32,
    kind: &'static str,
    u: String,
    v: String,
    walk: u64,
    reference: u64,
    real_walk: Option<u64>,
    real_reference: Option<u64>,
    confirmed: bool,
}

#[derive(Serialize)]
struct JsonReport {
    walk: &'static str,
    reference: &'static str,
    method: &'static str,
    checker_states: usize,
    live_guess_states: usize,
    start_states: usize,
    walk_states: usize,
    reference_states: usize,
    product_states: usize,
    transitions: usize,
    verdict: &'static str,
    counterexample: Option<JsonCounterexample>,
    error: Option<String>,
    seconds: f64,
    kernel_integer_halves: JsonKernels,
    cell_dyadic: JsonKernels,
    binary32_first_half: JsonKernels,
    binary64_first_half: JsonKernels,
    float_first_half: JsonKernels,
    float_clamp: JsonKernels,
    literal_first_half: JsonKernels,
    walk_fold: JsonKernels,
    rationals_source: JsonKernels,
    fixed_arithmetic: JsonKernels,
    simd_lanes: JsonKernels,
}

fn print_json(
    program: &Program,
    out: &mut String,
    report: &AllLevelsReport,
    seconds: f64,
    confirmed: Option<bool>,
    entry_points: &EntryPoints,
) {
    let c = &report.counts;
    let (verdict, counterexample, error) = match &report.verdict {
        Verdict::Proved => ("proved", None, None),
        Verdict::Counterexample(example) => {
            let (u, v) = example.representative();
            (
                "counterexample",
                Some(JsonCounterexample {
                    level: example.level.get(),
                    kind: example.face.kind.name(),
                    u,
                    v,
                    walk: example.walk_index,
                    reference: example.reference_index,
                    real_walk: example.real.map(|r| r.0),
                    real_reference: example.real.map(|r| r.1),
                    confirmed: confirmed == Some(true),
                }),
                None,
            )
        }
        Verdict::Failed(e) => ("failed", None, Some(e.to_string())),
    };
    let line = JsonReport {
        walk: report.walk.map_or("mutated", WalkVersion::name),
        reference: "spec-unbounded",
        method: "all-levels",
        checker_states: c.checker,
        live_guess_states: c.live_guesses,
        start_states: c.starts,
        walk_states: c.walk,
        reference_states: c.reference,
        product_states: c.product,
        transitions: c.transitions,
        verdict,
        counterexample,
        error,
        seconds,
        kernel_integer_halves: json_entry_point(
            entry_points.kernels.0.as_ref().map(|proof| proof.cases),
        ),
        cell_dyadic: json_entry_point(entry_points.dyadic.0.as_ref().map(|proof| proof.cases)),
        binary32_first_half: json_entry_point(
            entry_points.binary32.0.as_ref().map(|proof| proof.cases),
        ),
        binary64_first_half: json_entry_point(
            entry_points.binary64.0.as_ref().map(|proof| proof.cases),
        ),
        float_first_half: json_entry_point(
            entry_points
                .float
                .0
                .as_ref()
                .map(|proof| usize::try_from(proof.inputs).unwrap_or(usize::MAX)),
        ),
        float_clamp: json_entry_point(
            entry_points
                .clamp
                .0
                .as_ref()
                .map(|proof| proof.levels.clone().count()),
        ),
        literal_first_half: json_entry_point(
            entry_points
                .literal
                .0
                .as_ref()
                .map(|proof| usize::try_from(proof.inputs).unwrap_or(usize::MAX)),
        ),
        walk_fold: json_entry_point(
            entry_points
                .fold
                .0
                .as_ref()
                .map(|proof| proof.functions.len()),
        ),
        rationals_source: json_entry_point(
            entry_points
                .rationals
                .0
                .as_ref()
                .map(|proof| proof.functions.len()),
        ),
        fixed_arithmetic: json_entry_point(entry_points.fixed.0.as_ref().map(|proof| proof.tokens)),
        simd_lanes: json_lanes(&entry_points.lanes.0),
    };
    match serde_json::to_string(&line) {
        Ok(text) => {
            let _ = writeln!(out, "{text}");
        }
        Err(e) => program.report(format_args!("prove --all-levels: cannot write JSON: {e}")),
    }
}

/// The SIMD lanes' JSON verdict: the instruction sets run as its cases, and
/// those skipped (structure only) in its detail.
fn json_lanes(proof: &Result<LanesProof, LanesError>) -> JsonKernels {
    let mut verdict = json_entry_point(proof.as_ref().map(|proof| proof.checked.len()));
    if let Ok(proof) = proof {
        if !proof.skipped.is_empty() {
            verdict.detail = Some(format!("SKIPPED: {}", proof.skipped.join(", ")));
        }
    }
    verdict
}

/// One entry point's JSON verdict: its case count, or its counterexample.
fn json_entry_point<E: std::fmt::Display>(proof: Result<usize, &E>) -> JsonKernels {
    match proof {
        Ok(cases) => JsonKernels {
            verdict: "proved",
            cases,
            detail: None,
        },
        Err(e) => JsonKernels {
            verdict: "counterexample",
            cases: 0,
            detail: Some(e.to_string()),
        },
    }
}
