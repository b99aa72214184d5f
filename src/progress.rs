//! The progress of a run on stderr, as an [`Observer`]: a bar on a
//! terminal, otherwise a line now and then.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use crate::observe::{Observer, RunView};

/// The bar, or the lines printed when there is no terminal.
pub struct Progress {
    bar: ProgressBar,
    every: Option<Duration>,
    started: Instant,
    last: Instant,
    /// The simulated time the run goes to, s.
    duration: f64,
}

impl Progress {
    /// A bar if `bar`, else (with `every`) a line at the first output time
    /// after that much wall-clock time, and again each time as much has
    /// passed; `duration` is the run's end time in s.
    pub fn new(bar: bool, every: Option<Duration>, duration: f64) -> Self {
        let started = Instant::now();
        Self {
            bar: progress_bar(bar),
            every: every.filter(|_| !bar),
            started,
            last: started,
            duration,
        }
    }

    fn line(&mut self, driver: &dyn RunView) {
        let Some(every) = self.every else {
            return;
        };
        let duration = self.duration;
        let now = Instant::now();
        if now.duration_since(self.last) < every {
            return;
        }
        self.last = now;
        let elapsed = now.duration_since(self.started).as_secs_f64();
        let done = driver.time() / duration;
        let left = if done > 0.0 {
            format!(", about {:.0} s left", elapsed * (1.0 - done) / done)
        } else {
            String::new()
        };
        eprintln!(
            "t = {:.4} s of {duration} s ({:.0} %), step {}, {elapsed:.0} s elapsed{left}",
            driver.time(),
            100.0 * done,
            driver.statistics().steps,
        );
    }
}

impl Observer for Progress {
    fn on_step(&mut self, run: &dyn RunView) {
        if self.bar.is_hidden() {
            return;
        }
        self.bar
            .set_position((run.time() / self.duration * 1000.0).round() as u64);
        self.bar.set_message(format!(
            "t = {:.4e} s, step {}",
            run.time(),
            run.statistics().steps
        ));
    }

    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.line(run);
        self.on_step(run);
        Ok(())
    }

    fn on_finish(&mut self, _: &dyn RunView, _: Option<&anyhow::Error>) -> anyhow::Result<()> {
        self.bar.finish_and_clear();
        Ok(())
    }
}

pub(crate) fn progress_bar(show: bool) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(1000);
    if let Ok(style) =
        ProgressStyle::with_template("{bar:40} {percent:>3}% {msg} [{elapsed_precise}, {eta} left]")
    {
        bar.set_style(style);
    }
    bar
}
