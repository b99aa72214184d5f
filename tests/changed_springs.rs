//! A later open-close pass on a large factor moves on the factor at hand,
//! with the springs that came, went or changed since it was made applied
//! as rank-one terms (the Sherman-Morrison-Woodbury formula), instead of
//! factorising anew. These tests run walls on a solver posing as large,
//! with the rule and without it (`set_changed_springs(0)`): the same
//! passes and moves, fewer factorisations, the same wall.

use dda::bench::{wall, Stepping};
use dda::Scene;
use dda_core::solve::SparseCholesky;
use dda_core::{BlockKind, Statistics};
use std::sync::{Arc, Mutex};

mod common;
use common::LargeLogged;

/// A solver posing as large, writing down what it is asked.
fn large() -> (Box<LargeLogged>, Arc<Mutex<String>>) {
    let log = Arc::new(Mutex::new(String::new()));
    let solver = LargeLogged {
        solver: SparseCholesky::default(),
        log: log.clone(),
    };
    (Box::new(solver), log)
}

/// `scene` (2D, or 3D with `three`) for `steps` steps of 1 ms on a solver
/// posing as large, applying at most `limit` rank-one terms: the
/// statistics, the blocks' centroids (x, y, z) and the solver's log.
fn run(
    scene: &Scene,
    steps: usize,
    three: bool,
    limit: usize,
) -> (Statistics, Vec<[f64; 3]>, String) {
    let (solver, log) = large();
    let end = steps as f64 * 1e-3 - 1e-9;
    let (stats, centroids) = if three {
        let mut driver = scene.build_3d().unwrap().driver.with_solver(solver);
        driver.set_changed_springs(limit);
        driver.advance_to(end).unwrap();
        let at = driver
            .system
            .blocks
            .iter()
            .map(|b| b.centroid().coords.into());
        (driver.statistics().clone(), at.collect())
    } else {
        let mut driver = scene.build().unwrap().driver.with_solver(solver);
        driver.set_changed_springs(limit);
        driver.advance_to(end).unwrap();
        let at = (driver.system.blocks.iter()).map(|b| [b.centroid().x, b.centroid().y, 0.0]);
        (driver.statistics().clone(), at.collect())
    };
    let log = log.lock().unwrap().clone();
    (stats, centroids, log)
}

/// The largest distance between two runs' centroids, m.
fn apart(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    (a.iter().zip(b))
        .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

/// Both runs took every step, none cut or accepted unconverged, in the
/// same open-close passes.
fn alike(on: &Statistics, off: &Statistics, steps: usize) {
    for s in [on, off] {
        assert_eq!(s.steps, steps);
        assert_eq!(s.open_close_cuts, 0);
        assert_eq!(s.unconverged_steps, 0);
        assert_eq!(s.newton_failures, 0);
    }
    assert_eq!(on.open_close_iterations, off.open_close_iterations);
}

/// The 10 × 10 deformable wall settling at dt 1 ms for 0.3 s: of its 77
/// later passes, 50 start with at most 32 rank-one terms. Each of those
/// makes no factorisation (320 → 272 in all), in as many moves (1,751 →
/// 1,750), and the wall ends 2.5e-14 m from where a new factor at every
/// later pass leaves it. A wrong term (its sign turned) makes the moves
/// on such a factor fall short, and the pass factorises after all.
#[test]
fn a_later_pass_moves_on_the_factor_with_the_changed_springs() {
    let scene = wall(10, 2, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let steps = 300;
    let (on, at_on, log) = run(&scene, steps, false, 32);
    let (off, at_off, _) = run(&scene, steps, false, 0);
    let gap = apart(&at_on, &at_off);
    println!(
        "with the terms: {} passes so, {} factorisations, {} moves; without: {} and {}; centroids {gap:.2e} m apart",
        on.changed_spring_passes,
        on.factorizations,
        on.newton_iterations,
        off.factorizations,
        off.newton_iterations
    );
    alike(&on, &off, steps);
    assert_eq!(off.changed_spring_passes, 0);
    assert!(on.changed_spring_passes >= 40, "{on:?}");
    // Each such pass's terms solved side by side, once.
    assert_eq!(log.matches('M').count(), on.changed_spring_passes);
    assert!(
        on.factorizations + on.changed_spring_passes * 9 / 10 <= off.factorizations,
        "{} factorisations with the terms, {} without",
        on.factorizations,
        off.factorizations
    );
    assert!(
        on.newton_iterations <= off.newton_iterations + off.newton_iterations / 100,
        "{} moves with the terms, {} without",
        on.newton_iterations,
        off.newton_iterations
    );
    // Both solve each step to a residual of 1e-10 of its first.
    assert!(gap < 1e-12, "centroids {gap} m apart");
}

/// The 3D 10-course rigid wall settling at dt 1 ms for 0.3 s: a sliding
/// contact's friction turns with its slip, so its terms change with each
/// pass, and fewer later passes start so (7 of 95); those make no
/// factorisation (387 → 381), in nine more moves of 2,705, and the wall
/// ends where it would (1.8e-14 m apart).
#[test]
fn a_later_pass_in_3d_moves_on_the_factor_with_the_changed_springs() {
    let scene = wall(10, 3, Stepping::Fixed, BlockKind::Rigid).unwrap();
    let steps = 300;
    let (on, at_on, _) = run(&scene, steps, true, 32);
    let (off, at_off, _) = run(&scene, steps, true, 0);
    let gap = apart(&at_on, &at_off);
    println!(
        "with the terms: {} passes so, {} factorisations, {} moves; without: {} and {}; centroids {gap:.2e} m apart",
        on.changed_spring_passes,
        on.factorizations,
        on.newton_iterations,
        off.factorizations,
        off.newton_iterations
    );
    alike(&on, &off, steps);
    assert!(on.changed_spring_passes >= 5, "{on:?}");
    assert!(on.factorizations + 5 <= off.factorizations);
    // Measured: 2,714 moves against 2,705; with a wrong term, 2,731.
    assert!(on.newton_iterations <= off.newton_iterations + 15);
    assert!(gap < 1e-12, "centroids {gap} m apart");
}
