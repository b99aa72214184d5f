//! A 1 m cube on a 30° incline (reference B1 in 3D): with φ = 20° it slides
//! d = ½ g (sin θ − cos θ tan φ) t² = 0.9064 m in the first second, straight
//! down the dip; with φ = 35° friction holds it.

mod common;

use dda_3d::{Driver3d, Polyhedra};
use dda_core::Settings;
use nalgebra::{Point3, Rotation3, Vector3};

const THETA: f64 = 30.0;

/// The base (20 m along the dip, 4 m wide, 1 m thick, fixed) and the cube on
/// it, both turned about y so the incline dips towards +x. Returns the driver
/// and the down-dip unit vector.
fn incline(phi: f64, azimuth: f64) -> (Driver3d, Vector3<f64>) {
    // Turn about z too, so the dip is not along a coordinate axis.
    let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), azimuth.to_radians())
        * Rotation3::from_axis_angle(&Vector3::y_axis(), THETA.to_radians());
    let normal = turn * Vector3::z();
    let dip = turn * Vector3::x();
    let base = common::boxed(
        Point3::new(1.0, 2.0, -3.0),
        Vector3::new(20.0, 4.0, 1.0),
        turn,
    );
    let centre = Point3::new(1.0, 2.0, -3.0) + normal * 1.0 - dip * 4.0;
    let cube = common::boxed(centre, Vector3::repeat(1.0), turn);
    let mut system = Polyhedra::new(vec![base, cube], common::rock());
    system.gravity = Vector3::new(0.0, 0.0, -common::G);
    system.fix_block(0);
    let settings = Settings {
        dt: Some(1e-3),
        penalty: Some(1e10),
        ..Settings::default()
    };
    (common::driver(system, phi, settings), dip)
}

#[test]
fn cube_slides_the_analytical_distance_down_the_dip() {
    let (theta, phi, g) = (THETA.to_radians(), 20f64.to_radians(), common::G);
    let a = g * (theta.sin() - theta.cos() * phi.tan());
    assert!((0.5 * a - 0.9064).abs() < 1e-4, "the reference value");
    let (mut driver, dip) = incline(20.0, 35.0);
    let start = driver.system.blocks[1].centroid();
    let range = 0.025 * driver.length_scale();
    let found = dda_core::BlockSystem::find_contacts(&driver.system, range);
    assert_eq!(found.len(), 4, "one contact per corner of the cube's base");
    for t in [0.5, 1.0] {
        driver.advance_to(t).unwrap();
        let moved = driver.system.blocks[1].centroid() - start;
        let along = moved.dot(&dip);
        let exact = 0.5 * a * t * t;
        assert!(
            ((along - exact) / exact).abs() < 0.01,
            "t = {t}: slid {along:.6} m, exact {exact:.6} m"
        );
        let off = common::angle(&moved, &dip);
        assert!(off < 0.5, "t = {t}: {off}° off the dip");
    }
    let stats = driver.statistics();
    println!("{stats:?}");
}

/// The uphill corners carry little normal force and slip while the
/// downhill ones hold. The core driver turns a sliding contact's friction
/// towards each step's own slip; in 3D that direction wanders in the plane
/// with tiny vibrations, so the friction forces stop balancing and the cube
/// creeps by millimetres. Turning it towards the trial shear stretch
/// (carried + this step, the return mapping) keeps the cube within 3.3e-5 m
/// and stops the creep; that is a dda-core change, not yet made.
#[test]

fn cube_stays_put_when_friction_exceeds_the_slope() {
    let (mut driver, _) = incline(35.0, 35.0);
    let start = driver.system.blocks[1].centroid();
    driver.advance_to(1.0).unwrap();
    let one = driver.system.blocks[1].centroid();
    driver.advance_to(2.0).unwrap();
    let two = driver.system.blocks[1].centroid();
    let moved = (two - start).norm();
    let creep = (two - one).norm();
    println!(
        "moved {moved:e}, crept {creep:e}, {:?}",
        driver.statistics()
    );
    assert!(moved < 1e-4, "moved {moved:e} m in 2 s");
    assert!(creep < 1e-7, "crept {creep:e} m between 1 s and 2 s");
}
