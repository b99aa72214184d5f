//! Velocity-dependent friction: a block sliding down a 30° incline whose
//! friction falls from 25° at rest to 15° at speed, μ(v) = μd + (μs − μd)
//! exp(−v/vc), against a fine Runge-Kutta integration of
//! dv/dt = g (sin θ − cos θ μ(v)).

mod common;

const LAW: &str = common::RATE_LAW;

#[test]
fn block_slides_as_the_rate_law_ode_says() {
    let text = common::example_with("sliding_block_2d.ron", "Coulomb(friction_angle: 20.0)", LAW);
    let out = common::run_text("rate_friction", &text);
    let rows = dda::read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let theta = 30f64.to_radians();
    let start = common::at(&rows, 1, 0.0);
    for t in [0.5, 1.0] {
        let now = common::at(&rows, 1, t);
        let along = -((now.x - start.x) * theta.cos() + (now.y - start.y) * theta.sin());
        let exact = common::rate_friction_slide(t);
        assert!(
            ((along - exact) / exact).abs() < 0.01,
            "t = {t}: {along:.5} m, ODE {exact:.5} m"
        );
    }
    // Far from both constant-friction answers: the rate dependence matters.
    for phi in [15f64, 25.0] {
        let constant = 0.5 * 9.81 * (theta.sin() - theta.cos() * phi.to_radians().tan());
        assert!(
            (common::rate_friction_slide(1.0) / constant - 1.0).abs() > 0.1,
            "φ = {phi}°"
        );
    }
}
