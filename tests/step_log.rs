//! `steps.csv` (`output.steps`, `dda run --steps`): a row per accepted
//! step whose counts add up to the run's own in `summary.json`, whose
//! steps' lengths add up to its time, and which a run that fails keeps up
//! to its last step.

use std::path::{Path, PathBuf};

use dda::bench::{shake, wall, Stepping};
use dda::run::{run_scene, RunOptions};
use dda::scene::BlockKind;
use dda::step_log::read_steps;
use dda_contact::LawRegistry;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("step_log")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// The 10 × 10 deformable wall shaken near its sliding limit at dt 2 ms,
/// its passes held to two so that steps are cut: every step has its row,
/// and each column adds up to the summary's count.
#[test]
fn each_step_has_a_row_adding_up_to_the_run() {
    let mut scene = wall(10, 2, Stepping::Given(0.002), BlockKind::Deformable).unwrap();
    let seconds = 0.2;
    shake(&mut scene, 6.5, seconds);
    scene.analysis.duration = seconds;
    scene.analysis.open_close_limit = 2;
    scene.output.interval = Some(0.05);
    scene.output.steps = true;
    let dir = scratch("shaken");
    let options = RunOptions::default();
    run_scene(&scene, &dir, options, &LawRegistry::with_builtin()).unwrap();
    let rows = read_steps(dir.join("steps.csv")).unwrap();
    let s = summary(&dir);
    let count = |key: &str| s[key].as_u64().unwrap() as usize;
    assert_eq!(rows.len(), count("steps"));
    assert!(rows.iter().enumerate().all(|(i, r)| r.step == i + 1));
    let sum = |f: fn(&dda::step_log::StepRow) -> usize| rows.iter().map(f).sum::<usize>();
    assert_eq!(sum(|r| r.passes), count("open_close_iterations"));
    assert_eq!(sum(|r| r.moves), count("newton_iterations"));
    assert_eq!(sum(|r| r.factorizations), count("factorizations"));
    let cuts = count("open_close_cuts") + count("displacement_cuts") + count("penetration_cuts");
    assert_eq!(sum(|r| r.cuts), cuts);
    assert!(cuts > 0, "the limit of two passes cuts steps");
    assert_eq!(sum(|r| r.unconverged), count("unconverged_steps"));
    // The steps' lengths make the run's time, and a cut step is shorter.
    let time: f64 = rows.iter().map(|r| r.dt).sum();
    assert!((time - seconds).abs() < 1e-9, "{time}");
    assert!((rows.last().unwrap().time - seconds).abs() < 1e-12);
    for r in rows.iter().filter(|r| r.cuts > 0) {
        assert!(r.dt < 0.002 * (1.0 - 1e-9), "{r:?}");
    }
    // The energy is the summary's at the end; every step took time.
    let energy = s["energy"].as_f64().unwrap();
    assert!((rows.last().unwrap().energy - energy).abs() <= 1e-9 * energy.abs());
    assert!(rows.iter().all(|r| r.wall_ms >= 0.0 && r.passes >= 1));
    // Each step's phases lie within its wall time (each column rounded to
    // a microsecond), and over the run add up to the summary's.
    for r in &rows {
        let named = r.wall_ms - r.other_ms();
        assert!(named <= r.wall_ms + 0.003, "{r:?}");
    }
    let phases = &s["phases"];
    let ms = |key: &str| 1e3 * phases[key].as_f64().unwrap();
    let rounding = 5e-4 * rows.len() as f64 + 1e-6;
    let phase_sum = |f: fn(&dda::step_log::StepRow) -> f64| rows.iter().map(f).sum::<f64>();
    let search = ms("broad_phase") + ms("narrow_phase") + ms("pattern");
    for (name, logged, whole) in [
        ("search", phase_sum(|r| r.search_ms), search),
        ("assembly", phase_sum(|r| r.assembly_ms), ms("assembly")),
        (
            "factorization",
            phase_sum(|r| r.factorization_ms),
            ms("symbolic") + ms("numeric"),
        ),
        ("solve", phase_sum(|r| r.solve_ms), ms("solve")),
        (
            "open_close",
            phase_sum(|r| r.open_close_ms),
            ms("open_close"),
        ),
        ("commit", phase_sum(|r| r.commit_ms), ms("commit")),
    ] {
        assert!(whole > 0.0, "{name}: no time in the summary");
        assert!(
            (logged - whole).abs() <= rounding,
            "{name}: {logged} ms against {whole}"
        );
    }
    assert!(s["outputs"]
        .as_array()
        .unwrap()
        .iter()
        .any(|o| o == "steps.csv"));
}

/// `dda run --steps` writes it for a scene that does not ask; a scene
/// that does not, without the flag, has none.
#[test]
fn the_flag_writes_steps_for_any_scene() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/free_fall_2d.ron");
    let (with, without) = (scratch("flag"), scratch("none"));
    for (dir, flag) in [(&with, true), (&without, false)] {
        let mut args = vec![
            "run",
            example.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ];
        if flag {
            args.push("--steps");
        }
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
            .args(&args)
            .output()
            .unwrap();
        assert!(output.status.success(), "{output:?}");
    }
    let rows = read_steps(with.join("steps.csv")).unwrap();
    assert_eq!(
        rows.len(),
        summary(&with)["steps"].as_u64().unwrap() as usize
    );
    assert!(!without.join("steps.csv").exists());
}

/// A run stopped by a guard between output times (a block sinking into a
/// base of too soft a penalty) keeps a row for every step it took.
#[test]
fn a_failed_run_keeps_every_step() {
    let dir = scratch("failed");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.ron");
    std::fs::write(
        &scene,
        r#"Scene(
    analysis: (duration: 1.0, gravity: (0.0, -9.81), penalty: 1e6, dt: 0.01),
    materials: { "rock": (density: 2700.0, young: 1e10, poisson: 0.25) },
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, 0.5), width: 1.0, height: 1.0),
    ],
    output: (interval: 0.5, steps: true),
)"#,
    )
    .unwrap();
    let out = dir.join("out");
    let scene = dda::Scene::load(&scene).unwrap();
    let registry = LawRegistry::with_builtin();
    let failed = run_scene(&scene, &out, RunOptions::default(), &registry);
    assert!(failed.is_err(), "the run went on");
    let s = summary(&out);
    assert_eq!(s["status"], "failed", "{s}");
    let steps = s["steps"].as_u64().unwrap() as usize;
    let rows = read_steps(out.join("steps.csv")).unwrap();
    assert_eq!(rows.len(), steps);
    // It stopped before its first output time after the start.
    assert!(rows.last().unwrap().time < 0.5, "{:?}", rows.last());
}

/// `dda check` counts steps.csv in what a run will write, and warns where
/// a row per step grows beyond a gigabyte.
#[test]
fn check_estimates_the_step_log() {
    let dir = scratch("check");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/free_fall_2d.ron"),
    )
    .unwrap();
    assert!(text.contains("dt: 0.01") && text.contains("output: ("));
    let check = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
            .args(["check", path.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(output.status.success(), "{output:?}");
        String::from_utf8_lossy(&output.stdout).into_owned()
            + &String::from_utf8_lossy(&output.stderr)
    };
    let asked = text.replace("output: (", "output: (steps: true, ");
    let said = check("asked.ron", asked.clone());
    // 100 steps of about 100 bytes.
    assert!(
        said.contains("and steps.csv, a row per step (about 10.00 kB)"),
        "{said}"
    );
    assert!(!said.contains("warning"), "{said}");
    let said = check("long.ron", asked.replace("dt: 0.01", "dt: 1e-8"));
    assert!(
        said.contains("warning: steps.csv would be about 10.00 GB (a row per step)"),
        "{said}"
    );
    assert!(!check("plain.ron", text).contains("steps.csv"));
}
