//! `micromap-index prove --levels A..=B`: the walk against the reference on
//! every face of each level (or on random faces with `--sample N`).

use crate::usage_error;
use micromap_index::Level;
use micromap_index_verify::prove::{
    prove_level, sample_level, LevelReport, Method, Mismatch, Progress, ProveError, Reference,
    Settings, WalkVersion, FACE_KINDS,
};
use serde::Serialize;
use std::io::{IsTerminal, Write};
use std::ops::RangeInclusive;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Exit code after Ctrl-C, as shells report a SIGINT death.
const INTERRUPTED: u8 = 130;

struct Options {
    levels: RangeInclusive<u32>,
    settings: Settings,
    sample: Option<u64>,
    seed: u64,
    json: bool,
}

pub(crate) fn run(options: &[&str]) -> ExitCode {
    match parse(options) {
        Ok(options) => prove(&options),
        Err(message) => usage_error(&format!("prove: {message}")),
    }
}

fn parse(args: &[&str]) -> Result<Options, String> {
    let mut levels = None;
    let mut settings = Settings::default();
    let mut sample = None;
    let mut seed = None;
    let mut json = false;
    let mut rest = args.iter().copied();
    while let Some(arg) = rest.next() {
        // `--name value` or `--name=value`.
        let (name, inline_value) = match arg.split_once('=') {
            Some((name, value)) if name.starts_with("--") => (name, Some(value)),
            _ => (arg, None),
        };
        let mut value = |what: &str| {
            inline_value
                .or_else(|| rest.next())
                .ok_or_else(|| format!("{name} needs {what}"))
        };
        match name {
            "--levels" => levels = Some(parse_levels(value("A..=B")?)?),
            "--sample" => sample = Some(parse_count(value("a number of faces")?)?),
            "--seed" => seed = Some(parse_count(value("a number")?)?),
            "--threads" => settings.threads = parse_small(value("a number")?, "--threads")?,
            "--examples" => settings.examples = parse_small(value("a number")?, "--examples")?,
            "--spec-wide" | "--version1" | "--json" if inline_value.is_some() => {
                return Err(format!("{name} takes no value"))
            }
            "--spec-wide" => settings.reference = Reference::SpecWide,
            "--version1" => settings.walk = WalkVersion::Version1,
            "--json" => json = true,
            _ => return Err(format!("unknown option {arg:?}")),
        }
    }
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
    let level = |s: &str| {
        s.parse::<u32>()
            .map_err(|_| format!("bad level {s:?} in --levels {text:?}"))
    };
    let range = if let Some((a, b)) = text.split_once("..=") {
        level(a)?..=level(b)?
    } else if let Some((a, b)) = text.split_once("..") {
        let end = level(b)?
            .checked_sub(1)
            .ok_or_else(|| format!("empty --levels {text:?}"))?;
        level(a)?..=end
    } else {
        let n = level(text)?;
        n..=n
    };
    if range.is_empty() {
        return Err(format!("empty --levels {text:?}"));
    }
    Ok(range)
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

fn prove(options: &Options) -> ExitCode {
    let progress = Arc::new(Progress::new());
    install_ctrl_c(&progress);
    let show_bar = std::io::stderr().is_terminal();
    if !options.json {
        print_header(options);
    }
    let started = Instant::now();
    let mut any_mismatch = false;
    for level in options.levels.clone() {
        // Levels were checked against the reference's limit when parsing.
        let Ok(level) = Level::new(level) else {
            return usage_error("prove: level above 32");
        };
        let report = with_progress_bar(show_bar, level, &progress, || match options.sample {
            Some(samples) => {
                sample_level(level, samples, options.seed, &options.settings, &progress)
            }
            None => prove_level(level, &options.settings, &progress),
        });
        let report = match report {
            Ok(report) => report,
            Err(ProveError::Level(e)) => return usage_error(&format!("prove: {e}")),
            Err(e) => {
                eprintln!("micromap-index: prove: {e}");
                return ExitCode::FAILURE;
            }
        };
        any_mismatch |= report.mismatches() > 0
            || (report.complete && report.faces_checked != report.faces_expected);
        if options.json {
            print_json(&report, &options.settings);
        } else {
            print_row(&report);
        }
        if !report.complete {
            eprintln!(
                "micromap-index: prove: interrupted during level {level}; the row above counts only the finished part"
            );
            return ExitCode::from(INTERRUPTED);
        }
    }
    if !options.json {
        println!(
            "total {:.1} s; {}",
            started.elapsed().as_secs_f64(),
            if any_mismatch {
                "MISMATCHES: the walk differs from the reference"
            } else if options.sample.is_some() {
                "no mismatch on the sampled faces (a sample is not a proof)"
            } else {
                "equal on every face: proved for these levels"
            }
        );
    }
    if any_mismatch {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// First Ctrl-C: ask the check to stop after the work in flight, so the
/// finished part is still reported. Second Ctrl-C: exit at once.
fn install_ctrl_c(progress: &Arc<Progress>) {
    let progress = Arc::clone(progress);
    let result = ctrlc::set_handler(move || {
        if progress.is_cancelled() {
            std::process::exit(i32::from(INTERRUPTED));
        }
        progress.cancel();
    });
    if let Err(e) = result {
        eprintln!("micromap-index: prove: cannot catch Ctrl-C ({e}); it will end the run at once");
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
            eprint!("\r\x1b[K");
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
    eprint!(
        "\rlevel {level:>2} [{}{}] {percent:5.1}% {:7.1} s",
        "#".repeat(filled),
        ".".repeat(WIDTH as usize - filled),
        started.elapsed().as_secs_f64()
    );
    let _ = std::io::stderr().flush();
}

fn print_header(options: &Options) {
    let what = match options.sample {
        Some(samples) => format!("{samples} random faces per level (seed {})", options.seed),
        None => "every face of the lattice".into(),
    };
    println!(
        "{} vs {}: {what}",
        options.settings.walk.name(),
        options.settings.reference.name()
    );
    println!(
        "{:>5} {:>16} {:>16} {:>12} {:>10}",
        "level", "faces checked", "expected", "mismatches", "seconds"
    );
}

fn print_row(report: &LevelReport) {
    println!(
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
    );
    if report.mismatches() > 0 {
        let per_kind: Vec<String> = FACE_KINDS
            .iter()
            .zip(report.mismatches_by_kind)
            .filter(|(_, count)| *count > 0)
            .map(|(kind, count)| format!("{} {count}", kind.name()))
            .collect();
        println!("      by kind: {}", per_kind.join(", "));
        for example in &report.examples {
            let shown = ShownMismatch::from(example);
            println!(
                "      (u, v) = ({}, {}), {}: walk {}, {} {}",
                shown.u,
                shown.v,
                shown.kind,
                shown.walk,
                report.reference.name(),
                shown.reference
            );
        }
    }
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

fn print_json(report: &LevelReport, settings: &Settings) {
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
        Ok(text) => println!("{text}"),
        Err(e) => eprintln!("micromap-index: prove: cannot write JSON: {e}"),
    }
}
