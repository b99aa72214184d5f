//! A pass whose moves converge linearly reads its contacts' open-close
//! decisions once its residual is 1e-5 of the step's first; where any
//! would change it ends there, and the next pass starts from that iterate
//! instead of one solved to 1e-10 for states it then replaces. These tests
//! run walls with the rule and without it (`set_early_decision(0.0)`): the
//! same passes, fewer moves, the same wall, in symmetric and whole-tangent
//! passes alike.

use dda::bench::{wall, Stepping};
use dda::Scene;
use dda_core::solve::{LinearSolver, SparseCholesky};
use dda_core::{BlockKind, Statistics};
use std::sync::{Arc, Mutex};

mod common;
use common::{apart, LargeLogged};

/// `scene` (2D, or 3D with `three`) for `steps` steps of 1 ms, on a solver
/// posing as large where `large` (its kept factors converge linearly),
/// reading decisions early at `share`: the statistics and the blocks'
/// centroids (x, y, z).
fn run(
    scene: &Scene,
    steps: usize,
    three: bool,
    large: bool,
    share: f64,
) -> (Statistics, Vec<[f64; 3]>) {
    let solver: Box<dyn LinearSolver> = if large {
        Box::new(LargeLogged {
            solver: SparseCholesky::default(),
            log: Arc::new(Mutex::new(String::new())),
        })
    } else {
        Box::new(SparseCholesky::default())
    };
    let end = steps as f64 * 1e-3 - 1e-9;
    if three {
        let mut driver = scene.build_3d().unwrap().driver.with_solver(solver);
        driver.set_early_decision(share);
        driver.advance_to(end).unwrap();
        let at = (driver.system.blocks.iter()).map(|b| b.centroid().coords.into());
        (driver.statistics().clone(), at.collect())
    } else {
        let mut driver = scene.build().unwrap().driver.with_solver(solver);
        driver.set_early_decision(share);
        driver.advance_to(end).unwrap();
        let at = (driver.system.blocks.iter()).map(|b| [b.centroid().x, b.centroid().y, 0.0]);
        (driver.statistics().clone(), at.collect())
    }
}

/// Runs `scene` with the rule and without, prints both, and checks that
/// each took every step, none cut or unconverged, in the same passes, and
/// that the rule ended at least `ended` passes early; returns the
/// statistics (with, without) and how far apart the walls end (m).
fn both(
    scene: &Scene,
    steps: usize,
    three: bool,
    large: bool,
    ended: usize,
) -> (Statistics, Statistics, f64) {
    let (on, at_on) = run(scene, steps, three, large, 1e-5);
    let (off, at_off) = run(scene, steps, three, large, 0.0);
    let gap = apart(&at_on, &at_off);
    println!(
        "early: {} passes ended early, {} passes, {} moves, {} factorisations; \
         without: {} passes, {} moves, {} factorisations; centroids {gap:.2e} m apart",
        on.early_decisions,
        on.open_close_iterations,
        on.newton_iterations,
        on.factorizations,
        off.open_close_iterations,
        off.newton_iterations,
        off.factorizations,
    );
    for s in [&on, &off] {
        assert_eq!(s.steps, steps);
        assert_eq!(s.cuts(), 0);
        assert_eq!(s.unconverged_steps, 0);
        assert_eq!(s.newton_failures, 0);
    }
    assert_eq!(off.early_decisions, 0);
    assert!(on.early_decisions >= ended, "{on:?}");
    assert_eq!(on.open_close_iterations, off.open_close_iterations);
    (on, off, gap)
}

/// `a` took at most 90 % of `b`'s moves.
fn fewer_moves(a: &Statistics, b: &Statistics) {
    assert!(
        a.newton_iterations * 10 <= b.newton_iterations * 9,
        "{} moves against {}",
        a.newton_iterations,
        b.newton_iterations
    );
}

/// The 20 × 20 deformable wall settling at dt 1 ms for 0.3 s, its kept
/// factors posing as large (so its moves converge linearly): the passes
/// that a change of state ends early save their moves from 1e-5 to 1e-10
/// of the residual, and the next pass, starting a little farther from its
/// answer, solves it to the same tolerance: 72 such passes, 2,343 → 2,082
/// moves, the walls 1.4e-13 m apart. (The 10 × 10 wall, measured when the
/// rule came with 59 such passes, makes none since a half-offset bed
/// joint's springs stand for its overlap once: it rings too little.)
#[test]
fn a_pass_that_will_change_states_ends_at_its_early_decision() {
    let scene = wall(20, 2, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let (on, off, gap) = both(&scene, 300, false, true, 40);
    fewer_moves(&on, &off);
    // Both solve each step's last pass to a residual of 1e-10 of its first.
    assert!(gap < 1e-12, "centroids {gap} m apart");
}

/// The 3D 20-course deformable wall settling at dt 1 ms for 0.3 s, on the
/// same solver: in 3D a contact also decides between a vertex group's
/// entrances. 52 passes end early, 2,173 → 2,018 moves (3.0 a pass ended
/// early), the walls 2.9e-13 m apart. Each such pass saves its moves from
/// 1e-5 to 1e-10 of the residual, two or more; how many passes a step's
/// states end is the wall's own. The 12-course rigid wall, used while a
/// half-offset bed joint's springs stood for its overlap twice, now takes
/// one pass every step.
#[test]
fn a_pass_ends_at_its_early_decision_in_3d() {
    let scene = wall(20, 3, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let (on, off, gap) = both(&scene, 300, true, true, 40);
    let saved = off.newton_iterations.saturating_sub(on.newton_iterations);
    assert!(
        saved >= 2 * on.early_decisions,
        "{saved} moves saved by {} passes ended early",
        on.early_decisions
    );
    assert!(gap < 1e-12, "centroids {gap} m apart");
}

/// Passes with many contacts sliding end on the whole tangent; those read
/// their decisions early too. A wall that rings no longer has such passes
/// (the 30 × 30 one, used while a half-offset bed joint's springs stood
/// for its overlap twice, makes 11 whole-tangent moves in its first 60
/// steps and ends none early), so this is the 10 × 10 deformable wall
/// shaken at 5 m/s² (2 Hz; its bed joints slide at 6.87) at dt 2 ms, its
/// first 0.2 s. Measured: 46 passes ended early, 12 of them on the whole
/// tangent; 1,822 → 1,458 moves, 174 → 132 on the whole tangent.
///
/// On a sliding wall the rule does not leave the same wall: 149 passes
/// against 136, and the walls end 3.4e-5 m apart, where its bricks moved
/// up to 2.2e-4 m against its base. A contact held near its strength is
/// locked or sliding as the passes that reach it decide, both consistent
/// at the step's end, and the early decision reaches it by another path;
/// the residual tolerance alone (1e-8 or 1e-12 for 1e-10) parts the walls
/// by 1e-8 and 6e-11 m. The bound, 5e-5 m, is under a quarter of the
/// bricks' relative motion; `docs/limits.md` says so.
#[test]
fn a_whole_tangent_pass_ends_at_its_early_decision() {
    let mut scene = wall(10, 2, Stepping::Given(2e-3), BlockKind::Deformable).unwrap();
    dda::bench::shake(&mut scene, 5.0, 1.0);
    let (on, at_on) = run(&scene, 200, false, false, 1e-5);
    let (off, at_off) = run(&scene, 200, false, false, 0.0);
    let gap = apart(&at_on, &at_off);
    println!(
        "whole tangent: {} of {} passes ended early, {} moves, {} in all; without: {} and {}; \
         {} passes against {}; {gap:.2e} m apart",
        on.whole_tangent_early_decisions,
        on.early_decisions,
        on.whole_tangent_moves,
        on.newton_iterations,
        off.whole_tangent_moves,
        off.newton_iterations,
        on.open_close_iterations,
        off.open_close_iterations,
    );
    for s in [&on, &off] {
        assert_eq!(s.steps, 100);
        assert_eq!(s.cuts() + s.unconverged_steps, 0);
    }
    assert_eq!(off.whole_tangent_early_decisions, 0);
    assert!(on.whole_tangent_early_decisions >= 6, "{on:?}");
    assert!(on.whole_tangent_moves < off.whole_tangent_moves);
    fewer_moves(&on, &off);
    assert!(gap < 5e-5, "centroids {gap} m apart");
}
