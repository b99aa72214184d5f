//! A 1 m cube resting on an equal, fixed cube, corner on corner, for 5 s:
//! it settles into the contact springs (its weight over four corners) and
//! then must not drift.

mod common;

use dda_3d::Polyhedra;
use dda_core::Settings;
use nalgebra::{Point3, Rotation3, Vector3};

#[test]
fn a_cube_on_a_cube_stays_put() {
    let lower = common::boxed(
        Point3::new(0.0, 0.0, 0.5),
        Vector3::repeat(1.0),
        Rotation3::identity(),
    );
    let upper = common::boxed(
        Point3::new(0.0, 0.0, 1.5),
        Vector3::repeat(1.0),
        Rotation3::identity(),
    );
    let mut system = Polyhedra::new(vec![lower, upper], common::rock());
    system.gravity = Vector3::new(0.0, 0.0, -common::G);
    system.fix_block(0);
    let penalty = 1e10;
    let settings = Settings {
        dt: Some(2e-3),
        penalty: Some(penalty),
        ..Settings::default()
    };
    let mut driver = common::driver(system, 30.0, settings);
    let start = driver.system.blocks[1].centroid();
    driver.advance_to(1.0).unwrap();
    let one = driver.system.blocks[1].centroid();
    driver.advance_to(5.0).unwrap();
    let five = driver.system.blocks[1].centroid();
    println!("{:?}", driver.statistics());
    // Settling: the weight over four corner springs, plus the fixed
    // points' give under the lower cube.
    let weight = common::ROCK * common::G;
    let settle = start.z - five.z;
    assert!(
        settle > 0.0 && settle < 2.0 * weight / (4.0 * penalty) + 1e-6,
        "settled {settle:e}"
    );
    let drift = (five - start).norm();
    assert!(drift < 1e-4, "drifted {drift:e} m (size 1 m)");
    let creep = (five - one).norm();
    assert!(creep < 1e-7, "crept {creep:e} m between 1 s and 5 s");
    assert!(driver.system.blocks[1].rotation.norm() < 1e-6);
}
