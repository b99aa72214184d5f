//! Studies: one scene run over a grid of values of its fields (or a
//! bisection on one), each run judged by a figure against a reference and
//! by its outcome, into `study.csv` and charts. `dda study STUDY.ron --out
//! DIR` is [`run`]; `--shard I/N` runs one slice of the grid and
//! `--merge DIR...` ([`merge`]) gathers slices. See `docs/studies.md`.

pub mod bisect;
pub mod charts;
pub mod execute;
pub mod expr;
pub mod figure;
pub mod grid;
pub mod outcome;
pub mod progress;
pub mod shard;
pub mod spec;
pub mod table;
pub mod tree;

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{bail, Context};
use dda_contact::LawRegistry;

pub use execute::Plan;
pub use outcome::Outcome;
pub use shard::{merge, shard};
pub use spec::{Reference, Search, Study, Value};
pub use table::Row;

use crate::Scene;

/// How a study runs.
#[derive(Debug, Clone)]
pub struct Options {
    /// Where study.csv, the runs and the charts go.
    pub out: PathBuf,
    /// Runs at once; default one per core.
    pub jobs: Option<usize>,
    /// Run only grid points i with i mod N = I, as (I, N).
    pub shard: Option<(usize, usize)>,
    /// A line per finished run on stderr (a bar on a terminal).
    pub progress: bool,
}

/// What a study did.
#[derive(Debug, Clone)]
pub struct Report {
    pub fields: Vec<String>,
    /// Every run, in index order.
    pub rows: Vec<Row>,
    /// Chart files written.
    pub charts: Vec<PathBuf>,
    /// A search's last bracket (low, high).
    pub bracket: Option<(f64, f64)>,
}

/// Runs the study in `path` with the built-in contact laws.
pub fn run(path: &Path, options: &Options) -> anyhow::Result<Report> {
    run_with_registry(path, options, &LawRegistry::with_builtin())
}

/// [`run`] with `Custom` joint laws built through `registry`.
pub fn run_with_registry(
    path: &Path,
    options: &Options,
    registry: &LawRegistry,
) -> anyhow::Result<Report> {
    let study = Study::load(path)?;
    let text = std::fs::read_to_string(path)?;
    run_study(&study, path, &text, options, registry)
}

/// Runs a loaded study; `path` names it (and its scene is relative to it),
/// `text` is kept in `DIR/study.ron` for merges.
pub fn run_study(
    study: &Study,
    path: &Path,
    text: &str,
    options: &Options,
    registry: &LawRegistry,
) -> anyhow::Result<Report> {
    let origin = path.display().to_string();
    let scene = match (&study.scene, study.scene_file(path)) {
        (_, Some(file)) => Scene::load(&file).with_context(|| {
            format!("{origin}: the base scene {} does not load", file.display())
        })?,
        (spec::SceneSource::Inline(t), None) => {
            Scene::from_str(t, &format!("{origin} (inline scene)"))?
        }
        (spec::SceneSource::File(_), None) => unreachable!("a file source has a path"),
    };
    let set: grid::Point = study
        .set
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    let plan = Plan::new(
        origin.clone(),
        scene,
        set,
        study.figure.clone(),
        study.held.clone(),
        study.depth,
        registry,
    );
    check_paths(study, &plan)?;
    let out = &options.out;
    std::fs::create_dir_all(out.join("runs"))
        .with_context(|| format!("cannot create {}", out.display()))?;
    std::fs::write(out.join("study.ron"), text)
        .with_context(|| format!("cannot write {}", out.join("study.ron").display()))?;
    let jobs = options
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()?;
    let fields: Vec<String> = study.fields().iter().map(|s| s.to_string()).collect();
    let names: Vec<&str> = fields.iter().map(String::as_str).collect();
    let title = study.title_or(path);
    let csv_path = out.join("study.csv");
    let writer = Mutex::new(table::TableWriter::create(&csv_path, &names)?);
    let mut bracket = None;
    let mut brackets = Vec::new();
    let rows = match &study.search {
        None => grid::run(study, &plan, out, &pool, &writer, options)?,
        Some(Search::Bisect { .. }) => {
            if options.shard.is_some() {
                bail!("{origin}: a search runs its steps in order, one after another: run it without --shard");
            }
            let found = bisect::run(study, &plan, out, &pool, &writer, options.progress, jobs)?;
            brackets = found.brackets;
            bracket = Some(found.bracket);
            found.rows
        }
    };
    drop(writer);
    let mut rows = rows;
    rows.sort_by_key(|r| r.index);
    grid::fill_references(study, &fields, &mut rows)?;
    table::write_all(&csv_path, &names, &rows)?;
    let mut files = draw_charts(study, &title, &fields, &rows, out)?;
    if let (
        Some(Search::Bisect {
            field, expected, ..
        }),
        Some((lo, hi)),
    ) = (&study.search, bracket)
    {
        let chart_dir = out.join("charts");
        crate::pictures::create_dir(&chart_dir)?;
        let title = format!("{title}: {field} in [{lo:.5}, {hi:.5}]");
        files.extend(charts::bracket(
            &title,
            field,
            &rows,
            &brackets,
            *expected,
            &chart_dir,
            "bisection",
        )?);
    }
    Ok(Report {
        fields,
        rows,
        charts: files,
        bracket,
    })
}

/// Every sweep path must lead into the scene before any run starts. A
/// field the scene text does not have is added; if the scene then does
/// not load, the path was wrong (a bad value in a field that exists is the
/// run's failure, not the study's).
fn check_paths(study: &Study, plan: &Plan) -> anyhow::Result<()> {
    let firsts: Vec<(String, Value)> = match &study.search {
        Some(Search::Bisect { field, low, .. }) => vec![(field.clone(), Value::Number(*low))],
        None => study
            .sweep
            .iter()
            .map(|s| (s.field.clone(), s.values[0].clone()))
            .collect(),
    };
    for (field, value) in firsts.iter().filter(|(f, _)| f != execute::DIMENSION) {
        let text = plan.scene_text(&[(field.clone(), value.clone())])?;
        if tree::get(&plan.base, field).is_some() {
            continue;
        }
        if let Err(e) = Scene::from_str(&text, "the scene") {
            let (parent, name) = field.rsplit_once('.').unwrap_or(("", field));
            bail!(
                "{}: the field `{field}` is not in the scene: {} has no field `{name}` ({e})",
                plan.origin,
                if parent.is_empty() {
                    "the scene".to_string()
                } else {
                    format!("`{parent}`")
                }
            );
        }
    }
    Ok(())
}

/// The study's charts into `DIR/charts/`.
pub(crate) fn draw_charts(
    study: &Study,
    title: &str,
    fields: &[String],
    rows: &[Row],
    out: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    let dir = out.join("charts");
    crate::pictures::create_dir(&dir)?;
    let mut files = Vec::new();
    for (k, chart) in study.charts.iter().enumerate() {
        files.extend(match chart {
            spec::Chart::ErrorVsTime { series } => charts::error_vs_time(
                title,
                fields,
                rows,
                series.as_deref(),
                &dir,
                &format!("{k}_error_vs_time"),
            )?,
            spec::Chart::StabilityMap { x, y, boundary } => charts::stability_map(
                title,
                fields,
                rows,
                x,
                y,
                boundary.as_ref(),
                &dir,
                &format!("{k}_stability_map"),
            )?,
            spec::Chart::Bars { by } => charts::bars(
                title,
                &study.figure.label(),
                fields,
                rows,
                by,
                &dir,
                &format!("{k}_bars"),
            )?,
            spec::Chart::FigureAgainst { x, series } => charts::figure_against(
                title,
                &study.figure.label(),
                fields,
                rows,
                x,
                series.as_deref(),
                &dir,
                &format!("{k}_figure"),
            )?,
        });
    }
    Ok(files)
}

/// `dda study`: runs a study (or a shard of it), or merges shards, and
/// says what it wrote.
pub fn command(
    study: Option<PathBuf>,
    out: Option<PathBuf>,
    jobs: Option<usize>,
    shard_text: Option<String>,
    merge_dirs: Vec<PathBuf>,
    registry: &LawRegistry,
) -> anyhow::Result<()> {
    let report = if !merge_dirs.is_empty() {
        let Some(out) = out else {
            bail!("--merge needs --out DIR for the gathered study");
        };
        let report = merge(&merge_dirs, &out)?;
        println!("wrote {}", out.join("study.csv").display());
        report
    } else {
        let Some(path) = study else {
            bail!("give a study file, or --merge DIR...");
        };
        let out = out.unwrap_or_else(|| crate::run::default_out_dir(&path));
        let options = Options {
            out: out.clone(),
            jobs,
            shard: shard(shard_text.as_deref())?,
            progress: true,
        };
        let report = run_with_registry(&path, &options, registry)?;
        println!(
            "wrote {} ({} runs) and {}",
            out.join("study.csv").display(),
            report.rows.len(),
            out.join("runs").display()
        );
        if let Some((lo, hi)) = report.bracket {
            println!(
                "the outcome flips between {lo} and {hi} (estimate {} ± {})",
                0.5 * (lo + hi),
                0.5 * (hi - lo)
            );
        }
        report
    };
    let counts: Vec<String> = Outcome::ALL
        .iter()
        .filter_map(|o| {
            let n = report.rows.iter().filter(|r| r.outcome == *o).count();
            (n > 0).then(|| format!("{n} {o}"))
        })
        .collect();
    println!("outcomes: {}", counts.join(", "));
    for f in &report.charts {
        println!("wrote {}", f.display());
    }
    Ok(())
}
