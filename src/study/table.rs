//! `study.csv`: one row per run, written and flushed as each run ends, and
//! read back for charts and merges.

use std::fs::File;
use std::path::Path;

use anyhow::{bail, Context};

use super::outcome::Outcome;

/// One run of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Position in the grid (or the search's order).
    pub index: usize,
    /// The swept values, as labels, in the study's field order.
    pub values: Vec<String>,
    pub figure: Option<f64>,
    pub reference: Option<f64>,
    /// |figure − reference|.
    pub error: Option<f64>,
    /// error / |reference|.
    pub relative_error: Option<f64>,
    /// Seconds of wall time to build and run.
    pub wall_time: f64,
    pub steps: usize,
    /// Steps cut (open-close, displacement and penetration cuts).
    pub cuts: usize,
    pub open_close_iterations: usize,
    pub unconverged_steps: usize,
    /// Deepest penetration beyond the bound, m (when the summary has it).
    pub deepest_penetration: Option<f64>,
    /// Largest energy rise, J.
    pub energy_growth: Option<f64>,
    pub outcome: Outcome,
    /// The run's folder under `runs/`.
    pub run: String,
    /// Why a run failed or its figure could not be read.
    pub note: String,
}

/// Columns after the swept values.
const TAIL: [&str; 14] = [
    "figure",
    "reference",
    "error",
    "relative_error",
    "wall_time",
    "steps",
    "cuts",
    "open_close_iterations",
    "unconverged_steps",
    "deepest_penetration",
    "energy_growth",
    "outcome",
    "run",
    "note",
];

/// Columns whose values do not depend on the machine or its load.
pub fn deterministic(row: &Row) -> Row {
    Row {
        wall_time: 0.0,
        ..row.clone()
    }
}

impl Row {
    /// Sets the reference and the errors.
    pub fn judge_against(&mut self, reference: Option<f64>) {
        self.reference = reference;
        self.error = match (self.figure, reference) {
            (Some(f), Some(r)) => Some((f - r).abs()),
            _ => None,
        };
        self.relative_error = match (self.error, reference) {
            (Some(e), Some(r)) if r != 0.0 => Some(e / r.abs()),
            _ => None,
        };
    }
}

/// Writes rows as they come, each flushed.
pub struct TableWriter {
    csv: csv::Writer<File>,
}

impl TableWriter {
    pub fn create(path: &Path, fields: &[&str]) -> anyhow::Result<Self> {
        let file =
            File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
        let mut csv = csv::Writer::from_writer(file);
        let header: Vec<&str> = std::iter::once("index")
            .chain(fields.iter().copied())
            .chain(TAIL)
            .collect();
        csv.write_record(&header)?;
        csv.flush()?;
        Ok(Self { csv })
    }

    pub fn write(&mut self, row: &Row) -> anyhow::Result<()> {
        let num = |v: Option<f64>| v.map(|x| format!("{x:e}")).unwrap_or_default();
        let mut record = vec![row.index.to_string()];
        record.extend(row.values.iter().cloned());
        record.extend([
            num(row.figure),
            num(row.reference),
            num(row.error),
            num(row.relative_error),
            format!("{:.4}", row.wall_time),
            row.steps.to_string(),
            row.cuts.to_string(),
            row.open_close_iterations.to_string(),
            row.unconverged_steps.to_string(),
            num(row.deepest_penetration),
            num(row.energy_growth),
            row.outcome.to_string(),
            row.run.clone(),
            row.note.clone(),
        ]);
        self.csv.write_record(&record)?;
        self.csv.flush()?;
        Ok(())
    }
}

/// Writes a whole table, rows in index order.
pub fn write_all(path: &Path, fields: &[&str], rows: &[Row]) -> anyhow::Result<()> {
    let mut sorted = rows.to_vec();
    sorted.sort_by_key(|r| r.index);
    let mut w = TableWriter::create(path, fields)?;
    sorted.iter().try_for_each(|r| w.write(r))
}

/// The swept fields and rows of a study.csv.
pub fn read(path: &Path) -> anyhow::Result<(Vec<String>, Vec<Row>)> {
    let mut csv =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let header: Vec<String> = csv.headers()?.iter().map(String::from).collect();
    let n = header.len();
    if n < TAIL.len() + 1 || header[0] != "index" || header[n - TAIL.len()..] != TAIL {
        bail!(
            "{}: not a study table (the header should be index, the swept fields, then {})",
            path.display(),
            TAIL.join(",")
        );
    }
    let fields = header[1..n - TAIL.len()].to_vec();
    let mut rows = Vec::new();
    for (line, record) in csv.records().enumerate() {
        let r = record?;
        let at = |k: usize| r.get(k).unwrap_or("");
        let bad = |what: &str| {
            anyhow::anyhow!(
                "{}: row {}: {what} is not a number",
                path.display(),
                line + 2
            )
        };
        let num = |k: usize, what: &str| -> anyhow::Result<Option<f64>> {
            let s = at(k);
            if s.is_empty() {
                Ok(None)
            } else {
                s.parse().map(Some).map_err(|_| bad(what))
            }
        };
        let count = |k: usize, what: &str| -> anyhow::Result<usize> {
            at(k).parse().map_err(|_| bad(what))
        };
        let t = 1 + fields.len();
        rows.push(Row {
            index: count(0, "index")?,
            values: (1..t).map(|k| at(k).to_string()).collect(),
            figure: num(t, "figure")?,
            reference: num(t + 1, "reference")?,
            error: num(t + 2, "error")?,
            relative_error: num(t + 3, "relative_error")?,
            wall_time: num(t + 4, "wall_time")?.unwrap_or(0.0),
            steps: count(t + 5, "steps")?,
            cuts: count(t + 6, "cuts")?,
            open_close_iterations: count(t + 7, "open_close_iterations")?,
            unconverged_steps: count(t + 8, "unconverged_steps")?,
            deepest_penetration: num(t + 9, "deepest_penetration")?,
            energy_growth: num(t + 10, "energy_growth")?,
            outcome: at(t + 11).parse().map_err(|e: String| {
                anyhow::anyhow!("{}: row {}: {e}", path.display(), line + 2)
            })?,
            run: at(t + 12).to_string(),
            note: at(t + 13).to_string(),
        });
    }
    Ok((fields, rows))
}
