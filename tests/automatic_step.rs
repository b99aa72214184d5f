//! The automatic time step (implicit integrator, `dt` left out, gravity):
//! each step as long as keeps every block's points moving less than
//! 2.5e-4 of the median block size, at most 1/20 of sqrt(block size / g).
//! A wall at rest steps at that ceiling and stands; a rocking column steps
//! at about a millisecond near its impacts and loses Housner's share at
//! each; a sliding block slides Coulomb's distance. Without gravity the
//! step resolves the contact springs as before.

use dda::{Scene, Simulation};

mod common;

fn build(text: &str, name: &str) -> dda::scene::Model {
    Scene::from_str(text, name).unwrap().build().unwrap()
}

/// A shipped example with its `dt: …` line taken out.
fn without_dt(example: &str, line: &str) -> String {
    let text = std::fs::read_to_string(common::example(example)).unwrap();
    assert_eq!(text.matches(line).count(), 1, "{example}: {line}");
    text.replace(line, "")
}

#[test]
fn a_wall_at_rest_steps_at_the_ceiling_and_stands() {
    // 10 courses of 10 rigid bricks, dt and penalty automatic.
    let text = r#"Scene(
    analysis: (duration: 1.0, gravity: (0.0, -9.81)),
    materials: { "brick": (density: 1800.0, young: 5e9, poisson: 0.2, kind: Rigid) },
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: (2.5, -0.5), width: 7.0, height: 1.0, fixed: true),
        Wall(origin: (0.0, 0.0), length: 5.0, courses: 10, brick_length: 0.5, brick_height: 0.25, bond: Running),
    ],
)"#;
    let mut model = build(text, "wall.ron");
    let driver = &mut model.driver;
    let size = (0.5f64 * 0.25).sqrt();
    let ceiling = (size / 9.81).sqrt() / 20.0;
    assert!(
        (driver.dt() - ceiling).abs() < 1e-12 * ceiling,
        "{}",
        driver.dt()
    );
    assert!(driver
        .notes()
        .iter()
        .any(|n| n.contains("time step automatic")));
    let start: Vec<_> = driver.system.blocks.iter().map(|b| b.centroid()).collect();
    driver.advance_to(1.0).unwrap();
    let stats = driver.statistics();
    let drift = (driver.system.blocks.iter().zip(&start))
        .map(|(b, c)| (b.centroid() - c).norm())
        .fold(0.0, f64::max);
    println!(
        "steps {}, passes {}, drift {drift:.3e} m",
        stats.steps, stats.open_close_iterations
    );
    // Every step but the first few at the ceiling.
    assert!(
        (stats.steps as f64) < 1.1 / ceiling,
        "{} steps of at most {ceiling} s",
        stats.steps
    );
    assert_eq!(stats.open_close_cuts + stats.unconverged_steps, 0);
    // Measured 7.4e-6 m (the bricks settling into their springs).
    assert!(drift < 2e-5, "the wall drifted {drift} m");
}

#[test]
fn a_rocking_column_keeps_housners_share_at_the_automatic_step() {
    let mut model = build(
        &without_dt("rocking_column_2d.ron", "dt: 0.0005,"),
        "rocking.ron",
    );
    let driver = &mut model.driver;
    let mut rotations = vec![driver.history_values(1)[2]];
    let mut longest: f64 = 0.0;
    while driver.time() < 4.0 - 1e-9 {
        let before = driver.time();
        driver.step(4.0 - before).unwrap();
        longest = longest.max(driver.time() - before);
        rotations.push(driver.history_values(1)[2]);
    }
    let errors = common::housner_ratio_errors(&rotations);
    println!(
        "{} steps, longest {longest:.2e} s, ratios against Housner's {errors:+.4?}",
        driver.statistics().steps
    );
    for (n, e) in errors.iter().enumerate() {
        assert!(e.abs() < 0.01, "ratio {}: {:+.2} %", n + 1, 100.0 * e);
    }
}

#[test]
fn a_sliding_block_slides_coulombs_distance_at_the_automatic_step() {
    let mut model = build(
        &without_dt("sliding_block_2d.ron", "dt: 0.001,"),
        "sliding.ron",
    );
    // The example's 10 ms output interval is shorter than the automatic
    // step's ceiling (16 ms): the steps shorten to land on the output times,
    // they are not all written.
    assert!(model.driver.dt() > 0.01);
    assert_eq!(model.output_interval, Some(0.01));
    let driver = &mut model.driver;
    let start = driver.system.blocks[1].centroid();
    driver.advance_to(1.0).unwrap();
    let moved = (driver.system.blocks[1].centroid() - start).norm();
    let exact =
        dda::validate::formulas::incline_slide(9.81, 30f64.to_radians(), 20f64.to_radians(), 1.0);
    println!(
        "slid {moved:.6} m in {} steps, Coulomb {exact:.6} m",
        driver.statistics().steps
    );
    assert!(((moved - exact) / exact).abs() < 1e-3);
}

#[test]
fn without_gravity_the_step_resolves_the_contact_springs() {
    let text = r#"Scene(
    analysis: (duration: 0.01, penalty: 1e10, gravity: (0.0, 0.0)),
    materials: { "rock": (density: 2700.0, young: 1e10, poisson: 0.25) },
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 2.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, 0.5), width: 1.0, height: 1.0),
    ],
)"#;
    let model = build(text, "weightless.ron");
    let expected = 0.2 * (2700.0f64 / 1e10).sqrt();
    let dt = model.driver.dt();
    assert!(
        (dt - expected).abs() < 1e-9 * expected,
        "{dt} against {expected}"
    );
}
