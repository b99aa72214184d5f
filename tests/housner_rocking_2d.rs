//! Housner's free rocking (reference B3): a 1 m × 4 m block released at
//! half its slenderness angle on a rigid base with high friction. The time
//! to the first impact against the rigid-body answer (3 %), and the first
//! three amplitude ratios against Housner's recursion with
//! r = 1 − 1.5 sin² α, at the penalty (2e10 N/m³), time step (0.5 ms) and
//! inelastic impacts (`restitution: 0.0`) of examples/rocking_column_2d.ron:
//! within 1 %, in 2D and as the extruded prism at any depth.

use dda::extrude::extrude;
use dda::run::{run_scene, RunOptions};
use dda::{read_history_3d, Scene};
use dda_contact::LawRegistry;

mod common;

fn assert_ratios_within_1_percent(model: &str, rotations: &[f64]) {
    let errors = common::housner_ratio_errors(rotations);
    println!("{model}: amplitude ratios against Housner's: {errors:+.4?}");
    for (n, error) in errors.iter().enumerate() {
        assert!(
            error.abs() < 0.01,
            "{model}: ratio {}: {:+.2} %",
            n + 1,
            100.0 * error
        );
    }
}

#[test]
fn rocking_block_impacts_on_time_and_loses_housners_share_each_impact() {
    let rows = common::run_example("rocking_column_2d.ron");
    common::assert_rocks_like_housner(&rows);
    // With impacts as impulses every rebound, not only the first, loses
    // Housner's share.
    let column: Vec<f64> = (rows.iter().filter(|r| r.block == 1))
        .map(|r| r.rotation)
        .collect();
    assert_ratios_within_1_percent("2D", &column);
}

#[test]
fn the_extruded_column_rocks_like_housners_at_any_depth() {
    let plane = Scene::load(common::example("rocking_column_2d.ron")).unwrap();
    for depth in [0.2, 1.0, 4.0] {
        let out = common::out_dir(&format!("rocking-prism-{depth}"));
        let summary = run_scene(
            &extrude(&plane, depth).unwrap(),
            &out,
            RunOptions::default(),
            &LawRegistry::with_builtin(),
        )
        .unwrap();
        assert_eq!(summary.dimension, 3);
        assert_eq!(summary.unconverged_steps, 0);
        let rows = read_history_3d(out.join("history.csv")).unwrap();
        let _ = std::fs::remove_dir_all(&out);
        // 2D (x, y) is 3D (x, z): the 2D counter-clockwise turn about z is
        // a turn about −y.
        let column: Vec<f64> = (rows.iter().filter(|r| r.block == 1))
            .map(|r| -r.rotation[1])
            .collect();
        assert_ratios_within_1_percent(&format!("prism {depth} m deep"), &column);
    }
}
