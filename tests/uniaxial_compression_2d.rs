//! Uniaxial compression of one block (reference B7.1): the uniform-strain
//! block is exact, σy = −q, σx = τxy = 0, and the strains follow plane
//! stress or plane strain elasticity.

use dda::scene::Scene;
use dda_2d::Plane;

mod common;

const Q: f64 = 1e3; // two 500 N loads on a 1 m wide top
const E: f64 = 1e10;
const NU: f64 = 0.25;

fn compress(plane: Plane) -> (nalgebra::Vector3<f64>, nalgebra::Vector3<f64>) {
    let mut scene = Scene::load(common::example("uniaxial_compression_2d.ron")).unwrap();
    scene.analysis.plane = plane;
    let mut model = scene.build().unwrap();
    model.driver.advance_to(model.duration).unwrap();
    let block = &model.driver.system.blocks[0];
    (block.stress, block.strain)
}

fn close(value: f64, expected: f64, what: &str) {
    assert!(
        ((value - expected) / expected).abs() < 1e-6,
        "{what}: {value:e}, expected {expected:e}"
    );
}

#[test]
fn plane_stress_block_has_the_exact_stress_and_strain() {
    let (stress, strain) = compress(Plane::Stress);
    close(stress.y, -Q, "σy");
    assert!(
        stress.x.abs() < 1e-6 * Q && stress.z.abs() < 1e-6 * Q,
        "σx, τxy: {stress}"
    );
    close(strain.y, -Q / E, "εy");
    close(strain.x, NU * Q / E, "εx");
    assert!(strain.z.abs() < 1e-6 * Q / E);
}

#[test]
fn plane_strain_block_has_the_exact_stress_and_strain() {
    let (stress, strain) = compress(Plane::Strain);
    close(stress.y, -Q, "σy");
    assert!(
        stress.x.abs() < 1e-6 * Q && stress.z.abs() < 1e-6 * Q,
        "σx, τxy: {stress}"
    );
    close(strain.y, -(1.0 - NU * NU) * Q / E, "εy");
    close(strain.x, NU * (1.0 + NU) * Q / E, "εx");
    assert!(strain.z.abs() < 1e-6 * Q / E);
}

#[test]
fn history_reports_the_same_stress() {
    let rows = common::run_example("uniaxial_compression_2d.ron");
    let last = common::at(&rows, 0, 1.0);
    close(last.syy, -Q, "σy in history.csv");
}
