//! A 1 m cube on a 30° incline in 3D (reference B1), through the scene
//! format. With φ = 20° it slides d = ½ g (sin θ − cos θ tan φ) t² =
//! 0.9064 m in the first second, straight down the dip; the incline dips
//! towards the azimuth 35° so the dip is along no axis.

use dda::scene::BlockSpec;
use dda::{read_history_3d, HistoryRow3, Scene};
use nalgebra::{Rotation3, Vector3};

mod common;

/// The history of an example and the down-dip unit vector of its incline
/// (block 0), from the incline's rotation in the file.
fn run(name: &str) -> (Vec<HistoryRow3>, Vector3<f64>) {
    let scene = Scene::load(common::example(name)).unwrap();
    let BlockSpec::Box { rotation, .. } = &scene.blocks[0] else {
        panic!("the incline is a Box");
    };
    let turn = Rotation3::from_scaled_axis(Vector3::from(*rotation).map(f64::to_radians));
    let dip = turn * Vector3::x();
    // The rotation written in the file is Rz(35°)·Ry(30°).
    let (a, t) = (35f64.to_radians(), 30f64.to_radians());
    let expected = Vector3::new(a.cos() * t.cos(), a.sin() * t.cos(), -t.sin());
    assert!((dip - expected).norm() < 1e-12, "dip {dip}");
    let out = common::out_dir(name.trim_end_matches(".ron"));
    dda::run::run(&common::example(name), &out).unwrap();
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    (rows, dip)
}

/// Block 1's displacement from the start to the output nearest `t`.
fn moved(rows: &[HistoryRow3], t: f64) -> Vector3<f64> {
    let at = |time: f64| {
        rows.iter()
            .filter(|r| r.block == 1)
            .min_by(|a, b| (a.time - time).abs().total_cmp(&(b.time - time).abs()))
            .unwrap()
    };
    let (a, b) = (at(0.0), at(t));
    assert!((b.time - t).abs() < 1e-12);
    Vector3::from(b.position) - Vector3::from(a.position)
}

#[test]
fn the_cube_slides_the_analytical_distance_down_the_dip() {
    let (theta, phi, g) = (30f64.to_radians(), 20f64.to_radians(), 9.81);
    let a = g * (theta.sin() - theta.cos() * phi.tan());
    assert!((0.5 * a - 0.9064).abs() < 1e-4, "the reference value");
    let (rows, dip) = run("sliding_block_3d.ron");
    for t in [0.5, 1.0] {
        let d = moved(&rows, t);
        let along = d.dot(&dip);
        let exact = 0.5 * a * t * t;
        assert!(
            ((along - exact) / exact).abs() < 0.01,
            "t = {t}: slid {along:.6} m, exact {exact:.6} m"
        );
        let off = d.angle(&dip).to_degrees();
        assert!(off < 0.5, "t = {t}: {off}° off the dip");
    }
}
