//! The driver's energy check: in a scene no load or moving support works
//! on, Newmark (β = 1/2, γ = 1) and friction only dissipate, so the total
//! energy must not rise. Scenes that behave report no rise; a scene where
//! the method injects energy (the penalty raised under an existing
//! overlap) is reported instead of passing silently.

use dda::scene::Scene;

mod common;

fn run(scene: Scene) -> dda_core::Statistics {
    let mut model = scene.build().unwrap();
    model.driver.advance_to(model.duration).unwrap();
    model.driver.statistics().clone()
}

#[test]
fn dissipative_examples_report_no_energy_rise() {
    for name in [
        "sliding_block_2d.ron",
        "resting_block_2d.ron",
        "stacked_blocks_2d.ron",
        "free_fall_2d.ron",
        "spinning_block_2d.ron",
    ] {
        let stats = run(Scene::load(common::example(name)).unwrap());
        assert!(stats.energy_scale > 0.0, "{name}: the energy is tracked");
        assert_eq!(
            stats.energy_growth_steps, 0,
            "{name}: energy rose by {:e} J (scale {:e} J)",
            stats.energy_growth, stats.energy_scale
        );
    }
}

#[test]
fn energy_injected_by_a_penalty_raise_is_reported() {
    // A block set down on a base with a soft penalty: it sinks past the
    // penetration limit and the driver raises the penalty tenfold under the
    // existing overlap, multiplying the energy stored in it.
    let text = r#"Scene(
    analysis: (duration: 0.3, dt: 0.001, gravity: (0.0, -9.81), penalty: 1e6,
               raise_penalty: true, max_penetration_ratio: 1e-3),
    materials: { "rock": (density: 2700.0, young: 1e10, poisson: 0.25) },
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, 0.5), width: 1.0, height: 1.0),
    ],
)"#;
    let stats = run(Scene::from_str(text, "raise.ron").unwrap());
    assert!(stats.penalty_raises > 0, "{stats:?}");
    assert!(
        stats.energy_growth_steps > 0,
        "the rise goes unreported: {stats:?}"
    );
    assert!(stats.energy_growth > 1e-3 * stats.energy_scale);
}
