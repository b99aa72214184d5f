//! Running a scene to its end while writing the outputs.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context};
use dda_contact::LawRegistry;

use crate::checkpoint::{Checkpoint, Schedule};
use crate::guard::Guards;
use crate::observe::{Cursor, Observer, RunView};
use crate::output::{ContactWriter, HistoryWriter, PointsWriter};
use crate::progress::Progress;
use crate::scene::{AnyModel, Model, Scene};
use crate::simulation::Simulation;
use crate::step_log::StepsWriter;
use crate::summary::{SettleReport, SummaryWriter};
pub use crate::summary::{Status, Summary};
use crate::vtk::VtkWriter;

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
    /// VTK frames for ParaView whatever the scene's `output.vtk` says.
    pub vtk: bool,
    /// `steps.csv` whatever the scene's `output.steps` says.
    pub steps: bool,
    /// Leave the summary's warnings off stderr (they stay in summary.json).
    pub quiet: bool,
    /// Simulated seconds between checkpoints (`DIR/checkpoint.bin`, at the
    /// first output time after each), none when `None`.
    pub checkpoint_every: Option<f64>,
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
    /// Approximate size of `steps.csv` in bytes (a row per step), 0 where
    /// the run does not write it.
    pub steps_bytes: f64,
    /// Approximate peak memory of the run in bytes ([`memory_estimate`]).
    pub memory: f64,
    /// What is absurd about it, with what to change.
    pub warnings: Vec<String>,
}

/// More steps than this is a warning in [`estimate`].
pub const MAX_SENSIBLE_STEPS: f64 = 1e7;
/// A `history.csv` or `steps.csv` larger than this (bytes) is a warning
/// in [`estimate`].
pub const MAX_SENSIBLE_BYTES: f64 = 1e9;
/// A row of `steps.csv` as written, about: eighteen fields, most of them
/// short counts and times in ms, the time and energy at full precision
/// (78 bytes a row on the drum column's run, 91 on the 3D jointed slope's,
/// 117 on the 10,051-block wall's).
pub const STEP_ROW_BYTES: f64 = 100.0;

/// The steps and output size a built scene asks for.
pub fn estimate(model: &AnyModel) -> Estimate {
    match model {
        AnyModel::Plane(m) => estimate_model(m),
        AnyModel::Space(m) => estimate_model(m),
    }
}

/// [`estimate`] of a model of either dimension.
pub fn estimate_model<S: Simulation>(model: &Model<S>) -> Estimate {
    let (duration, dt) = (model.duration, model.driver.dt());
    let ratio = duration / dt;
    // A whole number of steps that division leaves a hair above is whole.
    let steps = if (ratio - ratio.round()).abs() <= 1e-9 * ratio {
        ratio.round()
    } else {
        ratio.ceil()
    };
    let output_times = match model.output_interval {
        Some(interval) => (duration / interval).ceil().min(steps) + 1.0,
        None => steps + 1.0,
    };
    let blocks = model.driver.block_count() as f64;
    let rows = output_times * blocks;
    // Numbers take about 20 characters each as written, with their commas.
    let fields = if S::DIMENSION == 3 { 18.0 } else { 9.0 };
    let bytes = rows * (20.0 * fields + 20.0);
    let steps_bytes = if model.write_steps {
        steps * STEP_ROW_BYTES
    } else {
        0.0
    };
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
    if steps_bytes > MAX_SENSIBLE_BYTES {
        warnings.push(format!(
            "steps.csv would be about {} (a row per step); leave output.steps and --steps out",
            bytes_text(steps_bytes)
        ));
    }
    Estimate {
        steps,
        output_times,
        rows,
        bytes,
        steps_bytes,
        memory: memory_estimate(blocks, S::DIMENSION),
        warnings,
    }
}

/// Peak memory of a run of `blocks` blocks (bytes): the step's matrix,
/// its factor and the contacts grow with the blocks and the square of
/// their DOF. Measured on walls of running bond: 45 MB at 1,621 deformable
/// 2D blocks, about 28 kB a block over a 20 MB base; 3D blocks hold four
/// times the matrix entries. Errs high, as a guard should.
pub fn memory_estimate(blocks: f64, dimension: u32) -> f64 {
    let per_block = if dimension == 3 { 4.0 * 40e3 } else { 40e3 };
    20e6 + blocks * per_block
}

/// What a run may use, in bytes: `DDA_MEMORY_LIMIT` if set (for a share of
/// a cluster node, say), else the memory the system has available.
pub fn memory_available() -> Option<f64> {
    if let Some(limit) = std::env::var("DDA_MEMORY_LIMIT")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
    {
        return Some(limit);
    }
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// More steps than this is refused by [`run_scene`]: weeks of computing,
/// almost always a slip of the duration or dt.
pub const MAX_STEPS: f64 = 1e9;
/// A `history.csv` larger than this (bytes) is refused by [`run_scene`]
/// (a `steps.csv` of [`MAX_STEPS`] rows is smaller).
pub const MAX_BYTES: f64 = 1e11;

/// A run whose step count or output size is absurd is an error before it
/// starts, with the estimate and what to change.
fn refuse_absurd(scene: &Scene, e: &Estimate) -> anyhow::Result<()> {
    let origin = scene.origin();
    if e.steps.is_nan() || e.steps > MAX_STEPS {
        bail!(
            "{origin}: the run would take {:.3e} steps (analysis.duration / dt), more than the {MAX_STEPS:.0e} a run may take; check analysis.duration and analysis.dt",
            e.steps
        );
    }
    if let Some(available) = memory_available() {
        if e.memory > available {
            bail!(
                "{origin}: a run of this scene needs about {} of memory, more than the {} available{}; run fewer blocks (larger spacings, fewer voussoirs or courses), rigid blocks (kind: Rigid), or on a larger machine",
                bytes_text(e.memory),
                bytes_text(available),
                if std::env::var("DDA_MEMORY_LIMIT").is_ok() { " (DDA_MEMORY_LIMIT)" } else { "" }
            );
        }
    }
    if e.bytes.is_nan() || e.bytes > MAX_BYTES {
        bail!(
            "{origin}: history.csv would be about {} ({:.3e} rows), more than {}; give a larger output.interval",
            bytes_text(e.bytes),
            e.rows,
            bytes_text(MAX_BYTES)
        );
    }
    Ok(())
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
/// scene's output asks for it, `points.csv` when it has measured points)
/// and `summary.json` into `out_dir`; progress and notes appear only when stderr is a terminal.
pub fn run(scene_path: &Path, out_dir: &Path) -> anyhow::Result<Summary> {
    let terminal = std::io::stderr().is_terminal();
    run_with(
        scene_path,
        out_dir,
        RunOptions {
            progress: terminal,
            notes: terminal,
            progress_lines: None,
            vtk: false,
            steps: false,
            quiet: false,
            checkpoint_every: None,
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
    let mut model = scene.build_any_with(registry)?;
    if options.steps {
        match &mut model {
            AnyModel::Plane(m) => m.write_steps = true,
            AnyModel::Space(m) => m.write_steps = true,
        }
    }
    refuse_absurd(scene, &estimate(&model))?;
    if let Some(every) = options.checkpoint_every {
        check_interval(every)?;
    }
    match model {
        AnyModel::Plane(model) => run_model(scene, model, out_dir, options, None),
        AnyModel::Space(model) => run_model(scene, model, out_dir, options, None),
    }
}

/// A checkpoint interval must be a positive number of seconds.
fn check_interval(every: f64) -> anyhow::Result<()> {
    if !(every.is_finite() && every > 0.0) {
        bail!("--checkpoint-every must be a positive number of simulated seconds, got {every}");
    }
    Ok(())
}

/// Goes on with the run whose checkpoint is in `out_dir`, writing on its
/// outputs there: of `scene` if given (it must be the scene the checkpoint
/// was taken of), else of the scene the checkpoint names. Checkpoints go on
/// at `options.checkpoint_every`, or as often as before.
pub fn resume(
    out_dir: &Path,
    scene: Option<&Path>,
    mut options: RunOptions,
    registry: &LawRegistry,
) -> anyhow::Result<Summary> {
    let checkpoint = Checkpoint::read(out_dir)?;
    let scene = checkpoint.scene(out_dir, scene)?;
    match options.checkpoint_every {
        Some(every) => check_interval(every)?,
        None => options.checkpoint_every = Some(checkpoint.every),
    }
    let restore = |e: dda_core::DdaError| {
        anyhow::anyhow!("{}: {e}", out_dir.join(crate::checkpoint::FILE).display())
    };
    match scene.build_any_with(registry)? {
        AnyModel::Plane(mut model) => {
            model.driver.restore(&checkpoint.driver).map_err(restore)?;
            run_model(&scene, model, out_dir, options, Some(checkpoint))
        }
        AnyModel::Space(mut model) => {
            model.driver.restore(&checkpoint.driver).map_err(restore)?;
            run_model(&scene, model, out_dir, options, Some(checkpoint))
        }
    }
}

/// Runs a built model to its end, writing the outputs of its dimension;
/// with `resumed`, the model is restored from that checkpoint and the
/// outputs are written on from where it found them.
pub fn run_model<S: Simulation>(
    scene: &Scene,
    model: Model<S>,
    out_dir: &Path,
    options: RunOptions,
    resumed: Option<Checkpoint>,
) -> anyhow::Result<Summary> {
    run_model_observed(scene, model, out_dir, options, resumed, &mut [])
}

/// [`run_model`] with more observers, shown the run after the outputs and
/// before the summary.
pub fn run_model_observed<S: Simulation>(
    scene: &Scene,
    mut model: Model<S>,
    out_dir: &Path,
    options: RunOptions,
    resumed: Option<Checkpoint>,
    extra: &mut [&mut dyn Observer],
) -> anyhow::Result<Summary> {
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let history_path = out_dir.join("history.csv");
    let vtk_wanted = options.vtk || scene.output.vtk;
    let steps_wanted = options.steps || model.write_steps;
    let mut outputs = vec!["history.csv".to_string()];
    if steps_wanted {
        outputs.push("steps.csv".to_string());
    }
    if model.write_contacts {
        outputs.push("contacts.csv".to_string());
    }
    let write_points = !model.driver.measured_points().is_empty();
    if write_points {
        outputs.push("points.csv".to_string());
    }
    if vtk_wanted {
        outputs.extend(VtkWriter::outputs().map(String::from));
    }
    outputs.push("summary.json".to_string());
    let mut summary = SummaryWriter::new(
        out_dir.join("summary.json"),
        scene.origin().to_string(),
        S::DIMENSION,
        model.duration,
        model.notes.clone(),
        outputs,
    );
    summary.earlier_wall_time = resumed.as_ref().map_or(0.0, |c| c.wall_time);
    summary.settling = resumed.as_ref().and_then(|c| c.settling.clone());
    // A file that cannot be made fails the run before it starts, and says so
    // in summary.json when that can still be written.
    let contacts_path = out_dir.join("contacts.csv");
    let points_path = out_dir.join("points.csv");
    let steps_path = out_dir.join("steps.csv");
    let opened = (|| -> anyhow::Result<_> {
        let Some(checkpoint) = &resumed else {
            let history = HistoryWriter::create(&history_path, S::HISTORY_HEADER)?;
            let contacts = match model.write_contacts {
                true => Some(ContactWriter::create(&contacts_path)?),
                false => None,
            };
            let points = match write_points {
                true => Some(PointsWriter::create(&points_path, S::DIMENSION)?),
                false => None,
            };
            let vtk = match vtk_wanted {
                true => Some(VtkWriter::create(out_dir)?),
                false => None,
            };
            let steps = match steps_wanted {
                true => Some(StepsWriter::create(&steps_path, &model.driver)?),
                false => None,
            };
            return Ok((history, contacts, points, vtk, steps));
        };
        let length = |name: &str| {
            match checkpoint.cursor(name) {
            Some(Cursor::File { length, .. }) => Ok(*length),
            _ => Err(anyhow::anyhow!(
                "the checkpoint does not say where {name} stood: it was taken of a run with other outputs"
            )),
        }
        };
        let history = HistoryWriter::resume(&history_path, length("history.csv")?)?;
        let contacts = match model.write_contacts {
            true => Some(ContactWriter::resume(
                &contacts_path,
                length("contacts.csv")?,
            )?),
            false => None,
        };
        let points = match write_points {
            true => Some(PointsWriter::resume(
                &points_path,
                length("points.csv")?,
                S::DIMENSION,
            )?),
            false => None,
        };
        let vtk = match (vtk_wanted, checkpoint.cursor("vtk")) {
            (false, _) => None,
            (true, Some(cursor)) => Some(VtkWriter::resume(out_dir, cursor)?),
            (true, None) => {
                bail!("the run was checkpointed without VTK frames; resume it without --vtk")
            }
        };
        let steps = match (steps_wanted, checkpoint.cursor("steps.csv")) {
            (false, _) => None,
            (true, Some(_)) => Some(StepsWriter::resume(
                &steps_path,
                length("steps.csv")?,
                &model.driver,
            )?),
            (true, None) => {
                bail!("the run was checkpointed without steps.csv; resume it with the outputs it was started with (no --steps, and the scene's output.steps as it was)")
            }
        };
        Ok((history, contacts, points, vtk, steps))
    })();
    let (mut history, mut contacts, mut points, mut vtk, mut steps) = match opened {
        Ok(files) => files,
        Err(e) => {
            let _ = summary.on_finish(&model.driver, Some(&e));
            return Err(e);
        }
    };
    // A resumed run was settled when it started.
    if let (Some(settle), None) = (&scene.analysis.settle, &resumed) {
        match model.driver.settle(settle.steps) {
            Ok(settling) => {
                let report = SettleReport::from(&settling);
                if !options.quiet && report.settled {
                    eprintln!(
                        "settled before the run in {} static steps ({:.2} s of wall time)",
                        report.steps, report.wall_time
                    );
                }
                summary.settling = Some(report);
            }
            Err(e) => {
                let e = anyhow::Error::new(e).context(
                    "the model failed to settle before the run (analysis.settle); no step of the run was taken",
                );
                let _ = summary.on_finish(&model.driver, Some(&e));
                return Err(e);
            }
        }
    }
    if options.notes {
        for note in model.all_notes() {
            eprintln!("note: {note}");
        }
    }
    let mut progress = Progress::new(options.progress, options.progress_lines, model.duration);
    // In this order: the bar is cleared before the summary's warnings.
    let mut observers: Vec<&mut dyn Observer> = vec![&mut progress, &mut history];
    if let Some(contacts) = &mut contacts {
        observers.push(contacts);
    }
    if let Some(points) = &mut points {
        observers.push(points);
    }
    if let Some(vtk) = &mut vtk {
        observers.push(vtk);
    }
    if let Some(steps) = &mut steps {
        observers.push(steps);
    }
    for observer in extra.iter_mut() {
        observers.push(&mut **observer);
    }
    summary.print_warnings = !options.quiet;
    let settling = summary.settling.clone();
    observers.push(&mut summary);

    let mut keeper = options.checkpoint_every.map(|every| Keeper {
        dir: out_dir.to_path_buf(),
        scene: crate::checkpoint::scene_path(scene),
        digest: crate::checkpoint::scene_digest(scene),
        schedule: Schedule {
            every,
            next: match &resumed {
                Some(c) if c.every == every => c.next_checkpoint,
                _ => model.driver.time() + every,
            },
        },
        started: Instant::now(),
        wall_before: resumed.as_ref().map_or(0.0, |c| c.wall_time),
        settling,
    });
    let first_output = resumed.as_ref().map_or(0, |c| c.next_output);
    let limit = model.settings.max_penetration_ratio * model.driver.length_scale();
    let damped = model.settings.contact_damping > 0.0;
    let mut guards = Guards::new(model.on_failure, limit, damped, &model.driver);
    let result = advance(
        &mut model,
        &mut observers,
        &mut guards,
        first_output,
        keeper.as_mut(),
    )
    .with_context(|| {
        format!(
            "the run failed at t = {} s, step {} ({} keeps the rows written until then)",
            model.driver.time(),
            model.driver.statistics().steps,
            history_path.display()
        )
    });
    for observer in &mut observers {
        observer.on_finish(&model.driver, result.as_ref().err())?;
    }
    drop(observers);
    result?;
    Ok(summary.summary.expect("the summary is written at the end"))
}

/// Writes checkpoints as the run goes.
struct Keeper {
    dir: PathBuf,
    scene: String,
    digest: u64,
    schedule: Schedule,
    started: Instant,
    /// Wall-clock seconds of the run before it was resumed.
    wall_before: f64,
    /// What the settling before the run did, kept for a resumed run.
    settling: Option<SettleReport>,
}

impl Keeper {
    /// A checkpoint at an output time, if one is due; `next_output` is the
    /// index of the next output time.
    fn at_output<S: Simulation>(
        &mut self,
        driver: &S,
        observers: &[&mut dyn Observer],
        next_output: u64,
    ) -> anyhow::Result<()> {
        if !self.schedule.due(driver.time()) {
            return Ok(());
        }
        let checkpoint = Checkpoint {
            version: env!("CARGO_PKG_VERSION").to_string(),
            scene: self.scene.clone(),
            digest: self.digest,
            driver: driver.save()?,
            next_output,
            cursors: observers.iter().filter_map(|o| o.cursor()).collect(),
            every: self.schedule.every,
            next_checkpoint: self.schedule.next,
            wall_time: self.wall_before + self.started.elapsed().as_secs_f64(),
            settling: self.settling.clone(),
        };
        checkpoint.write(&self.dir)
    }
}

/// Steps to the end, showing observers every accepted step, and time 0 and
/// every output time (every step without an interval). A new run starts
/// with `first_output` 0 (time 0); a resumed one with the index of the
/// output time after its checkpoint.
fn advance<S: Simulation>(
    model: &mut Model<S>,
    observers: &mut [&mut dyn Observer],
    guards: &mut Guards,
    first_output: u64,
    mut keeper: Option<&mut Keeper>,
) -> anyhow::Result<()> {
    let duration = model.duration;
    let driver = &mut model.driver;
    if duration - driver.time() <= 1e-9 * driver.dt() && first_output > 0 {
        bail!("the run had already reached its end, {duration} s, at the checkpoint");
    }
    if first_output == 0 {
        output(driver, observers)?;
    }
    match model.output_interval {
        Some(interval) => {
            for k in first_output.max(1).. {
                let mut t = k as f64 * interval;
                // The last output is the end itself, not a hair before or after it.
                if t >= duration - 1e-9 * interval {
                    t = duration;
                }
                let mut tripped = None;
                driver.advance_while(t, &mut |d| {
                    observers.iter_mut().for_each(|o| o.on_step(d));
                    guards.after_step(d).map_err(|e| tripped = Some(e)).is_ok()
                })?;
                if let Some(e) = tripped {
                    return Err(e);
                }
                output(driver, observers)?;
                if t == duration {
                    break;
                }
                if let Some(keeper) = keeper.as_deref_mut() {
                    keeper.at_output(driver, observers, k + 1)?;
                }
            }
        }
        None => {
            // Every step is an output time; the driver's steps to the end
            // are equal ones, so the run does not end on a short step whose
            // matrix no kept factor fits.
            let mut tripped = None;
            driver.advance_while(duration, &mut |d| {
                observers.iter_mut().for_each(|o| o.on_step(d));
                let written = guards.after_step(d).and_then(|()| {
                    output(d, observers)?;
                    match keeper.as_deref_mut() {
                        Some(keeper) => keeper.at_output(d, observers, 1),
                        None => Ok(()),
                    }
                });
                written.map_err(|e| tripped = Some(e)).is_ok()
            })?;
            if let Some(e) = tripped {
                return Err(e);
            }
        }
    }
    Ok(())
}

/// An output time: the run is checked, then shown to the observers.
fn output(run: &dyn RunView, observers: &mut [&mut dyn Observer]) -> anyhow::Result<()> {
    for i in 0..run.block_count() {
        if !run.is_finite(i) {
            bail!(
                "block {i} has a non-finite position or velocity: the model is unstable; {}",
                dda_core::error::OVERFLOW_ADVICE
            );
        }
    }
    observers.iter_mut().try_for_each(|o| o.on_output(run))
}
