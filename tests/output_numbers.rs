//! The numbers a run writes are the ones it computed: times without
//! accumulated round-off, and no nulls in the summary of a failed run.

use dda::run::{run_scene, RunOptions, Status};
use dda::Scene;
use dda_contact::LawRegistry;

mod common;

const FALL: &str = r#"Scene(
    analysis: (duration: 2.0, dt: 0.001, gravity: (0.0, -1.0)),
    output: (interval: 0.0),
    materials: { "rock": (density: 2700.0, young: 1e10, poisson: 0.25) },
    blocks: [ Rectangle(center: (0.0, 1.0), width: 1.0, height: 0.5) ],
)"#;

fn run(text: &str, name: &str) -> (anyhow::Result<dda::Summary>, std::path::PathBuf) {
    let out = common::out_dir(name);
    let scene = Scene::from_str(text, &format!("{name}.ron")).unwrap();
    let result = run_scene(
        &scene,
        &out,
        RunOptions::default(),
        &LawRegistry::with_builtin(),
    );
    (result, out)
}

#[test]
fn every_step_time_is_the_step_count_times_dt() {
    let (result, out) = run(FALL, "times");
    let summary = result.unwrap();
    assert_eq!(summary.steps, 2000);
    assert_eq!(summary.time, 2.0);
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    // Two thousand steps of 0.001 s written as they are, not as
    // 1.9999999999998905.
    for line in text.lines().skip(1) {
        let mut fields = line.split(',');
        let step: usize = fields.next().unwrap().parse().unwrap();
        let time = fields.next().unwrap();
        let expected = format!("{}", step as f64 / 1000.0);
        assert_eq!(time, expected, "step {step}");
    }
}

#[test]
fn a_failed_run_keeps_finite_numbers_in_its_summary() {
    // So fast that its kinetic energy overflows in the first step, and the
    // step after that is not finite.
    let text = FALL.replace(
        "width: 1.0, height: 0.5)",
        "width: 1.0, height: 0.5, velocity: (1e160, 0.0, 0.0))",
    );
    let (result, out) = run(&text, "runaway");
    assert!(result.is_err());
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    assert!(!json.contains("null"), "{json}");
    let summary: dda::Summary = serde_json::from_str(&json).unwrap();
    assert_eq!(summary.status, Status::Failed);
    assert!(summary.steps >= 1, "{json}");
    assert!(summary.time > 0.0, "{json}");
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("not finite when the run stopped: energy")),
        "{json}"
    );
}
