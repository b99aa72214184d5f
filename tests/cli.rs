//! The `dda` binary: run, check, outputs and failures.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use dda::output::HISTORY_HEADER;
use dda::read_history;

fn dda(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the dda binary runs")
}

/// A fresh, empty directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dda-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn data(name: &str) -> String {
    format!("tests/data/{name}")
}

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn run_writes_history_and_summary() {
    let out = scratch("free-fall");
    let result = dda(&[
        "run",
        &data("free_fall.ron"),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "stderr: {stderr}");
    // Stdout has only the final line.
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    assert!(
        stdout.starts_with("wrote ")
            && stdout.contains("history.csv")
            && stdout.contains("summary.json")
    );

    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("step,time,block,x,y,rotation,vx,vy,omega,sxx,syy,sxy")
    );
    assert_eq!(
        HISTORY_HEADER,
        "step,time,block,x,y,rotation,vx,vy,omega,sxx,syy,sxy"
    );

    let rows = read_history(out.join("history.csv")).unwrap();
    assert_eq!(rows.len(), 6, "6 output times × 1 block");
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row.block, 0);
        assert_eq!(row.step, k, "one step of 0.01 s per output");
        assert!(
            (row.time - 0.01 * k as f64).abs() < 1e-12,
            "time {}",
            row.time
        );
    }
    // Newmark (β = 1/2, γ = 1) is exact for constant acceleration.
    let (y0, g, t) = (1.0, 9.81, 0.05);
    let last = rows.last().unwrap();
    assert_eq!(last.time, t);
    let y = y0 - 0.5 * g * t * t;
    assert!(
        ((last.y - y) / y).abs() < 1e-9,
        "y = {} expected {y}",
        last.y
    );
    assert!(
        ((last.vy + g * t) / (g * t)).abs() < 1e-9,
        "vy = {}",
        last.vy
    );
    assert_eq!(last.x, 0.0);
    assert_eq!(last.rotation, 0.0);

    let s = summary(&out);
    assert_eq!(s["status"], "finished");
    assert_eq!(s["steps"], 5);
    assert_eq!(s["time"], 0.05);
    assert_eq!(s["dt"], 0.01);
    assert!(s["wall_time"].as_f64().unwrap() >= 0.0);
    assert!(s["notes"].is_array());
    assert!(s.get("error").is_none());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn the_library_run_matches_the_binary() {
    let out = scratch("library");
    let summary = dda::run(Path::new(&data("free_fall.ron")), &out).unwrap();
    assert_eq!(summary.status, dda::run::Status::Finished);
    assert_eq!(summary.steps, 5);
    let written: dda::Summary =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(written.steps, summary.steps);
    assert_eq!(written.time, summary.time);
    assert_eq!(read_history(out.join("history.csv")).unwrap().len(), 6);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn check_accepts_a_good_scene() {
    let result = dda(&["check", &data("free_fall.ron")]);
    assert!(result.status.success());
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(
        stdout.starts_with("tests/data/free_fall.ron: ok (1 block"),
        "{stdout}"
    );
    assert!(stdout.contains("duration 0.05 s"), "{stdout}");
}

#[test]
fn check_rejects_a_bad_scene_on_stderr() {
    let result = dda(&["check", &data("overlapping.ron")]);
    assert_eq!(result.status.code(), Some(1));
    assert!(result.stdout.is_empty());
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(
        stderr.starts_with(
            "error: tests/data/overlapping.ron:9:9: blocks[1]: the block overlaps blocks[0]"
        ),
        "{stderr}"
    );

    let result = dda(&["check", &data("no_such_scene.ron")]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(
        stderr.contains("no_such_scene.ron: cannot read the scene file"),
        "{stderr}"
    );
}

#[test]
fn a_failing_run_keeps_its_history_and_says_why() {
    let out = scratch("unstable");
    let result = dda(&["run", &data("unstable.ron"), "--out", out.to_str().unwrap()]);
    assert_eq!(result.status.code(), Some(1));
    assert!(result.stdout.is_empty());
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(stderr.contains("error: the run failed at t = "), "{stderr}");
    assert!(stderr.contains("non-finite"), "{stderr}");

    // The rows of time 0 were written before the failing step.
    let rows = read_history(out.join("history.csv")).unwrap();
    assert_eq!(rows.len(), 1);
    assert_eq!((rows[0].step, rows[0].time, rows[0].y), (0, 0.0, 1.0));
    let s = summary(&out);
    assert_eq!(s["status"], "failed");
    assert!(s["error"].as_str().unwrap().contains("non-finite"), "{s}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn usage_errors_exit_with_2() {
    assert_eq!(
        dda(&["run", &data("free_fall.ron")]).status.code(),
        Some(2),
        "--out is required"
    );
    assert_eq!(dda(&["frobnicate"]).status.code(), Some(2));
    assert!(dda(&["--help"]).status.success());
}

#[test]
fn without_an_interval_every_step_is_written() {
    let out = scratch("every-step");
    std::fs::create_dir_all(&out).unwrap();
    let text = std::fs::read_to_string(data("free_fall.ron")).unwrap();
    let text = text.replace("output: (interval: 0.01),", "");
    let scene = out.join("every_step.ron");
    std::fs::write(&scene, text).unwrap();
    let summary = dda::run(&scene, &out.join("out")).unwrap();
    assert_eq!(summary.steps, 5);
    let rows = read_history(out.join("out/history.csv")).unwrap();
    let steps: Vec<usize> = rows.iter().map(|r| r.step).collect();
    assert_eq!(steps, [0, 1, 2, 3, 4, 5]);
    assert_eq!(rows[5].time, 0.05);
    let _ = std::fs::remove_dir_all(&out);
}
