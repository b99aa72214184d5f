//! Runs that would never end, or fill the disk, are stopped before they
//! start or kept to one output row per step.

use std::path::{Path, PathBuf};

use dda::run::{run_with, RunOptions};

const QUIET: RunOptions = RunOptions {
    progress: false,
    notes: false,
    progress_lines: None,
    vtk: false,
    steps: false,
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

/// A scene that would need more memory than the run may use is refused
/// before it starts, with the estimate and what to change; `dda check`
/// gives the estimate.
#[test]
fn a_scene_too_big_for_the_memory_is_refused_up_front() {
    let (path, out) = scene("memory", "interval: 0.1", "interval: 0.1");
    let _ = std::fs::remove_dir_all(&out);
    let dda = |args: &[&str], limit: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
            .args(args)
            .env("DDA_MEMORY_LIMIT", limit)
            .output()
            .unwrap()
    };
    let p = path.to_str().unwrap();
    let refused = dda(&["run", p, "--out", out.to_str().unwrap()], "1e6");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("needs about")
            && stderr.contains("more than the 1.00 MB available (DDA_MEMORY_LIMIT)"),
        "{stderr}"
    );
    assert!(stderr.contains("kind: Rigid"), "{stderr}");
    assert!(!out.join("history.csv").exists(), "nothing is written");
    // The one-block scene needs 20 MB and change: enough room runs it.
    assert!(dda(&["run", p, "--out", out.to_str().unwrap()], "1e9")
        .status
        .success());
    let checked = dda(&["check", p], "1e9");
    assert!(String::from_utf8_lossy(&checked.stdout).contains("needs about 20.04 MB of memory"));
    // The estimate errs high of what a 4,936-block wall was measured to take (121 MB).
    assert!(dda::run::memory_estimate(4936.0, 2) > 121e6);
}
