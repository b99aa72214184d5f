//! Free flight: Newmark β = 1/2, γ = 1 integrates constant acceleration
//! exactly, so the centroid follows x0 + v0 t + g t²/2 and the velocity
//! v0 + g t to round-off, for any time step (reference A10, B7.3).

mod common;

use dda_3d::Polyhedra;
use dda_core::Settings;
use nalgebra::{Point3, Rotation3, Vector3};

#[test]
fn a_thrown_block_follows_the_parabola_to_round_off() {
    let block = common::boxed(
        Point3::new(3.0, -2.0, 10.0),
        Vector3::new(1.0, 0.8, 0.6),
        Rotation3::from_euler_angles(0.3, 0.2, -0.5),
    );
    let x0 = block.centroid();
    let mut system = Polyhedra::new(vec![block], common::rock());
    let g = Vector3::new(0.0, 0.0, -common::G);
    system.gravity = g;
    let settings = Settings {
        dt: Some(0.01),
        penalty: Some(1e10),
        // Nothing to hit: let a step move up to 0.2 of the length scale.
        max_displacement_ratio: 0.2,
        ..Settings::default()
    };
    let mut driver = common::driver(system, 30.0, settings);
    let v0 = Vector3::new(1.0, 2.0, 3.0);
    let mut start = dda_core::BlockVector::<12>::zeros();
    start.fixed_rows_mut::<3>(0).copy_from(&v0);
    driver.set_velocity(0, start);
    for t in [0.25, 0.5, 1.0] {
        driver.advance_to(t).unwrap();
        let x = driver.system.blocks[0].centroid();
        let exact = x0 + v0 * t + g * (t * t / 2.0);
        assert!(
            (x - exact).norm() < 1e-9 * exact.coords.norm(),
            "t = {t}: {x} vs {exact}"
        );
        let v = driver.velocities()[0];
        let vexact = v0 + g * t;
        assert!(
            (v.fixed_rows::<3>(0) - vexact).norm() < 1e-9 * vexact.norm(),
            "t = {t}: velocity {}",
            v.fixed_rows::<3>(0)
        );
        assert!(
            v.fixed_rows::<9>(3).norm() < 1e-12,
            "no spin or strain rate"
        );
    }
    assert_eq!(driver.statistics().steps, 100);
    assert!(driver.system.blocks[0].rotation.norm() < 1e-12);
}
