//! The `dda bench` command times walls of growing size against the smallest.

use dda::bench::simulate::{simulate, SimulateOptions, SimulateRow};
use dda::bench::{bench, wall, wall_scene, BenchOptions, Stepping};
use dda::scene::{BlockKind, Solver};
mod common;

#[test]
fn bench_reports_medians_and_ratios_to_the_smallest_wall() {
    let rows = bench(&BenchOptions {
        sizes: vec![3, 6],
        steps: 2,
        repeats: 3,
        kinds: vec![BlockKind::Deformable],
        dimensions: vec![2],
        solver: Solver::Direct,
    })
    .unwrap();
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0].ratio_to_baseline, 1.0);
    assert!(rows
        .iter()
        .all(|r| r.median_ms_per_step > 0.0 && r.per_step.passes_per_step >= 1.0));
    // The most passes one step took: at least the mean, at most all the
    // timed steps' passes.
    for r in &rows {
        let all = r.per_step.passes_per_step * 2.0;
        assert!(r.most_passes as f64 >= r.per_step.passes_per_step, "{r:?}");
        assert!(r.most_passes as f64 <= all + 1e-9, "{r:?}");
    }
    // The base plus n courses; running bond adds a half brick to every other course.
    let expected = |n: usize| 1 + n * n + n / 2;
    assert_eq!(rows[0].blocks, expected(3));
    assert_eq!(rows[1].blocks, expected(6));
    assert_eq!(rows[1].unknowns, 6 * expected(6));
    assert!(
        (rows[1].ratio_to_baseline - rows[1].median_ms_per_step / rows[0].median_ms_per_step).abs()
            < 1e-12
    );
    // The wall the benchmark times is a valid scene that stands.
    let mut model = wall_scene(4).build().unwrap();
    model.driver.advance_to(0.05).unwrap();
    assert_eq!(model.driver.statistics().unconverged_steps, 0);
}

#[test]
fn rigid_bricks_solve_for_half_the_unknowns() {
    let rows = bench(&BenchOptions {
        sizes: vec![3],
        steps: 1,
        repeats: 1,
        kinds: vec![BlockKind::Rigid],
        dimensions: vec![2],
        solver: Solver::Direct,
    })
    .unwrap();
    assert_eq!(
        (rows[0].kind, rows[0].unknowns),
        (BlockKind::Rigid, 3 * rows[0].blocks)
    );
}

#[test]
fn bench_command_prints_a_table() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(["bench", "--sizes", "3", "--steps", "1", "--repeats", "1"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("ms/step")
            && text.contains("where the time goes")
            && text.lines().count() == 6
            && !text.contains("N^p"),
        "{text}"
    );
}

#[test]
fn bench_command_times_rigid_bricks() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
        .args([
            "bench",
            "--sizes",
            "3",
            "--steps",
            "1",
            "--repeats",
            "1",
            "--rigid",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("rigid 2D") && text.contains("unknowns"),
        "{text}"
    );
}

/// `dda bench --study` times a study on one core and on more: one row per
/// job count, each with the study's runs and the ratio of its wall time to
/// the sum of their times (no timing is asserted: machines are shared).
#[test]
fn a_study_is_timed_on_one_core_and_on_two() {
    let study = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/studies/twenty_short_runs.ron");
    let rows = dda::bench::bench_study(&study, &[1, 2], 1).unwrap();
    assert_eq!(rows.iter().map(|r| r.jobs).collect::<Vec<_>>(), [1, 2]);
    for r in &rows {
        assert_eq!(r.runs, 20);
        assert!(r.median_wall_s > 0.0 && r.run_sum_s > 0.0);
        assert!((r.ratio - r.median_wall_s / r.run_sum_s).abs() < 1e-12);
    }
}

/// A step runs on one core where its work is small (`ONE_CORE_WORK`).
/// Before any contact is found the blocks stand for its work, so a large
/// wall's first step (its whole search and first factorisation) runs on
/// both cores; after a step the contacts decide.
#[test]
fn a_large_wall_steps_on_both_cores_from_its_first_step() {
    for (n, one_core) in [(10, true), (60, false)] {
        let mut model = wall_scene(n).build().unwrap();
        assert_eq!(
            model.driver.steps_on_one_core(),
            one_core,
            "{n} x {n}, first step"
        );
        model.driver.step(0.001).unwrap();
        assert_eq!(
            model.driver.steps_on_one_core(),
            one_core,
            "{n} x {n}, second step"
        );
    }
}

fn dda(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(args)
        .output()
        .unwrap()
}

/// One run times both kinds in 2D and 3D: a row per dimension, kind and
/// size, each ratio against its own series' smallest wall.
#[test]
fn both_kinds_in_both_dimensions_in_one_run() {
    let rows = bench(&BenchOptions {
        sizes: vec![2, 3],
        steps: 1,
        repeats: 1,
        kinds: vec![BlockKind::Rigid, BlockKind::Deformable],
        dimensions: vec![2, 3],
        solver: Solver::Direct,
    })
    .unwrap();
    let keys: Vec<(u32, BlockKind, usize)> = rows
        .iter()
        .map(|r| (r.dimension, r.kind, r.courses))
        .collect();
    use BlockKind::{Deformable, Rigid};
    assert_eq!(
        keys,
        [
            (2, Rigid, 2),
            (2, Rigid, 3),
            (2, Deformable, 2),
            (2, Deformable, 3),
            (3, Rigid, 2),
            (3, Rigid, 3),
            (3, Deformable, 2),
            (3, Deformable, 3),
        ]
    );
    for r in &rows {
        // The 3D wall is the 2D wall's prism model: the same blocks, with
        // 6 DOF (rigid) or 12 (deformable) each.
        let dofs = match (r.dimension, r.kind) {
            (2, Rigid) => 3,
            (2, Deformable) => 6,
            (3, Rigid) => 6,
            _ => 12,
        };
        assert_eq!(r.blocks, 1 + r.courses * r.courses + r.courses / 2);
        assert_eq!(r.unknowns, dofs * r.blocks, "{r:?}");
        if r.courses == 2 {
            assert_eq!(r.ratio_to_baseline, 1.0);
        }
    }
    let fits = dda::bench::scaling::fits(&rows.iter().map(|r| r.point()).collect::<Vec<_>>());
    assert_eq!(fits.len(), 4);
    for f in &fits {
        let t = |n: usize| {
            rows.iter()
                .find(|r| r.dimension == f.dimension && r.kind == f.kind && r.blocks == n)
                .unwrap()
                .median_ms_per_step
        };
        let expected = (t(f.to_blocks) / t(f.from_blocks)).ln()
            / (f.to_blocks as f64 / f.from_blocks as f64).ln();
        assert!((f.exponent - expected).abs() < 1e-9 && (f.least_squares - expected).abs() < 1e-9);
    }
}

/// The 3D wall is built through the scene path and stands.
#[test]
fn the_3d_wall_is_a_scene_of_boxes_that_stands() {
    let scene = wall(3, 3, Stepping::Fixed, BlockKind::Deformable).unwrap();
    assert_eq!(scene.dimension, 3);
    let mut model = scene.build_3d().unwrap();
    assert_eq!(model.driver.system.blocks.len(), 1 + 9 + 1);
    model.driver.advance_to(0.02).unwrap();
    assert_eq!(model.driver.statistics().unconverged_steps, 0);
    // Automatic stepping leaves dt and the penalty to the scene.
    let auto = wall(3, 2, Stepping::Automatic, BlockKind::Rigid).unwrap();
    assert!(auto.analysis.dt.is_none() && auto.analysis.penalty.is_none());
}

#[test]
fn a_chart_of_time_per_step_against_blocks() {
    let dir = std::env::temp_dir().join(format!("dda-bench-chart-{}", std::process::id()));
    let png = dir.join("scaling.png");
    let out = dda(&[
        "bench",
        "--sizes",
        "2,3",
        "--steps",
        "1",
        "--repeats",
        "1",
        "--kinds",
        "rigid,deformable",
        "--chart",
        png.to_str().unwrap(),
        "--json",
        dir.join("bench.json").to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("rigid 2D: p = ") && text.contains("deformable 2D: p = "),
        "{text}"
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let info = decoder.read_info().unwrap().info().clone();
    assert_eq!((info.width, info.height), (900, 600));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("bench.json")).unwrap()).unwrap();
    assert_eq!(json["mode"], "steps");
    assert_eq!(json["rows"].as_array().unwrap().len(), 4);
    assert_eq!(json["fits"].as_array().unwrap().len(), 2);
    let svg = dir.join("scaling.svg");
    let out = dda(&[
        "bench",
        "--sizes",
        "2,3",
        "--steps",
        "1",
        "--repeats",
        "1",
        "--chart",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let drawn = std::fs::read_to_string(&svg).unwrap();
    assert!(drawn.contains("N^1 through deformable 2D") && drawn.contains("blocks"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A rigid 2D wall of `n` courses run for `seconds`, at the steps `dts`
/// (automatic if none), silently, once.
fn rigid_wall(n: usize, seconds: f64, dts: Vec<f64>) -> SimulateOptions {
    SimulateOptions {
        sizes: vec![n],
        kinds: vec![BlockKind::Rigid],
        dimensions: vec![2],
        seconds,
        max_wall: 600.0,
        repeats: 1,
        progress_every: None,
        solver: Solver::Direct,
        dts,
        shake: None,
        settle: false,
        step_log: None,
    }
}

/// `--step-log DIR`: each simulated run's steps.csv, named after its wall,
/// a row per step adding up to the run's steps and moves.
#[test]
fn each_simulated_run_logs_its_steps() {
    let dir = common::out_dir("bench_step_log");
    let _ = std::fs::remove_dir_all(&dir);
    let options = SimulateOptions {
        kinds: vec![BlockKind::Rigid, BlockKind::Deformable],
        repeats: 2,
        step_log: Some(dir.clone()),
        ..rigid_wall(3, 0.05, vec![0.005])
    };
    let rows = simulate(&options).unwrap();
    for (r, kind) in rows.iter().zip(["rigid", "deformable"]) {
        for again in ["", "_run2"] {
            let path = dir.join(format!("3x3_{kind}_2d_dt0.005{again}.csv"));
            let steps = dda::step_log::read_steps(&path).unwrap();
            assert_eq!(steps.len(), r.steps, "{}", path.display());
            let moves: usize = steps.iter().map(|s| s.moves).sum();
            let per_step = moves as f64 / r.steps as f64;
            assert!((per_step - r.per_step.newton_per_step).abs() < 1e-12);
            // The most passes a step took is the log's largest (the runs'
            // counts do not wander, so either run's log reads it).
            let most = steps.iter().map(|s| s.passes).max().unwrap();
            assert_eq!(r.most_passes, most, "{}", path.display());
        }
    }
}

#[test]
fn a_wall_runs_for_simulated_time_with_automatic_dt() {
    let rows = simulate(&rigid_wall(2, 0.002, Vec::new())).unwrap();
    let r = &rows[0];
    assert!(r.completed && (r.reached - 0.002).abs() < 1e-12, "{r:?}");
    assert!(!r.dt_given);
    // The automatic step of a wall at rest is its ceiling, sqrt(brick
    // size / g) / 20 (here longer than the run), and the penalty 2E/size.
    let ceiling = ((0.5f64 * 0.25).sqrt() / 9.81).sqrt() / 20.0;
    assert!(
        (r.dt - ceiling).abs() < 1e-9 && r.penalty > 1e9,
        "automatic dt and penalty: {r:?}"
    );
    assert!(r.steps >= 1);
    assert!((r.seconds_per_simulated_second - r.wall_s / r.reached).abs() < 1e-9);
    assert!(r.drift >= 0.0 && r.drift < 1e-3);
    // The settlement at the end is one the run passed through.
    assert!(r.end_drift > 0.0 && r.end_drift <= r.drift, "{r:?}");
    // Its work per step and where the time went, as for timed steps: every
    // pass moves at least once, and the phases are parts of the step.
    let work = &r.per_step;
    assert!(work.passes_per_step >= 1.0, "{work:?}");
    assert!(work.newton_per_step >= work.passes_per_step, "{work:?}");
    assert_eq!(work.phase_ms_per_step.len(), 10, "{work:?}");
    assert_eq!(work.phase_ms_per_step[3].0, "assembly");
    assert_eq!(work.phase_ms_per_step[9].0, "other");
    let phases: f64 = work.phase_ms_per_step.iter().map(|(_, ms)| ms).sum();
    assert!(
        phases > 0.0 && phases <= r.ms_per_step,
        "{phases} ms of phases in a {} ms step",
        r.ms_per_step
    );
}

/// With `--dt` each wall runs at each step given (the penalty automatic):
/// a small wall at rest stands at 5 ms and at 50 ms, each row reporting
/// its step, with no cut, no unconverged step and a settlement of a few
/// micrometres; a step that is no time is refused by name.
#[test]
fn a_wall_runs_at_the_steps_given() {
    let rows = simulate(&rigid_wall(4, 0.2, vec![0.005, 0.05])).unwrap();
    assert_eq!(rows.len(), 2);
    for (r, dt) in rows.iter().zip([0.005, 0.05]) {
        assert!(r.dt_given && r.dt == dt, "{r:?}");
        assert!(r.completed && (r.reached - 0.2).abs() < 1e-9, "{r:?}");
        assert_eq!((r.cuts, r.unconverged_steps), (0, 0), "{r:?}");
        assert!(r.steps >= (0.2 / dt).round() as usize, "{r:?}");
        assert!(r.drift < 1e-4, "a wall at rest settles micrometres: {r:?}");
    }
    let refused = simulate(&rigid_wall(4, 0.2, vec![0.0]))
        .unwrap_err()
        .to_string();
    assert!(
        refused.contains("--dt") && refused.contains("more than 0"),
        "{refused}"
    );
}

/// Doolin's ntdda ran the 10 × 10 wall of Shi's (deformable) blocks at
/// dt 1 ms and blew up within 0.2 s, the wall drifting 0.155 m with no
/// step cut and no warning. Here the same wall at the same step (the
/// penalty automatic) stands for 0.3 s: every step converged, none cut,
/// and no brick settles more than 0.1 mm (measured: 2.9e-5 m over 1 s).
#[test]
fn the_wall_that_blew_up_in_ntdda_stands_at_1_ms() {
    let options = SimulateOptions {
        kinds: vec![BlockKind::Deformable],
        ..rigid_wall(10, 0.3, vec![0.001])
    };
    let rows = simulate(&options).unwrap();
    let r = &rows[0];
    assert!(r.completed && (r.reached - 0.3).abs() < 1e-9, "{r:?}");
    assert_eq!((r.cuts, r.unconverged_steps), (0, 0), "{r:?}");
    assert!(r.steps >= 300, "{r:?}");
    assert!(r.drift < 1e-4, "the wall drifted {} m", r.drift);
}

/// `--settle`: each wall starts its timed run from its static settlement,
/// so a wall at rest stays there; unsettled, it rings about it. Measured
/// on the 10 × 10 walls over 0.2 s: settled, no brick moves more than
/// 2.2e-15 m (rigid) and 5.3e-15 m (deformable); unsettled, 7.3e-6 and
/// 1.9e-5 m.
#[test]
fn a_settled_wall_stays_at_rest() {
    let options = |settle: bool| SimulateOptions {
        kinds: vec![BlockKind::Rigid, BlockKind::Deformable],
        settle,
        ..rigid_wall(10, 0.2, vec![])
    };
    for r in simulate(&options(true)).unwrap() {
        assert!(r.completed && r.settled == Some(true), "{r:?}");
        assert!(r.settle_s.is_some_and(|s| s > 0.0), "{r:?}");
        assert!(
            r.drift < 1e-9,
            "the settled wall moved {} m: {r:?}",
            r.drift
        );
    }
    for r in simulate(&options(false)).unwrap() {
        assert!(r.settled.is_none() && r.settle_s.is_none(), "{r:?}");
        assert!(r.drift > 1e-6, "the unsettled wall moved {} m", r.drift);
    }
}

/// A large deformable wall settles in a few static steps. Its first long
/// step's pass stalls 1e-3 of its loads out of balance (the Newton-Raphson
/// iteration of some 3,800 sliding joints, with no inertia); cut to a third
/// as a run's unsolved step is, the 70 × 70 wall's next long step then
/// changed 13,000-18,000 of its 20,000 contacts a pass for twenty passes
/// (26 passes, 95 s), and the 100 × 100 wall was cut 28 times (42 passes,
/// 171 s). A settling step is not cut for its balance, since the settling
/// ends only in balance: 3 steps and 5 passes, 1.8 s (4.2 s at 100 × 100).
///
/// Its first pass starts with every contact locked, thousands of them
/// slipping past their strength: counted by state alone, they never
/// handed the pass to the whole tangent at its first rise, and it went on
/// with fresh factors, 12 factorisations in the settling instead of 7
/// (the 100 × 100 wall 16, with a Newton failure, instead of 6).
#[test]
fn a_large_deformable_wall_settles_in_a_few_passes() {
    let r = settled_deformable_wall(70, 2);
    assert!(r.settle_steps.is_some_and(|s| s <= 4), "{r:?}");
    assert!(r.settle_passes.is_some_and(|p| p <= 6), "{r:?}");
    assert!(r.settle_factorizations.is_some_and(|f| f <= 8), "{r:?}");
}

/// The deformable wall of `n` courses in `dimension` 2 or 3, settled and
/// then run one step of 1 ms; it must have settled.
fn settled_deformable_wall(n: usize, dimension: u32) -> SimulateRow {
    let options = SimulateOptions {
        kinds: vec![BlockKind::Deformable],
        dimensions: vec![dimension],
        settle: true,
        ..rigid_wall(n, 0.001, vec![0.001])
    };
    let r = simulate(&options).unwrap().remove(0);
    println!(
        "settled in {:?} steps, {:?} passes, {:?} factorisations, {:?} s",
        r.settle_steps, r.settle_passes, r.settle_factorizations, r.settle_s
    );
    assert!(r.completed && r.settled == Some(true), "{r:?}");
    r
}

/// A large 3D deformable wall settles on few factorisations: its first
/// pass keeps its factor by a large factor's rules. Those rules were read
/// before the model's first factorisation, when its size was not yet
/// known, so the pass took a small factor's and gave its factor up at
/// every slow move: the 60 × 60 wall factorised 8 times (1.5 s) instead
/// of once (0.65 s).
#[test]
fn a_large_3d_wall_settles_on_few_factorisations() {
    let r = settled_deformable_wall(60, 3);
    assert!(r.settle_factorizations.is_some_and(|f| f <= 3), "{r:?}");
}

/// A settled 3D wall stands still too, each step in one move: the corners
/// of bricks meeting in a head joint at the wall's faces keep the springs
/// they had at the last step's end. When a corner's fallback spring area
/// (its share of the face most nearly facing the other block, picked by
/// round-off between two faces equally near) outweighed the true area,
/// 400-460 of the 10 × 10 rigid wall's 1,140 contacts changed springs
/// from step to step, so each step started some 1e-3 of the loads out of
/// balance: 4-6 moves a step and a creep of 1e-8 m over 0.2 s. Measured
/// since: 1.00 and 1.04 moves a step (rigid, deformable), no brick moving
/// more than 1.5e-14 m.
#[test]
fn a_settled_3d_wall_steps_on_one_move() {
    let options = SimulateOptions {
        kinds: vec![BlockKind::Rigid, BlockKind::Deformable],
        dimensions: vec![3],
        settle: true,
        ..rigid_wall(10, 0.2, vec![0.001])
    };
    for r in simulate(&options).unwrap() {
        println!(
            "{:?}: {:.3} moves a step, drift {:.2e} m",
            r.kind, r.per_step.newton_per_step, r.drift
        );
        assert!(r.completed && r.settled == Some(true), "{r:?}");
        assert!(r.per_step.newton_per_step <= 1.1, "{r:?}");
        assert!(r.drift < 1e-12, "the settled wall moved {} m", r.drift);
    }
}

/// `--shake`: a wall well within its friction limit (a 2 Hz sine of 3
/// m/s² at its base; its bed joints hold to 6.87) rides its base, so its
/// drift is the base's own displacement, A/ω·(t − sin ωt/ω) from rest,
/// in 2D and in its 3D prism model (measured within 2.6e-6 of it).
#[test]
fn a_shaken_wall_rides_its_base() {
    let (a, seconds) = (3.0, 0.2);
    let options = SimulateOptions {
        shake: Some(a),
        settle: false,
        dimensions: vec![2, 3],
        ..rigid_wall(4, seconds, vec![0.002])
    };
    let rows = simulate(&options).unwrap();
    let w = std::f64::consts::TAU * dda::bench::SHAKE_FREQUENCY;
    let base = a / w * (seconds - (w * seconds).sin() / w);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert!(r.completed && r.shake == Some(a), "{r:?}");
        println!(
            "{}D: drift {} m, the base's displacement {base} m",
            r.dimension, r.drift
        );
        assert!(
            (r.drift - base).abs() < 2e-5 * base,
            "{}D: drift {} m against the base's {base} m",
            r.dimension,
            r.drift
        );
    }
    // At rest it stays put.
    let rest = simulate(&rigid_wall(4, seconds, vec![0.002])).unwrap();
    assert!(
        rest[0].shake.is_none() && rest[0].drift < 1e-4 * base,
        "{:?}",
        rest[0]
    );
}

#[test]
fn shaking_needs_an_amplitude_above_zero() {
    let options = SimulateOptions {
        shake: Some(0.0),
        settle: false,
        ..rigid_wall(2, 0.01, Vec::new())
    };
    let message = simulate(&options).unwrap_err().to_string();
    assert!(
        message.contains("--shake") && message.contains("more than 0"),
        "{message}"
    );
}

/// A run past its wall-clock cap stops and says how far it got.
#[test]
fn a_simulated_run_stops_at_its_wall_clock_cap() {
    let out = dda(&[
        "bench",
        "--sizes",
        "10",
        "--simulate",
        "1000",
        "--max-wall",
        "0.2",
        "--json",
        std::env::temp_dir()
            .join(format!("dda-bench-cap-{}.json", std::process::id()))
            .to_str()
            .unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("s/sim s")
            && text.contains("newton")
            && text.contains("where the time goes")
            && text.contains("stopped at the wall-clock cap, at t = "),
        "{text}"
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("wall-clock cap"));
}

#[test]
fn bad_bench_options_are_clear_errors() {
    for (args, says) in [
        (vec!["--chart", "out.txt"], "name a .png or .svg file"),
        (vec!["--sizes", "0"], "1 to 1000 courses"),
        (vec!["--dimension", "4"], "2D or 3D, not 4"),
        (vec!["--simulate", "-1"], "more than 0, got -1"),
        (vec!["--simulate", "1", "--max-wall", "0"], "--max-wall"),
        (vec!["--steps", "0"], "--steps must be at least 1"),
        (vec!["--repeats", "0"], "--repeats must be at least 1"),
        (
            vec!["--targets", "--repeats", "0"],
            "--repeats must be at least 1",
        ),
        (vec!["--json", "."], "--json .: a folder; name a file"),
        (
            vec!["--targets", "--json", "."],
            "--json .: a folder; name a file",
        ),
        (
            vec!["--json", "/proc/no-such-folder/rows.json"],
            "--json: cannot create /proc/no-such-folder",
        ),
        (
            vec!["--kinds", "soft"],
            "possible values: rigid, deformable",
        ),
        (vec!["--rigid", "--kinds", "rigid"], "cannot be used with"),
        (vec!["--max-wall", "5"], "--simulate"),
        (vec!["--step-log", "logs"], "--simulate"),
        (
            vec!["--simulate", "1", "--step-log", "/proc/no/logs"],
            "--step-log: cannot create",
        ),
    ] {
        let mut all = vec!["bench"];
        all.extend(args.iter().copied());
        let out = dda(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(says),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// A 3D wall's bricks, all boxes, read one shared topology: the narrow
/// phase then reads one set of adjacency lists for all of them.
#[test]
fn a_3d_walls_bricks_share_one_topology() {
    let scene = wall(4, 3, Stepping::Fixed, BlockKind::Rigid).unwrap();
    let model = scene.build_3d().unwrap();
    let blocks = &model.driver.system.blocks;
    assert!(blocks.len() > 10);
    let first = blocks[0].shape();
    assert!(blocks[1..].iter().all(|b| b.shape().shares_topology(first)));
}

/// `dda bench --targets` on small walls (10 × 10 compared, 20 × 20 the
/// largest, 0.05 s simulated): every target has its row (19), written to the
/// JSON as it goes; the compared wall's verdict follows MuJoCo's time; the
/// timed rows name the runs they are the median of; and a MuJoCo run of
/// another wall is refused.
#[test]
fn targets_report_every_target_with_its_verdict() {
    use dda::bench::targets::{targets, MujocoRun, TargetOptions};
    // The JSON's folder is made as the run starts.
    let json = common::out_dir("bench_targets").join("targets.json");
    let mujoco = |wall_s: f64| MujocoRun {
        engine: "mujoco".into(),
        courses: 10,
        wall_s,
        drift_m: 1e-2,
    };
    let options = |m: MujocoRun| TargetOptions {
        compared: 10,
        ntdda: 10,
        standing: 10,
        largest: 20,
        seconds: 0.05,
        steps_2d: 2,
        steps_3d: 1,
        max_wall: 600.0,
        repeats: 1,
        mujoco: Some(m),
    };
    // MuJoCo far slower: the compared wall's verdict is its drift's. Each
    // timed wall run twice, the median (the slower of two) read.
    let twice = TargetOptions {
        repeats: 2,
        ..options(mujoco(1e6))
    };
    let report = targets(&twice, Some(&json)).unwrap();
    assert_eq!(report.targets.len(), 19, "{report:#?}");
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(written["targets"].as_array().unwrap().len(), 19);
    assert_eq!(written["repeats"], 2);
    // The 20 × 20 wall's steps (its six rows) and the growth to it (six).
    let medians = (report.targets.iter())
        .filter(|t| t.measured.contains("the median of 2 runs"))
        .count();
    assert_eq!(medians, 12, "{report:#?}");
    for t in &report.targets {
        assert!(t.met.is_some(), "{t:?}");
        assert!(!t.measured.is_empty());
    }
    // The compared wall's passes at dt 1 ms: both kinds at both penalties.
    let passes = (report.targets.iter())
        .find(|t| t.target.contains("open-close passes in any step"))
        .expect("the passes' row");
    assert_eq!(
        passes.measured.matches("passes a step, at most").count(),
        4,
        "{passes:?}"
    );
    assert_eq!(
        passes.measured.matches("penalty 1e9").count(),
        2,
        "{passes:?}"
    );
    // Beside them, the four walls settled first: a small wall at rest,
    // settled, takes one pass a step.
    assert!(
        passes.measured.contains(
            "the same 4 walls settled first (analysis.settle), one run each, not judged: at most 1 pass in one step, 0 unconverged steps"
        ),
        "{passes:?}"
    );
    let compared = &report.targets[..2];
    // Each kind's static settlement, as the wall at rest's row reads it.
    let at_rest = &(report.targets.iter())
        .find(|t| t.target.contains("wall at rest"))
        .expect("the wall at rest's row")
        .measured;
    for (t, kind) in compared.iter().zip(["rigid", "deformable"]) {
        let drift: f64 = t.measured.split("drift ").nth(1).unwrap()[..8]
            .trim()
            .parse()
            .unwrap();
        assert_eq!(t.met, Some(drift <= 1.8e-4), "{t:?}");
        let settled = |text: &str, before: &str| -> String {
            let after = text.split(before).nth(1);
            after
                .and_then(|t| t.get(..8))
                .unwrap_or("missing")
                .to_string()
        };
        let reading = (at_rest.split("; "))
            .skip_while(|r| !r.starts_with(kind))
            .find(|r| r.starts_with("static settlement"))
            .unwrap_or_default();
        assert_eq!(
            settled(&t.measured, "its static settlement "),
            settled(reading, "static settlement "),
            "{t:?} against {at_rest}"
        );
    }
    // MuJoCo far faster: not met. One run each: no median to name.
    let fast = targets(&options(mujoco(1e-9)), None).unwrap();
    assert!(fast.targets[..2].iter().all(|t| t.met == Some(false)));
    assert!(fast.targets.iter().all(|t| !t.measured.contains("median")));
    let mut other = mujoco(1.0);
    other.courses = 40;
    let refused = targets(&options(other), None).unwrap_err().to_string();
    assert!(
        refused.contains("--mujoco") && refused.contains("mujoco_wall.py 10"),
        "{refused}"
    );
}

/// The 10 × 10 wall at rest stands at steps of 5 and 10 ms over a second,
/// both kinds (no cut, moving at most twice its static settlement and
/// ending within 1 % of it), and at every larger step tried, up to 10.24
/// s: Newmark's step with β = 1/2, γ = 1 is unconditionally stable.
#[test]
fn a_wall_at_rest_stands_at_large_steps_without_drift() {
    use dda::bench::targets::{standing_steps, TargetOptions};
    let options = TargetOptions {
        compared: 10,
        ..TargetOptions::default()
    };
    let target = standing_steps(&options).unwrap();
    assert_eq!(target.met, Some(true), "{target:?}");
    for kind in ["rigid", "deformable"] {
        let reading = target.measured.split("; ").find(|r| r.starts_with(kind));
        assert!(
            reading.is_some_and(|r| r.contains("5 ms") && r.contains("10 ms")),
            "{target:?}"
        );
    }
    assert_eq!(
        target
            .measured
            .matches("stands at every step tried, up to 10.24 s")
            .count(),
        2,
        "{target:?}"
    );
}
