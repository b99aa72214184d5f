//! `dda bench` on walls: options checked up front, the runs, the tables,
//! the exponents, then the chart and the JSON.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::Context;
use serde::Serialize;

use super::report::{print_fits, print_simulate, print_steps};
use super::scaling::{self, Fit, Point};
use super::simulate::{simulate, SimulateOptions, SimulateRow};
use super::{bench, BenchOptions, BenchRow};
use crate::scene::BlockKind;
use dda_core::Solver;

/// Everything `dda bench` takes, but `--study`.
#[derive(Debug, Clone)]
pub struct Command {
    /// Wall sizes: `n` courses of `n` bricks.
    pub sizes: Vec<usize>,
    /// Steps timed per run (without `simulate`).
    pub steps: usize,
    /// Runs per size; default 3, or 1 with `simulate`.
    pub repeats: Option<usize>,
    pub kinds: Vec<BlockKind>,
    pub dimensions: Vec<u32>,
    /// Simulated seconds per run, with automatic dt and penalty.
    pub simulate: Option<f64>,
    /// Wall-clock cap per simulated run, s.
    pub max_wall: f64,
    /// With `simulate`: time steps to run each wall at, s (empty:
    /// automatic).
    pub dts: Vec<f64>,
    /// With `simulate`: the amplitude of the 2 Hz horizontal sine the
    /// walls' bases are shaken by, m/s² (`None`: at rest).
    pub shake: Option<f64>,
    /// With `simulate`: settle each wall before its timed run.
    pub settle: bool,
    /// With `simulate`: a folder for each run's `steps.csv`.
    pub step_log: Option<PathBuf>,
    /// The scaling chart's file, `.png` or `.svg`.
    pub chart: Option<PathBuf>,
    pub json: Option<PathBuf>,
    /// The step's linear solver.
    pub solver: Solver,
}

/// What `--json` writes.
#[derive(Serialize)]
struct Report<'a, R: Serialize> {
    /// "steps" (a number of steps at dt 1 ms) or "simulate".
    mode: &'static str,
    rows: &'a [R],
    fits: &'a [Fit],
}

/// The chart's file must be one it can be written as, before the runs.
fn check_chart(path: &Path) -> anyhow::Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    anyhow::ensure!(
        ext.eq_ignore_ascii_case("png") || ext.eq_ignore_ascii_case("svg"),
        "--chart {}: the chart is written as PNG or SVG; name a .png or .svg file",
        path.display()
    );
    check_writable("--chart", path)
}

/// A file written after the runs must be writable before them, so a
/// long benchmark does not end on an error that loses its results: its
/// folder is made, and a file beside it created and removed.
pub(crate) fn check_writable(option: &str, path: &Path) -> anyhow::Result<()> {
    anyhow::ensure!(
        !path.is_dir(),
        "{option} {}: a folder; name a file",
        path.display()
    );
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{option}: cannot create {}", dir.display()))?;
    }
    let mut probe = path.as_os_str().to_owned();
    probe.push(".partial");
    std::fs::File::create(&probe)
        .with_context(|| format!("{option}: cannot write {}", path.display()))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// The rows' points on the scaling chart, their exponents printed, and the
/// JSON report of the rows and exponents.
fn fitted<R: Serialize>(
    mode: &'static str,
    rows: &[R],
    point: impl Fn(&R) -> Point,
) -> anyhow::Result<(Vec<Point>, String)> {
    let points: Vec<Point> = rows.iter().map(point).collect();
    let fits = scaling::fits(&points);
    print_fits(&fits);
    let json = serde_json::to_string_pretty(&Report {
        mode,
        rows,
        fits: &fits,
    })?;
    Ok((points, json))
}

/// Runs `dda bench` on walls and prints its tables.
pub fn command(c: &Command) -> anyhow::Result<()> {
    if let Some(path) = &c.chart {
        check_chart(path)?;
    }
    if let Some(path) = &c.json {
        check_writable("--json", path)?;
    }
    anyhow::ensure!(c.repeats != Some(0), "--repeats must be at least 1");
    if let Some(dir) = &c.step_log {
        anyhow::ensure!(
            c.simulate.is_some(),
            "--step-log logs runs of a simulated time; give --simulate SECONDS too"
        );
        check_writable("--step-log", &dir.join("steps.csv"))?;
    }
    super::check_walls(&c.sizes, &c.dimensions)?;
    anyhow::ensure!(
        !c.kinds.is_empty(),
        "--kinds needs rigid, deformable or both"
    );
    let (points, json, title) = match c.simulate {
        Some(seconds) => {
            let repeats = c.repeats.unwrap_or(1);
            let rows = simulate(&SimulateOptions {
                sizes: c.sizes.clone(),
                kinds: c.kinds.clone(),
                dimensions: c.dimensions.clone(),
                seconds,
                max_wall: c.max_wall,
                repeats,
                progress_every: Some(Duration::from_secs(5)),
                solver: c.solver,
                dts: c.dts.clone(),
                shake: c.shake,
                settle: c.settle,
                step_log: c.step_log.clone(),
            })?;
            print_simulate(&rows, repeats);
            let (points, json) = fitted("simulate", &rows, SimulateRow::point)?;
            let title = format!(
                "Walls, {} s simulated: mean time per step",
                crate::output::plain_number(seconds)
            );
            (points, json, title)
        }
        None => {
            let repeats = c.repeats.unwrap_or(3);
            let rows = bench(&BenchOptions {
                sizes: c.sizes.clone(),
                steps: c.steps,
                repeats,
                kinds: c.kinds.clone(),
                dimensions: c.dimensions.clone(),
                solver: c.solver,
            })?;
            print_steps(&rows, c.steps, repeats);
            if c.solver != Solver::Direct {
                for r in &rows {
                    println!(
                        "{:>4}: {:.1} conjugate-gradient iterations per solve, {} solved directly at the cap",
                        r.courses, r.iterations_per_solve, r.solver_fallbacks
                    );
                }
            }
            let (points, json) = fitted("steps", &rows, BenchRow::point)?;
            let title = format!(
                "Walls at dt 1 ms: median time per step of {}",
                if repeats == 1 {
                    "one run".to_string()
                } else {
                    format!("{repeats} runs")
                }
            );
            (points, json, title)
        }
    };
    if let Some(path) = &c.chart {
        scaling::chart(&points, &title, path)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &c.json {
        crate::output::write_atomically(path, json.as_bytes())?;
    }
    Ok(())
}
