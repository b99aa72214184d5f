//! Mass-proportional damping: a free block sliding with no forces slows as
//! dv/dt = −α v, α = 2 ξ (2π f). Newmark (β = 1/2, γ = 1) gives
//! v_n = v0 / (1 + α dt)^n exactly, which tends to v0 exp(−α t).

use dda::scene::Scene;

#[test]
fn damping_slows_a_free_block_at_the_set_rate() {
    let (ratio, frequency, dt, v0) = (0.05, 2.0, 0.001, 3.0);
    let text = format!(
        r#"Scene(
    analysis: (duration: 1.0, dt: {dt:?}, gravity: (0.0, 0.0), max_displacement_ratio: 0.5,
               damping: (ratio: {ratio:?}, frequency: {frequency:?})),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    blocks: [Rectangle(center: (0.0, 0.0), width: 1.0, height: 1.0, velocity: ({v0:?}, 0.0, 0.0))],
)"#
    );
    let mut model = Scene::from_str(&text, "damped.ron")
        .unwrap()
        .build()
        .unwrap();
    model.driver.advance_to(1.0).unwrap();
    let v = model.driver.velocities()[0][0];
    let alpha = 2.0 * ratio * std::f64::consts::TAU * frequency;
    let steps = model.driver.statistics().steps as i32;
    assert_eq!(steps, 1000);
    let discrete = v0 / (1.0 + alpha * dt).powi(steps);
    assert!(
        ((v - discrete) / discrete).abs() < 1e-9,
        "v = {v}, discrete {discrete}"
    );
    let continuous = v0 * (-alpha).exp();
    assert!(
        ((v - continuous) / continuous).abs() < 1e-3,
        "v = {v}, exp {continuous}"
    );
    // Undamped, the block keeps its speed.
    let free = text.replace(
        &format!("damping: (ratio: {ratio:?}, frequency: {frequency:?})"),
        "",
    );
    let mut model = Scene::from_str(&free, "free.ron").unwrap().build().unwrap();
    model.driver.advance_to(1.0).unwrap();
    assert!((model.driver.velocities()[0][0] - v0).abs() < 1e-12);
}
