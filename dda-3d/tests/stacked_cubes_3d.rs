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
        // The penalty is per unit area of the 1 m² joint.
        settle > 0.0 && settle < 2.0 * weight / (penalty * 1.0) + 1e-6,
        "settled {settle:e}"
    );
    let drift = (five - start).norm();
    assert!(drift < 1e-4, "drifted {drift:e} m (size 1 m)");
    let creep = (five - one).norm();
    assert!(creep < 1e-7, "crept {creep:e} m between 1 s and 5 s");
    assert!(driver.system.blocks[1].rotation.norm() < 1e-6);
}

/// Offset by (0.3, 0.3): the overlap is a 0.7 m square whose corners are a
/// corner of each cube (vertex-face contacts) and two crossings of their
/// edges (edge-edge contacts). The upper cube's centroid lies over the
/// overlap, so it must stand on those four contacts.
#[test]
fn an_offset_cube_stands_on_vertex_face_and_edge_edge_contacts() {
    let lower = common::boxed(
        Point3::new(0.0, 0.0, 0.5),
        Vector3::repeat(1.0),
        Rotation3::identity(),
    );
    let upper = common::boxed(
        Point3::new(0.3, 0.3, 1.5),
        Vector3::repeat(1.0),
        Rotation3::identity(),
    );
    let mut system = Polyhedra::new(vec![lower, upper], common::rock());
    system.gravity = Vector3::new(0.0, 0.0, -common::G);
    system.fix_block(0);
    let settings = Settings {
        dt: Some(2e-3),
        penalty: Some(1e10),
        ..Settings::default()
    };
    let mut driver = common::driver(system, 30.0, settings);
    let range = 0.025 * driver.length_scale();
    let found = dda_core::BlockSystem::find_contacts(&driver.system, range);
    let mut labels: Vec<String> = found
        .iter()
        .map(|c| dda_3d::contact_label(&c.key))
        .collect();
    labels.sort();
    let edges = labels.iter().filter(|l| l.starts_with("0:e")).count();
    let corners = labels
        .iter()
        .filter(|l| l.ends_with("/0:f1") || l.ends_with("/1:f0"))
        .count();
    assert_eq!((found.len(), edges, corners), (4, 2, 2), "{labels:?}");
    let start = driver.system.blocks[1].centroid();
    driver.advance_to(1.0).unwrap();
    let one = driver.system.blocks[1].centroid();
    driver.advance_to(2.0).unwrap();
    let two = driver.system.blocks[1].centroid();
    let drift = (two - start).norm();
    assert!(drift < 1e-4, "drifted {drift:e} m");
    assert!(
        (two - one).norm() < 1e-7,
        "crept {:e} m",
        (two - one).norm()
    );
    // All four contacts carry the weight between them.
    let total: f64 = driver
        .contacts()
        .iter()
        .map(|c| c.record.normal_force)
        .sum();
    let weight = common::ROCK * common::G;
    assert!(
        ((total - weight) / weight).abs() < 1e-3,
        "contacts carry {total} N of {weight} N"
    );
    for c in driver.contacts() {
        assert!(
            c.record.normal_force > 0.0,
            "{} carries nothing",
            dda_3d::contact_label(&c.key)
        );
    }
}
