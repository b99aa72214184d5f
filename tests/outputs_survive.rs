//! Outputs survive a crash: a killed run leaves whole lines and a summary
//! that says how far it got; a full disk or an unwritable folder is a clear
//! error naming the file, never a panic.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn dda() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dda"))
}

/// The sliding-block example with `from` replaced by `to`, in its own folder.
fn scene(name: &str, replacements: &[(&str, &str)]) -> (PathBuf, PathBuf) {
    let mut text = std::fs::read_to_string("examples/sliding_block_2d.ron").unwrap();
    for (from, to) in replacements {
        assert!(text.contains(from), "{from} is not in the example");
        text = text.replace(from, to);
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("outputs_survive")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.ron");
    std::fs::write(&path, text).unwrap();
    (path, dir.join("out"))
}

/// `dda run SCENE --out OUT`, which must fail with exit code 1 and no
/// panic; its stderr.
fn run_fails(scene: &Path, out: &Path) -> String {
    let result = dda()
        .args([
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr).into_owned();
    assert_eq!(result.status.code(), Some(1), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

fn summary(out: &Path) -> Option<serde_json::Value> {
    let text = std::fs::read_to_string(out.join("summary.json")).ok()?;
    Some(serde_json::from_str(&text).expect("summary.json is always whole"))
}

/// Every line of a CSV file has the header's field count and the file
/// ends with a line break.
fn whole_lines(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(
        text.ends_with('\n'),
        "{} ends in a torn line",
        path.display()
    );
    let mut lines = text.lines();
    let fields = lines.next().unwrap().split(',').count();
    let mut rows = 0;
    for line in lines {
        assert_eq!(line.split(',').count(), fields, "torn line {line:?}");
        rows += 1;
    }
    rows
}

/// A run killed with SIGKILL keeps whole lines in history.csv and
/// contacts.csv, and its summary.json says "running" with the time it had
/// reached at its last update, which history.csv has reached too.
#[test]
fn a_killed_run_says_how_far_it_got() {
    // Long enough to outlive several summary updates.
    let (path, out) = scene(
        "killed",
        &[
            ("duration: 1.0", "duration: 1000.0"),
            ("interval: 0.01", "interval: 0.002, contacts: true"),
        ],
    );
    let mut child = dda()
        .args([
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    let reached = loop {
        if let Some(s) = summary(&out) {
            assert_eq!(s["status"], "running");
            let t = s["time"].as_f64().unwrap();
            if t > 0.0 {
                break t;
            }
        }
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "summary.json never showed progress"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    child.kill().unwrap();
    child.wait().unwrap();
    let s = summary(&out).unwrap();
    assert_eq!(s["status"], "running", "a killed run cannot say more");
    assert!(s["time"].as_f64().unwrap() >= reached);
    assert!(s["steps"].as_u64().unwrap() > 0);
    let rows = whole_lines(&out.join("history.csv"));
    assert!(rows >= 2, "the block's rows at t = 0 and later");
    whole_lines(&out.join("contacts.csv"));
    let history = dda::read_history(out.join("history.csv")).unwrap();
    let last = history.last().unwrap().time;
    assert!(
        last >= s["time"].as_f64().unwrap(),
        "history.csv reached {last} s, the summary {} s",
        s["time"]
    );
}

/// A full disk (history.csv on /dev/full) stops the run with an error
/// naming the file and the cause, exit code 1, and summary.json says the
/// run failed and why.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_a_clear_error() {
    let (path, out) = scene("full", &[]);
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink("/dev/full", out.join("history.csv")).unwrap();
    let stderr = run_fails(&path, &out);
    assert!(
        stderr.contains("history.csv") && stderr.contains("No space left on device"),
        "{stderr}"
    );
    let s = summary(&out).expect("summary.json is written even so");
    assert_eq!(s["status"], "failed");
    assert!(
        s["error"]
            .as_str()
            .unwrap()
            .contains("No space left on device"),
        "{s}"
    );
}

/// An output folder that cannot be made (its parent is a file) is an error
/// naming it before anything runs.
#[test]
fn an_unwritable_folder_is_a_clear_error() {
    let (path, out) = scene("unwritable", &[]);
    std::fs::write(&out, "a file, not a folder").unwrap();
    let inside = out.join("run");
    let stderr = run_fails(&path, &inside);
    assert!(
        stderr.contains(&format!("cannot create {}", inside.display())),
        "{stderr}"
    );
}
