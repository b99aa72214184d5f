//! Block sliding on a 30° incline with φ = 20° (reference B1):
//! d(t) = ½ g (sin θ − cos θ tan φ) t², 0.9064 m at 1 s.

mod common;

#[test]
fn block_slides_the_analytical_distance_down_the_dip() {
    let rows = common::run_example("sliding_block_2d.ron");
    let (theta, phi, g) = (30f64.to_radians(), 20f64.to_radians(), 9.81);
    let a = g * (theta.sin() - theta.cos() * phi.tan());
    let start = common::at(&rows, 1, 0.0);
    for t in [0.5, 1.0] {
        let now = common::at(&rows, 1, t);
        assert!((now.time - t).abs() < 1e-12);
        // Displacement along the dip (down the incline is (−cos θ, −sin θ)).
        let (dx, dy) = (now.x - start.x, now.y - start.y);
        let along = -(dx * theta.cos() + dy * theta.sin());
        let exact = 0.5 * a * t * t;
        assert!(
            ((along - exact) / exact).abs() < 0.01,
            "t = {t}: slid {along:.6} m, exact {exact:.6} m"
        );
        // Motion is along the dip: the normal component is only the settling
        // into the contact springs.
        let normal = -dx * theta.sin() + dy * theta.cos();
        assert!(normal.abs() < 1e-4, "moved {normal:e} m off the incline");
    }
    assert!(
        (0.5 * a - 0.9064).abs() < 1e-4,
        "the reference value of the issue"
    );
}
