//! The progress of a long step on stderr: an `indicatif` bar (done / total,
//! percentage, elapsed time and ETA), drawn only when stderr is a terminal
//! and the command was not asked to be quiet. Otherwise the bar is hidden
//! and nothing at all is written to stderr, so a pipe or a log file gets no
//! escape codes and no partial lines.
//!
//! A bar never leaves a half-drawn line: [`Progress::finish`] leaves its
//! last state on its own line (later output starts on the next one);
//! dropped unfinished (the step failed) it is cleared before the failure is
//! reported; and the Ctrl-C handler clears it ([`clear_on_interrupt`])
//! before it reports the interruption.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Duration;

/// The bar's line: `baking [=====>    ] 1,234/5,678 triangles (21%),
/// 3s elapsed, ETA 11s`.
const TEMPLATE: &str =
    "{prefix} [{bar:30}] {human_pos}/{human_len} {msg} ({percent}%), {elapsed} elapsed, ETA {eta}";

/// How often the elapsed time and the ETA are redrawn between updates.
const TICK: Duration = Duration::from_millis(250);

/// The bar on the terminal now (at most one), for the Ctrl-C handler.
static SHOWN: Mutex<Option<ProgressBar>> = Mutex::new(None);

fn shown() -> MutexGuard<'static, Option<ProgressBar>> {
    SHOWN.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The progress of one step, counted in some unit (`triangles`).
pub(crate) struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// A bar for the step `what` (`baking`) counting `total` `unit`s: drawn
    /// on stderr when it is a terminal and `quiet` is false, otherwise
    /// hidden (nothing written).
    pub(crate) fn on_stderr(
        what: &'static str,
        unit: &'static str,
        total: usize,
        quiet: bool,
    ) -> Self {
        if quiet || !std::io::stderr().is_terminal() {
            return Progress {
                bar: ProgressBar::hidden(),
            };
        }
        // indicatif also hides the bar when TERM is unset or dumb.
        let bar = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr())
            .with_style(style())
            .with_prefix(what)
            .with_message(unit);
        bar.enable_steady_tick(TICK);
        *shown() = Some(bar.clone());
        Progress { bar }
    }

    /// `done` of `total` units are done.
    pub(crate) fn update(&self, done: usize, total: usize) {
        self.bar.set_length(total as u64);
        self.bar.set_position(done as u64);
    }

    /// The step is done: its last state stays on its line, which the
    /// Ctrl-C handler leaves alone from now on.
    pub(crate) fn finish(&self) {
        self.bar.finish();
        *shown() = None;
    }
}

impl Drop for Progress {
    /// An unfinished bar (the step failed) is cleared, so the failure's
    /// message starts on a clean line.
    fn drop(&mut self) {
        *shown() = None;
        if !self.bar.is_finished() {
            self.bar.finish_and_clear();
        }
    }
}

/// The bar's style; the template is checked by the tests, and a template
/// error (none) would only fall back to indicatif's default bar.
fn style() -> ProgressStyle {
    ProgressStyle::with_template(TEMPLATE).map_or_else(
        |_| ProgressStyle::default_bar(),
        |style| style.progress_chars("=> "),
    )
}

/// Clears the bar on the terminal, if any, and stops its redraws: the Ctrl-C
/// handler's first step, so that its message starts on a clean line.
pub(crate) fn clear_on_interrupt() {
    if let Some(bar) = shown().take() {
        bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_template_parses() {
        assert!(ProgressStyle::with_template(TEMPLATE).is_ok());
    }

    /// Without a terminal (the tests' stderr is captured) or with quiet,
    /// the bar is hidden and registers nothing for the Ctrl-C handler.
    #[test]
    fn hidden_without_a_terminal_or_when_quiet() {
        for quiet in [true, false] {
            if !quiet && std::io::stderr().is_terminal() {
                continue;
            }
            let progress = Progress::on_stderr("baking", "triangles", 10, quiet);
            assert!(progress.bar.is_hidden());
            progress.update(5, 10);
            progress.finish();
            assert!(shown().is_none());
        }
    }
}
