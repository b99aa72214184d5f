//! The `dda` binary: run, check, outputs and failures.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use dda::output::{CONTACTS_HEADER, HISTORY_HEADER};
use dda::run::{run_scene, RunOptions};
use dda::{read_contacts, read_history, Scene};
use dda_core::ContactState;

// The example's law, so the test runs exactly what the example registers.
#[allow(dead_code)]
#[path = "../examples/custom_law.rs"]
mod custom_law;

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
    assert_eq!(
        s["outputs"],
        serde_json::json!(["history.csv", "summary.json"])
    );
    assert!(
        !out.join("contacts.csv").exists(),
        "contacts.csv only when asked for"
    );
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

/// A scene that settles says so, and its note on undamped springs speaks
/// of blocks landing in the run, not of release.
#[test]
fn check_says_a_scene_settles_first() {
    let result = dda(&["check", "examples/drum_column_2d.ron"]);
    assert!(result.status.success());
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(
        stdout.contains("settles under its loads at t = 0 before the run, in at most 20 static steps (analysis.settle)"),
        "{stdout}"
    );
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(
        stderr.contains("the model starts settled on its contacts")
            && !stderr.contains("released onto"),
        "{stderr}"
    );
}

/// A scene released onto its contacts, undamped and not settled, is told
/// both remedies for the bounces: damping, and a settled start.
#[test]
fn check_advises_damping_or_a_settled_start_for_a_released_scene() {
    let result = dda(&["check", "examples/arch_heyman_2d.ron"]);
    assert!(result.status.success());
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(
        stderr.contains("a block landing on, or released onto, its contacts bounces")
            && stderr.contains("analysis.contact_damping: 1.0 ends impacts")
            && stderr.contains("analysis.settle starts a model released onto its contacts at rest"),
        "{stderr}"
    );
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
    // An overflow of the load, not a step too long, is what to look for.
    assert!(
        stderr.contains("a value of the scene far beyond any physical scale"),
        "{stderr}"
    );

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
    assert_eq!(dda(&["run"]).status.code(), Some(2), "a scene is required");
    assert_eq!(dda(&["frobnicate"]).status.code(), Some(2));
    assert!(dda(&["--help"]).status.success());
}

#[test]
fn without_out_a_run_writes_to_out_and_the_scene_name() {
    let dir = scratch("default-out");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(data("free_fall.ron"), dir.join("my_drop.ron")).unwrap();
    let result = Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(["run", "my_drop.ron"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(stdout.contains("out/my_drop/history.csv"), "{stdout}");
    assert_eq!(
        read_history(dir.join("out/my_drop/history.csv"))
            .unwrap()
            .len(),
        6
    );
    assert!(dir.join("out/my_drop/summary.json").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_a_terminal_a_run_prints_progress_lines() {
    let out = scratch("progress");
    // Every output time, so even this short run prints its lines.
    let result = dda(&[
        "run",
        &data("free_fall.ron"),
        "--out",
        out.to_str().unwrap(),
        "--progress-every",
        "0",
    ]);
    assert!(result.status.success());
    let stderr = String::from_utf8(result.stderr).unwrap();
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("t = ")).collect();
    assert_eq!(lines.len(), 6, "{stderr}");
    assert!(
        lines[5].starts_with("t = 0.0500 s of 0.05 s (100 %), step 5"),
        "{stderr}"
    );
    // By default only runs longer than a few seconds report.
    let result = dda(&[
        "run",
        &data("free_fall.ron"),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(!stderr.contains("t = "), "{stderr}");
    let result = dda(&[
        "run",
        &data("free_fall.ron"),
        "--out",
        out.to_str().unwrap(),
        "--progress-every=-1",
    ]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(
        stderr.contains("--progress-every must be a number of seconds, zero or more, got -1"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn check_prints_the_steps_and_output_size_and_warns_when_absurd() {
    let result = dda(&["check", &data("free_fall.ron")]);
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(
        stdout.contains("expects 5 steps at dt, 6 output times, 6 history rows (about"),
        "{stdout}"
    );
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(!stderr.contains("warning"), "{stderr}");

    // A day at a microsecond, every step written.
    let dir = scratch("absurd");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(data("free_fall.ron"))
        .unwrap()
        .replace("duration: 0.05", "duration: 86400.0")
        .replace("dt: 0.01", "dt: 1e-6")
        .replace("interval: 0.01", "interval: 0.0");
    assert!(text.contains("86400"));
    let scene = dir.join("absurd.ron");
    std::fs::write(&scene, text).unwrap();
    let result = dda(&["check", scene.to_str().unwrap()]);
    assert!(result.status.success());
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(stdout.contains("expects 86400000000 steps"), "{stdout}");
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(
        stderr.contains("warning: 8.640e10 steps") && stderr.contains("will take a very long time"),
        "{stderr}"
    );
    assert!(
        stderr.contains("warning: history.csv would be about")
            && stderr.contains("give a larger output.interval"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn with_interval_zero_every_step_is_written() {
    let out = scratch("every-step");
    std::fs::create_dir_all(&out).unwrap();
    let text = std::fs::read_to_string(data("free_fall.ron")).unwrap();
    let text = text.replace("output: (interval: 0.01),", "output: (interval: 0.0),");
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

#[test]
fn contacts_csv_lists_every_contact_at_each_output_time() {
    let out = scratch("contacts");
    let result = dda(&[
        "run",
        &data("resting_contacts.ron"),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "stderr: {stderr}");
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(
        stdout.starts_with("wrote ")
            && stdout.contains("history.csv, ")
            && stdout.contains("contacts.csv and ")
            && stdout.contains("summary.json"),
        "{stdout}"
    );

    let text = std::fs::read_to_string(out.join("contacts.csv")).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("step,time,contact,block_a,block_b,state,fn,fs,slip")
    );
    assert_eq!(
        CONTACTS_HEADER,
        "step,time,contact,block_a,block_b,state,fn,fs,slip"
    );
    let rows = read_contacts(out.join("contacts.csv")).unwrap();
    let history = read_history(out.join("history.csv")).unwrap();

    // The output times of history.csv, at each of which (but time 0, before
    // the first contact search) every contact has a row.
    let times: Vec<(usize, f64)> = history
        .iter()
        .filter(|r| r.block == 0)
        .map(|r| (r.step, r.time))
        .collect();
    assert_eq!(times.len(), 6);
    for &(step, time) in &times[1..] {
        let now: Vec<_> = rows.iter().filter(|r| r.step == step).collect();
        assert!(!now.is_empty(), "no contact rows at t = {time}");
        assert!(now.iter().all(|r| r.time == time), "step {step}");
        // The block's two bottom corners rest on the base's top edge.
        let mut closed: Vec<&str> = now
            .iter()
            .filter(|r| r.state.is_closed())
            .map(|r| r.contact.as_str())
            .collect();
        closed.sort();
        assert_eq!(closed, ["1:v0/0:e2", "1:v1/0:e2"], "t = {time}");
        for r in &now {
            assert_eq!((r.block_a, r.block_b), (1, 0));
            assert!(r.slip >= 0.0);
            if r.state.is_closed() {
                assert!(r.normal_force > 0.0, "{r:?}");
                assert!(r.shear_force.is_finite());
            } else {
                assert_eq!(r.normal_force, 0.0);
            }
        }
    }
    assert!(
        rows.iter()
            .all(|r| times[1..].iter().any(|t| t.0 == r.step)),
        "rows only at output times"
    );
    // Resting: locked, and the corners carry the block's weight.
    let last: Vec<_> = rows.iter().filter(|r| r.step == times[5].0).collect();
    assert!(last
        .iter()
        .all(|r| r.state == ContactState::Locked || r.state == ContactState::Open));
    let weight = 2700.0 * 9.81;
    let carried: f64 = last.iter().map(|r| r.normal_force).sum();
    assert!(
        ((carried - weight) / weight).abs() < 0.02,
        "the corners carry {carried} N of a {weight} N weight"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn check_names_a_custom_law_it_does_not_know() {
    let result = dda(&["check", "examples/custom_law.ron"]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8(result.stderr).unwrap();
    let line = std::fs::read_to_string("examples/custom_law.ron")
        .unwrap()
        .lines()
        .position(|l| l.contains("default_joint:"))
        .unwrap()
        + 1;
    assert!(
        stderr.starts_with(&format!(
            "error: examples/custom_law.ron:{line}:5: default_joint: no contact law is registered as `barton_bandis`; known laws: coulomb, "
        )),
        "{stderr}"
    );
}

#[test]
fn the_custom_law_example_slides_as_its_mobilised_friction_says() {
    // The example's law: φ = φr + JRC log10(JCS / σn), capped.
    let law = custom_law::build_barton_bandis(&mut dda_contact::Params::from([
        ("residual_friction_angle", 20.0),
        ("jrc", 4.0),
        ("jcs", 2e6),
    ]))
    .unwrap();
    assert_eq!(law.max_friction_angle, 70.0);
    assert!((law.friction_angle(2e4) - 28.0).abs() < 1e-12);
    assert_eq!(law.friction_angle(0.0), 70.0);
    assert_eq!(law.friction_angle(1e9), 20.0, "never below φr");
    let registry = custom_law::registry();
    let mut params = dda_contact::Params::from([
        ("jrc", 4.0),
        ("jcs", -1.0),
        ("residual_friction_angle", 20.0),
    ]);
    let message = registry.build("barton_bandis", &mut params).err().unwrap();
    assert!(message.contains("need jcs > 0"), "{message}");

    // Its scene, shortened, with the example's registry.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/custom_law.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace("duration: 1.0,", "duration: 0.4,");
    let scene = Scene::from_str(&text, "custom_law.ron").unwrap();
    let out = scratch("custom-law");
    let summary = run_scene(&scene, &out, RunOptions::default(), &registry).unwrap();
    assert_eq!(summary.scene, "custom_law.ron");
    assert_eq!(summary.unconverged_steps, 0);
    let history = read_history(out.join("history.csv")).unwrap();
    let contacts = read_contacts(out.join("contacts.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);

    let block: Vec<_> = history.iter().filter(|r| r.block == 1).collect();
    let (first, last) = (block[0], block[block.len() - 1]);
    assert_eq!(last.time, 0.4);
    let travel = (last.x - first.x).hypot(last.y - first.y);
    // Friction mobilised at the end, from the contact forces.
    let end: Vec<_> = contacts
        .iter()
        .filter(|c| c.step == last.step && c.state.is_closed())
        .collect();
    assert_eq!(end.len(), 2);
    assert!(end.iter().all(|c| c.state == ContactState::Sliding));
    let shear: f64 = end.iter().map(|c| c.shear_force).sum();
    let normal: f64 = end.iter().map(|c| c.normal_force).sum();
    let phi = (shear / normal).atan().to_degrees();
    // Each corner's friction is the law's at its own normal stress, between
    // those of the two corners.
    let corner = |c: &dda::ContactRow| (c.shear_force / c.normal_force).atan().to_degrees();
    let (lo, hi) = (
        end.iter().map(|c| corner(c)).fold(f64::INFINITY, f64::min),
        end.iter().map(|c| corner(c)).fold(0.0, f64::max),
    );
    assert!(
        lo > 20.0 && hi < 30.0 && lo <= phi && phi <= hi,
        "{lo} {phi} {hi}"
    );
    // And the block slides as that angle says (it changes little while sliding).
    let (g, slope, t) = (9.81, 30f64.to_radians(), last.time);
    let expected = 0.5 * g * (slope.sin() - slope.cos() * phi.to_radians().tan()) * t * t;
    assert!(
        ((travel - expected) / expected).abs() < 0.03,
        "travel {travel} m, expected {expected} m for φ = {phi}°"
    );
}

#[test]
fn a_binary_that_registers_a_law_runs_scenes_naming_it() {
    // What the example's `main` does: the `dda` command with its registry.
    let dir = scratch("custom-law-binary");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("custom_law.ron");
    let text = std::fs::read_to_string("examples/custom_law.ron").unwrap();
    std::fs::write(&scene, text.replace("duration: 1.0,", "duration: 0.05,")).unwrap();
    let out = dir.join("out");
    let registry = custom_law::registry();
    let run = |args: &[&str]| {
        let args = ["dda"].iter().chain(args).map(|a| a.to_string());
        dda::cli::main_from(args, &registry)
    };
    let (scene, out_dir) = (scene.to_str().unwrap(), out.to_str().unwrap());
    assert_eq!(run(&["check", scene]), std::process::ExitCode::SUCCESS);
    assert_eq!(
        run(&["run", scene, "--out", out_dir]),
        std::process::ExitCode::SUCCESS
    );
    let history = read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(history.last().unwrap().time, 0.05);
}

#[test]
fn a_recorded_ground_motion_carries_the_base() {
    // tests/data/shaken_base.ron names its record relative to its own folder.
    let out = scratch("shaken-base");
    let result = dda(&[
        "run",
        &data("shaken_base.ron"),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "stderr: {stderr}");
    let rows = read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);

    // 0.1 g from t = 0: x = a t² / 2, to the fixed points' stiffness.
    let a = 0.1 * 9.81;
    let base: Vec<_> = rows.iter().filter(|r| r.block == 0).collect();
    assert_eq!(base.len(), 6);
    for r in &base {
        let x = a * r.time * r.time / 2.0;
        assert!(
            (r.x - x).abs() <= 1e-6 * x.max(1e-3),
            "t = {}: x = {} expected {x}",
            r.time,
            r.x
        );
        assert!(
            (r.vx - a * r.time).abs() < 1e-5,
            "t = {}: vx = {}",
            r.time,
            r.vx
        );
    }
    let end = base.last().unwrap();
    assert_eq!(end.time, 0.5);
    let x = a * 0.25 / 2.0;
    assert!(((end.x - x) / x).abs() < 1e-6, "x = {} expected {x}", end.x);
    // The block resting on it rides along (a < g tan 30°), lagging by its
    // contacts' shear compliance only.
    let rider = rows.iter().rfind(|r| r.block == 1).unwrap();
    assert!((rider.x - end.x).abs() < 1e-4, "{} vs {}", rider.x, end.x);

    // check names the record's blocks like any others.
    let result = dda(&["check", &data("shaken_base.ron")]);
    assert!(result.status.success());
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(stdout.contains("ok (2 blocks"), "{stdout}");
}

#[test]
fn a_3d_run_writes_the_3d_history_and_summary() {
    let out = scratch("wedge-3d");
    let result = dda(&[
        "run",
        "examples/wedge_3d.ron",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "stderr: {stderr}");
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("step,time,block,x,y,z,rx,ry,rz,vx,vy,vz,wx,wy,wz,sxx,syy,szz,syz,szx,sxy")
    );
    assert_eq!(dda::output::HISTORY_HEADER_3D, text.lines().next().unwrap());
    let rows = dda::read_history_3d(out.join("history.csv")).unwrap();
    assert_eq!(rows.len(), 2 * 101, "101 output times × 2 blocks");
    // Reading it as a 2D history says what it is.
    let message = read_history(out.join("history.csv"))
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("it is a 3D history: read it with read_history_3d"),
        "{message}"
    );
    let s = summary(&out);
    assert_eq!(s["dimension"], 3);
    assert_eq!(s["status"], "finished");
    assert_eq!(s["blocks"], 2);
    assert_eq!(s["steps"], 1000);
    let _ = std::fs::remove_dir_all(&out);

    // 2D summaries say their dimension too.
    let out = scratch("free-fall-dimension");
    dda::run(Path::new(&data("free_fall.ron")), &out).unwrap();
    assert_eq!(summary(&out)["dimension"], 2);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn check_accepts_a_3d_scene_and_locates_its_errors() {
    let result = dda(&["check", "examples/sliding_block_3d.ron"]);
    assert!(result.status.success());
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(
        stdout.starts_with("examples/sliding_block_3d.ron: ok (3D, 2 blocks, 1 material"),
        "{stdout}"
    );
    let dir = scratch("bad-3d");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("examples/stacked_cubes_3d.ron")
        .unwrap()
        .replace("center: (0.0, 0.0, 1.5)", "center: (0.0, 0.0, 1.4)");
    let bad = dir.join("sunk.ron");
    std::fs::write(&bad, text).unwrap();
    let result = dda(&["check", bad.to_str().unwrap()]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8(result.stderr).unwrap();
    assert!(
        stderr.contains("blocks[1]: the block overlaps blocks[0] at the start"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_3d_contacts_csv_has_the_2d_columns() {
    let out = scratch("stacked-3d-contacts");
    std::fs::create_dir_all(&out).unwrap();
    let text = std::fs::read_to_string("examples/stacked_cubes_3d.ron")
        .unwrap()
        .replace("duration: 5.0", "duration: 0.1")
        .replace(
            "output: (interval: 0.05)",
            "output: (interval: 0.05, contacts: true)",
        );
    let scene = Scene::from_str(&text, "stacked.ron").unwrap();
    run_scene(
        &scene,
        &out,
        RunOptions::default(),
        &dda_contact::LawRegistry::with_builtin(),
    )
    .unwrap();
    let text = std::fs::read_to_string(out.join("contacts.csv")).unwrap();
    assert_eq!(text.lines().next(), Some(CONTACTS_HEADER));
    let rows = read_contacts(out.join("contacts.csv")).unwrap();
    assert!(rows
        .iter()
        .any(|r| r.time == 0.1 && r.state == ContactState::Locked));
    let _ = std::fs::remove_dir_all(&out);
}
