//! A later open-close pass on a large factor moves on the factor at hand,
//! with the springs that came, went or changed since it was made applied
//! as rank-one terms (the Sherman-Morrison-Woodbury formula, between the
//! factor's sweeps), instead of factorising anew. These tests run walls
//! on a solver posing as large, with the rule and without it
//! (`set_changed_springs(0)`): the same passes, fewer factorisations, the
//! same wall.

use dda::bench::{wall, Stepping};
use dda::Scene;
use dda_core::solve::{LinearSolver, SparseCholesky};
use dda_core::{BlockKind, Statistics};
use std::sync::{Arc, Mutex};

mod common;
use common::{apart, ran_clean, save_and_resume, LargeLogged, Posing};

/// A solver posing as large (beyond the floor of changes left to the
/// moves), writing down what it is asked.
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
    run_on(scene, steps, three, limit, false)
}

/// [`run`], on a solver posing under the floor where `under`.
fn run_on(
    scene: &Scene,
    steps: usize,
    three: bool,
    limit: usize,
    under: bool,
) -> (Statistics, Vec<[f64; 3]>, String) {
    let (logged, log) = large();
    // 2²² entries: large, but below the factors whose later passes leave
    // small changes to the moves.
    let solver: Box<dyn LinearSolver> = if under {
        Box::new(Posing {
            solver: *logged,
            entries: 1 << 22,
        })
    } else {
        logged
    };
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

/// Both runs took every step, none cut or accepted unconverged, in the
/// same open-close passes.
fn alike(on: &Statistics, off: &Statistics, steps: usize) {
    for s in [on, off] {
        ran_clean(s, steps);
    }
    assert_eq!(on.open_close_iterations, off.open_close_iterations);
}

/// Prints two runs' counts (`a` named `names[0]`, `b` `names[1]`) and how
/// far apart their centroids end, and checks they ran alike.
fn report(names: [&str; 2], a: &Statistics, b: &Statistics, gap: f64, steps: usize) {
    println!(
        "{}: {} passes on the factor with changed springs, {} factorisations, {} moves; {}: {}, {} and {}; centroids {gap:.2e} m apart",
        names[0],
        a.changed_spring_passes,
        a.factorizations,
        a.newton_iterations,
        names[1],
        b.changed_spring_passes,
        b.factorizations,
        b.newton_iterations
    );
    alike(a, b, steps);
}

/// `a` made at least `fewer` factorisations fewer than `b`, in at most
/// `more` moves more.
fn fewer_factorisations(a: &Statistics, b: &Statistics, fewer: usize, more: usize) {
    assert!(
        a.factorizations + fewer <= b.factorizations,
        "{} factorisations against {}",
        a.factorizations,
        b.factorizations
    );
    assert!(
        a.newton_iterations <= b.newton_iterations + more,
        "{} moves against {}",
        a.newton_iterations,
        b.newton_iterations
    );
}

/// The 20 × 20 deformable wall settling at dt 1 ms for 0.3 s, posing as a
/// large factor under the floor (springs compared exactly): 53 later
/// passes start with at most 64 rank-one terms. Those make no
/// factorisation (320 → 272 in all), in about as many moves (1,929 →
/// 1,937), and the wall ends 7.9e-14 m from where a new factor at every
/// later pass leaves it. (The 10 × 10 wall, used while a half-offset bed
/// joint's springs stood for its overlap twice, now rings with 15 later
/// passes.) A wrong term (its sign turned) makes the moves
/// on such a factor fall short, and the pass factorises after all.
#[test]
fn a_later_pass_moves_on_the_factor_with_the_changed_springs() {
    let scene = wall(20, 2, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let steps = 300;
    let (on, at_on, log) = run_on(&scene, steps, false, 64, true);
    let (off, at_off, _) = run_on(&scene, steps, false, 0, true);
    let gap = apart(&at_on, &at_off);
    report(["with the terms", "without"], &on, &off, gap, steps);
    assert_eq!(off.changed_spring_passes, 0);
    assert!(on.changed_spring_passes >= 50, "{on:?}");
    // Each such pass's terms made into one update of the factor.
    assert_eq!(log.matches('U').count(), on.changed_spring_passes);
    let fewer = on.changed_spring_passes * 9 / 10;
    fewer_factorisations(&on, &off, fewer, off.newton_iterations / 100);
    // Both solve each step to a residual of 1e-10 of its first.
    assert!(gap < 1e-12, "centroids {gap} m apart");
}

/// The 3D 20-course deformable wall settling at dt 1 ms for 0.3 s: a
/// sliding contact's friction turns with its slip, so its terms change with
/// each pass; beyond the floor the small ones are left to the moves, and 63
/// later passes start so. They make 58 factorisations fewer (289 → 231),
/// for 106 moves more (1,912 → 2,018, 5.5 %: under two moves for each
/// factorisation saved), and the wall ends where it would (3.8e-13 m
/// apart). The 12-course rigid wall, used while a half-offset bed joint's
/// springs stood for its overlap twice, now takes one pass every step.
#[test]
fn a_later_pass_in_3d_moves_on_the_factor_with_the_changed_springs() {
    let scene = wall(20, 3, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let steps = 300;
    let (on, at_on, _) = run(&scene, steps, true, 64);
    let (off, at_off, _) = run(&scene, steps, true, 0);
    let gap = apart(&at_on, &at_off);
    report(["with the terms", "without"], &on, &off, gap, steps);
    assert!(on.changed_spring_passes >= 40, "{on:?}");
    fewer_factorisations(&on, &off, 40, off.newton_iterations / 10);
    assert!(gap < 1e-12, "centroids {gap} m apart");
}

/// Beyond the floor, a later pass's springs count as the factor's where
/// they changed no matrix entry by more than `LARGE_FACTOR_DRIFT` of its
/// largest: the sliding contacts whose shear stiffness the return map
/// changed from one pass to the next are left to the moves. The 3D
/// 20-course deformable wall over 0.3 s at dt 1 ms, posing beyond the
/// floor and under it: 63 later passes on the factor against 2, 231
/// factorisations against 286, for 2,018 moves against 1,915 (5.4 %); the
/// walls end 3.8e-13 m apart. With no floor the two runs are the same.
/// (The 20 × 20 wall, used while a half-offset bed joint's springs stood
/// for its overlap twice, now makes 86 such passes against 53.)
#[test]
fn beyond_the_floor_small_changes_are_left_to_the_moves() {
    let scene = wall(20, 3, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let steps = 300;
    let (beyond, at_beyond, _) = run_on(&scene, steps, true, 64, false);
    let (under, at_under, _) = run_on(&scene, steps, true, 64, true);
    let gap = apart(&at_beyond, &at_under);
    report(
        ["beyond the floor", "under it"],
        &beyond,
        &under,
        gap,
        steps,
    );
    assert!(beyond.changed_spring_passes >= under.changed_spring_passes + 40);
    fewer_factorisations(&beyond, &under, 40, under.newton_iterations / 10);
    assert!(gap < 1e-11, "centroids {gap} m apart");
}

/// The 20 × 20 deformable wall at dt 1 ms on a solver posing as large,
/// saved after its 150th step and resumed from its checkpoint in a driver
/// built afresh, takes its next 100 steps bit for bit as the saved run
/// goes on to take them, its later passes moving on the factor with the
/// changed springs: the springs' record lasts a step attempt, and the
/// floor of the changes left to the moves is read off the factor's
/// values, which the checkpoint keeps.
#[test]
fn a_wall_moving_on_the_changed_springs_resumes_bit_for_bit() {
    let scene = wall(20, 2, Stepping::Fixed, BlockKind::Deformable).unwrap();
    let fresh = || {
        let (solver, _) = large();
        scene.build().unwrap().driver.with_solver(solver)
    };
    let [before, went, came] = save_and_resume(fresh, 150, 100, |s| s.changed_spring_passes);
    println!(
        "resumed: {} moves, {} factorisations, {} passes on changed springs; went on: {}, {} and {}",
        came.0, came.1, came.2, went.0, went.1, went.2
    );
    assert!(went.2 >= before.2 + 10, "{} then {}", before.2, went.2);
    assert!(came == went);
}
