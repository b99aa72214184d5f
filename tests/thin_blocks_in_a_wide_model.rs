//! Regression: bricks thinner than the contact search range (which grows
//! with the model's size) were taken as deeply penetrating the next brick
//! behind one of its edges' lines, and the wall blew apart in its first
//! steps. A running-bond wall on a 40 m base must simply stand.

use dda::scene::Scene;

#[test]
fn a_brick_wall_on_a_wide_base_stands() {
    let text = r#"Scene(
    analysis: (duration: 0.2, dt: 0.001, penalty: 4e9, gravity: (0.0, -9.81)),
    materials: { "brick": (density: 1800.0, young: 5e9, poisson: 0.2) },
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 40.0, height: 1.0, fixed: true),
        Wall(origin: (-2.5, 0.0), length: 5.0, courses: 6, brick_length: 0.5, brick_height: 0.25, bond: Running),
    ],
)"#;
    let scene = Scene::from_str(text, "wall.ron").unwrap();
    let mut model = scene.build().unwrap();
    // The search range (2.5 % of the half diagonal, 0.5 m) is twice a brick's height.
    assert!(2.5 * 0.01 * model.driver.length_scale() > 0.25);
    let start: Vec<_> = model
        .driver
        .system
        .blocks
        .iter()
        .map(|b| b.centroid())
        .collect();
    model.driver.advance_to(model.duration).unwrap();
    let stats = model.driver.statistics();
    assert_eq!(stats.unconverged_steps, 0, "{stats:?}");
    assert_eq!(stats.deep_penetration_steps, 0, "{stats:?}");
    assert_eq!(stats.energy_growth_steps, 0, "{stats:?}");
    for (b, s) in model.driver.system.blocks.iter().zip(&start) {
        let moved = (b.centroid() - s).norm();
        assert!(moved < 1e-4, "a brick moved {moved:e} m");
    }
}
