//! Velocity-dependent friction: a block sliding down a 30° incline whose
//! friction falls from 25° at rest to 15° at speed, μ(v) = μd + (μs − μd)
//! exp(−v/vc), against a fine Runge-Kutta integration of
//! dv/dt = g (sin θ − cos θ μ(v)).

mod common;

const LAW: &str = "RateFriction(static_friction_angle: 25.0, dynamic_friction_angle: 15.0, characteristic_rate: 0.5)";

fn reference(t_end: f64) -> f64 {
    let (theta, g, vc) = (30f64.to_radians(), 9.81, 0.5);
    let (ms, md) = (25f64.to_radians().tan(), 15f64.to_radians().tan());
    let accel = |v: f64| g * (theta.sin() - theta.cos() * (md + (ms - md) * (-v / vc).exp()));
    // State (d, v); RK4 with 1e5 steps is exact to far below 1e-6.
    let n = 100_000;
    let h = t_end / n as f64;
    let (mut d, mut v) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let k1 = (v, accel(v));
        let k2 = (v + 0.5 * h * k1.1, accel(v + 0.5 * h * k1.1));
        let k3 = (v + 0.5 * h * k2.1, accel(v + 0.5 * h * k2.1));
        let k4 = (v + h * k3.1, accel(v + h * k3.1));
        d += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
    }
    d
}

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
        let exact = reference(t);
        assert!(
            ((along - exact) / exact).abs() < 0.01,
            "t = {t}: {along:.5} m, ODE {exact:.5} m"
        );
    }
    // Far from both constant-friction answers: the rate dependence matters.
    for phi in [15f64, 25.0] {
        let constant = 0.5 * 9.81 * (theta.sin() - theta.cos() * phi.to_radians().tan());
        assert!((reference(1.0) / constant - 1.0).abs() > 0.1, "φ = {phi}°");
    }
}
