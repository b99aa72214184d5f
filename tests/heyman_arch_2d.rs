//! Heyman's minimum thickness of a semicircular arch (reference B4): with
//! 25 voussoirs, φ = 35° and self-weight, t/R = 1.05 × 0.1074 stands and
//! t/R = 0.95 × 0.1074 collapses through hinges at the crown, the haunches
//! (about 54.5° from the crown) and the springings.

use dda::scene::Scene;
use dda_core::ContactState;

mod common;

const R: f64 = 10.0;
const N: usize = 25;

/// The keystone: voussoirs are numbered from the left springing.
const CROWN: usize = N / 2;

#[test]
fn arch_five_percent_above_the_minimum_stands() {
    let rows = common::run_example("arch_heyman_2d.ron");
    let start = common::at(&rows, CROWN, 0.0);
    let end = common::at(&rows, CROWN, 2.0);
    assert!((end.time - 2.0).abs() < 1e-12);
    let moved = common::distance(start, end);
    assert!(moved < 1e-3 * R, "the crown moved {moved:e} m");
}

/// Angle from the crown (degrees) of the joint between voussoirs k and k + 1
/// (joint k + 1 of N + 1, the springings being joints 0 and N).
fn joint_angle_from_crown(joint: usize) -> f64 {
    (90.0 - 180.0 * joint as f64 / N as f64).abs()
}

#[test]
fn arch_five_percent_below_the_minimum_collapses_through_hinges() {
    let scene = Scene::load(common::example("arch_heyman_collapse_2d.ron")).unwrap();
    let mut model = scene.build().unwrap();
    let y0 = model.driver.system.blocks[CROWN].centroid().y;
    let drop = |m: &dda::Model| y0 - m.driver.system.blocks[CROWN].centroid().y;

    // The mechanism: joints where one side has opened (a hinge) while the
    // arch is still whole, a few tenths of a second into the collapse.
    model.driver.advance_to(0.5).unwrap();
    let early = drop(&model);
    let mut hinges: Vec<usize> = Vec::new();
    for joint in 0..=N {
        // Joint j lies between voussoir j − 1 and j; the abutments (blocks N
        // and N + 1) hold the springings, joints 0 and N.
        let (a, b) = match joint {
            0 => (N, 0),
            j if j == N => (N - 1, N + 1),
            j => (j - 1, j),
        };
        let states: Vec<ContactState> = model
            .driver
            .contacts()
            .iter()
            .filter(|c| {
                (c.blocks[0] == a && c.blocks[1] == b) || (c.blocks[0] == b && c.blocks[1] == a)
            })
            .map(|c| c.record.state)
            .collect();
        let open = states.contains(&ContactState::Open);
        let closed = states.iter().any(|s| s.is_closed());
        if open && closed {
            hinges.push(joint);
        }
    }
    let angles: Vec<f64> = hinges.iter().map(|&j| joint_angle_from_crown(j)).collect();
    let near = |target: f64, within: f64| angles.iter().any(|a| (a - target).abs() <= within);
    assert!(
        (4..=7).contains(&hinges.len()),
        "hinges at {angles:?} degrees from the crown"
    );
    // Joints are 7.2° apart: the nearest ones to each hinge of the mechanism.
    assert!(near(3.6, 0.1), "a hinge beside the keystone: {angles:?}");
    assert!(
        angles.iter().filter(|a| (*a - 54.5).abs() <= 4.0).count() == 2,
        "hinges at both haunches: {angles:?}"
    );
    assert!(
        angles.iter().filter(|a| (*a - 90.0).abs() <= 0.1).count() >= 1,
        "a springing hinge: {angles:?}"
    );

    // And the crown keeps dropping.
    model.driver.advance_to(1.0).unwrap();
    let later = drop(&model);
    model.driver.advance_to(1.5).unwrap();
    let latest = drop(&model);
    assert!(
        early > 1e-3 * R && later > 2.0 * early && latest > later,
        "crown drop {early} → {later} → {latest} m"
    );

    // Through the whole collapse, debris included, every step converges.
    model.driver.advance_to(model.duration).unwrap();
    let stats = model.driver.statistics();
    assert_eq!(model.duration, 3.0);
    assert_eq!(stats.unconverged_steps, 0, "{stats:?}");
    println!("{stats:?}");
}
