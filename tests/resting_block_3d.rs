//! A 1 m cube on a 30° incline with φ = 35° in 3D, through the scene
//! format: friction holds it; it may only settle into the contact springs.

use dda::read_history_3d;
use nalgebra::Vector3;

mod common;

#[test]
fn the_cube_stays_put_when_friction_exceeds_the_slope() {
    let out = common::out_dir("resting-3d");
    dda::run::run(&common::example("resting_block_3d.ron"), &out).unwrap();
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let at = |t: f64| {
        let r = rows
            .iter()
            .find(|r| r.block == 1 && (r.time - t).abs() < 1e-9)
            .expect("an output at t");
        Vector3::from(r.position)
    };
    let moved = (at(2.0) - at(0.0)).norm();
    let creep = (at(2.0) - at(1.0)).norm();
    assert!(moved < 1e-4, "moved {moved:e} m in 2 s");
    assert!(creep < 1e-7, "crept {creep:e} m between 1 s and 2 s");
}
