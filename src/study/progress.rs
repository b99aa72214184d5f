//! `dda study`'s progress on stderr.

use std::io::IsTerminal;

use super::table::Row;

/// `dda study`'s progress: a bar on a terminal, otherwise a line per run.
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    lines: bool,
    count: std::sync::atomic::AtomicUsize,
    total: usize,
}

impl Progress {
    pub fn new(show: bool, total: usize) -> Self {
        let terminal = show && std::io::stderr().is_terminal();
        let bar = terminal.then(|| {
            let bar = indicatif::ProgressBar::new(total as u64);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} runs, {elapsed} ({eta} left) {msg}",
            ) {
                bar.set_style(style);
            }
            bar
        });
        Self {
            bar,
            lines: show && !terminal,
            count: Default::default(),
            total,
        }
    }

    pub fn finished(&self, row: &Row) {
        let n = self
            .count
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed)
            + 1;
        let figure = row.figure.map_or("–".to_string(), |f| format!("{f:.6e}"));
        let line = format!(
            "{}: {}, figure {figure}, {:.2} s",
            row.run, row.outcome, row.wall_time
        );
        if let Some(bar) = &self.bar {
            bar.inc(1);
            bar.set_message(line);
        } else if self.lines {
            let of = if self.total > 0 {
                format!("/{}", self.total)
            } else {
                String::new()
            };
            eprintln!("[{n}{of}] {line}");
        }
    }

    pub fn end(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
