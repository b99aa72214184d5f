//! Where the method fails, the run says so, in summary.json and on the
//! terminal, instead of quietly writing garbage: a step that cannot
//! converge even at the smallest time step, a penetration beyond the
//! allowed bound, and energy growth in a scene that should only lose energy.
//! By default each stops the run with a report naming the time, the blocks
//! and contacts, and what to change; `on_failure: Continue` runs on and
//! warns.

use std::process::Command;

mod common;

/// Runs `dda run` on scene text with `on_failure: Continue`; returns
/// (summary.json as JSON, stderr).
fn run(name: &str, analysis: &str, height: f64) -> (serde_json::Value, String) {
    let analysis = format!("{analysis}, on_failure: Continue");
    let (summary, stderr, ok) = run_scene(name, &analysis, height, 0.0);
    assert!(ok, "{stderr}");
    (summary, stderr)
}

/// Runs `dda run` with the default `on_failure: Stop` on a block dropped
/// from `height` at `speed` (m/s, downwards); returns (summary.json,
/// stderr), the run having failed.
fn stopped(name: &str, analysis: &str, height: f64, speed: f64) -> (serde_json::Value, String) {
    let (summary, stderr, ok) = run_scene(name, analysis, height, speed);
    assert!(!ok, "the run went on: {stderr}");
    assert_eq!(summary["status"], "failed", "{summary}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    (summary, stderr)
}

fn run_scene(
    name: &str,
    analysis: &str,
    height: f64,
    speed: f64,
) -> (serde_json::Value, String, bool) {
    let text = format!(
        r#"Scene(
    analysis: (duration: 0.3, gravity: (0.0, -9.81), {analysis}),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, {height:?}), width: 1.0, height: 1.0, velocity: (0.0, {:?}, 0.0)),
    ],
)"#,
        -speed
    );
    run_text(name, &text)
}

/// Runs `dda run` on the scene `text` in a folder of its own; returns
/// (summary.json as JSON, stderr, whether the run succeeded).
fn run_text(name: &str, text: &str) -> (serde_json::Value, String, bool) {
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
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    (
        summary,
        String::from_utf8_lossy(&result.stderr).into_owned(),
        result.status.success(),
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
    // One open-close pass allowed: the first step, in which the block
    // resting on its base is thrown up, can never agree (nothing before it
    // foresees its contacts opening).
    let (summary, stderr, ok) = run_scene(
        "unconverged",
        "penalty: 1e10, dt: 0.01, open_close_limit: 1, on_failure: Continue",
        0.5,
        -1.0,
    );
    assert!(ok, "{stderr}");
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

/// A landing that cannot reach open-close agreement at a stiff penalty and
/// dt 10 ms, with `settings` added: the summary, stderr and the error, which
/// says so.
fn unconverged_stop(name: &str, settings: &str) -> (serde_json::Value, String, String) {
    // Thrown up from its base: see the test above.
    let (summary, stderr) = stopped(
        name,
        &format!("penalty: 1e10, dt: 0.01, {settings}"),
        0.5,
        -1.0,
    );
    let error = summary["error"].as_str().unwrap().to_string();
    assert!(
        error.contains("could not reach open-close agreement even at the smallest time step"),
        "{error}"
    );
    (summary, stderr, error)
}

/// The same three by default: the run stops at the step, with the time,
/// the blocks or contacts, and advice that fits the cause.
#[test]
fn a_step_that_cannot_converge_stops_the_run() {
    let (summary, stderr, error) = unconverged_stop("unconverged-stop", "open_close_limit: 1");
    // The corners of block 1 leaving the base, block 0.
    assert!(error.contains("(block 1 on block 0)"), "{error}");
    assert!(stderr.contains("on_failure: Continue"), "{stderr}");
    // Stopped at the throw, not at the end.
    assert!(summary["time"].as_f64().unwrap() < 0.3, "{summary}");
}

/// The same with contact damping on: the advice does not ask for the
/// damping the run already has.
#[test]
fn a_damped_step_that_cannot_converge_is_not_told_to_add_damping() {
    let (_, _, error) = unconverged_stop(
        "unconverged-damped-stop",
        "open_close_limit: 1, contact_damping: 1.0",
    );
    assert!(
        error.contains("a smaller dt or a larger analysis.open_close_limit"),
        "{error}"
    );
    assert!(!error.contains("contact_damping"), "{error}");
}

/// Too soft a penalty: the advice is a stiffer one, not a smaller dt.
#[test]
fn a_soft_penalty_stops_the_run_and_asks_for_a_stiffer_one() {
    let (summary, _) = stopped("soft-stop", "penalty: 1e6, dt: 0.01", 0.5, 0.0);
    let error = summary["error"].as_str().unwrap();
    assert!(error.contains("penetrated"), "{error}");
    assert!(error.contains("(block 1 into block 0)"), "{error}");
    assert!(error.contains("raise analysis.penalty"), "{error}");
    assert!(!error.contains("a dt below"), "{error}");
}

/// A block thrown at its base at 300 m/s closes 3 m in one 10 ms step:
/// the advice is a smaller dt, not a stiffer penalty.
#[test]
fn a_fast_impact_stops_the_run_and_asks_for_a_smaller_dt() {
    let (summary, _) = stopped("fast-stop", "penalty: 1e10, dt: 0.01", 0.6, 300.0);
    let error = summary["error"].as_str().unwrap();
    assert!(error.contains("penetrated"), "{error}");
    assert!(error.contains("a dt below"), "{error}");
    assert!(!error.contains("raise analysis.penalty"), "{error}");
}

#[test]
fn energy_growth_stops_the_run() {
    let (summary, _) = stopped(
        "energy-stop",
        "penalty: 1e6, dt: 0.001, raise_penalty: true",
        0.5,
        0.0,
    );
    let error = summary["error"].as_str().unwrap();
    assert!(error.contains("the total energy rose"), "{error}");
    assert!(error.contains("block 1 ("), "{error}");
    assert!(error.contains("leave raise_penalty off"), "{error}");
}

/// A penalty 5e19 times the automatic one (1e30 against 2e10 N/m³) leaves
/// the block's factorisation to round-off: the run stops there, and the
/// error names the penalty against the automatic one, not zero masses,
/// which scene validation already refuses.
#[test]
fn a_matrix_swamped_by_the_penalty_names_the_penalty() {
    let (summary, _) = stopped("npd-stop", "penalty: 1e30, dt: 0.001", 0.5, 0.0);
    let error = summary["error"].as_str().unwrap();
    assert!(error.contains("not positive definite"), "{error}");
    assert!(
        error.contains(
            "the penalty, 1.000e30 N/m³, is 5.0e19 times the automatic one (2.000e10 N/m³"
        ),
        "{error}"
    );
    assert!(error.contains("analysis.penalty left out"), "{error}");
    assert!(!error.contains("zero mass"), "{error}");
}

/// The block sliding on its incline at the same penalty factorises, but
/// its energy check reads the springs' round-off as a rise that no cut,
/// raise or unconverged pass explains: the error names the penalty
/// instead of asking for the scene to be reported.
#[test]
fn an_energy_rise_at_a_swamping_penalty_names_the_penalty() {
    let text = std::fs::read_to_string(common::example("sliding_block_2d.ron"))
        .unwrap()
        .replace("penalty: 2e10", "penalty: 1e30")
        .replace("duration: 1.0", "duration: 0.01");
    assert!(text.contains("penalty: 1e30"));
    let (_, stderr, ok) = run_text("swamped-energy", &text);
    assert!(!ok, "{stderr}");
    assert!(stderr.contains("the total energy rose"), "{stderr}");
    assert!(
        stderr.contains("is 5.0e19 times the automatic one"),
        "{stderr}"
    );
    assert!(stderr.contains("round-off"), "{stderr}");
    assert!(!stderr.contains("please report the scene"), "{stderr}");
}
