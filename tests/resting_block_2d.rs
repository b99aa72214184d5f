//! Block on a 30° incline with φ = 35° (reference B1 variant): friction
//! holds it. It may only settle into the contact springs, then must not creep.

mod common;

#[test]
fn block_stays_put_when_friction_exceeds_the_slope() {
    let rows = common::run_example("resting_block_2d.ron");
    let start = common::at(&rows, 1, 0.0);
    let one = common::at(&rows, 1, 1.0);
    let two = common::at(&rows, 1, 2.0);
    assert!((two.time - 2.0).abs() < 1e-12);
    let moved = common::distance(start, two);
    let creep = common::distance(one, two);
    assert!(moved < 1e-4, "moved {moved:e} m in 2 s");
    assert!(creep < 1e-7, "crept {creep:e} m between 1 s and 2 s");
}
