//! The 70 × 70 running-bond wall of deformable bricks (4,936 blocks),
//! released unstressed at its automatic step, shortens under its weight
//! and rebounds about 0.08 s later. As it rebounds its head joints near the
//! top go into tension and open one course per open-close pass, from the
//! top down, and with contact damping its bed joints there pass between
//! locked and sliding in a wave that moves a brick per pass: neither
//! repeats the states of two passes before, so neither is a cycle to
//! break. Within Shi's six passes a step, the undamped wall cut 8 steps to
//! a third in its first 0.1 s, and the damped one cut 8 by t = 0.083 s and
//! accepted one unconverged (`dda run` stopped there, at t = 0.0814 s);
//! the default of twenty passes carries both through without a cut.
//! (About 50 s in a release build.)

use dda::bench::{wall, Stepping};
use dda::scene::BlockKind;

#[test]
fn a_damped_wall_rebounds_without_a_cut() {
    // The wall `dda bench` runs, dt and penalty automatic, damped.
    let mut scene = wall(70, 2, Stepping::Automatic, BlockKind::Deformable).unwrap();
    scene.analysis.duration = 0.083;
    scene.analysis.contact_damping = 1.0;
    let mut model = scene.build().unwrap();
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
