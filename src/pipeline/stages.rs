//! Progress of the stages before the render (reading, estimation, building): a spinner with
//! the elapsed time in a terminal, a line per finished stage in a log (stderr not a terminal),
//! or nothing. The render itself has its own bar (see [`crate::render::RenderSettings`]).

use std::time::{Duration, Instant};

/// Stages at least this long leave a line on stderr.
pub const LOG_AFTER: Duration = Duration::from_secs(1);

/// How stages report their progress (all of it on stderr).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Progress {
    /// Nothing (quiet, or a library caller).
    #[default]
    Off,
    /// A terminal: a spinner while a stage runs, then its line; the render's progress bar.
    Bar,
    /// A log: one line per finished stage that took a second or more, e.g.
    /// `estimated normals, radii (3.1 s)` (quicker stages are in the render's summary).
    Lines,
}

impl Progress {
    /// [`Progress::Bar`] when `enabled`, else [`Progress::Off`] (the old boolean).
    pub fn bar_if(enabled: bool) -> Self {
        if enabled {
            Progress::Bar
        } else {
            Progress::Off
        }
    }

    /// Whether a stage that took `took` leaves its line: one of a second or more, unless off.
    pub fn logs(self, took: Duration) -> bool {
        self != Progress::Off && took >= LOG_AFTER
    }

    /// Starts the stage `doing` (e.g. "reading frame 60"): a spinner in a terminal.
    pub fn start(self, doing: &str) -> Stage {
        let bar = (self == Progress::Bar).then(|| {
            let bar = indicatif::ProgressBar::new_spinner();
            bar.set_style(
                indicatif::ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
                    .expect("valid template"),
            );
            bar.set_message(doing.to_string());
            bar.enable_steady_tick(Duration::from_millis(120));
            bar
        });
        Stage {
            progress: self,
            start: Instant::now(),
            bar,
        }
    }
}

/// A stage under way (see [`Progress::start`]).
#[derive(Debug)]
pub struct Stage {
    progress: Progress,
    start: Instant,
    bar: Option<indicatif::ProgressBar>,
}

impl Stage {
    /// Ends the stage: its line `done (1.2 s)` on stderr if it took a second or more (and
    /// progress is not [`Progress::Off`]); returns how long it took.
    pub fn finish(self, done: &str) -> Duration {
        let took = self.start.elapsed();
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        if self.progress.logs(took) {
            eprintln!("{}", stage_line(done, took));
        }
        took
    }
}

impl Stage {
    /// Ends the stage without a line (the caller writes its own); returns how long it took.
    pub fn finish_silently(self) -> Duration {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        self.start.elapsed()
    }
}

/// The log line of a finished stage: `done (0.8 s)`.
pub fn stage_line(done: &str, took: Duration) -> String {
    format!("{done} ({:.1} s)", took.as_secs_f64())
}

/// `n` with thousands separators: 1,000,000.
pub fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_grouped_by_thousands_and_lines_carry_the_time() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(2562), "2,562");
        assert_eq!(thousands(1_000_000), "1,000,000");
        assert_eq!(
            stage_line("read 5 particles", Duration::from_millis(840)),
            "read 5 particles (0.8 s)"
        );
    }

    #[test]
    fn stages_of_a_second_or_more_leave_a_line_unless_off() {
        let (quick, slow) = (Duration::from_millis(999), Duration::from_millis(1000));
        for p in [Progress::Bar, Progress::Lines] {
            assert!(!p.logs(quick) && p.logs(slow), "{p:?}");
        }
        assert!(!Progress::Off.logs(Duration::from_secs(100)));
    }
}
