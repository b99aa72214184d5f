//! A search for where the outcome flips: bisection on one field, one
//! value per job tried inside the bracket at each round.

use std::path::Path;
use std::sync::Mutex;

use anyhow::bail;
use rayon::prelude::*;

use super::execute::{self, Plan};
use super::grid::expression_reference;
use super::outcome::Outcome;
use super::progress::Progress;
use super::spec::{Search, Study, Value};
use super::table::{self, Row, TableWriter};

/// What a search found.
pub struct Found {
    /// Every run, in order.
    pub rows: Vec<Row>,
    /// The bracket after each run.
    pub brackets: Vec<(f64, f64)>,
    /// The last bracket.
    pub bracket: (f64, f64),
}

/// Runs the study's search, writing each row as its round ends.
pub fn run(
    study: &Study,
    plan: &Plan,
    out: &Path,
    pool: &rayon::ThreadPool,
    writer: &Mutex<TableWriter>,
    progress: bool,
    jobs: usize,
) -> anyhow::Result<Found> {
    let Some(Search::Bisect {
        field,
        low,
        high,
        tolerance,
        ..
    }) = &study.search
    else {
        bail!("{}: the study has no search", plan.origin);
    };
    let origin = &plan.origin;
    let csv_path = out.join("study.csv");
    let names = [field.as_str()];
    let mut brackets = Vec::new();

    let mut rows: Vec<Row> = Vec::new();
    let (mut lo, mut hi) = (*low, *high);
    let mut points = vec![lo, hi];
    let progress = Progress::new(progress, 0);
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
    write_search(out, field, lo, hi, study)?;
    Ok(Found {
        rows,
        brackets,
        bracket: (lo, hi),
    })
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
