//! Step control of the driver: cuts when open-close iterations do not
//! agree or a point moves too far, and penalty raises when penetration is
//! too deep; each leaves an accurate, accepted step.

use dda::scene::Scene;

fn drop_scene(extra: &str) -> String {
    format!(
        r#"Scene(
    analysis: (duration: 0.3, dt: 0.01, gravity: (0.0, -9.81), {extra}),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, angle: 0.0, fixed: true),
        Rectangle(center: (0.0, 0.55), width: 1.0, height: 1.0, angle: 0.0),
    ],
)"#
    )
}

fn run(extra: &str) -> dda::Model {
    let scene = Scene::from_str(&drop_scene(extra), "drop.ron").unwrap();
    let mut model = scene.build().unwrap();
    model.driver.advance_to(model.duration).unwrap();
    model
}

#[test]
fn a_step_whose_contacts_do_not_settle_is_cut_to_a_third() {
    // With one pass allowed, a step in which a contact changes state
    // unforeseen cannot agree: the first, in which the block, resting on
    // its base, is thrown up at 1 m/s, is cut to a third down to the floor
    // (1/1000 of dt: six cuts, as 3^6 < 1000 < 3^7), then accepted and
    // reported as unconverged. The steps of its flight are foreseen from
    // the steps before them. (A dropped block's landing, foreseen now, used
    // to be such a step.)
    let text = drop_scene("open_close_limit: 1, penalty: 2e10")
        .replace("duration: 0.3", "duration: 0.05")
        .replace("(0.0, 0.55)", "(0.0, 0.5)")
        .replace(
            "angle: 0.0),\n    ]",
            "angle: 0.0, velocity: (0.0, 1.0, 0.0)),\n    ]",
        );
    assert!(text.contains("velocity"), "{text}");
    let scene = Scene::from_str(&text, "throw.ron").unwrap();
    let mut model = scene.build().unwrap();
    model.driver.advance_to(model.duration).unwrap();
    let stats = model.driver.statistics();
    assert!(stats.unconverged_steps > 0, "{stats:?}");
    assert_eq!(
        stats.open_close_cuts,
        6 * stats.unconverged_steps,
        "{stats:?}"
    );
    // The block still cannot pass through the base (top of base at y = 0).
    let y = model.driver.system.blocks[1].centroid().y;
    assert!(y > 0.49, "centroid at {y}");
}

#[test]
fn a_step_that_moves_too_far_is_cut() {
    // The length scale is half the model diagonal, 2.25 m: 0.1 % of it is
    // 2.25 mm, less than the block falls in one 10 ms step near landing.
    let model = run("max_displacement_ratio: 0.001, penalty: 2e10");
    let stats = model.driver.statistics();
    assert!(stats.displacement_cuts > 0, "{stats:?}");
    assert!(stats.steps > 30, "more, shorter steps: {}", stats.steps);
}

#[test]
fn too_deep_a_penetration_raises_the_penalty() {
    // A soft penalty lets the block sink 1.3 mm, beyond 1e-4 of the model size.
    let model = run("penalty: 2e7, max_penetration_ratio: 1e-4, raise_penalty: true");
    let stats = model.driver.statistics();
    assert!(stats.penalty_raises > 0, "{stats:?}");
    assert!(model.driver.penalty() >= 2e8);
    let y = model.driver.system.blocks[1].centroid().y;
    assert!(
        (0.5 - y) < 2.6e-4,
        "penetration after the raise: {}",
        0.5 - y
    );
}
