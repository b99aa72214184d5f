//! Large rotation (reference A8, B6): a free cube spinning at ω = 1 rad/s
//! with ω·Δt = 0.01 for one revolution, about z and about a skew axis. The
//! exact-rotation update keeps the volume and the shape and sweeps exactly
//! ω·t; Shi's linear update inflates the volume by (1 + (ωΔt)²) per step.

mod common;

use std::f64::consts::TAU;

use dda_3d::{Driver3d, Polyhedra, RotationUpdate};
use dda_core::{BlockVector, Settings};
use nalgebra::{Point3, Rotation3, Unit, Vector3};

fn spinning(axis: Unit<Vector3<f64>>, update: RotationUpdate) -> Driver3d {
    let block = common::boxed(
        Point3::new(3.0, 4.0, 5.0),
        Vector3::repeat(1.0),
        Rotation3::identity(),
    );
    let mut system = Polyhedra::new(vec![block], common::rock());
    system.rotation_update = update;
    let settings = Settings {
        dt: Some(0.01),
        penalty: Some(1e10),
        // A corner moves 1 % of the length scale per step: do not cut.
        max_displacement_ratio: 0.05,
        ..Settings::default()
    };
    let mut driver = common::driver(system, 30.0, settings);
    let mut v = BlockVector::<12>::zeros();
    v.fixed_rows_mut::<3>(3).copy_from(&axis.into_inner());
    driver.set_velocity(0, v);
    driver
}

fn revolve_exactly(axis: Unit<Vector3<f64>>) {
    let mut driver = spinning(axis, RotationUpdate::Exact);
    let block = &driver.system.blocks[0];
    let (volume, c) = (block.volume(), block.centroid());
    let start: Vec<Point3<f64>> = block.vertices().to_vec();
    for t in [1.0, 2.5, 4.0, TAU] {
        driver.advance_to(t).unwrap();
        let block = &driver.system.blocks[0];
        let turned = Rotation3::from_axis_angle(&axis, t);
        assert!(
            (block.volume() / volume - 1.0).abs() < 1e-9,
            "t = {t}: volume drift {:e}",
            block.volume() / volume - 1.0
        );
        assert!((block.centroid() - c).norm() < 1e-12, "the centroid stays");
        for (v, s) in block.vertices().iter().zip(&start) {
            assert!(
                ((v - c).norm() / (s - c).norm() - 1.0).abs() < 1e-9,
                "distance to the centroid"
            );
            assert!(
                (v - (c + turned * (s - c))).norm() < 1e-9,
                "t = {t}: vertex off the rigid rotation by {:e}",
                (v - (c + turned * (s - c))).norm()
            );
        }
        // The accumulated rotation vector is the swept angle about the axis,
        // reduced to [0, π].
        // Compared as matrices: angle_to takes acos of a value round-off can
        // push past 1 when the two agree.
        let swept = (block.orientation().matrix() - turned.matrix()).norm();
        assert!(swept < 1e-9, "t = {t}: rotation off by {swept:e}");
        let angle = block.rotation.norm();
        let reduced = if t % TAU <= std::f64::consts::PI {
            t % TAU
        } else {
            TAU - t % TAU
        };
        assert!((angle - reduced).abs() < 1e-9, "t = {t}: angle {angle}");
        assert!(block.strain.norm() < 1e-12 && block.stress.norm() < 1e-3);
    }
    assert!(
        driver.system.blocks[0].rotation.norm() < 1e-9,
        "a full turn"
    );
    assert_eq!(driver.statistics().steps, 629, "ω·Δt stayed 0.01");
}

#[test]
fn exact_update_spins_rigidly_about_z() {
    revolve_exactly(Vector3::z_axis());
}

#[test]
fn exact_update_spins_rigidly_about_a_skew_axis() {
    revolve_exactly(Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0)));
}

#[test]
fn linear_update_inflates_the_volume_as_predicted() {
    let axis = Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0));
    let mut driver = spinning(axis, RotationUpdate::Linear);
    let volume = driver.system.blocks[0].volume();
    driver.advance_to(TAU).unwrap();
    let drift = driver.system.blocks[0].volume() / volume - 1.0;
    // det(I + [r]×) = 1 + |r|²: steps of 0.01 rad do not fill the turn,
    // which is taken in 629 equal steps of 2π/629 = 0.0099893 rad.
    let h = TAU / 629.0;
    let predicted = (1.0 + h * h).powi(629) - 1.0;
    assert!(
        ((drift - predicted) / predicted).abs() < 1e-6,
        "drift {drift} vs {predicted}"
    );
    assert!(
        drift > 0.064,
        "the linear update visibly inflates the block"
    );
}
