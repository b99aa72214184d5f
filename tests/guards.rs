//! Runs that would never end, or fill the disk, are stopped before they
//! start or kept to one output row per step.

use std::path::{Path, PathBuf};

use dda::run::{run_with, RunOptions};

const QUIET: RunOptions = RunOptions {
    progress: false,
    notes: false,
    progress_lines: None,
    vtk: false,
    quiet: false,
    checkpoint_every: None,
};

/// The free-fall example (1 s, dt 10 ms) with `from` replaced by `to`,
/// written to its own folder.
fn scene(name: &str, from: &str, to: &str) -> (PathBuf, PathBuf) {
    let text = std::fs::read_to_string("examples/free_fall_2d.ron").unwrap();
    assert!(text.contains(from), "{from} is not in the example");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("guards")
        .join(name);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.ron");
    std::fs::write(&path, text.replace(from, to)).unwrap();
    (path, dir.join("out"))
}

fn rows(out: &Path) -> usize {
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    text.lines().count() - 1
}

/// An interval too small to advance time (1e-16 s, or the smallest double)
/// once wrote the step-0 rows again and again until the disk filled; it is
/// now every step, and the note says so.
#[test]
fn an_interval_below_the_step_writes_every_step_once() {
    for interval in ["1e-16", "5e-324"] {
        let (path, out) = scene(interval, "interval: 0.1", &format!("interval: {interval}"));
        let summary = run_with(&path, &out, QUIET).unwrap();
        assert_eq!(summary.steps, 100);
        assert_eq!(rows(&out), 101, "one row per step and one at t = 0");
        let scene = dda::Scene::load(&path).unwrap();
        let (every, note) = scene.output_interval(0.01);
        assert_eq!(every, None);
        assert!(note.unwrap().contains("every step is written"));
    }
}

/// A duration of 1e300 s, or a step of 1e-12 s, is refused up front with
/// the step count and the settings to check, and nothing is written.
#[test]
fn absurd_step_counts_are_refused_before_the_run() {
    for (name, from, to, steps) in [
        (
            "long",
            "duration: 1.0",
            "duration: 1e300",
            "1.000e302 steps",
        ),
        ("tiny_dt", "dt: 0.01", "dt: 1e-12", "1.000e12 steps"),
    ] {
        let (path, out) = scene(name, from, to);
        let message = format!("{:#}", run_with(&path, &out, QUIET).unwrap_err());
        assert!(message.contains(steps), "{message}");
        assert!(
            message.contains("check analysis.duration and analysis.dt"),
            "{message}"
        );
        assert!(
            message.contains("scene.ron"),
            "the file is named: {message}"
        );
        assert!(!out.join("history.csv").exists());
    }
}
