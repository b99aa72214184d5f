//! One run of a study: the base scene with the run's values set by path,
//! written into its folder, run with the usual outputs (`history.csv`,
//! `contacts.csv` when the figure needs it, `summary.json`), and judged.
//!
//! The run loop is `run::run_model`'s with one more observer, which
//! measures what the files do not hold: the blocks' areas or volumes and
//! the total energy at the start and the end.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};
use dda_contact::LawRegistry;

use super::figure::{size, Figure, Measures};
use super::outcome::Outcome;
use super::spec::{Held, Value};
use super::table::Row;
use super::tree;
use crate::observe::{Observer, RunView};
use crate::pictures::RunData;
use crate::run::{run_model_observed, RunOptions};
use crate::scene::{AnyModel, Model, MotionSpec, Scene};
use crate::simulation::Simulation;
use crate::summary::Summary;

/// The pseudo-field that runs a 2D scene as its extruded 3D prism model.
pub const DIMENSION: &str = "dimension";

/// What every run of a study shares.
pub struct Plan<'a> {
    /// The study file, for errors.
    pub origin: String,
    /// The base scene as RON text (every field written).
    pub base: String,
    /// Fields set in every run.
    pub set: Vec<(String, Value)>,
    pub figure: Figure,
    pub held: Option<Held>,
    /// Prism depth for `dimension: 3`, m.
    pub depth: f64,
    pub registry: &'a LawRegistry,
}

impl<'a> Plan<'a> {
    /// The base scene as text whose files are named absolutely, so a run's
    /// copy in another folder finds them.
    pub fn new(
        origin: String,
        mut scene: Scene,
        set: Vec<(String, Value)>,
        figure: Figure,
        held: Option<Held>,
        depth: f64,
        registry: &'a LawRegistry,
    ) -> Self {
        let resolved = scene.ground_motion.as_ref().and_then(|g| match &g.motion {
            MotionSpec::Record { path, .. } if Path::new(path.as_str()).is_relative() => {
                let file = scene.resolve(path.as_str());
                Some(std::fs::canonicalize(&file).unwrap_or(file))
            }
            _ => None,
        });
        if let (Some(file), Some(g)) = (resolved, scene.ground_motion.as_mut()) {
            if let MotionSpec::Record { path, .. } = &mut g.motion {
                *path = file.display().to_string();
            }
        }
        Self {
            origin,
            base: scene.to_ron(),
            set,
            figure,
            held,
            depth,
            registry,
        }
    }

    /// The scene text of a run, or a path error naming the study file.
    pub fn scene_text(&self, values: &[(String, Value)]) -> anyhow::Result<String> {
        let mut text = self.base.clone();
        for (path, value) in self.set.iter().chain(values) {
            if path == DIMENSION {
                continue;
            }
            let old = tree::get(&text, path);
            text = tree::set(&text, path, &value.ron(old.as_deref())).map_err(|e| {
                anyhow::anyhow!(
                    "{}: the field `{path}` is not in the scene: at `{}`, {}",
                    self.origin,
                    e.at,
                    e.message
                )
            })?;
        }
        if self.figure.needs_contacts() {
            text = tree::set(&text, "output.contacts", "true")
                .map_err(|e| anyhow::anyhow!("{}: {}", self.origin, e.message))?;
        }
        Ok(text)
    }

    /// Loads the run's scene from `dir/scene.ron` (so errors name a file and
    /// line), extruded when `dimension` is 3.
    pub fn scene(&self, values: &[(String, Value)], dir: &Path) -> anyhow::Result<Scene> {
        let text = self.scene_text(values)?;
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let file = dir.join("scene.ron");
        std::fs::write(&file, &text).with_context(|| format!("cannot write {}", file.display()))?;
        let scene = Scene::load(&file)?;
        let dimension = values
            .iter()
            .chain(&self.set)
            .find(|(p, _)| p == DIMENSION)
            .map(|(_, v)| v.number());
        match dimension {
            None => Ok(scene),
            Some(Some(d)) if d == scene.dimension as f64 => Ok(scene),
            Some(Some(3.0)) => {
                let solid = crate::extrude::extrude(&scene, self.depth)?;
                let file = dir.join("scene_3d.ron");
                std::fs::write(&file, solid.to_ron())
                    .with_context(|| format!("cannot write {}", file.display()))?;
                Ok(Scene::load(&file)?)
            }
            Some(_) => bail!(
                "{}: `dimension` takes 2 (the scene as it is) or 3 (a 2D scene's extruded prisms); the base scene is {}D",
                self.origin,
                scene.dimension
            ),
        }
    }

    /// Runs one point of the grid in `dir`; never fails: a run that cannot
    /// be built or stops early is a row with outcome `failed`.
    pub fn run(&self, index: usize, values: &[(String, Value)], dir: &Path) -> Row {
        let started = Instant::now();
        let mut row = Row {
            index,
            values: values.iter().map(|(_, v)| v.label()).collect(),
            figure: None,
            reference: None,
            error: None,
            relative_error: None,
            wall_time: 0.0,
            steps: 0,
            cuts: 0,
            open_close_iterations: 0,
            unconverged_steps: 0,
            deepest_penetration: None,
            energy_growth: None,
            outcome: Outcome::Failed,
            run: dir
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            note: String::new(),
        };
        let ran = self
            .scene(values, dir)
            .and_then(|scene| run_measured(&scene, dir, self.registry));
        row.wall_time = started.elapsed().as_secs_f64();
        let (summary, measures) = match ran {
            Ok(done) => done,
            Err(e) => {
                row.note = one_line(&format!("{e:#}"));
                return row;
            }
        };
        row.steps = summary.steps;
        row.cuts = summary.cuts();
        row.open_close_iterations = summary.open_close_iterations;
        row.unconverged_steps = summary.unconverged_steps;
        row.deepest_penetration =
            (summary.deep_penetration_steps > 0).then_some(summary.deepest_penetration);
        row.energy_growth = summary
            .energy_growth
            .is_finite()
            .then_some(summary.energy_growth);
        if let Some(e) = &summary.error {
            row.note = one_line(e);
        }
        let data = match RunData::load(dir) {
            Ok(d) => d,
            Err(e) => {
                row.note = one_line(&format!("{e:#}"));
                row.outcome = Outcome::judge(&summary, None);
                return row;
            }
        };
        match self.figure.read(&data, &measures) {
            Ok(f) => row.figure = Some(f),
            Err(e) if row.note.is_empty() => row.note = e,
            Err(_) => {}
        }
        // At the end, as the verification tests judge: an arch bounces on
        // its springs by centimetres while settling, and stands.
        let moved = self.held.as_ref().and_then(|h| {
            (h.block < data.block_count()).then(|| {
                (
                    data.displacement(data.times.len() - 1, h.block),
                    h.tolerance,
                )
            })
        });
        row.outcome = Outcome::judge(&summary, moved);
        row
    }
}

fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

/// Runs a loaded scene into `dir` with the measures; `Err` only when it
/// could not start (it could not be built, or is absurdly long).
pub fn run_measured(
    scene: &Scene,
    dir: &Path,
    registry: &LawRegistry,
) -> anyhow::Result<(Summary, Measures)> {
    let model = scene.build_any_with(registry)?;
    let e = crate::run::estimate(&model);
    if e.steps.is_nan() || e.steps > crate::run::MAX_STEPS || e.bytes > crate::run::MAX_BYTES {
        bail!(
            "{}: the run would take {:.3e} steps and write {}: check analysis.duration, analysis.dt and output.interval",
            scene.origin(),
            e.steps,
            crate::run::bytes_text(e.bytes)
        );
    }
    match model {
        AnyModel::Plane(model) => run_model(scene, model, dir),
        AnyModel::Space(model) => run_model(scene, model, dir),
    }
}

/// The block sizes and total energy at the start and the end.
struct Measure {
    measures: Measures,
}

impl Observer for Measure {
    fn on_step(&mut self, run: &dyn RunView) {
        let e = run.statistics().energy;
        if e.is_finite() {
            self.measures.energy_start.get_or_insert(e);
            self.measures.energy_end = Some(e);
        }
    }

    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        if self.measures.size_start.is_empty() {
            self.measures.size_start = sizes(run);
        }
        Ok(())
    }

    fn on_finish(&mut self, run: &dyn RunView, _: Option<&anyhow::Error>) -> anyhow::Result<()> {
        self.measures.size_end = sizes(run);
        Ok(())
    }
}

fn sizes(run: &dyn RunView) -> Vec<f64> {
    (0..run.block_count())
        .map(|b| size(&run.block_shape(b), run.dimension()))
        .collect()
}

fn run_model<S: Simulation>(
    scene: &Scene,
    model: Model<S>,
    dir: &Path,
) -> anyhow::Result<(Summary, Measures)> {
    let mut measure = Measure {
        measures: Measures::default(),
    };
    // Quiet: the study's own progress is on the terminal; the warnings
    // stay in each run's summary.json.
    let options = RunOptions {
        quiet: true,
        ..RunOptions::default()
    };
    let summary = match run_model_observed(scene, model, dir, options, None, &mut [&mut measure]) {
        Ok(summary) => summary,
        // A run that failed midway still wrote its summary.
        Err(e) => match std::fs::read_to_string(dir.join("summary.json")) {
            Ok(text) => serde_json::from_str(&text).context("the run's summary does not read")?,
            Err(_) => return Err(e),
        },
    };
    Ok((summary, measure.measures))
}

/// A run's folder name: its index and values, like `003_dt=0.001`.
pub fn folder(index: usize, values: &[(String, Value)]) -> PathBuf {
    let mut name = format!("{index:03}");
    for (path, v) in values {
        let short = path.rsplit('.').next().unwrap_or(path);
        let label: String = v
            .label()
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '+') {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        name.push_str(&format!("_{short}={label}"));
    }
    PathBuf::from(name)
}
