//! `dda bench`: step time of running-bond walls of growing size.
//!
//! The machines are shared and noisy, so each size is run several times and
//! reported by its median, and as a ratio to the smallest wall measured in
//! the same run (the baseline).

use std::time::Instant;

use serde::Serialize;

use dda_core::{Solver, Statistics};

use crate::scene::{BlockKind, Scene};

/// What to measure.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Wall sizes: `n` courses of `n` bricks.
    pub sizes: Vec<usize>,
    /// Steps timed per run (after one untimed step).
    pub steps: usize,
    /// Runs per size; the median is reported.
    pub repeats: usize,
    /// The bricks' kind: rigid bricks solve for half the unknowns.
    pub kind: BlockKind,
    /// The step's linear solver.
    pub solver: Solver,
}

/// One size's result.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRow {
    pub courses: usize,
    pub kind: BlockKind,
    pub blocks: usize,
    pub contacts: usize,
    /// Unknowns of the step's system.
    pub unknowns: usize,
    /// Median wall time per step, milliseconds.
    pub median_ms_per_step: f64,
    /// The same relative to the smallest wall's.
    pub ratio_to_baseline: f64,
    /// Wall-clock seconds per simulated second (median run).
    pub seconds_per_simulated_second: f64,
    /// Per step of the median run: open-close passes, Newton-Raphson
    /// iterations, numeric factorizations and symbolic analyses.
    pub passes_per_step: f64,
    pub newton_per_step: f64,
    pub factorizations_per_step: f64,
    pub analyses_per_step: f64,
    /// Step cuts (open-close, displacement, penetration) and steps accepted
    /// unconverged, over the timed steps of the median run.
    pub cuts: usize,
    pub unconverged_steps: usize,
    /// Milliseconds per step in each phase of the median run, in step order.
    pub phase_ms_per_step: Vec<(String, f64)>,
    /// The largest centroid displacement of any brick since the wall was
    /// built, m.
    pub drift: f64,
    /// The process's peak resident memory so far, MB (Linux; 0 elsewhere).
    pub peak_memory_mb: f64,
    /// Iterative solver: conjugate-gradient iterations per solve, and the
    /// solves that reached the cap, over the timed steps of the median run.
    pub iterations_per_solve: f64,
    pub solver_fallbacks: usize,
}

/// A running-bond wall of `n` courses of `n` bricks (0.5 m × 0.25 m) on a
/// fixed base, at rest under gravity.
pub fn wall_scene(n: usize) -> Scene {
    let length = 0.5 * n as f64;
    let text = format!(
        r#"Scene(
    analysis: (duration: 1.0, dt: 0.001, penalty: 1e9, gravity: (0.0, -9.81)),
    materials: {{ "brick": (density: 1800.0, young: 5e9, poisson: 0.2) }},
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: ({c:?}, -0.5), width: {w:?}, height: 1.0, fixed: true),
        Wall(origin: (0.0, 0.0), length: {length:?}, courses: {n}, brick_length: 0.5, brick_height: 0.25, bond: Running),
    ],
)"#,
        c = length / 2.0,
        w = length + 2.0,
    );
    Scene::from_str(&text, &format!("wall_{n}x{n}.ron"))
        .expect("the benchmark wall is a valid scene")
}

/// One timed run of a wall.
struct Run {
    ms_per_step: f64,
    seconds_per_simulated_second: f64,
    stats: Statistics,
    drift: f64,
    blocks: usize,
    contacts: usize,
    unknowns: usize,
}

fn run(n: usize, options: &BenchOptions) -> anyhow::Result<Run> {
    let mut scene = wall_scene(n);
    scene.materials[0].1.kind = options.kind;
    scene.analysis.solver = options.solver;
    let mut model = scene.build()?;
    let start: Vec<_> = model
        .driver
        .system
        .blocks
        .iter()
        .map(|b| b.centroid())
        .collect();
    let dt = model.driver.dt();
    model.driver.step(dt)?;
    let before = model.driver.statistics().clone();
    let t0 = model.driver.time();
    let started = Instant::now();
    for _ in 0..options.steps {
        model.driver.step(dt)?;
    }
    let wall = started.elapsed().as_secs_f64();
    let after = model.driver.statistics();
    let drift = model
        .driver
        .system
        .blocks
        .iter()
        .zip(&start)
        .map(|(b, c)| (b.centroid() - c).norm())
        .fold(0.0, f64::max);
    Ok(Run {
        ms_per_step: wall * 1e3 / options.steps as f64,
        seconds_per_simulated_second: wall / (model.driver.time() - t0),
        stats: difference(after, &before),
        drift,
        blocks: model.driver.system.blocks.len(),
        contacts: model.driver.contacts().len(),
        unknowns: model.driver.unknowns(),
    })
}

/// The counters and times of `after` since `before`.
fn difference(after: &Statistics, before: &Statistics) -> Statistics {
    Statistics {
        steps: after.steps - before.steps,
        open_close_iterations: after.open_close_iterations - before.open_close_iterations,
        newton_iterations: after.newton_iterations - before.newton_iterations,
        factorizations: after.factorizations - before.factorizations,
        symbolic_analyses: after.symbolic_analyses - before.symbolic_analyses,
        open_close_cuts: after.open_close_cuts - before.open_close_cuts,
        displacement_cuts: after.displacement_cuts - before.displacement_cuts,
        penetration_cuts: after.penetration_cuts - before.penetration_cuts,
        unconverged_steps: after.unconverged_steps - before.unconverged_steps,
        times: after.times.since(&before.times),
        iterative_solves: after.iterative_solves - before.iterative_solves,
        iterative_iterations: after.iterative_iterations - before.iterative_iterations,
        iterative_fallbacks: after.iterative_fallbacks - before.iterative_fallbacks,
        ..Statistics::default()
    }
}

/// Peak resident memory of this process, MB (Linux's VmHWM; 0 elsewhere).
fn peak_memory_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(0.0, |kb| kb / 1024.0)
}

/// Runs the benchmark.
pub fn bench(options: &BenchOptions) -> anyhow::Result<Vec<BenchRow>> {
    let mut rows: Vec<BenchRow> = Vec::new();
    for &n in &options.sizes {
        let mut runs = Vec::with_capacity(options.repeats);
        for _ in 0..options.repeats.max(1) {
            runs.push(run(n, options)?);
        }
        runs.sort_by(|a, b| a.ms_per_step.total_cmp(&b.ms_per_step));
        let median = &runs[runs.len() / 2];
        let stats = &median.stats;
        let steps = stats.steps.max(1) as f64;
        let per_step = |count: usize| count as f64 / steps;
        rows.push(BenchRow {
            courses: n,
            kind: options.kind,
            blocks: median.blocks,
            contacts: median.contacts,
            unknowns: median.unknowns,
            median_ms_per_step: median.ms_per_step,
            ratio_to_baseline: 1.0,
            seconds_per_simulated_second: median.seconds_per_simulated_second,
            passes_per_step: per_step(stats.open_close_iterations),
            newton_per_step: per_step(stats.newton_iterations),
            factorizations_per_step: per_step(stats.factorizations),
            analyses_per_step: per_step(stats.symbolic_analyses),
            cuts: stats.open_close_cuts + stats.displacement_cuts + stats.penetration_cuts,
            unconverged_steps: stats.unconverged_steps,
            phase_ms_per_step: stats
                .times
                .phases()
                .iter()
                .map(|(name, t)| (name.to_string(), t.as_secs_f64() * 1e3 / steps))
                .collect(),
            drift: median.drift,
            peak_memory_mb: peak_memory_mb(),
            iterations_per_solve: stats.iterative_iterations as f64
                / stats.iterative_solves.max(1) as f64,
            solver_fallbacks: stats.iterative_fallbacks,
        });
    }
    let baseline = rows.first().map(|r| r.median_ms_per_step).unwrap_or(1.0);
    for r in &mut rows {
        r.ratio_to_baseline = r.median_ms_per_step / baseline;
    }
    Ok(rows)
}

/// One study timing: the runs at `jobs` at once.
#[derive(Debug, Clone, Serialize)]
pub struct StudyBenchRow {
    pub jobs: usize,
    pub runs: usize,
    /// Median wall time of the whole study, seconds.
    pub median_wall_s: f64,
    /// The sum of its runs' own wall times in that repeat, seconds.
    pub run_sum_s: f64,
    /// Wall time over the sum of run times: 1 on one core, 1/jobs at best.
    pub ratio: f64,
}

/// Times the study in `path` at each of `jobs` runs at once, `repeats`
/// times each (the median repeat is reported), its outputs in a temporary
/// folder: how well the runs share the cores.
pub fn bench_study(
    path: &std::path::Path,
    jobs: &[usize],
    repeats: usize,
) -> anyhow::Result<Vec<StudyBenchRow>> {
    let out = std::env::temp_dir().join(format!("dda-bench-study-{}", std::process::id()));
    let mut rows = Vec::new();
    for &j in jobs {
        let mut timings: Vec<(f64, f64, usize)> = (0..repeats.max(1))
            .map(|_| {
                let _ = std::fs::remove_dir_all(&out);
                let started = Instant::now();
                let report = crate::study::run(
                    path,
                    &crate::study::Options {
                        out: out.clone(),
                        jobs: Some(j),
                        shard: None,
                        progress: false,
                    },
                )?;
                let wall = started.elapsed().as_secs_f64();
                let sum = report.rows.iter().map(|r| r.wall_time).sum();
                Ok((wall, sum, report.rows.len()))
            })
            .collect::<anyhow::Result<_>>()?;
        timings.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (wall, sum, runs) = timings[timings.len() / 2];
        rows.push(StudyBenchRow {
            jobs: j,
            runs,
            median_wall_s: wall,
            run_sum_s: sum,
            ratio: wall / sum,
        });
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok(rows)
}
