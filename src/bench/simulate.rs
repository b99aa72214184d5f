//! `dda bench --simulate SECONDS`: each wall run for a simulated time with
//! the scene's automatic dt and penalty, as a user would run it: wall
//! seconds per simulated second, steps, cuts, unconverged steps and the
//! largest drift, under a wall-clock cap that reports how far a run got.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::Context;
use serde::Serialize;

use dda_core::Solver;

use super::{
    centroids, check_walls, drift, peak_memory_mb, scaling, shake, wall, MostPasses, PerStep,
    Stepping, Timed,
};
use crate::observe::Observer;
use crate::output::plain_number;
use crate::scene::{AnyModel, BlockKind};
use crate::step_log::StepsWriter;

/// What to run.
#[derive(Debug, Clone)]
pub struct SimulateOptions {
    /// Wall sizes: `n` courses of `n` bricks.
    pub sizes: Vec<usize>,
    pub kinds: Vec<BlockKind>,
    pub dimensions: Vec<u32>,
    /// Simulated time per run, s.
    pub seconds: f64,
    /// Wall-clock cap per run, s: a run still going then stops and reports
    /// the time it reached. Default 600.
    pub max_wall: f64,
    /// Runs per wall; the median by wall time per simulated second is
    /// reported.
    pub repeats: usize,
    /// Wall seconds between progress lines on stderr; `None`: silent.
    pub progress_every: Option<Duration>,
    /// The step's linear solver.
    pub solver: Solver,
    /// Time steps to run each wall at, s, the penalty automatic; empty:
    /// the automatic step.
    pub dts: Vec<f64>,
    /// The amplitude of the horizontal sine (2 Hz) each wall's base is
    /// shaken by for the whole run, m/s² ([`shake`]); `None`: at rest.
    pub shake: Option<f64>,
    /// Whether each wall settles under its weight before its timed run
    /// ([`crate::simulation::Simulation::settle`], in at most a scene's
    /// default number of static steps); its wall time is not the run's.
    pub settle: bool,
    /// A folder for each run's `steps.csv` ([`crate::step_log`]), named
    /// after its wall (`40x40_deformable_2d.csv`, with `_dt0.001` at a
    /// given step and `_run2` for a later repeat); `None`: none written.
    pub step_log: Option<PathBuf>,
}

/// One wall's run (the median of its repeats).
#[derive(Debug, Clone, Serialize)]
pub struct SimulateRow {
    pub courses: usize,
    pub dimension: u32,
    pub kind: BlockKind,
    pub blocks: usize,
    /// The nominal time step (automatic, or as given), s, and the
    /// automatic penalty (N/m per m of contact in 2D, per m² in 3D).
    pub dt: f64,
    /// Whether the time step was given rather than automatic.
    pub dt_given: bool,
    /// The amplitude of the sine the base was shaken by, m/s² (`None`: at
    /// rest).
    pub shake: Option<f64>,
    pub penalty: f64,
    /// Simulated time asked and reached, s.
    pub seconds: f64,
    pub reached: f64,
    /// Whether the run reached `seconds` within the wall-clock cap.
    pub completed: bool,
    /// Wall-clock time of the run, s, and per simulated second reached.
    pub wall_s: f64,
    pub seconds_per_simulated_second: f64,
    /// Accepted steps, their mean wall time (ms), step cuts (open-close,
    /// displacement, penetration) and steps accepted unconverged.
    pub steps: usize,
    pub ms_per_step: f64,
    pub cuts: usize,
    pub unconverged_steps: usize,
    /// The most open-close passes one step took, its cut attempts'
    /// included.
    pub most_passes: usize,
    /// The run's work per step and where its time went.
    #[serde(flatten)]
    pub per_step: PerStep,
    /// The largest centroid displacement of any brick from where it was
    /// built, over every step of the run, m; on a shaken base, with the
    /// base's own motion.
    pub drift: f64,
    /// The largest centroid displacement of any brick at the run's end, m:
    /// a wall at rest ends at its static settlement unless it creeps.
    pub end_drift: f64,
    /// The settling before the run (`--settle`): its wall time, s, and
    /// whether it settled; `None` without.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settle_s: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settled: Option<bool>,
    /// The settling's static steps, open-close passes and factorisations
    /// (its cut attempts' included); `None` without.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settle_steps: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settle_passes: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settle_factorizations: Option<usize>,
    /// The process's peak resident memory so far, MB (Linux; 0 elsewhere).
    pub peak_memory_mb: f64,
    /// The runs made of this wall, this the median by wall time per
    /// simulated second.
    pub runs: usize,
}

impl SimulateRow {
    /// The row as a point of the scaling chart.
    pub fn point(&self) -> scaling::Point {
        scaling::Point {
            dimension: self.dimension,
            kind: self.kind,
            blocks: self.blocks,
            ms_per_step: self.ms_per_step,
        }
    }
}

/// Runs every wall for `options.seconds` of simulated time.
pub fn simulate(options: &SimulateOptions) -> anyhow::Result<Vec<SimulateRow>> {
    check_walls(&options.sizes, &options.dimensions)?;
    anyhow::ensure!(
        options.seconds.is_finite() && options.seconds > 0.0,
        "--simulate takes a simulated time in seconds, more than 0, got {}",
        options.seconds
    );
    anyhow::ensure!(
        options.max_wall.is_finite() && options.max_wall > 0.0,
        "--max-wall takes wall-clock seconds, more than 0, got {}",
        options.max_wall
    );
    if let Some(a) = options.shake {
        anyhow::ensure!(
            a.is_finite() && a > 0.0,
            "--shake takes the amplitude of the base's acceleration in m/s², more than 0, got {a}"
        );
    }
    for &dt in &options.dts {
        anyhow::ensure!(
            dt.is_finite() && dt > 0.0,
            "--dt takes time steps in seconds, more than 0, got {dt}"
        );
    }
    if let Some(dir) = &options.step_log {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("--step-log: cannot create {}", dir.display()))?;
    }
    let steppings: Vec<Stepping> = if options.dts.is_empty() {
        vec![Stepping::Automatic]
    } else {
        options.dts.iter().map(|&dt| Stepping::Given(dt)).collect()
    };
    let mut rows = Vec::new();
    for &dimension in &options.dimensions {
        for &kind in &options.kinds {
            for &n in &options.sizes {
                for &stepping in &steppings {
                    let mut runs = (0..options.repeats.max(1))
                        .map(|k| run(n, dimension, kind, stepping, options, k))
                        .collect::<anyhow::Result<Vec<_>>>()?;
                    runs.sort_by(|a, b| {
                        a.seconds_per_simulated_second
                            .total_cmp(&b.seconds_per_simulated_second)
                    });
                    let (k, made) = (runs.len() / 2, runs.len());
                    rows.push(SimulateRow {
                        runs: made,
                        ..runs.swap_remove(k)
                    });
                }
            }
        }
    }
    Ok(rows)
}

/// One run of the `n` × `n` wall of `kind` in `dimension`, stepped as
/// `stepping` says, for `options.seconds` (the `repeat`-th of its runs:
/// its step log is named so).
pub(crate) fn run(
    n: usize,
    dimension: u32,
    kind: BlockKind,
    stepping: Stepping,
    options: &SimulateOptions,
    repeat: usize,
) -> anyhow::Result<SimulateRow> {
    let mut scene = wall(n, dimension, stepping, kind)?;
    scene.analysis.solver = options.solver;
    if let Some(amplitude) = options.shake {
        shake(&mut scene, amplitude, options.seconds);
    }
    let what = format!("{n} × {n} wall, {}", scaling::series_name(dimension, kind));
    let log = options.step_log.as_ref().map(|dir| {
        let kind = scaling::kind_name(kind);
        let dt = match stepping {
            Stepping::Given(dt) => format!("_dt{dt}"),
            _ => String::new(),
        };
        let again = if repeat > 0 {
            format!("_run{}", repeat + 1)
        } else {
            String::new()
        };
        dir.join(format!("{n}x{n}_{kind}_{dimension}d{dt}{again}.csv"))
    });
    let log = log.as_deref();
    let mut row = match scene.build_any()? {
        AnyModel::Plane(mut m) => simulate_driver(&mut m.driver, options, &what, log)?,
        AnyModel::Space(mut m) => simulate_driver(&mut m.driver, options, &what, log)?,
    };
    row.courses = n;
    row.dimension = dimension;
    row.kind = kind;
    row.dt_given = matches!(stepping, Stepping::Given(_));
    row.shake = options.shake;
    Ok(row)
}

fn simulate_driver<D: Timed>(
    driver: &mut D,
    options: &SimulateOptions,
    what: &str,
    log: Option<&Path>,
) -> anyhow::Result<SimulateRow> {
    let mut log = match log {
        Some(path) => Some(StepsWriter::create(path, &*driver)?),
        None => None,
    };
    let settling = match options.settle {
        true => Some(driver.settle(crate::scene::Settle::default().steps)?),
        false => None,
    };
    let start = centroids(driver);
    let cap = Duration::from_secs_f64(options.max_wall);
    let started = Instant::now();
    let mut last_line = started;
    let mut last_written = started;
    let mut largest = 0.0f64;
    let mut passes = MostPasses::from(driver.statistics());
    let end = driver.time() + options.seconds;
    let mut logged = Ok(());
    let advanced = driver.advance_while(end, &mut |d: &D| {
        largest = largest.max(drift(d, &start));
        passes.step(d.statistics());
        let now = Instant::now();
        if let Some(log) = &mut log {
            log.on_step(d);
            // Written as the run goes, a batch a second.
            if now - last_written >= Duration::from_secs(1) {
                last_written = now;
                logged = log.on_output(d);
            }
        }
        if let Some(every) = options.progress_every {
            if now - last_line >= every {
                last_line = now;
                eprintln!(
                    "{what}: t = {:.4} of {} s, {} steps, {:.1} s of wall time",
                    d.time(),
                    plain_number(options.seconds),
                    d.statistics().steps,
                    (now - started).as_secs_f64()
                );
            }
        }
        logged.is_ok() && now - started < cap
    });
    // The steps taken are written even where the run failed, whose error
    // comes first.
    let flushed = match &mut log {
        Some(log) => log.on_finish(&*driver, None),
        None => Ok(()),
    };
    let completed = advanced?;
    logged.and(flushed)?;
    let wall_s = started.elapsed().as_secs_f64();
    let stats = driver.statistics();
    let reached = driver.time();
    if !completed {
        eprintln!(
            "{what}: stopped at the wall-clock cap of {} s, at t = {reached:.4} of {} s",
            plain_number(options.max_wall),
            plain_number(options.seconds)
        );
    }
    Ok(SimulateRow {
        courses: 0,
        dimension: D::DIMENSION,
        kind: BlockKind::Deformable,
        blocks: driver.block_count(),
        dt: driver.dt(),
        dt_given: false,
        shake: None,
        penalty: driver.penalty(),
        seconds: options.seconds,
        reached,
        completed,
        wall_s,
        seconds_per_simulated_second: wall_s / reached.max(f64::MIN_POSITIVE),
        steps: stats.steps,
        ms_per_step: wall_s * 1e3 / stats.steps.max(1) as f64,
        cuts: stats.cuts(),
        unconverged_steps: stats.unconverged_steps,
        most_passes: passes.most,
        per_step: PerStep::of(stats),
        drift: largest,
        end_drift: drift(driver, &start),
        settle_s: settling.as_ref().map(|s| s.wall_time.as_secs_f64()),
        settle_steps: settling.as_ref().map(|s| s.steps),
        settle_passes: settling
            .as_ref()
            .map(|s| s.statistics.open_close_iterations),
        settle_factorizations: settling.as_ref().map(|s| s.statistics.factorizations),
        settled: settling.map(|s| s.settled),
        peak_memory_mb: peak_memory_mb(),
        runs: 1,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A 40 × 40 rigid wall's run: `wall_s` s for a simulated second,
    /// drifting `drift` m and ending there.
    pub(crate) fn row(wall_s: f64, drift: f64) -> SimulateRow {
        SimulateRow {
            courses: 40,
            dimension: 2,
            kind: BlockKind::Rigid,
            blocks: 1621,
            dt: 9.5e-3,
            dt_given: false,
            shake: None,
            penalty: 2.8e10,
            seconds: 1.0,
            reached: 1.0,
            completed: true,
            wall_s,
            seconds_per_simulated_second: wall_s,
            steps: 106,
            ms_per_step: wall_s * 1e3 / 106.0,
            cuts: 0,
            unconverged_steps: 0,
            most_passes: 1,
            per_step: Default::default(),
            drift,
            end_drift: drift,
            settle_s: None,
            settle_steps: None,
            settle_passes: None,
            settle_factorizations: None,
            settled: None,
            peak_memory_mb: 80.0,
            runs: 1,
        }
    }
}
