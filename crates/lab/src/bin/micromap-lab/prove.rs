//! `micromap-lab prove --levels A..=B`: the walk against the reference on
//! every face of each level (or on random faces with `--sample N`).
//!
//! Exit 0 equal on every face, 1 a mismatch, 2 usage error (an empty level
//! range or `--sample 0` included: a check of nothing is not a success),
//! 130 interrupted, 3 or 141 if stdout cannot be written.

use cli_support::args::{level_range, ArgError, Command, Flag, RangeError};
use cli_support::output::{self, Exit, Program, Stdout};
use micromap_index::Level;
use micromap_index_lab::prove::{
    prove_level, sample_level, LevelReport, Method, Mismatch, Progress, ProveError, Reference,
    Settings, WalkVersion, FACE_KINDS,
};
use serde::Serialize;
use std::io::IsTerminal;
use std::ops::RangeInclusive;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// `--version1`, in both forms of `prove`.
pub(crate) const VERSION1: Flag =
    Flag::switch("--version1", "the talk's first walk (which fails)").repeatable();
/// `--json`, in both forms of `prove`.
pub(crate) const JSON: Flag =
    Flag::switch("--json", "JSON lines instead of the table").repeatable();

/// The flag table of `prove --levels`. Every flag may be repeated (the last
/// counts).
pub(crate) static PROVE: Command = Command {
    name: "prove",
    forms: &["--levels A..=B [OPTIONS]"],
    about: "  Compares the walk with the reference on every face of each level's lattice
  (a proof for all real points); per level: faces checked, mismatches,
  seconds. A..B excludes B; a single level N is N..=N; an empty range is a
  usage error. Exit 0 equal, 1 mismatch, 130 interrupted.",
    flags: &[
        Flag::value(
            "--levels",
            "A..=B",
            "the levels (A..B excludes B; N is N..=N)",
        )
        .wants("A..=B")
        .repeatable(),
        Flag::switch(
            "--spec-wide",
            "the 64-bit reference (levels to 32; default 32-bit, to 16)",
        )
        .repeatable(),
        VERSION1,
        Flag::value(
            "--sample",
            "N",
            "N >= 1 random faces per level, walked step by step",
        )
        .wants("a number of faces")
        .repeatable(),
        Flag::value("--seed", "S", "the sample's seed (default 1)")
            .wants("a number")
            .repeatable(),
        JSON,
        Flag::value("--threads", "T", "worker threads (default: all cores)")
            .wants("a number")
            .repeatable(),
        Flag::value("--examples", "K", "mismatches shown per level")
            .wants("a number")
            .repeatable(),
    ],
};

struct Options {
    levels: RangeInclusive<u32>,
    settings: Settings,
    sample: Option<u64>,
    seed: u64,
    json: bool,
}

pub(crate) fn run(program: &Program, options: &[&str]) -> Exit {
    if options.contains(&"--all-levels") {
        return crate::prove_all_levels::run(program, options);
    }
    match parse(options) {
        Ok(options) => {
            let mut out = Stdout::line_by_line(program);
            let result = prove(program, &options, &mut out);
            out.finish(output::either(result))
        }
        Err(message) => program.usage_error(&format!("prove: {message}")),
    }
}

fn parse(args: &[&str]) -> Result<Options, String> {
    let parsed = PROVE.parse(args).map_err(|e| match e {
        ArgError::TakesNoValue(name, _) => format!("{name} takes no value"),
        other => other.describe(),
    })?;
    let mut settings = Settings::default();
    let levels = parsed.get("--levels").map(parse_levels).transpose()?;
    let sample = parsed.get("--sample").map(parse_count).transpose()?;
    let seed = parsed.get("--seed").map(parse_count).transpose()?;
    if let Some(threads) = parsed.get("--threads") {
        settings.threads = parse_small(threads, "--threads")?;
    }
    if let Some(examples) = parsed.get("--examples") {
        settings.examples = parse_small(examples, "--examples")?;
    }
    if parsed.flag("--spec-wide") {
        settings.reference = Reference::SpecWide;
    }
    if parsed.flag("--version1") {
        settings.walk = WalkVersion::Version1;
    }
    let json = parsed.flag("--json");
    let levels = levels.ok_or("--levels A..=B is required")?;
    let max = settings.reference.max_level();
    if *levels.end() > max {
        return Err(format!(
            "level {} is above {max}, the highest the {} reference supports{}",
            levels.end(),
            settings.reference.name(),
            if max < Level::MAX {
                " (--spec-wide goes to 32)"
            } else {
                ""
            }
        ));
    }
    if sample == Some(0) {
        return Err("--sample 0 checks nothing; give at least 1 face".into());
    }
    if seed.is_some() && sample.is_none() {
        return Err("--seed only applies with --sample".into());
    }
    Ok(Options {
        levels,
        settings,
        sample,
        seed: seed.unwrap_or(1),
        json,
    })
}

/// `A..=B`, `A..B` (B excluded) or a single level `N`.
fn parse_levels(text: &str) -> Result<RangeInclusive<u32>, String> {
    level_range(text).map_err(|e| match e {
        RangeError::BadLevel(level) => format!("bad level {level:?} in --levels {text:?}"),
        RangeError::Empty => format!("empty --levels {text:?}"),
    })
}

/// A count: digits with optional `_` separators, or `MeK` for `M * 10^K`
/// (`1e9`).
fn parse_count(text: &str) -> Result<u64, String> {
    let bad = || format!("bad number {text:?}");
    let digits = |s: &str| -> Result<u64, String> {
        let s: String = s.chars().filter(|&c| c != '_').collect();
        if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad());
        }
        s.parse().map_err(|_| bad())
    };
    match text.split_once(['e', 'E']) {
        Some((mantissa, exponent)) => {
            let exponent = u32::try_from(digits(exponent)?).map_err(|_| bad())?;
            10u64
                .checked_pow(exponent)
                .and_then(|scale| digits(mantissa).ok()?.checked_mul(scale))
                .ok_or_else(bad)
        }
        None => digits(text),
    }
}

fn parse_small(text: &str, name: &str) -> Result<usize, String> {
    text.parse::<usize>()
        .ok()
        .filter(|&n| n <= 4096)
        .ok_or_else(|| format!("bad {name} {text:?}"))
}

fn prove(program: &Program, options: &Options, out: &mut Stdout) -> Result<Exit, Exit> {
    let progress = Arc::new(Progress::new());
    install_ctrl_c(program, &progress);
    let show_bar = std::io::stderr().is_terminal();
    if !options.json {
        print_header(options, out)?;
    }
    let started = Instant::now();
    let mut any_mismatch = false;
    for level in options.levels.clone() {
        // Levels were checked against the reference's limit when parsing.
        let Ok(level) = Level::new(level) else {
            return Err(program.usage_error("prove: level above 32"));
        };
        let report = with_progress_bar(show_bar, level, &progress, || match options.sample {
            Some(samples) => {
                sample_level(level, samples, options.seed, &options.settings, &progress)
            }
            None => prove_level(level, &options.settings, &progress),
        });
        let report = match report {
            Ok(report) => report,
            Err(ProveError::Level(e)) => return Err(program.usage_error(&format!("prove: {e}"))),
            Err(e) => {
                program.report(format_args!("prove: {e}"));
                return Err(Exit::Failed);
            }
        };
        any_mismatch |= report.mismatches() > 0
            || (report.complete && report.faces_checked != report.faces_expected);
        if options.json {
            print_json(program, &report, &options.settings, out)?;
        } else {
            print_row(&report, out)?;
        }
        if !report.complete {
            program.report(format_args!(
                "prove: interrupted during level {level}; the row above counts only the finished part"
            ));
            return Ok(Exit::Interrupted);
        }
    }
    if !options.json {
        out.line(format_args!(
            "total {:.1} s; {}",
            started.elapsed().as_secs_f64(),
            if any_mismatch {
                "MISMATCHES: the walk differs from the reference"
            } else if options.sample.is_some() {
                "no mismatch on the sampled faces (a sample is not a proof)"
            } else {
                "equal on every face: proved for these levels"
            }
        ))?;
    }
    Ok(if any_mismatch {
        Exit::Failed
    } else {
        Exit::Success
    })
}

/// First Ctrl-C: ask the check to stop after the work in flight, so the
/// finished part is still reported. Second Ctrl-C: exit at once.
fn install_ctrl_c(program: &Program, progress: &Arc<Progress>) {
    let progress = Arc::clone(progress);
    let result = ctrlc::set_handler(move || {
        if progress.is_cancelled() {
            std::process::exit(i32::from(Exit::Interrupted.code()));
        }
        progress.cancel();
    });
    if let Err(e) = result {
        program.report(format_args!(
            "prove: cannot catch Ctrl-C ({e}); it will end the run at once"
        ));
    }
}

/// Runs `work`, drawing a progress bar on stderr meanwhile if `show`.
fn with_progress_bar<T>(
    show: bool,
    level: Level,
    progress: &Progress,
    work: impl FnOnce() -> T,
) -> T {
    if !show {
        return work();
    }
    let finished = AtomicBool::new(false);
    let started = Instant::now();
    std::thread::scope(|scope| {
        scope.spawn(|| {
            while !finished.load(Ordering::Relaxed) {
                draw_bar(level, progress, started);
                std::thread::sleep(Duration::from_millis(200));
            }
            output::to_stderr("\r\x1b[K");
        });
        let result = work();
        finished.store(true, Ordering::Relaxed);
        result
    })
}

fn draw_bar(level: Level, progress: &Progress, started: Instant) {
    const WIDTH: u64 = 30;
    let (done, total) = progress.units();
    let filled = (done * WIDTH).checked_div(total).unwrap_or(0).min(WIDTH) as usize;
    let percent = (done as f64 * 100.0) / (total.max(1) as f64);
    output::to_stderr(format_args!(
        "\rlevel {level:>2} [{}{}] {percent:5.1}% {:7.1} s",
        "#".repeat(filled),
        ".".repeat(WIDTH as usize - filled),
        started.elapsed().as_secs_f64()
    ));
}

fn print_header(options: &Options, out: &mut Stdout) -> Result<(), Exit> {
    let what = match options.sample {
        Some(samples) => format!("{samples} random faces per level (seed {})", options.seed),
        None => "every face of the lattice".into(),
    };
    out.line(format_args!(
        "{} vs {}: {what}",
        options.settings.walk.name(),
        options.settings.reference.name()
    ))?;
    out.line(format_args!(
        "{:>5} {:>16} {:>16} {:>12} {:>10}",
        "level", "faces checked", "expected", "mismatches", "seconds"
    ))
}

fn print_row(report: &LevelReport, out: &mut Stdout) -> Result<(), Exit> {
    out.line(format_args!(
        "{:>5} {:>16} {:>16} {:>12} {:>10.3}{}",
        report.level.get(),
        report.faces_checked,
        report.faces_expected,
        report.mismatches(),
        report.seconds,
        if report.complete {
            ""
        } else {
            "  (interrupted)"
        }
    ))?;
    if report.mismatches() > 0 {
        let per_kind: Vec<String> = FACE_KINDS
            .iter()
            .zip(report.mismatches_by_kind)
            .filter(|(_, count)| *count > 0)
            .map(|(kind, count)| format!("{} {count}", kind.name()))
            .collect();
        out.line(format_args!("      by kind: {}", per_kind.join(", ")))?;
        for example in &report.examples {
            let shown = ShownMismatch::from(example);
            out.line(format_args!(
                "      (u, v) = ({}, {}), {}: walk {}, {} {}",
                shown.u,
                shown.v,
                shown.kind,
                shown.walk,
                report.reference.name(),
                shown.reference
            ))?;
        }
    }
    Ok(())
}

/// One level as a JSON line.
#[derive(Serialize)]
struct JsonReport<'a> {
    level: u32,
    walk: &'a str,
    reference: &'a str,
    method: &'a str,
    seed: Option<u64>,
    faces_checked: u128,
    faces_expected: u128,
    mismatches: u128,
    mismatches_by_kind: serde_json::Map<String, serde_json::Value>,
    examples: Vec<ShownMismatch>,
    seconds: f64,
    complete: bool,
    threads: usize,
}

/// A mismatch with its point as exact rationals.
#[derive(Serialize)]
struct ShownMismatch {
    u: String,
    v: String,
    kind: &'static str,
    walk: u64,
    reference: u64,
}

impl From<&Mismatch> for ShownMismatch {
    fn from(mismatch: &Mismatch) -> Self {
        let (u, v) = mismatch.face.to_rational();
        ShownMismatch {
            u: u.to_string(),
            v: v.to_string(),
            kind: mismatch.face.kind.name(),
            walk: mismatch.walk,
            reference: mismatch.reference,
        }
    }
}

fn print_json(
    program: &Program,
    report: &LevelReport,
    settings: &Settings,
    out: &mut Stdout,
) -> Result<(), Exit> {
    let (method, seed) = match report.method {
        Method::Exhaustive => ("exhaustive", None),
        Method::Sampled { seed } => ("sampled", Some(seed)),
    };
    let mismatches_by_kind = FACE_KINDS
        .iter()
        .zip(report.mismatches_by_kind)
        // Counts fit u64: a level has fewer than 2^66 faces and no run gets near 2^64.
        .map(|(kind, count)| {
            (
                kind.name().to_string(),
                u64::try_from(count).unwrap_or(u64::MAX).into(),
            )
        })
        .collect();
    let line = JsonReport {
        level: report.level.get(),
        walk: report.walk.name(),
        reference: report.reference.name(),
        method,
        seed,
        faces_checked: report.faces_checked,
        faces_expected: report.faces_expected,
        mismatches: report.mismatches(),
        mismatches_by_kind,
        examples: report.examples.iter().map(ShownMismatch::from).collect(),
        seconds: report.seconds,
        complete: report.complete,
        threads: if settings.threads > 0 {
            settings.threads
        } else {
            std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
        },
    };
    match serde_json::to_string(&line) {
        Ok(text) => out.line(text),
        Err(e) => {
            program.report(format_args!("prove: cannot write JSON: {e}"));
            Err(Exit::Io)
        }
    }
}
