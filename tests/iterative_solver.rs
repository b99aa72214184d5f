//! The iterative solver (`analysis: (solver: Iterative())`: conjugate
//! gradients preconditioned by block Jacobi) against the direct one on the
//! shipped examples: the same history.csv, compared as
//!
//! * lengths: positions, and rotations times the model size w0 (the
//!   largest coordinate), against w0;
//! * speeds: velocities, and angular velocities times w0, against the
//!   largest such speed of the run;
//! * stresses against the largest stress of the run.
//!
//! Measured worst differences at the default tolerance 1e-11: the sliding
//! block 1.1e-8, the stacked blocks 7e-11, the wedge 2.8e-8 (its
//! stresses), the Heyman arch 6e-7. The arch's voussoirs ring on their
//! contact springs and carry what an increment's tolerance leaves along,
//! so its difference does not follow the tolerance: 8.8e-6 with a start
//! carried across steps, positions 7e-11 to 2e-9 of w0 at tolerances from
//! 1e-9 to 1e-13. The tolerances keep a headroom of 10 or more over all
//! of these: 1e-6, and 1e-4 for the arch.

use dda::scene::Solver;
use dda::Scene;

mod common;

/// Runs a shipped example with `solver` and returns history.csv's header
/// and rows, and the summary.
fn history(name: &str, solver: Solver) -> (Vec<String>, Vec<Vec<f64>>, dda::Summary) {
    let tag = if solver == Solver::Direct {
        "solver-direct"
    } else {
        "solver-iterative"
    };
    let (summary, out) = common::run_edited(name, tag, |scene| scene.analysis.solver = solver);
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows, summary)
}

/// The largest difference of the two histories, each quantity against
/// its scale (see the module's documentation).
fn difference(header: &[String], a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len(), "as many output rows");
    let kind = |name: &str| match name {
        "x" | "y" | "z" => "position",
        "rotation" | "rx" | "ry" | "rz" => "rotation",
        "vx" | "vy" | "vz" => "velocity",
        "omega" | "wx" | "wy" | "wz" => "spin",
        n if n.starts_with('s') && n.len() == 3 => "stress",
        _ => "other",
    };
    let columns = |k: &str| -> Vec<usize> {
        (0..header.len())
            .filter(|&c| kind(&header[c]) == k)
            .collect()
    };
    let largest = |cols: &[usize], factor: f64| {
        a.iter()
            .flat_map(|r| cols.iter().map(move |&c| factor * r[c].abs()))
            .fold(0.0, f64::max)
    };
    let w0 = largest(&columns("position"), 1.0);
    let speed = largest(&columns("velocity"), 1.0).max(largest(&columns("spin"), w0));
    let stress = largest(&columns("stress"), 1.0);
    let mut worst: f64 = 0.0;
    for (k, factor, scale) in [
        ("position", 1.0, w0),
        ("rotation", w0, w0),
        ("velocity", 1.0, speed),
        ("spin", w0, speed),
        ("stress", 1.0, stress),
    ] {
        for c in columns(k) {
            for (ra, rb) in a.iter().zip(b) {
                worst = worst.max(factor * (ra[c] - rb[c]).abs() / scale);
            }
        }
    }
    worst
}

fn assert_same_answers(name: &str, tolerance: f64) {
    let (header, direct, _) = history(name, Solver::Direct);
    let (_, iterative, summary) = history(name, Solver::iterative());
    assert!(summary.iterative_solves > 0, "{name}: the iterations ran");
    assert_eq!(
        summary.iterative_fallbacks, 0,
        "{name}: no system reached the cap"
    );
    let worst = difference(&header, &direct, &iterative);
    eprintln!(
        "{name}: largest difference {worst:.2e}, {:.1} iterations per solve",
        summary.iterative_iterations as f64 / summary.iterative_solves as f64
    );
    assert!(worst <= tolerance, "{name}: {worst:e} > {tolerance:e}");
}

#[test]
fn the_sliding_block_is_the_same_with_either_solver() {
    assert_same_answers("sliding_block_2d.ron", 1e-6);
}

#[test]
fn the_stacked_blocks_are_the_same_with_either_solver() {
    assert_same_answers("stacked_blocks_2d.ron", 1e-6);
}

#[test]
fn the_wedge_is_the_same_with_either_solver() {
    assert_same_answers("wedge_3d.ron", 1e-6);
}

#[test]
fn the_heyman_arch_is_the_same_with_either_solver() {
    assert_same_answers("arch_heyman_2d.ron", 1e-4);
}

/// At a cap of two iterations the systems are solved by sparse Cholesky
/// instead, counted, and the answers are the direct solver's.
#[test]
fn systems_at_the_iteration_cap_are_solved_directly() {
    let name = "stacked_blocks_2d.ron";
    let (header, direct, _) = history(name, Solver::Direct);
    let capped = Solver::Iterative {
        tolerance: 1e-11,
        max_iterations: 2,
    };
    let (_, iterative, summary) = history(name, capped);
    assert!(summary.iterative_fallbacks > 0, "{summary:?}");
    assert!(difference(&header, &direct, &iterative) <= 1e-6);
}

#[test]
fn bad_solver_values_are_refused_with_the_fix() {
    let text = |solver: &str| {
        std::fs::read_to_string(common::example("sliding_block_2d.ron"))
            .unwrap()
            .replacen("analysis: (", &format!("analysis: (solver: {solver}, "), 1)
    };
    assert!(Scene::from_str(&text("Iterative()"), "ok.ron").is_ok());
    for (solver, says) in [
        ("Iterative(tolerance: 0.0)", "(0, 1)"),
        ("Iterative(tolerance: 2.0)", "(0, 1)"),
        ("Iterative(max_iterations: 0)", "at least 1"),
    ] {
        let message = format!(
            "{:#}",
            Scene::from_str(&text(solver), "bad.ron")
                .and_then(|s| s.build().map(|_| ()))
                .unwrap_err()
        );
        assert!(
            message.contains("analysis.solver") && message.contains(says),
            "{solver}: {message}"
        );
    }
}

/// `dda bench` with the iterative solver reports its iterations per solve.
#[test]
fn the_bench_times_the_iterative_solver() {
    let rows = dda::bench::bench(&dda::bench::BenchOptions {
        sizes: vec![3],
        steps: 2,
        repeats: 1,
        kinds: vec![dda::scene::BlockKind::Deformable],
        dimensions: vec![2],
        solver: Solver::iterative(),
    })
    .unwrap();
    assert!(rows[0].iterations_per_solve > 1.0, "{:?}", rows[0]);
    assert_eq!(rows[0].solver_fallbacks, 0);
}
