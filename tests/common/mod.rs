//! Helpers shared by the verification tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use dda::HistoryRow;

/// Path of a shipped example.
pub fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name)
}

/// A fresh output folder for one test.
pub fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dda-test-{}-{}", test, std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs an example the way `dda run` does and reads its history back.
pub fn run_example(name: &str) -> Vec<HistoryRow> {
    let out = out_dir(name.trim_end_matches(".ron"));
    dda::run::run(&example(name), &out).expect("the example runs");
    let rows = dda::read_history(out.join("history.csv")).expect("history.csv reads back");
    let _ = std::fs::remove_dir_all(&out);
    rows
}

/// The row of `block` at the output time closest to `time`.
pub fn at(rows: &[HistoryRow], block: usize, time: f64) -> &HistoryRow {
    rows.iter()
        .filter(|r| r.block == block)
        .min_by(|a, b| (a.time - time).abs().total_cmp(&(b.time - time).abs()))
        .expect("the block has rows")
}

/// Distance between the centroids of two rows.
pub fn distance(a: &HistoryRow, b: &HistoryRow) -> f64 {
    ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt()
}
