//! Displacement-dependent friction with a sharp drop (reference B1 variant):
//! a block on a 30° incline with φ = 25° until 0.05 m of slip, then 15°,
//! moves along two parabolas; d(1 s) = 0.8549 m.

mod common;

#[test]
fn block_follows_the_piecewise_parabola() {
    let rows = common::run_example("two_stage_friction_2d.ron");
    let theta = 30f64.to_radians();
    let exact = common::two_stage_slide;
    assert!(
        (exact(1.0) - 0.8549).abs() < 5e-5,
        "the issue's reference value"
    );
    let start = common::at(&rows, 1, 0.0);
    for t in [0.3, 0.6, 1.0] {
        let now = common::at(&rows, 1, t);
        let along = -((now.x - start.x) * theta.cos() + (now.y - start.y) * theta.sin());
        let expect = exact(t);
        assert!(
            ((along - expect) / expect).abs() < 0.01,
            "t = {t}: {along:.5} m, exact {expect:.5} m"
        );
    }
}
