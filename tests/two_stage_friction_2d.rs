//! Displacement-dependent friction with a sharp drop (reference B1 variant):
//! a block on a 30° incline with φ = 25° until 0.05 m of slip, then 15°,
//! moves along two parabolas; d(1 s) = 0.8549 m.

mod common;

#[test]
fn block_follows_the_piecewise_parabola() {
    let rows = common::run_example("two_stage_friction_2d.ron");
    let (theta, g) = (30f64.to_radians(), 9.81);
    let a = |phi: f64| g * (theta.sin() - theta.cos() * phi.to_radians().tan());
    let (a1, a2, d1) = (a(25.0), a(15.0), 0.05);
    let t1 = (2.0 * d1 / a1).sqrt();
    let exact = |t: f64| {
        if t <= t1 {
            0.5 * a1 * t * t
        } else {
            d1 + a1 * t1 * (t - t1) + 0.5 * a2 * (t - t1).powi(2)
        }
    };
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
