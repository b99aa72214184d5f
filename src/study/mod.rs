//! Studies: one scene run over a grid of values of its fields (or a
//! bisection on one), each run judged by a figure against a reference and
//! by its outcome, into `study.csv` and charts. `dda study STUDY.ron --out
//! DIR` is [`run`]; `--shard I/N` runs one slice of the grid and
//! `--merge DIR...` ([`merge`]) gathers slices. See `docs/studies.md`.

pub mod charts;
pub mod execute;
pub mod expr;
pub mod figure;
pub mod outcome;
pub mod spec;
pub mod table;
pub mod tree;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{bail, Context};
use dda_contact::LawRegistry;
use rayon::prelude::*;

pub use execute::Plan;
pub use outcome::Outcome;
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

/// A point of the grid: (field, value) per swept field.
type Point = Vec<(String, Value)>;

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
    let set: Point = study
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
        None => {
            let grid = grid(study);
            let mine: Vec<usize> = match options.shard {
                Some((i, n)) => (0..grid.len()).filter(|k| k % n == i).collect(),
                None => (0..grid.len()).collect(),
            };
            // Reference runs first, so the others' errors are known as they end.
            let finest = finest_points(study, &grid);
            let (first, rest): (Vec<usize>, Vec<usize>) =
                mine.iter().partition(|k| finest.contains(k));
            let progress = Progress::new(options.progress, mine.len());
            let done: Mutex<Vec<Row>> = Mutex::new(Vec::new());
            for batch in [first, rest] {
                pool.install(|| {
                    batch.par_iter().try_for_each(|&k| -> anyhow::Result<()> {
                        let dir = out.join("runs").join(execute::folder(k, &grid[k]));
                        let mut row = plan.run(k, &grid[k], &dir);
                        let mut done = done.lock().expect("no run panics holding the lock");
                        row.judge_against(reference(study, &grid, &done, k)?);
                        progress.finished(&row);
                        writer
                            .lock()
                            .expect("no run panics holding the lock")
                            .write(&row)?;
                        done.push(row);
                        Ok(())
                    })
                })?;
            }
            progress.end();
            done.into_inner().expect("the runs have ended")
        }
        Some(Search::Bisect {
            field,
            low,
            high,
            tolerance,
            ..
        }) => {
            if options.shard.is_some() {
                bail!("{origin}: a search runs its steps in order, one after another: run it without --shard");
            }
            let mut rows: Vec<Row> = Vec::new();
            let (mut lo, mut hi) = (*low, *high);
            let mut points = vec![lo, hi];
            let progress = Progress::new(options.progress, 0);
            let mut ends: Option<(Outcome, Outcome)> = None;
            loop {
                let start = rows.len();
                let ran: Vec<Row> = pool.install(|| {
                    points
                        .par_iter()
                        .enumerate()
                        .map(|(j, v)| {
                            let point = vec![(field.clone(), Value::Number(*v))];
                            let k = start + j;
                            let dir = out.join("runs").join(execute::folder(k, &point));
                            let mut row = plan.run(k, &point, &dir);
                            row.judge_against(expression_reference(study, &point));
                            progress.finished(&row);
                            row
                        })
                        .collect()
                });
                for row in &ran {
                    writer.lock().expect("single thread here").write(row)?;
                }
                let (o_lo, o_hi) = match ends {
                    None => {
                        let e = (ran[0].outcome, ran[1].outcome);
                        if e.0 == e.1 {
                            rows.extend(ran);
                            brackets.extend([(lo, hi), (lo, hi)]);
                            table::write_all(&csv_path, &names, &rows)?;
                            bail!(
                                "{origin}: search on `{field}`: both ends of the bracket [{lo}, {hi}] are {}: widen it until the outcome flips",
                                e.0
                            );
                        }
                        ends = Some(e);
                        e
                    }
                    Some(e) => e,
                };
                // The lowest tried value whose outcome is not the low end's,
                // and the tried value below it.
                let mut tried: Vec<(f64, Outcome)> = vec![(lo, o_lo), (hi, o_hi)];
                tried.extend(points.iter().copied().zip(ran.iter().map(|r| r.outcome)));
                tried.sort_by(|a, b| a.0.total_cmp(&b.0));
                tried.retain(|t| t.0 >= lo && t.0 <= hi);
                if let Some(j) = tried.iter().position(|t| t.1 != o_lo).filter(|&j| j > 0) {
                    (lo, hi) = (tried[j - 1].0, tried[j].0);
                }
                brackets.extend(std::iter::repeat_n((lo, hi), ran.len()));
                rows.extend(ran);
                if hi - lo <= *tolerance {
                    break;
                }
                let k = jobs.max(1);
                points = (1..=k)
                    .map(|j| lo + (hi - lo) * j as f64 / (k + 1) as f64)
                    .collect();
            }
            progress.end();
            bracket = Some((lo, hi));
            write_search(out, field, lo, hi, study)?;
            rows
        }
    };
    drop(writer);
    let mut rows = rows;
    rows.sort_by_key(|r| r.index);
    fill_references(study, &fields, &mut rows)?;
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

/// Every combination of the swept values, the first sweep slowest.
fn grid(study: &Study) -> Vec<Point> {
    let mut points: Vec<Point> = vec![Vec::new()];
    for s in &study.sweep {
        points = points
            .into_iter()
            .flat_map(|p| {
                s.values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push((s.field.clone(), v.clone()));
                    q
                })
            })
            .collect();
    }
    points
}

/// For `Finest(field)`: each grid point's reference point.
fn finest_of(study: &Study, grid: &[Point], k: usize) -> Option<usize> {
    let Some(Reference::Finest(field)) = &study.reference else {
        return None;
    };
    let others = |p: &Point| -> Vec<String> {
        p.iter()
            .filter(|(f, _)| f != field)
            .map(|(_, v)| v.label())
            .collect()
    };
    let value = |p: &Point| {
        p.iter()
            .find(|(f, _)| f == field)
            .and_then(|(_, v)| v.number())
            .unwrap_or(f64::INFINITY)
    };
    let mine = others(&grid[k]);
    (0..grid.len())
        .filter(|&j| others(&grid[j]) == mine)
        .min_by(|&a, &b| value(&grid[a]).total_cmp(&value(&grid[b])))
}

fn finest_points(study: &Study, grid: &[Point]) -> Vec<usize> {
    let mut v: Vec<usize> = (0..grid.len())
        .filter_map(|k| finest_of(study, grid, k))
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// The reference of grid point `k`, from the rows done so far.
fn reference(study: &Study, grid: &[Point], done: &[Row], k: usize) -> anyhow::Result<Option<f64>> {
    Ok(match &study.reference {
        Some(Reference::Finest(_)) => finest_of(study, grid, k)
            .and_then(|j| done.iter().find(|r| r.index == j))
            .and_then(|r| r.figure),
        _ => expression_reference(study, &grid[k]),
    })
}

/// A number or expression reference at `point` (`None` for the others or
/// when the expression cannot be evaluated).
fn expression_reference(study: &Study, point: &Point) -> Option<f64> {
    match &study.reference {
        Some(Reference::Number(x)) => Some(*x),
        Some(Reference::Expression(e)) => {
            let var = |name: &str| {
                if name == "t" {
                    return study.figure.time();
                }
                point
                    .iter()
                    .chain(
                        study
                            .set
                            .iter()
                            .map(|(k, v)| (k.clone(), v.clone()))
                            .collect::<Vec<_>>()
                            .iter(),
                    )
                    .find(|(f, _)| f == name)
                    .and_then(|(_, v)| v.number())
            };
            expr::eval(e, &var).ok()
        }
        _ => None,
    }
}

/// Fills every row's reference from the whole table (a merge, or a shard's
/// rows whose reference run was elsewhere).
fn fill_references(study: &Study, fields: &[String], rows: &mut [Row]) -> anyhow::Result<()> {
    if let Some(Reference::Expression(e)) = &study.reference {
        // Say once, clearly, when the expression itself is wrong.
        let var = |name: &str| {
            (name == "t" || fields.iter().any(|f| f == name) || study.set.contains_key(name))
                .then_some(1.0)
        };
        if let Err(why) = expr::eval(e, &var) {
            bail!("the reference expression: {why}");
        }
    }
    let points: Vec<Point> = rows
        .iter()
        .map(|r| {
            fields
                .iter()
                .cloned()
                .zip(r.values.iter().map(|v| match v.parse() {
                    Ok(x) => Value::Number(x),
                    Err(_) => Value::Text(v.clone()),
                }))
                .collect()
        })
        .collect();
    let snapshot = rows.to_vec();
    for (k, row) in rows.iter_mut().enumerate() {
        let reference = match &study.reference {
            Some(Reference::Finest(field)) => {
                let c = fields.iter().position(|f| f == field);
                c.and_then(|c| {
                    let others = |r: &Row| -> Vec<String> {
                        r.values
                            .iter()
                            .enumerate()
                            .filter(|(j, _)| *j != c)
                            .map(|(_, v)| v.clone())
                            .collect()
                    };
                    let mine = others(&snapshot[k]);
                    snapshot
                        .iter()
                        .filter(|r| others(r) == mine)
                        .min_by(|a, b| {
                            let v = |r: &Row| r.values[c].parse::<f64>().unwrap_or(f64::INFINITY);
                            v(a).total_cmp(&v(b))
                        })
                        .and_then(|r| r.figure)
                })
            }
            _ => expression_reference(study, &points[k]),
        };
        row.judge_against(reference);
    }
    Ok(())
}

/// The study's charts into `DIR/charts/`.
fn draw_charts(
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

/// `DIR/search.json`: the bracket a search ended with.
fn write_search(out: &Path, field: &str, lo: f64, hi: f64, study: &Study) -> anyhow::Result<()> {
    let expected = match &study.search {
        Some(Search::Bisect { expected, .. }) => *expected,
        None => None,
    };
    let json = serde_json::json!({
        "field": field,
        "low": lo,
        "high": hi,
        "estimate": 0.5 * (lo + hi),
        "half_width": 0.5 * (hi - lo),
        "expected": expected,
    });
    crate::output::write_json(&out.join("search.json"), &json)
}

/// Gathers the study.csv of shard folders (each with its study.ron) into
/// `out`: one table in index order, references filled, the charts drawn.
pub fn merge(dirs: &[PathBuf], out: &Path) -> anyhow::Result<Report> {
    let Some(first) = dirs.first() else {
        bail!("--merge needs the folders of the shards to gather");
    };
    let spec_path = first.join("study.ron");
    let text = std::fs::read_to_string(&spec_path).with_context(|| {
        format!(
            "{}: not a study folder (no study.ron): give folders `dda study --shard` wrote",
            first.display()
        )
    })?;
    let study = Study::parse(&text, &spec_path.display().to_string())?;
    let mut fields: Option<Vec<String>> = None;
    let mut rows: Vec<Row> = Vec::new();
    for dir in dirs {
        let other = std::fs::read_to_string(dir.join("study.ron")).unwrap_or_default();
        if other != text {
            bail!(
                "{}: its study.ron differs from {}'s: merge only shards of one study",
                dir.display(),
                first.display()
            );
        }
        let (f, r) = table::read(&dir.join("study.csv"))?;
        if fields.as_ref().is_some_and(|g| *g != f) {
            bail!(
                "{}: its study.csv has other columns than the first",
                dir.display()
            );
        }
        fields = Some(f);
        for row in r {
            if rows.iter().any(|q| q.index == row.index) {
                bail!(
                    "run {} is in more than one of the folders: merge each shard once",
                    row.index
                );
            }
            rows.push(row);
        }
    }
    let fields = fields.unwrap_or_default();
    rows.sort_by_key(|r| r.index);
    fill_references(&study, &fields, &mut rows)?;
    crate::pictures::create_dir(out)?;
    std::fs::write(out.join("study.ron"), &text)?;
    let names: Vec<&str> = fields.iter().map(String::as_str).collect();
    table::write_all(&out.join("study.csv"), &names, &rows)?;
    let title = study.title_or(&spec_path);
    let charts = draw_charts(&study, &title, &fields, &rows, out)?;
    Ok(Report {
        fields,
        rows,
        charts,
        bracket: None,
    })
}

/// `I/N` (0 ≤ I < N), or SLURM's array task id and count when not given.
pub fn shard(text: Option<&str>) -> anyhow::Result<Option<(usize, usize)>> {
    let env = |k: &str| std::env::var(k).ok();
    let (i, n, from) = match text {
        Some(t) => {
            let bad = || anyhow::anyhow!("--shard {t}: give I/N with 0 ≤ I < N, like 0/3");
            let (i, n) = t.split_once('/').ok_or_else(bad)?;
            let i: usize = i.trim().parse().map_err(|_| bad())?;
            let n: usize = n.trim().parse().map_err(|_| bad())?;
            (i, n, "--shard")
        }
        None => match (env("SLURM_ARRAY_TASK_ID"), env("SLURM_ARRAY_TASK_COUNT")) {
            (Some(id), Some(count)) => {
                let num = |s: &str, what: &str| -> anyhow::Result<usize> {
                    s.trim()
                        .parse()
                        .with_context(|| format!("{what}={s} is not a whole number"))
                };
                let min = env("SLURM_ARRAY_TASK_MIN")
                    .map(|m| num(&m, "SLURM_ARRAY_TASK_MIN"))
                    .transpose()?
                    .unwrap_or(0);
                let id = num(&id, "SLURM_ARRAY_TASK_ID")?;
                (
                    id.saturating_sub(min),
                    num(&count, "SLURM_ARRAY_TASK_COUNT")?,
                    "SLURM_ARRAY_TASK_ID/COUNT",
                )
            }
            _ => return Ok(None),
        },
    };
    if n == 0 || i >= n {
        bail!("{from}: shard {i} of {n}: give 0 ≤ I < N");
    }
    Ok(Some((i, n)))
}

/// `dda study`'s progress: a bar on a terminal, otherwise a line per run.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
    lines: bool,
    count: std::sync::atomic::AtomicUsize,
    total: usize,
}

impl Progress {
    fn new(show: bool, total: usize) -> Self {
        let terminal = show && std::io::stderr().is_terminal();
        let bar = terminal.then(|| {
            let bar = indicatif::ProgressBar::new(total as u64);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} runs, {elapsed} ({eta} left) {msg}",
            ) {
                bar.set_style(style);
            }
            bar
        });
        Self {
            bar,
            lines: show && !terminal,
            count: Default::default(),
            total,
        }
    }

    fn finished(&self, row: &Row) {
        let n = self
            .count
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed)
            + 1;
        let figure = row.figure.map_or("–".to_string(), |f| format!("{f:.6e}"));
        let line = format!(
            "{}: {}, figure {figure}, {:.2} s",
            row.run, row.outcome, row.wall_time
        );
        if let Some(bar) = &self.bar {
            bar.inc(1);
            bar.set_message(line);
        } else if self.lines {
            let of = if self.total > 0 {
                format!("/{}", self.total)
            } else {
                String::new()
            };
            eprintln!("[{n}{of}] {line}");
        }
    }

    fn end(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
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
