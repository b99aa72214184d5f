//! The `dda` command: run, check or extrude scene files.
//!
//! [`main_with`] is the whole command with a registry of contact laws, so a
//! binary of a few lines gives `dda run` and `dda check` laws of its own:
//!
//! ```no_run
//! use dda_contact::{Coulomb, LawRegistry, Params};
//!
//! fn main() -> std::process::ExitCode {
//!     let mut registry = LawRegistry::with_builtin();
//!     registry.register("sticky", |p: &mut Params| {
//!         Ok(Coulomb { cohesion: 1e5, ..Coulomb::frictional(p.take("friction_angle")?) })
//!     });
//!     dda::cli::main_with(registry)
//! }
//! ```

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use clap::{Parser, Subcommand};
use dda_contact::LawRegistry;

use crate::extrude::{extrude_with, Extrusion};
use crate::pictures::plot::{plot, PlotOptions};
use crate::pictures::render::{render, ColorField, RenderOptions};
use crate::run::{bytes_text, default_out_dir, estimate_model, run_with_registry, RunOptions};
use crate::scene::{AnyModel, Model, MotionSpec};
use crate::{Scene, Simulation};

#[derive(Parser)]
#[command(
    name = "dda",
    version,
    about = "Discontinuous Deformation Analysis of block systems"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene, writing DIR/history.csv (and DIR/contacts.csv if asked) as it goes and DIR/summary.json at the end
    Run {
        /// The scene file (RON); with --resume, the one the checkpoint names when left out
        #[arg(required_unless_present = "resume")]
        scene: Option<PathBuf>,
        /// Output directory (created if missing); out/<scene name> under the current folder when left out
        #[arg(long, short, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Seconds between progress lines on stderr when it is not a terminal (0: one per output time)
        #[arg(long, value_name = "SECONDS", default_value_t = 5.0)]
        progress_every: f64,
        /// Also write VTK frames for ParaView (DIR/blocks.pvd, DIR/contacts.pvd, DIR/vtk/), as the scene's output.vtk does
        #[arg(long)]
        vtk: bool,
        /// Also write DIR/steps.csv, a row per accepted step (its length, open-close passes, Newton-Raphson moves, factorisations, cuts, wall time and its phases), as the scene's output.steps does
        #[arg(long)]
        steps: bool,
        /// Save the whole run to DIR/checkpoint.bin at the first output time after every SECONDS of simulated time
        #[arg(long, value_name = "SECONDS")]
        checkpoint_every: Option<f64>,
        /// Go on with the run checkpointed in DIR, writing on its outputs there
        #[arg(long, value_name = "DIR", conflicts_with = "out")]
        resume: Option<PathBuf>,
    },
    /// Time steps of running-bond walls of growing size: median milliseconds per step, where the time goes, and how it grows with the blocks
    Bench {
        /// Wall sizes (n courses of n bricks), comma separated
        #[arg(long, value_delimiter = ',', default_values_t = [10usize, 20, 40])]
        sizes: Vec<usize>,
        /// Steps timed per run
        #[arg(long, default_value_t = 20)]
        steps: usize,
        /// Runs per size, the median reported (default 3; 1 with --simulate; with --targets, runs of each timed wall, default 3)
        #[arg(long)]
        repeats: Option<usize>,
        /// The bricks' kinds, each timed in turn, comma separated
        #[arg(long, value_enum, value_delimiter = ',', default_values_t = [KindArg::Deformable], conflicts_with = "rigid")]
        kinds: Vec<KindArg>,
        /// Make the bricks rigid (3 DOF each instead of Shi's 6): --kinds rigid
        #[arg(long)]
        rigid: bool,
        /// Dimensions, comma separated: 2, or 3 for the walls' prism models, 0.25 m (one brick) deep
        #[arg(long, value_delimiter = ',', default_values_t = [2u32])]
        dimension: Vec<u32>,
        /// Run each wall for this simulated time, in s, with the scene's automatic dt and penalty, instead of a number of steps
        #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
        simulate: Option<f64>,
        /// With --simulate: stop a run after this much wall-clock time, in s, and report how far it got
        #[arg(
            long,
            value_name = "SECONDS",
            default_value_t = 600.0,
            requires = "simulate",
            allow_negative_numbers = true
        )]
        max_wall: f64,
        /// With --simulate: run each wall at each of these time steps, in s, comma separated, with the automatic penalty, instead of the automatic step (how large a step it stands at)
        #[arg(
            long,
            value_name = "SECONDS",
            value_delimiter = ',',
            requires = "simulate",
            allow_negative_numbers = true
        )]
        dt: Vec<f64>,
        /// With --simulate: shake each wall's base along the wall by a 2 Hz sine of this acceleration amplitude, in m/s², for the whole run (a rigid wall's bed joints slide beyond 6.87)
        #[arg(
            long,
            value_name = "M/S2",
            requires = "simulate",
            allow_negative_numbers = true
        )]
        shake: Option<f64>,
        /// With --simulate: settle each wall at rest under its weight before its timed run (static steps that take no time, as a scene's analysis.settle), so the run starts from its static settlement; the settling's wall time is reported apart
        #[arg(long, requires = "simulate")]
        settle: bool,
        /// With --simulate: write each run's steps.csv into this folder (a row per step: its length, passes, moves, factorisations, cuts, wall time and its phases), named after its wall, as 40x40_deformable_2d.csv; dda plot FILE charts one
        #[arg(long, value_name = "DIR", requires = "simulate")]
        step_log: Option<PathBuf>,
        /// Also draw time per step against blocks, log-log with the N^1 line, into this file (.png or .svg)
        #[arg(long, value_name = "FILE")]
        chart: Option<PathBuf>,
        /// Also write the results as JSON to this file
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// The step's linear solver: direct (sparse Cholesky) or iterative (conjugate gradients, default tolerance and cap)
        #[arg(long, default_value = "direct", value_parser = ["direct", "iterative"])]
        solver: String,
        /// Time this study instead, on one core and on all: its wall time against the sum of its runs' times
        #[arg(long, value_name = "STUDY.ron", conflicts_with_all = ["simulate", "chart", "rigid", "kinds", "dimension"])]
        study: Option<PathBuf>,
        /// Measure every speed target of the walls in one run instead (40 × 40 against MuJoCo, 20 × 20 against ntdda, 10 × 10 at dt 1 ms, 40 × 40 at rest at steps of 5 ms to 10 s, 10,051 blocks in 2D and 3D, the growth from 1,621 to 10,051 blocks; each timed wall the median of --repeats runs, 3 by default; a few minutes): a Markdown table with each verdict, the machine and the date
        #[arg(long, conflicts_with_all = ["study", "simulate", "chart", "rigid", "kinds", "dimension", "sizes", "steps", "dt"])]
        targets: bool,
        /// With --targets: MuJoCo's run of the 40 × 40 wall, the JSON of benches/mujoco_wall.py 40 run just before on the same machine
        #[arg(long, value_name = "FILE", requires = "targets")]
        mujoco: Option<PathBuf>,
    },
    /// Charts of a run (DIR/history.csv, DIR/contacts.csv, DIR/steps.csv): displacement, speed and rotation of chosen blocks, contact forces, each step's wall time, where it went, work and length; SVG and PNG into DIR/plots
    Plot {
        /// The run's folder (what `dda run --out` was given), or a steps file alone (as `dda bench --step-log` writes), charted into plots/ beside it
        dir: PathBuf,
        /// Blocks to draw, comma separated; default: all up to 6, else the 6 that moved farthest
        #[arg(long, value_delimiter = ',')]
        blocks: Vec<usize>,
        /// Where the charts go (default DIR/plots)
        #[arg(long, short, value_name = "FOLDER")]
        out: Option<PathBuf>,
    },
    /// An animation of a run (DIR/render/animation.gif) and a still (still.svg, still.png): the scene's blocks moved rigidly by the history, contacts as force lines
    Render {
        /// The run's folder (what `dda run --out` was given)
        dir: PathBuf,
        /// What colours the blocks
        #[arg(long, value_enum, default_value_t = ColorField::Displacement)]
        color: ColorField,
        /// Frames of the animation, evenly spaced over the output times (default: every output time, at most 200)
        #[arg(long)]
        frames: Option<usize>,
        /// The scene file (default: the one DIR/summary.json names)
        #[arg(long, value_name = "SCENE")]
        scene: Option<PathBuf>,
        /// Time of the still, in s (default: the last output time drawn)
        #[arg(long, value_name = "SECONDS")]
        still: Option<f64>,
        /// Draw the run up to this time only, in s (default: to its end)
        #[arg(long, value_name = "SECONDS")]
        until: Option<f64>,
        /// Picture size in pixels, WIDTHxHEIGHT
        #[arg(long, default_value = "800x600", value_parser = parse_size)]
        size: (u32, u32),
        /// Where the pictures go (default DIR/render)
        #[arg(long, short, value_name = "FOLDER")]
        out: Option<PathBuf>,
    },
    /// Run a study: a scene swept over its fields (or bisected on one), each run judged, into DIR/study.csv, DIR/runs/ and DIR/charts/
    Study {
        /// The study file (RON); see docs/studies.md
        #[arg(required_unless_present = "merge")]
        study: Option<PathBuf>,
        /// Output directory (created if missing); out/<study name> when left out
        #[arg(long, short, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Runs at once (default: one per core)
        #[arg(long, value_name = "N")]
        jobs: Option<usize>,
        /// Run only grid points i with i mod N = I (default from SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT)
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Gather the study.csv of these shard folders into --out, with the charts
        #[arg(long, value_name = "DIR", num_args = 1.., conflicts_with_all = ["study", "shard"])]
        merge: Vec<PathBuf>,
    },
    /// Run the verification catalogue (every shipped example with an analytical answer) and compare: a table on stdout, DIR/validation.csv, exit code 1 if any case fails
    Validate {
        /// Only the cases that take a few seconds each
        #[arg(long)]
        quick: bool,
        /// Where each case's run and validation.csv go
        #[arg(long, short, value_name = "DIR", default_value = "out/validate")]
        out: PathBuf,
        /// Runs at once (default: one per core)
        #[arg(long, value_name = "N")]
        jobs: Option<usize>,
        /// Run only these cases (comma separated names from the table's first column)
        #[arg(long, value_name = "NAME", value_delimiter = ',')]
        only: Vec<String>,
        /// The folder of the shipped examples (default: ./examples, else the one dda was built from)
        #[arg(long, value_name = "DIR")]
        examples: Option<PathBuf>,
    },
    /// Load, validate and build a scene without running it
    Check {
        /// The scene file (RON)
        scene: PathBuf,
    },
    /// Write a 2D scene's 3D prism model: 2D (x, y) becomes 3D (x, 0, y), z up, each block a prism of DEPTH along y centred on y = 0
    Extrude {
        /// The 2D scene file (RON)
        scene: PathBuf,
        /// The prisms' length along y, in m
        #[arg(long, value_name = "DEPTH")]
        depth: f64,
        /// The 3D scene file to write
        #[arg(long, short, value_name = "FILE")]
        out: PathBuf,
        /// Hold every free block's corners against motion along y (plane strain)
        #[arg(long)]
        plane_strain: bool,
    },
    /// Make a scene from Doolin's DDAML input files: the geometry (.geo: joint lines, fixed, load, measured and hole points) and the analysis (.ana: materials, joint properties, time stepping)
    Import {
        /// The geometry file (DDAML .geo)
        geo: PathBuf,
        /// The analysis file (DDAML .ana)
        ana: Option<PathBuf>,
        /// The scene file to write
        #[arg(long, short, value_name = "FILE")]
        out: PathBuf,
    },
}

/// The `dda` command on this process's arguments, with `Custom` joint laws
/// built through `registry`.
pub fn main_with(registry: LawRegistry) -> ExitCode {
    main_from(std::env::args_os(), &registry)
}

/// [`main_with`] on the given arguments (the first is the program name):
/// errors are printed on stderr and give exit code 1, as for `dda` itself.
pub fn main_from<I, A>(args: I, registry: &LawRegistry) -> ExitCode
where
    I: IntoIterator<Item = A>,
    A: Into<std::ffi::OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    match execute(cli.command, registry) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn execute(command: Command, registry: &LawRegistry) -> anyhow::Result<()> {
    use std::io::IsTerminal;
    match command {
        Command::Run {
            scene,
            out,
            progress_every,
            vtk,
            steps,
            checkpoint_every,
            resume,
        } => {
            let every = Duration::try_from_secs_f64(progress_every).map_err(|_| {
                anyhow::anyhow!(
                    "--progress-every must be a number of seconds, zero or more, got {progress_every}"
                )
            })?;
            let terminal = std::io::stderr().is_terminal();
            let options = RunOptions {
                progress: terminal,
                notes: true,
                progress_lines: (!terminal).then_some(every),
                vtk,
                steps,
                quiet: false,
                checkpoint_every,
            };
            let (summary, out) = match (resume, scene) {
                (Some(dir), scene) => (
                    crate::run::resume(&dir, scene.as_deref(), options, registry)?,
                    dir,
                ),
                (None, Some(scene)) => {
                    let out = out.unwrap_or_else(|| default_out_dir(&scene));
                    (run_with_registry(&scene, &out, options, registry)?, out)
                }
                (None, None) => unreachable!("clap requires a scene without --resume"),
            };
            let files: Vec<String> = summary
                .outputs
                .iter()
                .map(|f| out.join(f).display().to_string())
                .collect();
            println!("wrote {}", list(&files));
        }
        Command::Plot { dir, blocks, out } => {
            let files = plot(&dir, &PlotOptions { blocks, out })?;
            let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
            println!("wrote {}", list(&names));
        }
        Command::Render {
            dir,
            color,
            frames,
            scene,
            still,
            until,
            size,
            out,
        } => {
            let options = RenderOptions {
                color,
                frames,
                scene,
                out,
                still,
                until,
                size,
                progress: std::io::stderr().is_terminal(),
            };
            let rendered = render(&dir, &options, registry)?;
            let names: Vec<String> = rendered
                .files
                .iter()
                .map(|f| f.display().to_string())
                .collect();
            println!("wrote {} ({} frames)", list(&names), rendered.frames);
        }
        Command::Study {
            study,
            out,
            jobs,
            shard,
            merge,
        } => crate::study::command(study, out, jobs, shard, merge, registry)?,
        Command::Validate {
            quick,
            out,
            jobs,
            only,
            examples,
        } => {
            use crate::validate;
            let cases = validate::select(&validate::catalogue(), quick, &only)?;
            let options = validate::Options {
                out,
                examples: examples.unwrap_or_else(validate::default_examples),
                jobs,
            };
            validate::command(&cases, &options, registry)?;
        }
        Command::Check { scene: path } => {
            let scene = Scene::load(&path)?;
            match scene.build_any_with(registry)? {
                AnyModel::Plane(model) => check(&path, &scene, &model),
                AnyModel::Space(model) => check(&path, &scene, &model),
            }
        }
        Command::Bench {
            targets: true,
            mujoco,
            json,
            repeats,
            ..
        } => {
            anyhow::ensure!(repeats != Some(0), "--repeats must be at least 1");
            let mujoco = mujoco
                .map(|path| crate::bench::targets::MujocoRun::load(&path))
                .transpose()?;
            let defaults = crate::bench::targets::TargetOptions::default();
            let options = crate::bench::targets::TargetOptions {
                mujoco,
                repeats: repeats.unwrap_or(defaults.repeats),
                ..defaults
            };
            crate::bench::targets::command(&options, json)?;
        }
        Command::Bench {
            study: Some(study),
            repeats,
            json,
            ..
        } => {
            if let Some(path) = &json {
                crate::bench::command::check_writable("--json", path)?;
            }
            anyhow::ensure!(repeats != Some(0), "--repeats must be at least 1");
            let repeats = repeats.unwrap_or(3);
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            let rows = crate::bench::bench_study(&study, &[1, cores], repeats)?;
            println!(
                "{}: median of {repeats} runs of the whole study",
                study.display()
            );
            println!(
                "{:>5} {:>5} {:>10} {:>12} {:>14}",
                "jobs", "runs", "wall s", "sum of runs", "wall / sum"
            );
            for r in &rows {
                println!(
                    "{:>5} {:>5} {:>10.2} {:>12.2} {:>14.2}",
                    r.jobs, r.runs, r.median_wall_s, r.run_sum_s, r.ratio
                );
            }
            if let Some(path) = json {
                crate::output::write_atomically(
                    &path,
                    serde_json::to_string_pretty(&rows)?.as_bytes(),
                )?;
            }
        }
        Command::Bench {
            sizes,
            steps,
            repeats,
            kinds,
            rigid,
            dimension,
            simulate,
            max_wall,
            dt,
            shake,
            settle,
            step_log,
            chart,
            json,
            solver,
            study: None,
            ..
        } => {
            let solver = match solver.as_str() {
                "iterative" => dda_core::Solver::iterative(),
                _ => dda_core::Solver::Direct,
            };
            let kinds: Vec<crate::scene::BlockKind> = if rigid {
                vec![crate::scene::BlockKind::Rigid]
            } else {
                kinds.into_iter().map(KindArg::kind).collect()
            };
            crate::bench::command(&crate::bench::Command {
                sizes,
                steps,
                repeats,
                kinds,
                dimensions: dimension,
                simulate,
                max_wall,
                dts: dt,
                shake,
                settle,
                step_log,
                chart,
                json,
                solver,
            })?;
        }
        Command::Extrude {
            scene: path,
            depth,
            out,
            plane_strain,
        } => {
            let scene = Scene::load(&path)?;
            let mut solid = extrude_with(
                &scene,
                &Extrusion {
                    depth,
                    plane_strain,
                },
            )?;
            let header = format!(
                "// The 3D prism model of {}, made by `dda extrude --depth {depth}{}`:\n\
                 // 2D (x, y) is 3D (x, 0, y), z up; each block is a prism from\n\
                 // y = {} to y = {}; loads and fixed points are on y = 0.\n",
                path.display(),
                if plane_strain { " --plane-strain" } else { "" },
                -depth / 2.0,
                depth / 2.0,
            );
            if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("cannot create {}", dir.display()))?;
            }
            keep_record_found(&mut solid, &scene, &out);
            std::fs::write(&out, header + &solid.to_ron() + "\n")
                .with_context(|| format!("cannot write {}", out.display()))?;
            println!("wrote {}", out.display());
        }
        Command::Import { geo, ana, out } => {
            let imported = crate::import::import_ddaml(&geo, ana.as_deref())?;
            for note in &imported.notes {
                eprintln!("note: {note}");
            }
            std::fs::write(&out, &imported.text)
                .with_context(|| format!("cannot write {}", out.display()))?;
            println!(
                "wrote {} ({} blocks)",
                out.display(),
                imported.scene.block_count()
            );
        }
    }
    Ok(())
}

/// A ground-motion record named relative to the 2D scene's folder is named
/// so the 3D scene, written elsewhere, still finds it.
fn keep_record_found(solid: &mut Scene, scene: &Scene, out: &std::path::Path) {
    let Some(ground) = &mut solid.ground_motion else {
        return;
    };
    let MotionSpec::Record { path, .. } = &mut ground.motion else {
        return;
    };
    let here = |p: &std::path::Path| {
        let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
        std::fs::canonicalize(dir.unwrap_or(std::path::Path::new("."))).ok()
    };
    let input = std::path::Path::new(scene.origin());
    if std::path::Path::new(path.as_str()).is_relative() && here(input) != here(out) {
        let file = scene.resolve(path.as_str());
        let file = std::fs::canonicalize(&file).unwrap_or(file);
        *path = file.display().to_string();
    }
}

/// A brick kind on the command line.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum KindArg {
    Rigid,
    Deformable,
}

impl KindArg {
    fn kind(self) -> crate::scene::BlockKind {
        match self {
            KindArg::Rigid => crate::scene::BlockKind::Rigid,
            KindArg::Deformable => crate::scene::BlockKind::Deformable,
        }
    }
}

/// `800x600` as (800, 600).
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("{text:?} is not WIDTHxHEIGHT in pixels, like 800x600");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if !(64..=4096).contains(&w) || !(64..=4096).contains(&h) {
        return Err(format!(
            "{text}: width and height must be 64 to 4096 pixels"
        ));
    }
    Ok((w, h))
}

/// What `dda check` says of a scene built into `model`.
fn check<S: Simulation>(path: &Path, scene: &Scene, model: &Model<S>) {
    let laws = scene.law_table().laws;
    let dt = model.driver.dt();
    let auto = if scene.analysis.dt.is_none() {
        " (automatic)"
    } else {
        ""
    };
    let space = if S::DIMENSION == 3 { "3D, " } else { "" };
    println!(
        "{}: ok ({space}{}, {}, {}, duration {} s, dt {dt:.4e} s{auto})",
        path.display(),
        count(model.driver.block_count(), "block"),
        count(scene.materials.len(), "material"),
        count(laws.len(), "joint law"),
        model.duration,
    );
    let expected = estimate_model(model);
    let every = if model.output_interval.is_none() {
        " (every step)".to_string()
    } else {
        String::new()
    };
    println!(
        "expects {:.0} steps at dt, {:.0} output times{every}, {:.0} history rows (about {}{})",
        expected.steps,
        expected.output_times,
        expected.rows,
        bytes_text(expected.bytes),
        if model.write_contacts {
            ", plus contacts.csv"
        } else {
            ""
        },
    );
    if model.write_steps {
        println!(
            "and steps.csv, a row per step (about {})",
            bytes_text(expected.steps_bytes)
        );
    }
    println!("needs about {} of memory", bytes_text(expected.memory));
    let settles = scene.analysis.settle.map(|s| s.steps);
    if let Some(steps) = settles {
        println!("settles under its loads at t = 0 before the run, in at most {steps} static steps (analysis.settle)");
    }
    for note in model.all_notes() {
        // Settled, nothing is released onto the contacts.
        let note = match settles {
            Some(_) if note == dda_core::driver::UNDAMPED_NOTE => {
                dda_core::driver::UNDAMPED_SETTLED_NOTE.to_string()
            }
            _ => note,
        };
        eprintln!("note: {note}");
    }
    for warning in &expected.warnings {
        eprintln!("warning: {warning}");
    }
}

/// "a", "a and b", "a, b and c".
fn list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

fn count(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}
