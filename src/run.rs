//! Running a scene to its end while writing the outputs.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context};
use dda_contact::LawRegistry;
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};

use crate::output::{round_time, write_json, ContactWriter, HistoryWriter};
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
    #[serde(default, skip_serializing_if = "not_finite")]
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
    /// Steps whose open-close passes cycled between two sets of states,
    /// settled by keeping each cycling contact sliding or closed.
    #[serde(default)]
    pub cycle_breaks: usize,
    /// The first contacts that cycled: when, which, between which states,
    /// and the state kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cycles: Vec<CycleReport>,
    /// Open-close passes solved again with friction's coupling to the
    /// normal force in the tangent after the symmetric iteration failed.
    #[serde(default)]
    pub coupled_solves: usize,
    /// Open-close passes whose Newton iteration kept its best, unconverged iterate.
    #[serde(default)]
    pub newton_failures: usize,
    /// Accepted steps ending with a penetration deeper than the limit, and the deepest (m).
    #[serde(default)]
    pub deep_penetration_steps: usize,
    #[serde(default, skip_serializing_if = "not_finite")]
    pub deepest_penetration: f64,
    /// Total energy at the end (J, per unit thickness in 2D) when nothing
    /// works on the blocks, and how far it rose above its lowest value in
    /// the steps where it rose beyond a quarter of the energy in play.
    #[serde(default, skip_serializing_if = "not_finite")]
    pub energy: f64,
    #[serde(default)]
    pub energy_growth_steps: usize,
    #[serde(default, skip_serializing_if = "not_finite")]
    pub energy_growth: f64,
    /// What went wrong in the run that the results depend on; also printed.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// Normal penalty at the end (after any raises).
    #[serde(default, skip_serializing_if = "not_finite")]
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

/// Numbers JSON cannot hold are left out rather than written as null.
fn not_finite(v: &f64) -> bool {
    !v.is_finite()
}

/// What a run prints on stderr besides errors.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunOptions {
    /// A progress bar.
    pub progress: bool,
    /// The driver's notes on automatic choices, at the start.
    pub notes: bool,
    /// Without a bar: a progress line at the first output time after this
    /// much wall-clock time, and again each time as much has passed (so a
    /// short run prints none). `None`: no lines.
    pub progress_lines: Option<Duration>,
}

/// How often a run without a terminal reports its progress by default.
pub const PROGRESS_EVERY: Duration = Duration::from_secs(5);

/// Where `dda run SCENE` writes when no folder is given: `out/<scene file
/// name without .ron>` under the current folder.
pub fn default_out_dir(scene_path: &Path) -> PathBuf {
    let stem = scene_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "scene".to_string());
    Path::new("out").join(stem)
}

/// What a run is expected to take and write, before it runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// Steps at the nominal time step (cut steps come on top).
    pub steps: f64,
    /// Output times, time 0 included.
    pub output_times: f64,
    /// Rows of `history.csv` (one per block per output time).
    pub rows: f64,
    /// Approximate size of `history.csv` in bytes.
    pub bytes: f64,
    /// What is absurd about it, with what to change.
    pub warnings: Vec<String>,
}

/// More steps than this is a warning in [`estimate`].
pub const MAX_SENSIBLE_STEPS: f64 = 1e7;
/// A `history.csv` larger than this (bytes) is a warning in [`estimate`].
pub const MAX_SENSIBLE_BYTES: f64 = 1e9;

/// The steps and output size a built scene asks for.
pub fn estimate(model: &AnyModel) -> Estimate {
    let (duration, dt) = (model.duration(), model.dt());
    let ratio = duration / dt;
    // A whole number of steps that division leaves a hair above is whole.
    let steps = if (ratio - ratio.round()).abs() <= 1e-9 * ratio {
        ratio.round()
    } else {
        ratio.ceil()
    };
    let output_times = match model.output_interval() {
        Some(interval) => (duration / interval).ceil().min(steps) + 1.0,
        None => steps + 1.0,
    };
    let blocks = model.block_count() as f64;
    let rows = output_times * blocks;
    // Numbers take about 20 characters each as written, with their commas.
    let fields = if model.dimension() == 3 { 18.0 } else { 9.0 };
    let bytes = rows * (20.0 * fields + 20.0);
    let mut warnings = Vec::new();
    if steps > MAX_SENSIBLE_STEPS {
        warnings.push(format!(
            "{steps:.3e} steps ({duration} s at dt {dt:.3e} s) will take a very long time; check the duration, give a larger dt, or a softer penalty (an automatic dt follows the penalty)"
        ));
    }
    if bytes > MAX_SENSIBLE_BYTES {
        warnings.push(format!(
            "history.csv would be about {}; give a larger output.interval",
            bytes_text(bytes)
        ));
    }
    Estimate {
        steps,
        output_times,
        rows,
        bytes,
        warnings,
    }
}

/// "12 kB", "3.4 MB", "1.2 GB".
pub fn bytes_text(bytes: f64) -> String {
    let units = [("GB", 1e9), ("MB", 1e6), ("kB", 1e3)];
    for (unit, size) in units {
        if bytes >= size {
            return format!("{:.2} {unit}", bytes / size);
        }
    }
    format!("{bytes:.0} B")
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
            progress_lines: None,
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
        for note in model.all_notes() {
            eprintln!("note: {note}");
        }
    }
    let started = Instant::now();
    let mut progress = Progress {
        bar: progress_bar(options.progress),
        every: options.progress_lines.filter(|_| !options.progress),
        started,
        last: started,
        known: Known::default(),
    };
    let result = advance(&mut model, &mut writers, &mut progress);
    progress.bar.finish_and_clear();
    let result = result.with_context(|| {
        format!(
            "the run failed at t = {} s, step {} ({} keeps the rows written until then)",
            model.driver.time(),
            model.driver.statistics().steps,
            history_path.display()
        )
    });

    let driver = &model.driver;
    let mut stats = driver.statistics().clone();
    let (mut time, mut penalty) = (driver.time(), driver.penalty());
    let mut warnings = warnings(&stats);
    // A run that blew up may leave numbers JSON cannot hold (they would be
    // null); their last finite values stand in, said so.
    let known = &progress.known;
    let mut replaced = Vec::new();
    let mut keep = |name: &str, value: &mut f64, good: Option<f64>| {
        if !value.is_finite() {
            match good {
                Some(good) => {
                    replaced.push(format!("{name} ({value}; {good} given)"));
                    *value = good;
                }
                None => replaced.push(format!("{name} ({value}; left out)")),
            }
        }
    };
    keep("time", &mut time, known.time);
    keep("penalty", &mut penalty, known.penalty);
    keep("energy", &mut stats.energy, known.energy);
    keep(
        "energy_growth",
        &mut stats.energy_growth,
        known.energy_growth,
    );
    keep(
        "deepest_penetration",
        &mut stats.deepest_penetration,
        known.deepest_penetration,
    );
    if !replaced.is_empty() {
        warnings.push(format!(
            "not finite when the run stopped: {}; the values given are the last finite ones written, at an output time",
            replaced.join(", ")
        ));
    }
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
        time: round_time(time),
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
        cycle_breaks: stats.cycle_breaks,
        cycles: stats.cycles.iter().map(CycleReport::from).collect(),
        coupled_solves: stats.coupled_solves,
        newton_failures: stats.newton_failures,
        deep_penetration_steps: stats.deep_penetration_steps,
        deepest_penetration: stats.deepest_penetration,
        energy: stats.energy,
        energy_growth_steps: stats.energy_growth_steps,
        energy_growth: stats.energy_growth,
        warnings,
        penalty,
        dt: driver.dt(),
        notes: model.all_notes(),
        outputs,
    };
    write_json(&out_dir.join("summary.json"), &summary)?;
    for warning in &summary.warnings {
        eprintln!("warning: {warning}");
    }
    result.map(|_| summary)
}

/// A contact whose open-close state cycled in a step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CycleReport {
    /// End of the step (s).
    pub time: f64,
    /// The entering block and the block it touches.
    pub blocks: [u32; 2],
    /// The entering vertex and the feature (edge, face or vertex) entered.
    pub features: [u32; 2],
    /// The two states the passes alternated between, and the one kept.
    pub between: [String; 2],
    pub kept: String,
}

impl From<&dda_core::Cycle> for CycleReport {
    fn from(c: &dda_core::Cycle) -> Self {
        let name = |s: dda_core::ContactState| format!("{s:?}").to_lowercase();
        Self {
            time: round_time(c.time),
            blocks: [c.key.block_a, c.key.block_b],
            features: [c.key.feature_a, c.key.feature_b],
            between: [name(c.between[0]), name(c.between[1])],
            kept: name(c.kept),
        }
    }
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
    if let Some(first) = stats.cycles.first() {
        let c = CycleReport::from(first);
        out.push(format!(
            "in {} steps some contacts' open-close passes alternated between two states; each was \
             settled by keeping the state that stores less work (sliding over locked, closed over open). \
             The first: at t = {} s, the contact of block {} on block {}, {} and {}, kept {} \
             (summary.json lists up to 20 under \"cycles\")",
            stats.cycle_breaks, c.time, c.blocks[0], c.blocks[1], c.between[0], c.between[1], c.kept
        ));
    }
    if stats.energy_growth_steps > 0 {
        // The advice follows what the run saw: friction itself never adds
        // energy, so a rise comes from raised penalties, unsolved passes or
        // steps accepted without agreement.
        let mut causes = Vec::new();
        if stats.penalty_raises > 0 {
            causes.push(format!(
                "the penalty was raised {} times, which multiplies the force of every existing overlap: leave raise_penalty off",
                stats.penalty_raises
            ));
        }
        if stats.newton_failures > 0 {
            causes.push(format!(
                "{} passes kept an unconverged Newton-Raphson iterate: a softer penalty or a smaller dt makes the springs less stiff against the blocks' inertia",
                stats.newton_failures
            ));
        }
        if stats.unconverged_steps > 0 {
            causes.push("steps were accepted without open-close agreement (see above)".into());
        }
        let advice = if causes.is_empty() {
            "no cut, raise or unconverged pass explains it; please report the scene".to_string()
        } else {
            causes.join("; ")
        };
        out.push(format!(
            "the total energy rose by up to {:.3e} J in {} steps although nothing did work on the blocks; \
             the method added energy and the results are suspect ({advice})",
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
    progress: &mut Progress,
) -> anyhow::Result<()> {
    let duration = model.duration;
    let driver = &mut model.driver;
    record(driver, writers, progress, duration)?;
    match model.output_interval {
        Some(interval) => {
            for k in 1.. {
                let mut t = k as f64 * interval;
                // The last output is the end itself, not a hair before or after it.
                if t >= duration - 1e-9 * interval {
                    t = duration;
                }
                driver.advance_to(t)?;
                record(driver, writers, progress, duration)?;
                if t == duration {
                    break;
                }
            }
        }
        None => {
            // The driver's own end test (as in advance_to).
            while duration - driver.time() > 1e-9 * driver.dt() {
                driver.step(duration - driver.time())?;
                record(driver, writers, progress, duration)?;
            }
        }
    }
    Ok(())
}

/// The last finite values, at an output time, of the summary's numbers.
#[derive(Debug, Clone, Default)]
struct Known {
    time: Option<f64>,
    penalty: Option<f64>,
    energy: Option<f64>,
    energy_growth: Option<f64>,
    deepest_penetration: Option<f64>,
}

impl Known {
    fn update<S: Simulation>(&mut self, driver: &S) {
        let stats = driver.statistics();
        let pairs = [
            (&mut self.time, driver.time()),
            (&mut self.penalty, driver.penalty()),
            (&mut self.energy, stats.energy),
            (&mut self.energy_growth, stats.energy_growth),
            (&mut self.deepest_penetration, stats.deepest_penetration),
        ];
        for (slot, value) in pairs {
            if value.is_finite() {
                *slot = Some(value);
            }
        }
    }
}

/// The bar, or the lines printed when there is no terminal, and what the
/// run last wrote.
struct Progress {
    bar: ProgressBar,
    every: Option<Duration>,
    started: Instant,
    last: Instant,
    /// The last finite value of each number of the summary that a blown-up
    /// run can lose, as of the last output time (see [`Known`]).
    known: Known,
}

impl Progress {
    fn line<S: Simulation>(&mut self, driver: &S, duration: f64) {
        let Some(every) = self.every else {
            return;
        };
        let now = Instant::now();
        if now.duration_since(self.last) < every {
            return;
        }
        self.last = now;
        let elapsed = now.duration_since(self.started).as_secs_f64();
        let done = driver.time() / duration;
        let left = if done > 0.0 {
            format!(", about {:.0} s left", elapsed * (1.0 - done) / done)
        } else {
            String::new()
        };
        eprintln!(
            "t = {:.4} s of {duration} s ({:.0} %), step {}, {elapsed:.0} s elapsed{left}",
            driver.time(),
            100.0 * done,
            driver.statistics().steps,
        );
    }
}

fn record<S: Simulation>(
    driver: &S,
    writers: &mut Writers,
    progress: &mut Progress,
    duration: f64,
) -> anyhow::Result<()> {
    progress.line(driver, duration);
    let bar = &progress.bar;
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
    progress.known.update(driver);
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
