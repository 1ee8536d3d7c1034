//! Render progress for people and for logs.
//!
//! On a terminal, an `indicatif` bar with the fraction done, paths/s and an ETA. Elsewhere
//! (CI, pipes, files) a plain line at most every [`LINE_INTERVAL`]:
//! `render: 64/256 spp, 12.3 s, 1.23 Mpaths/s, ETA 36.9 s`.
//!
//! The fraction done is the furthest of the stopping rules ([`oracle::StopRule`]): samples
//! per pixel, wall time, and, for a target error, the samples needed to reach it estimated
//! from the Monte Carlo rate: relative error ∝ 1/√spp, so the target needs
//! spp·(err/target)² samples.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use oracle::{Progress, StopRule};

/// Shortest time between two plain progress lines.
pub const LINE_INTERVAL: Duration = Duration::from_secs(5);

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressMode {
    /// A live bar on stderr (stderr is a terminal).
    Bar,
    /// Plain lines on stderr, at most every [`LINE_INTERVAL`].
    Lines,
    /// Nothing.
    Quiet,
}

impl ProgressMode {
    /// `Quiet` if asked, else `Bar` when stderr is a terminal and `Lines` otherwise.
    pub fn detect(quiet: bool) -> Self {
        if quiet {
            ProgressMode::Quiet
        } else if std::io::stderr().is_terminal() {
            ProgressMode::Bar
        } else {
            ProgressMode::Lines
        }
    }
}

/// Shows the progress of one render.
pub struct ProgressReporter {
    mode: ProgressMode,
    stop: StopRule,
    /// The spp bound was not asked for (a time or error budget set it): show `N spp`, not `N/M`.
    spp_is_cap: bool,
    bar: Option<ProgressBar>,
    last_line: Instant,
}

impl ProgressReporter {
    /// A reporter for a render under `stop`. With `spp_is_cap`, `stop.spp` is only a safety
    /// bound and is not shown as the target.
    pub fn new(mode: ProgressMode, stop: StopRule, spp_is_cap: bool) -> Self {
        let bar = (mode == ProgressMode::Bar).then(|| {
            let bar = ProgressBar::with_draw_target(Some(BAR_STEPS), ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template("{spinner} [{bar:30}] {percent:>3}% {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
            bar.set_style(style);
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        });
        ProgressReporter {
            mode,
            stop,
            spp_is_cap,
            bar,
            last_line: Instant::now(),
        }
    }

    /// Prints `line` on stderr unless quiet, without tearing a live bar.
    pub fn note(&self, line: &str) {
        match (&self.bar, self.mode) {
            (Some(bar), _) => bar.suspend(|| eprintln!("{line}")),
            (None, ProgressMode::Quiet) => {}
            (None, _) => eprintln!("{line}"),
        }
    }

    /// Takes the progress report sent after one pass.
    pub fn update(&mut self, p: &Progress) {
        match self.mode {
            ProgressMode::Quiet => {}
            ProgressMode::Bar => {
                if let Some(bar) = &self.bar {
                    bar.set_position((fraction_done(&self.stop, p) * BAR_STEPS as f64) as u64);
                    bar.set_message(status(&self.stop, p, self.spp_is_cap));
                }
            }
            ProgressMode::Lines => {
                if self.last_line.elapsed() >= LINE_INTERVAL {
                    self.last_line = Instant::now();
                    eprintln!("render: {}", status(&self.stop, p, self.spp_is_cap));
                }
            }
        }
    }

    /// Removes the bar (the caller prints the final summary line).
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Drop for ProgressReporter {
    fn drop(&mut self) {
        self.finish();
    }
}

/// Resolution of the bar's position.
const BAR_STEPS: u64 = 1000;

/// Progress over a counted list of steps (a study's variants): a bar on a terminal, one
/// line per finished step elsewhere, nothing when quiet.
pub struct StepProgress {
    mode: ProgressMode,
    bar: Option<ProgressBar>,
}

impl StepProgress {
    /// Progress over `total` steps.
    pub fn new(mode: ProgressMode, total: usize) -> Self {
        let bar = (mode == ProgressMode::Bar).then(|| {
            let bar = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template("[{bar:30}] {pos}/{len} {msg} (ETA {eta})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
            bar.set_style(style);
            bar
        });
        StepProgress { mode, bar }
    }

    /// Shows that step `what` has begun.
    pub fn start(&self, what: &str) {
        if let Some(bar) = &self.bar {
            bar.set_message(what.to_string());
        }
    }

    /// Marks a step done with its result line (printed above the bar, or as a plain line).
    pub fn done(&self, line: &str) {
        match (&self.bar, self.mode) {
            (Some(bar), _) => {
                bar.suspend(|| eprintln!("{line}"));
                bar.inc(1);
            }
            (None, ProgressMode::Quiet) => {}
            (None, _) => eprintln!("{line}"),
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// The progress text: `64/256 spp, 12.3 s, 1.23 Mpaths/s, ETA 36 s`, with
/// `, rel. error 0.031 (target 0.01)` when a target error is set.
pub fn status(stop: &StopRule, p: &Progress, spp_is_cap: bool) -> String {
    let secs = p.elapsed.as_secs_f64();
    let mut s = if spp_is_cap {
        format!("{} spp", p.spp_done)
    } else {
        format!("{}/{} spp", p.spp_done, p.spp_target)
    };
    let mpaths = format_sig3(rate(p.paths, secs) / 1e6);
    s += &format!(", {}, {mpaths} Mpaths/s", format_duration(secs));
    if let Some(target) = stop.target_rel_err {
        s += &format!(", rel. error {} (target {target})", format_sig3(p.rel_err as f64));
    }
    if let Some(eta) = eta(stop, p) {
        s += &format!(", ETA {}", format_duration(eta.as_secs_f64()));
    }
    s
}

/// Fraction of the render done, in [0, 1]: the furthest of the stopping rules.
pub fn fraction_done(stop: &StopRule, p: &Progress) -> f64 {
    let mut f = p.spp_done as f64 / stop.spp.max(1) as f64;
    if let Some(budget) = stop.time {
        if !budget.is_zero() {
            f = f.max(p.elapsed.as_secs_f64() / budget.as_secs_f64());
        }
    }
    if let Some(target) = stop.target_rel_err {
        // err ∝ 1/√spp: the target needs spp·(err/target)² samples, so the fraction done
        // is (target/err)².
        if p.spp_done > 0 && p.rel_err.is_finite() && p.rel_err > 0.0 {
            f = f.max((target as f64 / p.rel_err as f64).powi(2));
        }
    }
    f.clamp(0.0, 1.0)
}

/// Time left, extrapolated from the rate so far; `None` before any progress.
pub fn eta(stop: &StopRule, p: &Progress) -> Option<Duration> {
    let f = fraction_done(stop, p);
    if f <= 0.0 {
        return None;
    }
    let left = p.elapsed.as_secs_f64() * (1.0 - f) / f;
    Duration::try_from_secs_f64(left).ok()
}

/// Events per second (0 for no time).
pub fn rate(count: u64, secs: f64) -> f64 {
    if secs > 0.0 {
        count as f64 / secs
    } else {
        0.0
    }
}

/// `x` with 3 significant digits (at least: large integers keep all theirs).
pub fn format_sig3(x: f64) -> String {
    let a = x.abs();
    let decimals = if a == 0.0 || !a.is_finite() || a >= 100.0 {
        0
    } else if a >= 10.0 {
        1
    } else if a >= 1.0 {
        2
    } else {
        // 0.0123 → 4 decimals.
        (2 - a.log10().floor() as i32).clamp(2, 9) as usize
    };
    format!("{x:.decimals$}")
}

/// Seconds for people: `0.42 s`, `12.3 s`, `4 min 05 s`, `2 h 07 min`.
pub fn format_duration(secs: f64) -> String {
    if !secs.is_finite() {
        return "∞".into();
    }
    if secs < 60.0 {
        return format!("{} s", format_sig3(secs));
    }
    let total = secs.round() as u64;
    if total < 3600 {
        format!("{} min {:02} s", total / 60, total % 60)
    } else {
        format!("{} h {:02} min", total / 3600, (total % 3600) / 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn progress(spp_done: u32, elapsed: f64, rel_err: f32) -> Progress {
        Progress {
            spp_done,
            spp_target: 256,
            elapsed: Duration::from_secs_f64(elapsed),
            paths: 1_234_000 * elapsed as u64,
            rays: 0,
            rel_err,
        }
    }

    fn rule(spp: u32, time: Option<f64>, target: Option<f32>) -> StopRule {
        StopRule {
            spp,
            time: time.map(Duration::from_secs_f64),
            target_rel_err: target,
        }
    }

    #[test]
    fn fraction_and_eta_follow_the_nearest_rule() {
        // spp bound: 64 of 256 after 12 s → 25 %, 36 s left.
        let p = progress(64, 12.0, 0.1);
        let r = rule(256, None, None);
        assert_eq!(fraction_done(&r, &p), 0.25);
        assert_eq!(eta(&r, &p), Some(Duration::from_secs(36)));
        // A 20 s budget is nearer: 60 % done, 8 s left.
        let r = rule(256, Some(20.0), None);
        let f = fraction_done(&r, &p);
        assert!((f - 0.6).abs() < 1e-12, "expected 0.6, got {f}");
        // Error 0.1 towards 0.05: needs 4× the samples → 25 %; towards 0.08: 64 %.
        let r = rule(1 << 20, None, Some(0.05));
        assert!(
            (fraction_done(&r, &p) - 0.25).abs() < 1e-9,
            "{}",
            fraction_done(&r, &p)
        );
        let r = rule(1 << 20, None, Some(0.08));
        let f = fraction_done(&r, &p);
        assert!((f - 0.64).abs() < 1e-6, "expected 0.64, got {f}");
        // Nothing done yet: no ETA.
        assert_eq!(eta(&rule(256, None, None), &progress(0, 0.0, f32::NAN)), None);
    }

    #[test]
    fn status_line_format() {
        let p = progress(64, 12.3, 0.031);
        assert_eq!(
            status(&rule(256, None, None), &p, false),
            "64/256 spp, 12.3 s, 1.20 Mpaths/s, ETA 36.9 s"
        );
        assert_eq!(
            status(&rule(1 << 24, None, Some(0.01)), &p, true),
            "64 spp, 12.3 s, 1.20 Mpaths/s, rel. error 0.0310 (target 0.01), ETA 1 min 46 s"
        );
    }

    #[test]
    fn number_formats() {
        let cases = [
            (format_sig3(1234.0), "1234"),
            (format_sig3(45.61), "45.6"),
            (format_sig3(2.0), "2.00"),
            (format_sig3(0.0), "0"),
            (format_sig3(0.012345), "0.0123"),
            (format_duration(0.42), "0.420 s"),
            (format_duration(245.0), "4 min 05 s"),
            (format_duration(7620.0), "2 h 07 min"),
        ];
        for (got, expected) in cases {
            assert_eq!(got, expected);
        }
    }
}
