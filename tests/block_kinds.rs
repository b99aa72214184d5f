//! Rigid blocks (translation and rotation only) against Shi's deformable
//! ones: every validation case a rigid block can run gives its analytical
//! answer within the tolerance of its own test; a rigid block never strains;
//! rigid and deformable blocks rest on each other; and a rigid block adds
//! half the unknowns of a deformable one to the step's system.

use dda::bench::wall_scene;
use dda::extrude::extrude;
use dda::scene::BlockKind;
use dda::{read_history, read_history_3d, AnyModel, HistoryRow, HistoryRow3, Scene, Simulation};
use nalgebra::{Rotation3, Unit, Vector3};

mod common;

/// An example's text with every material rigid.
fn rigid(name: &str) -> String {
    let text = std::fs::read_to_string(common::example(name)).unwrap();
    assert!(text.contains("(density:"), "{name} has a material");
    text.replace("(density:", "(kind: Rigid, density:")
}

/// Runs scene text as `dda run` does; the 2D history.
fn history(name: &str, text: &str) -> Vec<HistoryRow> {
    let out = common::run_text(name, text);
    let rows = read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    rows
}

/// Runs scene text as `dda run` does; the 3D history.
fn history_3d(name: &str, text: &str) -> Vec<HistoryRow3> {
    let out = common::run_text(name, text);
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    rows
}

/// Block `block`'s centroid at the output nearest `t` (3D).
fn position(rows: &[HistoryRow3], block: usize, t: f64) -> Vector3<f64> {
    let row = rows
        .iter()
        .filter(|r| r.block == block)
        .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))
        .unwrap();
    assert!((row.time - t).abs() < 1e-9, "an output at {t}");
    Vector3::from(row.position)
}

#[test]
fn a_rigid_block_slides_the_analytical_distance_in_2d_and_3d() {
    let (theta, phi, g) = (30f64.to_radians(), 20f64.to_radians(), 9.81);
    let a = g * (theta.sin() - theta.cos() * phi.tan());
    let rows = history("slide-rigid", &rigid("sliding_block_2d.ron"));
    let start = common::at(&rows, 1, 0.0);
    for t in [0.5, 1.0] {
        let now = common::at(&rows, 1, t);
        let (dx, dy) = (now.x - start.x, now.y - start.y);
        let along = -(dx * theta.cos() + dy * theta.sin());
        let exact = 0.5 * a * t * t;
        assert!(
            ((along - exact) / exact).abs() < 0.01,
            "2D, t = {t}: slid {along:.6} m, exact {exact:.6} m"
        );
        let normal = -dx * theta.sin() + dy * theta.cos();
        assert!(normal.abs() < 1e-4, "moved {normal:e} m off the incline");
        assert!([now.sxx, now.syy, now.sxy].iter().all(|s| *s == 0.0));
    }
    // The 3D incline dips 30° towards the azimuth 35°.
    let rows = history_3d("slide-rigid-3d", &rigid("sliding_block_3d.ron"));
    let (az, dip) = (35f64.to_radians(), theta);
    let down = Vector3::new(az.cos() * dip.cos(), az.sin() * dip.cos(), -dip.sin());
    for t in [0.5, 1.0] {
        let d = position(&rows, 1, t) - position(&rows, 1, 0.0);
        let exact = 0.5 * a * t * t;
        let along = d.dot(&down);
        assert!(
            ((along - exact) / exact).abs() < 0.01,
            "3D, t = {t}: slid {along:.6} m, exact {exact:.6} m"
        );
        assert!(d.angle(&down).to_degrees() < 0.5);
    }
}

#[test]
fn a_rigid_block_rests_where_friction_holds_it_in_2d_and_3d() {
    let rows = history("rest-rigid", &rigid("resting_block_2d.ron"));
    let (start, one, two) = (
        common::at(&rows, 1, 0.0),
        common::at(&rows, 1, 1.0),
        common::at(&rows, 1, 2.0),
    );
    assert!((two.time - 2.0).abs() < 1e-12);
    let (moved, creep) = (common::distance(start, two), common::distance(one, two));
    assert!(moved < 1e-4, "2D: moved {moved:e} m in 2 s");
    assert!(creep < 1e-7, "2D: crept {creep:e} m between 1 s and 2 s");
    let rows = history_3d("rest-rigid-3d", &rigid("resting_block_3d.ron"));
    let moved = (position(&rows, 1, 2.0) - position(&rows, 1, 0.0)).norm();
    let creep = (position(&rows, 1, 2.0) - position(&rows, 1, 1.0)).norm();
    assert!(moved < 1e-4, "3D: moved {moved:e} m in 2 s");
    assert!(creep < 1e-7, "3D: crept {creep:e} m between 1 s and 2 s");
}

#[test]
fn a_rigid_wedge_slides_along_the_intersection_or_stays() {
    let (s, along, reactions) = common::reference_wedge();
    let ratio = along - reactions * 20f64.to_radians().tan();
    let rows = history_3d("wedge-rigid", &rigid("wedge_3d.ron"));
    let moved = position(&rows, 1, 1.0) - position(&rows, 1, 0.0);
    let measured = 2.0 * moved.dot(&s) / 9.81;
    assert!(
        ((measured - ratio) / ratio).abs() < 0.02,
        "a/g = {measured}, exact {ratio}"
    );
    assert!(moved.angle(&s).to_degrees() < 0.5);
    let rows = history_3d("wedge-stable-rigid", &rigid("wedge_stable_3d.ron"));
    let moved = (position(&rows, 1, 1.0) - position(&rows, 1, 0.0)).norm();
    assert!(moved < 1e-4, "moved {moved:e} m in 1 s");
}

#[test]
fn a_rigid_block_rocks_like_housners() {
    common::assert_rocks_like_housner(&history("rocking-rigid", &rigid("rocking_column_2d.ron")));
}

/// A 1 m × 2 m column on a fixed base (as tests/column_2d_3d.rs), the
/// column of `column` and the base of `base`.
fn column_scene(base: &str, column: &str) -> Scene {
    let text = format!(
        r#"Scene(
    analysis: (duration: 1.0, dt: 0.002, mode: Static, penalty: 2e10, gravity: (0.0, -9.81)),
    materials: {{ "stone": (density: 2500.0, young: 1e12, poisson: 0.2) }},
    default_joint: Coulomb(friction_angle: 40.0),
    blocks: [
        Rectangle(kind: {base}, center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Rectangle(kind: {column}, center: (0.0, 1.0), width: 1.0, height: 2.0),
    ],
)"#
    );
    Scene::from_str(&text, "column.ron").unwrap()
}

/// The column's settlement into its joint after 1 s of static relaxation,
/// and the largest strain and stress of each block at the end.
fn settle(scene: &Scene) -> (f64, [f64; 2], [f64; 2]) {
    fn run<S: Simulation>(d: &mut S, vertical: usize) -> f64 {
        let height = |d: &S| d.history_values(1)[vertical] - d.history_values(0)[vertical];
        let start = height(d);
        d.advance_to(1.0).unwrap();
        assert_eq!(d.statistics().unconverged_steps, 0);
        start - height(d)
    }
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    match scene.build_any().unwrap() {
        AnyModel::Plane(mut m) => {
            let settled = run(&mut m.driver, 1);
            let b = &m.driver.system.blocks;
            let strain = [0, 1].map(|i| largest(b[i].strain.as_slice()));
            let stress = [0, 1].map(|i| largest(b[i].stress.as_slice()));
            (settled, strain, stress)
        }
        AnyModel::Space(mut m) => {
            let settled = run(&mut m.driver, 2);
            let b = &m.driver.system.blocks;
            let strain = [0, 1].map(|i| largest(b[i].strain.as_slice()));
            let stress = [0, 1].map(|i| largest(b[i].stress.as_slice()));
            (settled, strain, stress)
        }
    }
}

#[test]
fn rigid_and_deformable_columns_settle_alike_on_either_kind_of_base() {
    // W / (p·B), as tests/column_2d_3d.rs (the stiff stone adds 1 %).
    let expected = 2500.0 * 9.81 * 2.0 / (2e10 * 1.0);
    let kinds = [
        ("Deformable", "Deformable"),
        ("Rigid", "Rigid"),
        ("Deformable", "Rigid"),
        ("Rigid", "Deformable"),
    ];
    for (base, column) in kinds {
        let plane = column_scene(base, column);
        for (scene, what) in [
            (plane.clone(), "2D".to_string()),
            (extrude(&plane, 1.0).unwrap(), "3D".to_string()),
        ] {
            let (settled, strain, stress) = settle(&scene);
            let case = format!("{what}, {column} column on a {base} base");
            println!("{case}: settled {settled:e} m, strain {strain:?}, stress {stress:?}");
            assert!(
                (settled / expected - 1.0).abs() < 0.02,
                "{case}: settled {settled:e} m, W/(pB) = {expected:e} m"
            );
            for (k, kind) in [base, column].iter().enumerate() {
                if *kind == "Rigid" {
                    assert_eq!((strain[k], stress[k]), (0.0, 0.0), "{case}: block {k}");
                } else {
                    assert!(strain[k] > 0.0 && stress[k] > 0.0, "{case}: block {k}");
                }
            }
        }
    }
}

#[test]
fn a_rigid_block_falls_on_the_parabola_and_spins_without_drift() {
    let rows = history("fall-rigid", &rigid("free_fall_2d.ron"));
    let first = common::at(&rows, 0, 0.0);
    assert_eq!(rows.len(), 11);
    for r in &rows {
        let y = first.y - 0.5 * 9.81 * r.time * r.time;
        assert!(((r.y - y) / y).abs() < 1e-9, "t = {}: y = {}", r.time, r.y);
        assert!((r.vy + 9.81 * r.time).abs() <= 1e-9 * 9.81 * r.time.max(1.0));
    }
    let rows = history_3d("fall-rigid-3d", &rigid("free_fall_3d.ron"));
    assert_eq!(rows.len(), 5);
    for row in &rows {
        let t = row.time;
        let x = Vector3::new(3.0 + t, -2.0 + 2.0 * t, 10.0 + 3.0 * t - 9.81 * t * t / 2.0);
        assert!((Vector3::from(row.position) - x).norm() < 1e-9 * x.norm());
        assert!(row.stress.iter().all(|s| *s == 0.0));
    }

    // One revolution at ω·Δt = 0.01 keeps the area and the radii.
    let mut scene = Scene::load(common::example("spinning_block_2d.ron")).unwrap();
    scene.materials[0].1.kind = BlockKind::Rigid;
    let mut model = scene.build().unwrap();
    let block = &model.driver.system.blocks[0];
    let (area, c0) = (block.area(), block.centroid());
    let radii: Vec<f64> = block.vertices().iter().map(|v| (v - c0).norm()).collect();
    model.driver.advance_to(model.duration).unwrap();
    let block = &model.driver.system.blocks[0];
    assert!((block.area() / area - 1.0).abs() < 1e-9);
    for (v, r) in block.vertices().iter().zip(&radii) {
        assert!(((v - block.centroid()).norm() / r - 1.0).abs() < 1e-9);
    }
    assert!((block.rotation - std::f64::consts::TAU).abs() < 1e-9);
    assert_eq!(model.driver.statistics().steps, 629);

    // And in 3D about a skew axis, turning rigidly.
    let n = 14f64.sqrt();
    let text = rigid("spinning_block_3d.ron").replace(
        "velocity: (0.0, 0.0, 0.0, 0.0, 0.0, 1.0)",
        &format!(
            "velocity: (0.0, 0.0, 0.0, {:?}, {:?}, {:?})",
            1.0 / n,
            2.0 / n,
            3.0 / n
        ),
    );
    let mut model = Scene::from_str(&text, "spin.ron")
        .unwrap()
        .build_3d()
        .unwrap();
    let block = &model.driver.system.blocks[0];
    let (volume, c) = (block.volume(), block.centroid());
    let start = block.vertices().to_vec();
    model.driver.advance_to(model.duration).unwrap();
    let block = &model.driver.system.blocks[0];
    let axis = Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0));
    let turned = Rotation3::from_axis_angle(&axis, std::f64::consts::TAU);
    let off = block
        .vertices()
        .iter()
        .zip(&start)
        .map(|(v, s)| (v - (c + turned * (s - c))).norm())
        .fold(0.0, f64::max);
    assert!((block.volume() / volume - 1.0).abs() < 1e-9);
    assert!(off < 1e-9, "a corner is {off:e} m off the rigid turn");
}

#[test]
fn a_rigid_arch_stands_above_heymans_minimum() {
    let rows = history("arch-rigid", &rigid("arch_heyman_2d.ron"));
    const CROWN: usize = 12;
    let (start, end) = (common::at(&rows, CROWN, 0.0), common::at(&rows, CROWN, 2.0));
    assert!((end.time - 2.0).abs() < 1e-12);
    let moved = common::distance(start, end);
    assert!(moved < 1e-3 * 10.0, "the crown moved {moved:e} m");
    assert!(rows.iter().all(|r| [r.sxx, r.syy, r.sxy] == [0.0; 3]));
}

#[test]
fn a_rigid_arch_collapses_below_heymans_minimum() {
    // The crown keeps dropping, as in tests/heyman_arch_2d.rs.
    let text = rigid("arch_heyman_collapse_2d.ron");
    let mut model = Scene::from_str(&text, "collapse.ron")
        .unwrap()
        .build()
        .unwrap();
    const CROWN: usize = 12;
    let y0 = model.driver.system.blocks[CROWN].centroid().y;
    let mut drops = Vec::new();
    for t in [0.5, 1.0, 1.5] {
        model.driver.advance_to(t).unwrap();
        drops.push(y0 - model.driver.system.blocks[CROWN].centroid().y);
    }
    assert!(
        drops[0] > 1e-3 * 10.0 && drops[1] > 2.0 * drops[0] && drops[2] > drops[1],
        "crown drop {drops:?} m"
    );
    assert_eq!(model.driver.statistics().unconverged_steps, 0);
}

#[test]
fn a_rigid_block_adds_half_the_unknowns_of_a_deformable_one() {
    let wall = wall_scene(4);
    let mut rigid = wall.clone();
    rigid.materials[0].1.kind = BlockKind::Rigid;
    let blocks = 1 + 4 * 4 + 2;
    for (scene, per_block) in [(&wall, 6), (&rigid, 3)] {
        let mut model = scene.build().unwrap();
        assert_eq!(model.driver.unknowns(), per_block * blocks);
        model.driver.advance_to(0.01).unwrap();
        assert_eq!(model.driver.unknowns(), per_block * blocks);
        assert_eq!(model.driver.statistics().unconverged_steps, 0);
    }
    for (scene, per_block) in [(&wall, 12), (&rigid, 6)] {
        let model = extrude(scene, 0.5).unwrap().build_3d().unwrap();
        assert_eq!(model.driver.unknowns(), per_block * blocks);
    }
}
