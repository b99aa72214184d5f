//! Where the method fails, the run says so, in summary.json and on the
//! terminal, instead of quietly writing garbage: a step that cannot
//! converge even at the smallest time step, a penetration beyond the
//! allowed bound, and energy growth in a scene that should only lose energy.

use std::process::Command;

mod common;

/// Runs `dda run` on scene text; returns (summary.json as JSON, stderr).
fn run(name: &str, analysis: &str, height: f64) -> (serde_json::Value, String) {
    let text = format!(
        r#"Scene(
    analysis: (duration: 0.3, gravity: (0.0, -9.81), {analysis}),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, {height:?}), width: 1.0, height: 1.0),
    ],
)"#
    );
    let out = common::out_dir(name);
    std::fs::create_dir_all(&out).unwrap();
    let scene = out.join("scene.ron");
    std::fs::write(&scene, text).unwrap();
    let result = Command::new(env!("CARGO_BIN_EXE_dda"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    (
        summary,
        String::from_utf8_lossy(&result.stderr).into_owned(),
    )
}

fn warned(summary: &serde_json::Value, stderr: &str, phrase: &str) -> bool {
    let in_summary = summary["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|w| w.as_str().unwrap().contains(phrase));
    in_summary && stderr.contains(phrase)
}

#[test]
fn a_well_behaved_run_reports_nothing() {
    let (summary, stderr) = run("stable", "penalty: 1e10, dt: 0.01", 0.55);
    assert_eq!(
        summary["warnings"].as_array().unwrap().len(),
        0,
        "{summary}"
    );
    assert!(!stderr.contains("warning"), "{stderr}");
}

#[test]
fn a_step_that_cannot_converge_at_the_smallest_step_is_reported() {
    // One open-close pass allowed: the step in which the dropped block lands
    // can never agree.
    let (summary, stderr) = run(
        "unconverged",
        "penalty: 1e10, dt: 0.01, open_close_limit: 1",
        0.55,
    );
    assert!(
        summary["unconverged_steps"].as_u64().unwrap() > 0,
        "{summary}"
    );
    assert!(
        warned(
            &summary,
            &stderr,
            "could not converge even at the smallest time step"
        ),
        "{stderr}"
    );
}

#[test]
fn penetration_beyond_the_bound_is_reported() {
    // A penalty so soft the block sinks about 13 mm, past 1e-3 of the model size.
    let (summary, stderr) = run("deep", "penalty: 1e6, dt: 0.01", 0.5);
    assert!(
        summary["deep_penetration_steps"].as_u64().unwrap() > 0,
        "{summary}"
    );
    assert!(summary["deepest_penetration"].as_f64().unwrap() > 2e-3);
    assert!(
        warned(&summary, &stderr, "penetrating beyond the allowed bound"),
        "{stderr}"
    );
}

#[test]
fn energy_growth_is_reported() {
    // The same soft contact with Shi's penalty raise: each raise multiplies
    // the energy stored in the existing overlap.
    let (summary, stderr) = run(
        "energy",
        "penalty: 1e6, dt: 0.001, raise_penalty: true",
        0.5,
    );
    assert!(summary["penalty_raises"].as_u64().unwrap() > 0, "{summary}");
    assert!(
        summary["energy_growth_steps"].as_u64().unwrap() > 0,
        "{summary}"
    );
    assert!(
        warned(&summary, &stderr, "the total energy rose"),
        "{stderr}"
    );
    // The advice is the cause this run saw, not a smaller dt.
    assert!(
        warned(&summary, &stderr, "leave raise_penalty off"),
        "{stderr}"
    );
    let energy = summary["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .find(|w| w.contains("the total energy rose"))
        .unwrap();
    assert!(!energy.contains("smaller dt"), "{energy}");
}
