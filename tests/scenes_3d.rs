//! 3D scene features end to end: ground motion, driven points, load
//! histories, joint sets and custom laws, contacts.csv.

use dda::{read_contacts, read_history_3d, Scene};
use dda_contact::{Coulomb, LawRegistry, Params};
use dda_core::GroundMotion;
use nalgebra::Vector3;

mod common;

/// A fixed 4 m × 4 m × 1 m slab with a 1 m cube on it, `extra` fields
/// added to the scene.
fn slab_and_cube(extra: &str) -> String {
    format!(
        r#"Scene(
    dimension: 3,
    analysis: (duration: 1.0, dt: 0.002, penalty: 1e10),
    output: (interval: 0.1, contacts: true),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    default_joint: Coulomb(friction_angle: 30.0),
    blocks: [
        Box(center: (0.0, 0.0, -0.5), size: (4.0, 4.0, 1.0), fixed: true),
        Box(center: (0.0, 0.0, 0.5), size: (1.0, 1.0, 1.0)),
    ],
    {extra}
)"#
    )
}

#[test]
fn the_shaken_slab_follows_the_ground_and_carries_the_cube() {
    // One sine pulse of acceleration: the ground ends at rest, displaced by
    // A T² / (2π).
    let (a, period) = (Vector3::new(1.0, 0.5, 0.0), 0.5);
    let text = slab_and_cube(
        "ground_motion: (blocks: [0], motion: Pulse(amplitude: (1.0, 0.5, 0.0), period: 0.5)),",
    );
    let scene = Scene::from_str(&text, "shaken.ron").unwrap();
    let mut model = scene.build_3d().unwrap();
    let ground = GroundMotion::Pulse {
        amplitude: a,
        period,
    };
    let start: Vec<_> = model
        .driver
        .system
        .blocks
        .iter()
        .map(|b| b.centroid())
        .collect();
    model.driver.advance_to(1.0).unwrap();
    let moved = |k: usize| model.driver.system.blocks[k].centroid() - start[k];
    let expected = ground.displacement(1.0);
    assert!(
        (expected - a * period * period / std::f64::consts::TAU).norm() < 1e-12,
        "{expected}"
    );
    // Peak acceleration 1.1 m/s² < g tan 30°: the cube rides along.
    for k in [0, 1] {
        let off = (moved(k) - expected).norm();
        assert!(
            off < 1e-3 * expected.norm(),
            "block {k} is {off:e} m off the ground"
        );
    }
}

#[test]
fn a_four_column_record_drives_the_slab() {
    let dir = common::out_dir("record-3d");
    std::fs::create_dir_all(&dir).unwrap();
    // Constant velocity (0.1, 0, 0.05) m/s from t = 0.
    std::fs::write(
        dir.join("quake.csv"),
        "time, vx, vy, vz\n0.0, 0.1, 0.0, 0.05\n2.0, 0.1, 0.0, 0.05\n",
    )
    .unwrap();
    let text = slab_and_cube(
        r#"ground_motion: (blocks: [0], motion: Record(path: "quake.csv", quantity: Velocity)),"#,
    );
    std::fs::write(dir.join("scene.ron"), &text).unwrap();
    let summary = dda::run::run(&dir.join("scene.ron"), &dir).unwrap();
    assert_eq!(summary.dimension, 3);
    let rows = read_history_3d(dir.join("history.csv")).unwrap();
    let base: Vec<_> = rows.iter().filter(|r| r.block == 0).collect();
    let (first, last) = (base[0], base[base.len() - 1]);
    let moved = Vector3::from(last.position) - Vector3::from(first.position);
    assert!(
        (moved - Vector3::new(0.1, 0.0, 0.05)).norm() < 1e-4,
        "the slab moved {moved}"
    );
    // The same record read as x and z only (a 2D-style record of `time,
    // vx, vz`) gives the same motion.
    std::fs::write(
        dir.join("quake_xz.csv"),
        "time, vx, vz\n0.0, 0.1, 0.05\n2.0, 0.1, 0.05\n",
    )
    .unwrap();
    let text = text.replace(
        r#"path: "quake.csv""#,
        r#"path: "quake_xz.csv", components: "xz""#,
    );
    std::fs::write(dir.join("scene_xz.ron"), &text).unwrap();
    let mut model = Scene::load(dir.join("scene_xz.ron"))
        .unwrap()
        .build_3d()
        .unwrap();
    let c0 = model.driver.system.blocks[0].centroid();
    model.driver.advance_to(1.0).unwrap();
    let moved_xz = model.driver.system.blocks[0].centroid() - c0;
    assert!((moved_xz - moved).norm() < 1e-12, "{moved_xz} vs {moved}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn driven_points_and_rollers_move_a_free_box() {
    // No gravity; the box is pulled by two driven points at 0.2 m/s along x.
    // A roller (held along z only) at a third corner lets it slide.
    let text = r#"Scene(
        dimension: 3,
        analysis: (duration: 1.0, dt: 0.01, gravity: (0.0, 0.0, 0.0), penalty: 1e10),
        materials: { "rock": (density: 2700.0, young: 1e10) },
        blocks: [ Box(center: (0.0, 0.0, 0.0), size: (1.0, 1.0, 1.0)) ],
        fixed_points: [
            (block: 0, point: (-0.5, -0.5, -0.5), velocity: (0.2, 0.0, 0.0)),
            (block: 0, point: (-0.5, 0.5, -0.5), velocity: (0.2, 0.0, 0.0)),
            (block: 0, point: (0.5, 0.5, -0.5), axis: (0.0, 0.0, 2.0)),
        ],
    )"#;
    let mut model = Scene::from_str(text, "driven.ron")
        .unwrap()
        .build_3d()
        .unwrap();
    let system = &model.driver.system;
    assert_eq!(system.fixed.len(), 3);
    assert_eq!(system.fixed[2].axis, Some(Vector3::z()));
    model.driver.advance_to(1.0).unwrap();
    let c = model.driver.system.blocks[0].centroid();
    assert!((c.x - 0.2).abs() < 1e-6, "x = {}", c.x);
    assert!(c.y.abs() < 1e-6 && c.z.abs() < 1e-6, "{c}");
}

#[test]
fn a_load_history_gives_its_impulse() {
    // A force ramping from 0 to 1 kN along y over 1 s on a free cube:
    // momentum m v ≈ ½ F t.
    let text = r#"Scene(
        dimension: 3,
        analysis: (duration: 1.0, dt: 0.01, gravity: (0.0, 0.0, 0.0),
                   max_displacement_ratio: 0.2),
        materials: { "rock": (density: 2000.0, young: 1e10) },
        blocks: [ Box(center: (0.0, 0.0, 0.0), size: (1.0, 1.0, 1.0)) ],
        loads: [ PointLoad(block: 0, point: (0.0, 0.0, 0.0),
                           history: [(0.0, 0.0, 0.0, 0.0), (1.0, 0.0, 1e3, 0.0)]) ],
    )"#;
    let mut model = Scene::from_str(text, "ramp.ron")
        .unwrap()
        .build_3d()
        .unwrap();
    model.driver.advance_to(1.0).unwrap();
    let v = model.driver.velocities()[0];
    // Newmark with γ = 1 takes each step's force at its end: the impulse is
    // the right Riemann sum of the ramp, ½ F t (1 + Δt/t).
    let (f, m, dt) = (1e3, 2000.0, 0.01);
    let impulse: f64 = (1..=100).map(|k| f * (k as f64 * dt) * dt).sum();
    let expected = impulse / m;
    assert!((expected - 0.5 * f / m * (1.0 + dt)).abs() < 1e-12);
    assert!(((v[1] - expected) / expected).abs() < 1e-9, "vy = {}", v[1]);
    assert!(v[0].abs() < 1e-12 && v[2].abs() < 1e-12);
}

#[test]
fn joint_sets_and_custom_laws_reach_the_3d_contacts() {
    // A frictionless joint set between the slab and the cube, on a slab
    // tilted 10°: the cube slides with a = g sin 10°.
    let text = slab_and_cube(
        r#"joints: [ (blocks: [(0, 1)], law: Custom(name: "slick", params: {})) ],"#,
    )
    .replace(
        "Box(center: (0.0, 0.0, -0.5), size: (4.0, 4.0, 1.0), fixed: true)",
        "Box(center: (0.0, 0.0, -0.5), size: (4.0, 4.0, 1.0), rotation: (0.0, 10.0, 0.0), fixed: true)",
    )
    .replace(
        "Box(center: (0.0, 0.0, 0.5), size: (1.0, 1.0, 1.0))",
        "Box(center: (0.17364817766693033, 0.0, 0.4848077530122081), size: (1.0, 1.0, 1.0), rotation: (0.0, 10.0, 0.0))",
    )
    .replace("duration: 1.0", "duration: 0.5");
    let scene = Scene::from_str(&text, "slick.ron").unwrap();
    let message = scene.build_3d().err().unwrap().to_string();
    assert!(message.contains("joints[0].law"), "{message}");
    let mut registry = LawRegistry::with_builtin();
    registry.register("slick", |_: &mut Params| Ok(Coulomb::frictional(0.0)));
    let mut model = scene.build_3d_with(&registry).unwrap();
    let c0 = model.driver.system.blocks[1].centroid();
    model.driver.advance_to(0.5).unwrap();
    let moved = model.driver.system.blocks[1].centroid() - c0;
    let theta = 10f64.to_radians();
    let exact = 0.5 * 9.81 * theta.sin() * 0.25;
    let dip = Vector3::new(theta.cos(), 0.0, -theta.sin());
    assert!(
        ((moved.dot(&dip) - exact) / exact).abs() < 0.01,
        "slid {} m, exact {exact}",
        moved.dot(&dip)
    );
    // And the run writes 3D contact labels for the pair.
    let dir = common::out_dir("slick-3d");
    let summary =
        dda::run::run_scene(&scene, &dir, dda::run::RunOptions::default(), &registry).unwrap();
    assert_eq!(summary.dimension, 3);
    let contacts = read_contacts(dir.join("contacts.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let sliding: Vec<_> = contacts
        .iter()
        .filter(|c| c.time == 0.5 && c.normal_force > 0.0)
        .collect();
    assert_eq!(sliding.len(), 4, "{sliding:?}");
    for c in sliding {
        assert_eq!(c.state, dda_core::ContactState::Sliding, "{}", c.contact);
        assert_eq!(c.shear_force, 0.0, "frictionless");
    }
}
