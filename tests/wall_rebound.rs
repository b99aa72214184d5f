//! The 70 × 70 running-bond wall of deformable bricks (4,936 blocks),
//! released unstressed at its automatic step, shortens under its weight
//! and rebounds about 0.08 s later. As it rebounds its head joints near the
//! top go into tension and open one course per open-close pass, from the
//! top down, and with contact damping its bed joints there pass between
//! locked and sliding in a wave that moves a brick per pass: neither
//! repeats the states of two passes before, so neither is a cycle to
//! break. Within Shi's six passes a step, the undamped wall cut 8 steps to
//! a third in its first 0.1 s and the damped one failed at t = 0.0814 s,
//! no step agreeing even at the smallest dt; the default of twenty passes
//! carries both through without a cut. (About 40 s in a release build.)

use dda::Scene;

#[test]
fn a_damped_wall_rebounds_without_a_cut() {
    let text = r#"Scene(
    analysis: (duration: 0.083, contact_damping: 1.0, gravity: (0.0, -9.81)),
    materials: { "brick": (density: 1800.0, young: 5e9, poisson: 0.2) },
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: (17.5, -0.5), width: 37.0, height: 1.0, fixed: true),
        Wall(origin: (0.0, 0.0), length: 35.0, courses: 70, brick_length: 0.5, brick_height: 0.25, bond: Running),
    ],
)"#;
    let mut model = Scene::from_str(text, "wall_70x70.ron")
        .unwrap()
        .build()
        .unwrap();
    let driver = &mut model.driver;
    let result = driver.advance_to(0.083);
    let stats = driver.statistics();
    println!(
        "{} steps, {} passes, {} factorisations, {} cuts, {} unconverged, t = {:.4} s",
        stats.steps,
        stats.open_close_iterations,
        stats.factorizations,
        stats.open_close_cuts,
        stats.unconverged_steps,
        driver.time()
    );
    assert!(result.is_ok(), "{result:?}");
    assert!(
        (driver.time() - 0.083).abs() < 1e-9,
        "t = {}",
        driver.time()
    );
    assert_eq!(stats.open_close_cuts, 0, "a step was cut");
    assert_eq!(
        stats.unconverged_steps, 0,
        "a step was accepted unconverged"
    );
}
