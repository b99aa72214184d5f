//! Contact springs stand for the length (2D) or area (3D) they represent:
//! a 1 m × 2 m column standing on a base settles by W / (p·B) into its
//! joint in 2D, and its extruded prism, whatever its depth, by the same
//! amount within 2 %.

use dda::extrude::extrude;
use dda::{AnyModel, Scene, Simulation};

const SCENE: &str = r#"Scene(
    analysis: (duration: 1.0, dt: 0.002, mode: Static, penalty: 2e10, gravity: (0.0, -9.81)),
    materials: { "stone": (density: 2500.0, young: 1e12, poisson: 0.2) },
    default_joint: Coulomb(friction_angle: 40.0),
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, 1.0), width: 1.0, height: 2.0),
    ],
)"#;

/// The column's settlement into its joint after 1 s of static relaxation:
/// its drop less the base's (the base sinks a little into the springs of
/// its fixed points, which differ between 2D and 3D).
fn settlement(scene: &Scene) -> f64 {
    fn run<S: Simulation>(d: &mut S, vertical: usize) -> f64 {
        let height = |d: &S| d.history_values(1)[vertical] - d.history_values(0)[vertical];
        let start = height(d);
        d.advance_to(1.0).unwrap();
        start - height(d)
    }
    match scene.build_any().unwrap() {
        AnyModel::Plane(mut m) => run(&mut m.driver, 1),
        AnyModel::Space(mut m) => run(&mut m.driver, 2),
    }
}

#[test]
fn a_column_and_its_extruded_prism_settle_alike_at_any_depth() {
    let plane = Scene::from_str(SCENE, "column.ron").unwrap();
    // Weight per unit thickness over the penalty per unit length times the
    // 1 m base (the very stiff stone adds 1 % of its own).
    let expected = 2500.0 * 9.81 * 2.0 / (2e10 * 1.0);
    let flat = settlement(&plane);
    assert!(
        (flat / expected - 1.0).abs() < 0.02,
        "2D settled {flat:e} m, W/(pB) = {expected:e} m"
    );
    for depth in [0.2, 1.0, 4.0] {
        let prism = settlement(&extrude(&plane, depth).unwrap());
        println!("depth {depth} m: 3D {prism:e} m, 2D {flat:e} m");
        assert!(
            (prism / flat - 1.0).abs() < 0.02,
            "{depth} m deep: settled {prism:e} m, 2D {flat:e} m"
        );
    }
}
