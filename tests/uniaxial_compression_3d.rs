//! Uniaxial compression of one box in 3D (reference B7.1) through the
//! scene format: four point loads q·A/4 on the top corners, one fixed point
//! at the middle of the base, static mode. Uniform strain is exact:
//! σz = −q, εz = −q/E, εx = εy = νq/E, all else zero.

use dda::Scene;

mod common;

const Q: f64 = 1e3;
const E: f64 = 1e10;
const NU: f64 = 0.25;

fn close(value: f64, expected: f64, what: &str) {
    assert!(
        ((value - expected) / expected).abs() < 1e-6,
        "{what}: {value:e}, expected {expected:e}"
    );
}

#[test]
fn a_compressed_box_has_the_exact_stress_and_strain() {
    let scene = Scene::load(common::example("uniaxial_compression_3d.ron")).unwrap();
    let mut model = scene.build_3d().unwrap();
    model.driver.advance_to(model.duration).unwrap();
    let b = &model.driver.system.blocks[0];
    close(b.stress[2], -Q, "σz");
    close(b.strain[2], -Q / E, "εz");
    close(b.strain[0], NU * Q / E, "εx");
    close(b.strain[1], NU * Q / E, "εy");
    for k in [0, 1, 3, 4, 5] {
        assert!(b.stress[k].abs() < 1e-6 * Q, "stress {k}: {}", b.stress[k]);
    }
    for k in 3..6 {
        assert!(b.strain[k].abs() < 1e-6 * Q / E, "shear strain {k}");
    }
    assert!(b.rotation.norm() < 1e-12, "symmetric loads turn nothing");
}

#[test]
fn history_reports_the_same_stress() {
    let out = common::out_dir("compression-3d");
    dda::run::run(&common::example("uniaxial_compression_3d.ron"), &out).unwrap();
    let rows = dda::read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let last = rows.last().unwrap();
    assert_eq!(last.time, 1.0);
    close(last.stress[2], -Q, "szz in history.csv");
}
