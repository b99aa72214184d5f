//! Running a scene to its end while writing the outputs.

use std::io::IsTerminal;
use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Context};
use dda_contact::LawRegistry;
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};

use crate::output::{write_json, ContactWriter, HistoryWriter};
use crate::scene::{AnyModel, Model, Scene};
use crate::simulation::Simulation;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    Finished,
    Failed,
}

/// What `summary.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub scene: String,
    /// 2 or 3.
    #[serde(default = "two")]
    pub dimension: u32,
    pub status: Status,
    /// Why the run stopped early (failed runs only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    pub blocks: usize,
    pub steps: usize,
    /// Simulated time reached, seconds.
    pub time: f64,
    /// Simulated time asked for, seconds.
    pub duration: f64,
    /// Seconds of wall-clock time for the run.
    pub wall_time: f64,
    pub open_close_iterations: usize,
    pub newton_iterations: usize,
    pub factorizations: usize,
    pub open_close_cuts: usize,
    pub displacement_cuts: usize,
    pub penalty_raises: usize,
    /// Steps cut because a contact penetrated too deep.
    #[serde(default)]
    pub penetration_cuts: usize,
    /// Steps accepted at the smallest time step without open-close agreement.
    pub unconverged_steps: usize,
    /// Open-close passes whose Newton iteration kept its best, unconverged iterate.
    #[serde(default)]
    pub newton_failures: usize,
    /// Accepted steps ending with a penetration deeper than the limit, and the deepest (m).
    #[serde(default)]
    pub deep_penetration_steps: usize,
    #[serde(default)]
    pub deepest_penetration: f64,
    /// Total energy at the end (J, per unit thickness in 2D) when nothing
    /// works on the blocks, and how far it rose above its lowest value in
    /// the steps where it rose beyond a quarter of the energy in play.
    #[serde(default)]
    pub energy: f64,
    #[serde(default)]
    pub energy_growth_steps: usize,
    #[serde(default)]
    pub energy_growth: f64,
    /// What went wrong in the run that the results depend on; also printed.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// Normal penalty at the end (after any raises).
    pub penalty: f64,
    /// Nominal time step.
    pub dt: f64,
    /// Why automatic values were chosen.
    pub notes: Vec<String>,
    /// The files written in the output directory, this one included.
    #[serde(default)]
    pub outputs: Vec<String>,
}

fn two() -> u32 {
    2
}

/// What a run prints on stderr besides errors.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunOptions {
    /// A progress bar.
    pub progress: bool,
    /// The driver's notes on automatic choices, at the start.
    pub notes: bool,
}

/// Runs a scene file, writing `history.csv` (and `contacts.csv` when the
/// scene's output asks for it) and `summary.json` into `out_dir`; progress and notes appear only when stderr is a terminal.
pub fn run(scene_path: &Path, out_dir: &Path) -> anyhow::Result<Summary> {
    let terminal = std::io::stderr().is_terminal();
    run_with(
        scene_path,
        out_dir,
        RunOptions {
            progress: terminal,
            notes: terminal,
        },
    )
}

/// [`run`] with explicit options. A run that fails midway still writes
/// `summary.json` (status "failed") and keeps the rows it wrote.
pub fn run_with(scene_path: &Path, out_dir: &Path, options: RunOptions) -> anyhow::Result<Summary> {
    run_with_registry(scene_path, out_dir, options, &LawRegistry::with_builtin())
}

/// [`run_with`] with `Custom` joint laws built through `registry`.
pub fn run_with_registry(
    scene_path: &Path,
    out_dir: &Path,
    options: RunOptions,
    registry: &LawRegistry,
) -> anyhow::Result<Summary> {
    let scene = Scene::load(scene_path)?;
    run_scene(&scene, out_dir, options, registry)
}

/// Runs a loaded scene of either dimension (named by [`Scene::origin`] in
/// the summary).
pub fn run_scene(
    scene: &Scene,
    out_dir: &Path,
    options: RunOptions,
    registry: &LawRegistry,
) -> anyhow::Result<Summary> {
    match scene.build_any_with(registry)? {
        AnyModel::Plane(model) => run_model(scene, model, out_dir, options),
        AnyModel::Space(model) => run_model(scene, model, out_dir, options),
    }
}

/// Runs a built model to its end, writing the outputs of its dimension.
pub fn run_model<S: Simulation>(
    scene: &Scene,
    mut model: Model<S>,
    out_dir: &Path,
    options: RunOptions,
) -> anyhow::Result<Summary> {
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let history_path = out_dir.join("history.csv");
    let mut writers = Writers {
        history: HistoryWriter::create(&history_path, S::HISTORY_HEADER)?,
        contacts: None,
    };
    let mut outputs = vec!["history.csv".to_string()];
    if model.write_contacts {
        writers.contacts = Some(ContactWriter::create(&out_dir.join("contacts.csv"))?);
        outputs.push("contacts.csv".to_string());
    }
    outputs.push("summary.json".to_string());
    if options.notes {
        for note in model.driver.notes() {
            eprintln!("note: {note}");
        }
    }
    let bar = progress_bar(options.progress);
    let started = Instant::now();
    let result = advance(&mut model, &mut writers, &bar);
    bar.finish_and_clear();
    let result = result.with_context(|| {
        format!(
            "the run failed at t = {} s, step {} ({} keeps the rows written until then)",
            model.driver.time(),
            model.driver.statistics().steps,
            history_path.display()
        )
    });

    let driver = &model.driver;
    let stats = driver.statistics();
    let summary = Summary {
        scene: scene.origin().to_string(),
        dimension: S::DIMENSION,
        status: if result.is_ok() {
            Status::Finished
        } else {
            Status::Failed
        },
        error: result.as_ref().err().map(|e| format!("{e:#}")),
        blocks: driver.block_count(),
        steps: stats.steps,
        time: driver.time(),
        duration: model.duration,
        wall_time: started.elapsed().as_secs_f64(),
        open_close_iterations: stats.open_close_iterations,
        newton_iterations: stats.newton_iterations,
        factorizations: stats.factorizations,
        open_close_cuts: stats.open_close_cuts,
        displacement_cuts: stats.displacement_cuts,
        penalty_raises: stats.penalty_raises,
        penetration_cuts: stats.penetration_cuts,
        unconverged_steps: stats.unconverged_steps,
        newton_failures: stats.newton_failures,
        deep_penetration_steps: stats.deep_penetration_steps,
        deepest_penetration: stats.deepest_penetration,
        energy: stats.energy,
        energy_growth_steps: stats.energy_growth_steps,
        energy_growth: stats.energy_growth,
        warnings: warnings(stats),
        penalty: driver.penalty(),
        dt: driver.dt(),
        notes: driver.notes().to_vec(),
        outputs,
    };
    write_json(&out_dir.join("summary.json"), &summary)?;
    for warning in &summary.warnings {
        eprintln!("warning: {warning}");
    }
    result.map(|_| summary)
}

/// The driver's reports of steps it could not do well.
fn warnings(stats: &dda_core::Statistics) -> Vec<String> {
    let mut out = Vec::new();
    if stats.unconverged_steps > 0 {
        out.push(format!(
            "{} steps could not converge even at the smallest time step and were accepted without \
             open-close agreement; their contact states may be wrong (try a smaller dt, a softer penalty \
             or a larger open_close_limit)",
            stats.unconverged_steps
        ));
    }
    if stats.deep_penetration_steps > 0 {
        out.push(format!(
            "{} steps ended with a contact penetrating beyond the allowed bound (deepest {:.3e} m); \
             blocks overlap more than the penalty method allows (try a stiffer penalty or a smaller dt)",
            stats.deep_penetration_steps, stats.deepest_penetration
        ));
    }
    if stats.energy_growth_steps > 0 {
        out.push(format!(
            "the total energy rose by up to {:.3e} J in {} steps although nothing did work on the blocks; \
             the method added energy and the results are suspect (try a smaller dt, or leave raise_penalty off)",
            stats.energy_growth, stats.energy_growth_steps
        ));
    }
    out
}

/// The files written as the run goes.
struct Writers {
    history: HistoryWriter,
    contacts: Option<ContactWriter>,
}

/// Steps to the end, writing a history row set at time 0 and at every
/// output time (every step without an interval).
fn advance<S: Simulation>(
    model: &mut Model<S>,
    writers: &mut Writers,
    bar: &ProgressBar,
) -> anyhow::Result<()> {
    let duration = model.duration;
    let driver = &mut model.driver;
    record(driver, writers, bar, duration)?;
    match model.output_interval {
        Some(interval) => {
            for k in 1.. {
                let mut t = k as f64 * interval;
                // The last output is the end itself, not a hair before or after it.
                if t >= duration - 1e-9 * interval {
                    t = duration;
                }
                driver.advance_to(t)?;
                record(driver, writers, bar, duration)?;
                if t == duration {
                    break;
                }
            }
        }
        None => {
            // The driver's own end test (as in advance_to).
            while duration - driver.time() > 1e-9 * driver.dt() {
                driver.step(duration - driver.time())?;
                record(driver, writers, bar, duration)?;
            }
        }
    }
    Ok(())
}

fn record<S: Simulation>(
    driver: &S,
    writers: &mut Writers,
    bar: &ProgressBar,
    duration: f64,
) -> anyhow::Result<()> {
    for i in 0..driver.block_count() {
        if !driver.is_finite(i) {
            bail!(
                "block {i} has a non-finite position or velocity: the model is unstable (try a smaller dt or penalty)"
            );
        }
    }
    writers.history.write(driver)?;
    if let Some(contacts) = &mut writers.contacts {
        contacts.write(driver)?;
    }
    bar.set_position((driver.time() / duration * 1000.0).round() as u64);
    bar.set_message(format!(
        "t = {:.4e} s, step {}",
        driver.time(),
        driver.statistics().steps
    ));
    Ok(())
}

fn progress_bar(show: bool) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(1000);
    if let Ok(style) =
        ProgressStyle::with_template("{bar:40} {percent:>3}% {msg} [{elapsed_precise}, {eta} left]")
    {
        bar.set_style(style);
    }
    bar
}
