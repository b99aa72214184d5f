//! The grid of a sweep: its points, run in parallel with the reference
//! runs first, and the references of each point.

use std::path::Path;
use std::sync::Mutex;

use anyhow::bail;
use rayon::prelude::*;

use super::execute::{self, Plan};
use super::progress::Progress;
use super::spec::{Reference, Study, Value};
use super::table::{Row, TableWriter};
use super::{expr, Options};

/// A point of the grid: (field, value) per swept field.
pub type Point = Vec<(String, Value)>;

/// Runs this shard's points of the grid, each row written as it ends.
pub fn run(
    study: &Study,
    plan: &Plan,
    out: &Path,
    pool: &rayon::ThreadPool,
    writer: &Mutex<TableWriter>,
    options: &Options,
) -> anyhow::Result<Vec<Row>> {
    let grid = points(study);
    let mine: Vec<usize> = match options.shard {
        Some((i, n)) => (0..grid.len()).filter(|k| k % n == i).collect(),
        None => (0..grid.len()).collect(),
    };
    // Reference runs first, so the others' errors are known as they end.
    let finest = finest_points(study, &grid);
    let (first, rest): (Vec<usize>, Vec<usize>) = mine.iter().partition(|k| finest.contains(k));
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
    Ok(done.into_inner().expect("the runs have ended"))
}

/// Every combination of the swept values, the first sweep slowest.
pub fn points(study: &Study) -> Vec<Point> {
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
pub fn expression_reference(study: &Study, point: &Point) -> Option<f64> {
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
pub fn fill_references(study: &Study, fields: &[String], rows: &mut [Row]) -> anyhow::Result<()> {
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
