//! Impacts as impulses (`analysis.restitution`): a block dropped flat
//! onto a fixed base leaves its first impact with e times its striking
//! speed √(2gh), in 2D (two corners strike at once) and 3D (four corners:
//! rows a rigid block cannot tell apart, which share the impulse), at
//! several time steps; with e = 0 its corners close once and stay closed.
//! An impulse never adds energy: it takes (1 − e²) of the kinetic energy.

use dda::scene::Scene;
use dda_core::{BlockSystem, Driver};

/// Drop height of the block's underside above the base, m.
const DROP: f64 = 0.05;
const G: f64 = 9.81;
/// The dropped block's mass: 2700 kg/m³ × 1 m × 0.5 m (× 1 m).
const MASS: f64 = 1350.0;

fn scene_2d(e: f64, dt: f64) -> String {
    format!(
        r#"Scene(
    analysis: (duration: 0.3, dt: {dt}, penalty: 2e10, gravity: (0.0, -{G}), restitution: {e}),
    output: (interval: 0.0),
    materials: {{ "stone": (density: 2700.0, young: 1e11, poisson: 0.25) }},
    default_joint: Coulomb(friction_angle: 40.0),
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, {}), width: 1.0, height: 0.5),
    ],
)"#,
        DROP + 0.25
    )
}

fn scene_3d(e: f64, dt: f64) -> String {
    format!(
        r#"Scene(
    dimension: 3,
    analysis: (duration: 0.3, dt: {dt}, penalty: 2e10, gravity: (0.0, 0.0, -{G}), restitution: {e}),
    output: (interval: 0.0),
    materials: {{ "stone": (density: 2700.0, young: 1e11, poisson: 0.25) }},
    default_joint: Coulomb(friction_angle: 40.0),
    blocks: [
        Box(center: (0.0, 0.0, -0.5), size: (3.0, 3.0, 1.0), fixed: true),
        Box(center: (0.0, 0.0, {}), size: (1.0, 1.0, 0.5)),
    ],
)"#,
        DROP + 0.25
    )
}

/// What the dropped block did: its vertical speed just before and just
/// after the first impact, the steps after it in which a contact of the
/// block changed between open and closed, and the total energy's change
/// (kinetic, gravity, strain, springs) across the impact's step against the
/// energy before it.
struct Drop {
    before: f64,
    after: f64,
    changes_after: usize,
    energy_rise: f64,
}

/// Runs a driver to 0.3 s step by step, reading the dropped block's
/// (block 1) velocity along `up` (1 in 2D, 2 in 3D).
fn drop<S: BlockSystem<N, T>, const N: usize, const T: usize>(
    driver: &mut Driver<S, N, T>,
    up: usize,
) -> Drop {
    // (vertical velocity, closed contacts, impacts so far, total energy)
    let state = |d: &Driver<S, N, T>| {
        let closed = (d.contacts().iter())
            .filter(|c| c.record.state.is_closed())
            .count();
        let stats = d.statistics();
        (d.velocities()[1][up], closed, stats.impacts, stats.energy)
    };
    let (mut before, mut after) = (None, None);
    let mut last = state(driver);
    let (mut changes_after, mut energy_rise) = (0, 0.0);
    while driver.time() < 0.3 - 1e-9 {
        driver.step(0.3 - driver.time()).unwrap();
        let now = state(driver);
        if now.2 > last.2 && before.is_none() {
            before = Some(last.0);
            after = Some(now.0);
            // Against the block's kinetic energy as it strikes (1350 kg,
            // per metre of thickness in 2D).
            energy_rise = (now.3 - last.3) / (0.5 * MASS * last.0 * last.0);
        } else if before.is_some() && now.1 != last.1 {
            changes_after += 1;
        }
        last = now;
    }
    Drop {
        before: before.expect("the block struck the base"),
        after: after.unwrap(),
        changes_after,
        energy_rise,
    }
}

fn drop_2d(e: f64, dt: f64) -> Drop {
    let scene = Scene::from_str(&scene_2d(e, dt), "drop_2d.ron").unwrap();
    drop(&mut scene.build().unwrap().driver, 1)
}

fn drop_3d(e: f64, dt: f64) -> Drop {
    let scene = Scene::from_str(&scene_3d(e, dt), "drop_3d.ron").unwrap();
    drop(&mut scene.build_3d().unwrap().driver, 2)
}

#[test]
fn a_dropped_block_leaves_with_e_times_its_striking_speed_in_2d_and_3d() {
    let striking = (2.0 * G * DROP).sqrt();
    for dt in [1e-3, 5e-4, 2.5e-4] {
        for e in [0.0, 0.5, 1.0] {
            for (dimension, got) in [("2D", drop_2d(e, dt)), ("3D", drop_3d(e, dt))] {
                println!(
                    "{dimension} dt {:.2} ms e {e}: struck at {:.4} m/s (free fall {striking:.4}), left at {:+.4} m/s, {} contact changes after, energy across the impact {:+.2e}",
                    dt * 1e3,
                    -got.before,
                    got.after,
                    got.changes_after,
                    got.energy_rise
                );
                assert!(
                    got.energy_rise <= 1e-12,
                    "{dimension} dt {dt} e {e}: the impact's step added {:+.2e} of the energy",
                    got.energy_rise
                );
                // The step before the impact ends within one step's fall of it.
                assert!(
                    (-got.before - striking).abs() < G * dt + 1e-9,
                    "{dimension} dt {dt} e {e}: struck at {}",
                    -got.before
                );
                // The rebound: e times the speed at the step's start, less the
                // gravity of the rest of that step.
                assert!(
                    (got.after - e * -got.before).abs() < G * dt + 0.01 * striking,
                    "{dimension} dt {dt} e {e}: left at {}, e·u = {}",
                    got.after,
                    e * -got.before
                );
                if e == 0.0 {
                    assert_eq!(
                        got.changes_after, 0,
                        "{dimension} dt {dt}: an inelastic impact ends at once"
                    );
                }
            }
        }
    }
}
