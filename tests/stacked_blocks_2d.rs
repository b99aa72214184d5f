//! Ten blocks stacked on a fixed base: the top block settles by the sum of
//! the joint closures (the weight above each joint over the stiffness of its
//! two corner contacts), then stays put.

use dda::scene::Scene;

mod common;

#[test]
fn stack_settles_by_the_joint_compressions_and_does_not_creep() {
    let scene = Scene::load(common::example("stacked_blocks_2d.ron")).unwrap();
    let penalty = scene
        .analysis
        .penalty
        .expect("the example sets its penalty");
    let rows = common::run_example("stacked_blocks_2d.ron");
    let top = 10;
    let weight = 2700.0 * 1.0 * 0.5 * 9.81;
    // Joint k from the top carries k blocks on two corner springs.
    // Each joint is 1 m long; the penalty is per unit length.
    let expected: f64 = (1..=10).map(|k| k as f64 * weight / (penalty * 1.0)).sum();
    let start = common::at(&rows, top, 0.0);
    let one = common::at(&rows, top, 1.0);
    let five = common::at(&rows, top, 5.0);
    assert!((five.time - 5.0).abs() < 1e-12);
    let settlement = start.y - five.y;
    assert!(
        ((settlement - expected) / expected).abs() < 0.1,
        "settled {settlement:e} m, expected {expected:e} m"
    );
    let creep = common::distance(one, five);
    assert!(
        creep < 1e-7,
        "top block crept {creep:e} m between 1 s and 5 s"
    );
}
