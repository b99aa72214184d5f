//! A step whose motion the last step foresaw within `WARM_START_MISS`
//! starts its Newton-Raphson moves from that motion instead of at rest
//! (`driver/predict.rs`), its tolerance still a share of its residual at
//! rest. These tests run walls with warm starts and without
//! (`set_warm_starts(false)`).

use dda::bench::{wall, Stepping};
use dda::Scene;
use dda_core::{BlockKind, Statistics};

mod common;
use common::{apart, ran_clean};

/// `scene` (2D, or its 3D model with `three`) run to `end` s, warm starts
/// on or off: the statistics and every block's centroid.
fn run(scene: &Scene, end: f64, three: bool, warm: bool) -> (Statistics, Vec<[f64; 3]>) {
    if three {
        let mut driver = scene.build_3d().unwrap().driver;
        driver.set_warm_starts(warm);
        driver.advance_to(end).unwrap();
        let at = (driver.system.blocks.iter()).map(|b| b.centroid().coords.into());
        (driver.statistics().clone(), at.collect())
    } else {
        let mut driver = scene.build().unwrap().driver;
        driver.set_warm_starts(warm);
        driver.advance_to(end).unwrap();
        let at = (driver.system.blocks.iter()).map(|b| [b.centroid().x, b.centroid().y, 0.0]);
        (driver.statistics().clone(), at.collect())
    }
}

fn report(warm: &Statistics, cold: &Statistics, gap: f64) {
    println!(
        "warm starts {} of {} steps; moves {} against {} at rest, passes {} and {}, factorisations {} and {}; centroids {gap:.2e} m apart",
        warm.warm_starts,
        warm.steps,
        warm.newton_iterations,
        cold.newton_iterations,
        warm.open_close_iterations,
        cold.open_close_iterations,
        warm.factorizations,
        cold.factorizations
    );
}

/// The 3D model of the 40 × 40 deformable wall at dt 1 ms, its first 40
/// steps: 34 of them follow one foreseen within `WARM_START_MISS` whose
/// first pass took three moves or more, and started from their foreseen
/// motion the steps take 247 moves against 324 at rest, in as many passes
/// and factorisations. Both runs solve every step to 1e-10 of the same
/// residual at rest, and end 1.8e-13 m apart. (The rigid wall, used while
/// a half-offset bed joint's springs stood for its overlap twice, with 195
/// moves against 216 in 20 steps, now solves most steps in one move.)
#[test]
fn a_wall_at_dt_1_ms_starts_its_steps_from_their_foreseen_motion() {
    let scene = wall(40, 3, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let end = 0.04 - 1e-9;
    let (warm, at_warm) = run(&scene, end, true, true);
    let (cold, at_cold) = run(&scene, end, true, false);
    let gap = apart(&at_warm, &at_cold);
    report(&warm, &cold, gap);
    assert_eq!(cold.warm_starts, 0);
    assert!(4 * warm.warm_starts >= 3 * warm.steps, "{warm:?}");
    for s in [&warm, &cold] {
        ran_clean(s, 40);
    }
    assert!(
        20 * warm.newton_iterations <= 19 * cold.newton_iterations,
        "{} moves against {}",
        warm.newton_iterations,
        cold.newton_iterations
    );
    assert!(gap < 1e-7, "centroids {gap} m apart");
}

/// The same wall at its automatic step (9.5 ms) for 0.1 s, while it
/// settles: its steps miss their foresight by more than `WARM_START_MISS`,
/// so none starts from it, and the run is the one without warm starts to
/// the last bit.
#[test]
fn a_settling_wall_at_its_automatic_step_starts_at_rest() {
    let scene = wall(20, 2, Stepping::Automatic, BlockKind::Deformable).unwrap();
    let end = 0.1;
    let (warm, at_warm) = run(&scene, end, false, true);
    let (cold, at_cold) = run(&scene, end, false, false);
    report(&warm, &cold, apart(&at_warm, &at_cold));
    assert!(warm.steps >= 10, "{warm:?}");
    assert_eq!(warm.warm_starts, 0);
    assert_eq!(warm.newton_iterations, cold.newton_iterations);
    assert_eq!(at_warm, at_cold);
}
