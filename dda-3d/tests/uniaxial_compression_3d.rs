//! Uniaxial compression of one box (reference B7.1 in 3D): a uniform
//! pressure q on the top (four point loads q·A/4 at the top corners), one
//! fixed point at the centre of the base, static mode. Uniform strain is
//! exact: σz = −q, εz = −q/E, εx = εy = νq/E, all else zero.

mod common;

use dda_3d::{FixedPoint, Force, PointLoad, Polyhedra};
use dda_core::Settings;
use nalgebra::{Point3, Rotation3, Vector3};

#[test]
fn a_compressed_box_has_the_exact_stress_and_strain() {
    let (q, e, nu) = (1e3, 1e10, 0.25);
    let (w, d, h) = (1.0, 0.8, 2.0);
    let block = common::boxed(
        Point3::new(0.0, 0.0, h / 2.0),
        Vector3::new(w, d, h),
        Rotation3::identity(),
    );
    let top: Vec<Point3<f64>> = block.vertices()[4..].to_vec();
    let mut system = Polyhedra::new(vec![block], common::rock());
    for p in top {
        system.loads.push(PointLoad {
            block: 0,
            point: p,
            force: Force::Constant(Vector3::new(0.0, 0.0, -q * w * d / 4.0)),
        });
    }
    system.fixed.push(FixedPoint::at(0, Point3::origin()));
    let settings = Settings {
        dt: Some(0.01),
        velocity_ratio: 0.0,
        penalty: Some(1e10),
        ..Settings::default()
    };
    let mut driver = common::driver(system, 30.0, settings);
    driver.advance_to(1.0).unwrap();
    let b = &driver.system.blocks[0];
    let close = |value: f64, expected: f64, what: &str| {
        assert!(
            ((value - expected) / expected).abs() < 1e-6,
            "{what}: {value:e}, expected {expected:e}"
        );
    };
    close(b.stress[2], -q, "σz");
    close(b.strain[2], -q / e, "εz");
    close(b.strain[0], nu * q / e, "εx");
    close(b.strain[1], nu * q / e, "εy");
    for k in [0, 1, 3, 4, 5] {
        assert!(b.stress[k].abs() < 1e-6 * q, "stress {k}: {}", b.stress[k]);
    }
    for k in 3..6 {
        assert!(b.strain[k].abs() < 1e-6 * q / e, "shear strain {k}");
    }
    assert!(b.rotation.norm() < 1e-12, "symmetric loads turn nothing");
    // The volume changes by the strain: (1 − q/E)(1 + νq/E)².
    let ratio = b.volume() / (w * d * h);
    let expected = (1.0 - q / e) * (1.0 + nu * q / e).powi(2);
    assert!((ratio - expected).abs() < 1e-12);
}
