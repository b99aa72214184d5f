//! `dda bench`: step time of running-bond walls of growing size.
//!
//! The machines are shared and noisy, so each size is run several times and
//! reported by its median, and as a ratio to the smallest wall of the same
//! kind and dimension measured in the same run (the baseline). Walls are
//! built by [`walls`], timed by fixed step counts here or over a simulated
//! time by [`simulate`]; [`scaling`] fits how time per step grows with the
//! blocks and draws it; [`study`] times a study's use of the cores.

pub mod command;
pub mod largest_step;
pub mod report;
pub mod scaling;
pub mod simulate;
pub mod study;
pub mod targets;
pub mod walls;

use std::time::{Duration, Instant};

use serde::Serialize;

use dda_core::{Solver, Statistics};

use crate::scene::{AnyModel, BlockKind};
use crate::simulation::Simulation;

pub use command::{command, Command};
pub use study::{bench_study, StudyBenchRow};
pub use walls::{shake, wall, wall_scene, Stepping, SHAKE_FREQUENCY};

/// What to measure.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Wall sizes: `n` courses of `n` bricks.
    pub sizes: Vec<usize>,
    /// Steps timed per run (after one untimed step).
    pub steps: usize,
    /// Runs per size; the median is reported.
    pub repeats: usize,
    /// The bricks' kinds, each timed in turn: rigid bricks solve for half
    /// the unknowns.
    pub kinds: Vec<BlockKind>,
    /// Dimensions, each timed in turn: 2, or 3 for the walls' prism models
    /// ([`walls::DEPTH_3D`] deep).
    pub dimensions: Vec<u32>,
    /// The step's linear solver.
    pub solver: Solver,
}

/// One size's result.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRow {
    pub courses: usize,
    pub dimension: u32,
    pub kind: BlockKind,
    pub blocks: usize,
    pub contacts: usize,
    /// Unknowns of the step's system.
    pub unknowns: usize,
    /// Median wall time per step, milliseconds.
    pub median_ms_per_step: f64,
    /// The same relative to the smallest wall's of the same kind and
    /// dimension.
    pub ratio_to_baseline: f64,
    /// Wall-clock seconds per simulated second (median run).
    pub seconds_per_simulated_second: f64,
    /// The median run's work per step and where its time went.
    #[serde(flatten)]
    pub per_step: PerStep,
    /// Step cuts (open-close, displacement, penetration) and steps accepted
    /// unconverged, over the timed steps of the median run.
    pub cuts: usize,
    pub unconverged_steps: usize,
    /// The most open-close passes one timed step took, its cut attempts'
    /// included (median run).
    pub most_passes: usize,
    /// The largest centroid displacement of any brick since the wall was
    /// built, m.
    pub drift: f64,
    /// The process's peak resident memory so far, MB (Linux; 0 elsewhere).
    pub peak_memory_mb: f64,
    /// Iterative solver: conjugate-gradient iterations per solve, and the
    /// solves that reached the cap, over the timed steps of the median run.
    pub iterations_per_solve: f64,
    pub solver_fallbacks: usize,
    /// The runs made of this wall, this the median by time per step.
    pub runs: usize,
}

/// A run's work per step, and where its time went.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PerStep {
    /// Open-close passes, Newton-Raphson iterations, numeric
    /// factorizations and symbolic analyses per step.
    pub passes_per_step: f64,
    pub newton_per_step: f64,
    pub factorizations_per_step: f64,
    pub analyses_per_step: f64,
    /// Newton-Raphson moves on the whole tangent (friction's coupling to
    /// the normal force taken in), GMRES's products in them (each a
    /// product with the matrix and a solve on the factor) and the
    /// factorizations among them, per step.
    pub whole_tangent_moves_per_step: f64,
    pub whole_tangent_products_per_step: f64,
    pub whole_tangent_factorizations_per_step: f64,
    /// Residuals those moves' line searches assembled, per step: each an
    /// assembly of the contacts' forces at a trial share of a move.
    pub line_search_residuals_per_step: f64,
    /// Steps whose first pass started on the kept factor unweighed (the
    /// step's tangent not assembled to weigh it), as a share of the steps.
    pub unweighed_starts_per_step: f64,
    /// Steps whose first pass started from the foreseen motion instead of
    /// at rest, as a share of the steps.
    pub warm_starts_per_step: f64,
    /// Milliseconds per step in each phase, in step order, then `other`:
    /// the rest of the driver's step (each attempt's setup, the checks of
    /// its motion and penetration, impacts), so the phases add up to it.
    pub phase_ms_per_step: Vec<(String, f64)>,
}

impl PerStep {
    /// The counters and phase times of `stats` over its steps.
    pub fn of(stats: &Statistics) -> Self {
        let steps = stats.steps.max(1) as f64;
        let per_step = |count: usize| count as f64 / steps;
        Self {
            passes_per_step: per_step(stats.open_close_iterations),
            newton_per_step: per_step(stats.newton_iterations),
            factorizations_per_step: per_step(stats.factorizations),
            analyses_per_step: per_step(stats.symbolic_analyses),
            whole_tangent_moves_per_step: per_step(stats.whole_tangent_moves),
            whole_tangent_products_per_step: per_step(stats.whole_tangent_products),
            whole_tangent_factorizations_per_step: per_step(stats.whole_tangent_factorizations),
            line_search_residuals_per_step: per_step(stats.line_search_residuals),
            unweighed_starts_per_step: per_step(stats.unweighed_starts),
            warm_starts_per_step: per_step(stats.warm_starts),
            phase_ms_per_step: phase_ms_per_step(stats, steps),
        }
    }
}

/// Milliseconds per step in each phase of `stats`, then the rest of its
/// steps' wall time.
fn phase_ms_per_step(stats: &Statistics, steps: f64) -> Vec<(String, f64)> {
    let ms = |t: Duration| t.as_secs_f64() * 1e3 / steps;
    let mut phases: Vec<(String, f64)> = (stats.times.phases().iter())
        .map(|(name, t)| (name.to_string(), ms(*t)))
        .collect();
    let named: f64 = phases.iter().map(|(_, ms)| ms).sum();
    phases.push(("other".to_string(), (ms(stats.wall_time) - named).max(0.0)));
    phases
}

impl BenchRow {
    /// The row as a point of the scaling chart.
    pub fn point(&self) -> scaling::Point {
        scaling::Point {
            dimension: self.dimension,
            kind: self.kind,
            blocks: self.blocks,
            ms_per_step: self.median_ms_per_step,
        }
    }
}

/// What the benchmark needs of a driver beyond [`Simulation`].
pub(crate) trait Timed: Simulation {
    fn contact_count(&self) -> usize;
    fn unknown_count(&self) -> usize;
    /// Block `i`'s centroid, m (z = 0 in 2D).
    fn centroid(&self, i: usize) -> [f64; 3] {
        let v = self.history_values(i);
        let mut c = [0.0; 3];
        let d = Self::DIMENSION as usize;
        c[..d].copy_from_slice(&v[..d]);
        c
    }
}

macro_rules! timed {
    ($driver:ty) => {
        impl Timed for $driver {
            fn contact_count(&self) -> usize {
                self.contacts().len()
            }
            fn unknown_count(&self) -> usize {
                self.unknowns()
            }
        }
    };
}
timed!(dda_2d::Driver2d);
timed!(dda_3d::Driver3d);

/// The centroids of all blocks.
pub(crate) fn centroids<D: Timed>(driver: &D) -> Vec<[f64; 3]> {
    (0..driver.block_count())
        .map(|i| driver.centroid(i))
        .collect()
}

/// The largest distance of a block's centroid from `start`, m.
pub(crate) fn drift<D: Timed>(driver: &D, start: &[[f64; 3]]) -> f64 {
    start
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let c = driver.centroid(i);
            ((c[0] - s[0]).powi(2) + (c[1] - s[1]).powi(2) + (c[2] - s[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

/// The most open-close passes one step took, read after each step from
/// the driver's running count (a cut step's attempts included).
pub(crate) struct MostPasses {
    counted: usize,
    pub most: usize,
}

impl MostPasses {
    /// From the driver's count now, before the steps read.
    pub fn from(stats: &Statistics) -> Self {
        Self {
            counted: stats.open_close_iterations,
            most: 0,
        }
    }

    /// After a step: its passes weighed against the most so far.
    pub fn step(&mut self, stats: &Statistics) {
        let now = stats.open_close_iterations;
        self.most = self.most.max(now - self.counted);
        self.counted = now;
    }
}

/// One timed run of a wall.
struct Run {
    ms_per_step: f64,
    seconds_per_simulated_second: f64,
    stats: Statistics,
    most_passes: usize,
    drift: f64,
    blocks: usize,
    contacts: usize,
    unknowns: usize,
}

fn run(n: usize, dimension: u32, kind: BlockKind, options: &BenchOptions) -> anyhow::Result<Run> {
    let mut scene = wall(n, dimension, Stepping::Fixed, kind)?;
    scene.analysis.solver = options.solver;
    let steps = options.steps;
    match scene.build_any()? {
        AnyModel::Plane(mut m) => time_steps(&mut m.driver, steps),
        AnyModel::Space(mut m) => time_steps(&mut m.driver, steps),
    }
}

/// One untimed step, then `steps` timed ones at the driver's dt.
fn time_steps<D: Timed>(driver: &mut D, steps: usize) -> anyhow::Result<Run> {
    let start = centroids(driver);
    let dt = driver.dt();
    driver.step(dt)?;
    let before = driver.statistics().clone();
    let t0 = driver.time();
    let started = Instant::now();
    let mut passes = MostPasses::from(driver.statistics());
    for _ in 0..steps {
        driver.step(dt)?;
        passes.step(driver.statistics());
    }
    let wall = started.elapsed().as_secs_f64();
    Ok(Run {
        ms_per_step: wall * 1e3 / steps as f64,
        seconds_per_simulated_second: wall / (driver.time() - t0),
        stats: difference(driver.statistics(), &before),
        most_passes: passes.most,
        drift: drift(driver, &start),
        blocks: driver.block_count(),
        contacts: driver.contact_count(),
        unknowns: driver.unknown_count(),
    })
}

/// The counters and times of `after` since `before`.
fn difference(after: &Statistics, before: &Statistics) -> Statistics {
    Statistics {
        steps: after.steps - before.steps,
        open_close_iterations: after.open_close_iterations - before.open_close_iterations,
        newton_iterations: after.newton_iterations - before.newton_iterations,
        factorizations: after.factorizations - before.factorizations,
        whole_tangent_moves: after.whole_tangent_moves - before.whole_tangent_moves,
        whole_tangent_factorizations: after.whole_tangent_factorizations
            - before.whole_tangent_factorizations,
        whole_tangent_products: after.whole_tangent_products - before.whole_tangent_products,
        line_search_residuals: after.line_search_residuals - before.line_search_residuals,
        unweighed_starts: after.unweighed_starts - before.unweighed_starts,
        warm_starts: after.warm_starts - before.warm_starts,
        symbolic_analyses: after.symbolic_analyses - before.symbolic_analyses,
        open_close_cuts: after.open_close_cuts - before.open_close_cuts,
        displacement_cuts: after.displacement_cuts - before.displacement_cuts,
        penetration_cuts: after.penetration_cuts - before.penetration_cuts,
        newton_cuts: after.newton_cuts - before.newton_cuts,
        unsolved_steps: after.unsolved_steps - before.unsolved_steps,
        unconverged_steps: after.unconverged_steps - before.unconverged_steps,
        times: after.times.since(&before.times),
        wall_time: after.wall_time.saturating_sub(before.wall_time),
        iterative_solves: after.iterative_solves - before.iterative_solves,
        iterative_iterations: after.iterative_iterations - before.iterative_iterations,
        iterative_fallbacks: after.iterative_fallbacks - before.iterative_fallbacks,
        ..Statistics::default()
    }
}

/// Peak resident memory of this process, MB (Linux's VmHWM; 0 elsewhere).
pub(crate) fn peak_memory_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(0.0, |kb| kb / 1024.0)
}

/// Checks what is asked before anything runs.
pub(crate) fn check_walls(sizes: &[usize], dimensions: &[u32]) -> anyhow::Result<()> {
    anyhow::ensure!(!sizes.is_empty(), "--sizes needs at least one wall size");
    if let Some(n) = sizes.iter().find(|&&n| !(1..=1000).contains(&n)) {
        anyhow::bail!("--sizes: a wall is 1 to 1000 courses, not {n}");
    }
    if let Some(d) = dimensions.iter().find(|&&d| d != 2 && d != 3) {
        anyhow::bail!("--dimension: walls are 2D or 3D, not {d}");
    }
    anyhow::ensure!(!dimensions.is_empty(), "--dimension needs 2 or 3");
    Ok(())
}

/// Runs the benchmark: each dimension, each kind, each size in turn.
pub fn bench(options: &BenchOptions) -> anyhow::Result<Vec<BenchRow>> {
    check_walls(&options.sizes, &options.dimensions)?;
    anyhow::ensure!(options.steps >= 1, "--steps must be at least 1");
    let mut rows: Vec<BenchRow> = Vec::new();
    for &dimension in &options.dimensions {
        for &kind in &options.kinds {
            let first = rows.len();
            for &n in &options.sizes {
                rows.push(bench_one(n, dimension, kind, options)?);
            }
            let baseline = rows[first].median_ms_per_step;
            for r in &mut rows[first..] {
                r.ratio_to_baseline = r.median_ms_per_step / baseline;
            }
        }
    }
    Ok(rows)
}

fn bench_one(
    n: usize,
    dimension: u32,
    kind: BlockKind,
    options: &BenchOptions,
) -> anyhow::Result<BenchRow> {
    let mut runs = Vec::with_capacity(options.repeats);
    for _ in 0..options.repeats.max(1) {
        runs.push(run(n, dimension, kind, options)?);
    }
    runs.sort_by(|a, b| a.ms_per_step.total_cmp(&b.ms_per_step));
    let median = &runs[runs.len() / 2];
    let stats = &median.stats;
    Ok(BenchRow {
        courses: n,
        dimension,
        kind,
        blocks: median.blocks,
        contacts: median.contacts,
        unknowns: median.unknowns,
        median_ms_per_step: median.ms_per_step,
        ratio_to_baseline: 1.0,
        seconds_per_simulated_second: median.seconds_per_simulated_second,
        per_step: PerStep::of(stats),
        cuts: stats.cuts(),
        unconverged_steps: stats.unconverged_steps,
        most_passes: median.most_passes,
        drift: median.drift,
        peak_memory_mb: peak_memory_mb(),
        iterations_per_solve: stats.iterative_iterations as f64
            / stats.iterative_solves.max(1) as f64,
        solver_fallbacks: stats.iterative_fallbacks,
        runs: runs.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The whole-tangent moves, their products and factorisations, and
    /// the unweighed and warm starts, since the untimed step, per timed
    /// step.
    #[test]
    fn whole_tangent_work_is_counted_per_timed_step() {
        let before = Statistics {
            steps: 1,
            whole_tangent_moves: 2,
            whole_tangent_products: 9,
            line_search_residuals: 6,
            whole_tangent_factorizations: 1,
            unweighed_starts: 1,
            warm_starts: 1,
            ..Statistics::default()
        };
        let after = Statistics {
            steps: 5,
            whole_tangent_moves: 8,
            whole_tangent_products: 39,
            line_search_residuals: 20,
            whole_tangent_factorizations: 3,
            unweighed_starts: 4,
            warm_starts: 3,
            ..Statistics::default()
        };
        let work = PerStep::of(&difference(&after, &before));
        assert_eq!(work.whole_tangent_moves_per_step, 1.5);
        assert_eq!(work.whole_tangent_products_per_step, 7.5);
        assert_eq!(work.line_search_residuals_per_step, 3.5);
        assert_eq!(work.whole_tangent_factorizations_per_step, 0.5);
        assert_eq!(work.unweighed_starts_per_step, 0.75);
        assert_eq!(work.warm_starts_per_step, 0.5);
    }

    /// Timed steps' statistics keep their own wall time, and the phases
    /// with `other` add up to it: 2 steps in 10 ms, 4 ms of them named.
    #[test]
    fn the_phases_and_the_rest_add_up_to_the_timed_steps() {
        let ms = Duration::from_millis;
        let before = Statistics {
            steps: 1,
            wall_time: ms(3),
            ..Statistics::default()
        };
        let mut after = Statistics {
            steps: 3,
            wall_time: ms(13),
            ..Statistics::default()
        };
        after.times.assembly = ms(3);
        after.times.solve = ms(1);
        let timed = difference(&after, &before);
        assert_eq!(timed.wall_time, ms(10));
        let phases = PerStep::of(&timed).phase_ms_per_step;
        assert_eq!(phases.len(), 10);
        assert_eq!(phases[9].0, "other");
        assert!((phases[9].1 - 3.0).abs() < 1e-12, "{phases:?}");
        let sum: f64 = phases.iter().map(|(_, ms)| ms).sum();
        assert!((sum - 5.0).abs() < 1e-12, "{phases:?}");
    }
}
