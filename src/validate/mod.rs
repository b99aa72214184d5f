//! The verification catalogue behind `dda validate`: every shipped example
//! with an analytical answer, run and compared with it.
//!
//! A [`Case`] names its example, the quantity it measures from the run's
//! outputs, the analytical reference computed from the scene's own
//! parameters, the error measure and the tolerance the README states.
//! [`run_cases`] runs a list of cases in parallel, each into its own folder,
//! printing a table row and writing a `validation.csv` row as each ends;
//! [`command`] is that, failing when a case fails.

pub mod catalogue;
pub mod formulas;
mod runner;
mod table;

use std::cell::OnceCell;
use std::path::{Path, PathBuf};

use crate::scene::Scene;
use crate::study::figure::Measures;
use crate::summary::Summary;
use crate::{HistoryRow, HistoryRow3};

pub use catalogue::catalogue;
pub use runner::run_cases;
pub use table::{Row, CSV_HEADER};

/// How a case's value is compared with its reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorMeasure {
    /// |value − reference| / |reference|.
    Relative,
    /// |value − reference|, in the quantity's unit.
    Absolute,
}

impl ErrorMeasure {
    /// The error of `value` against `reference`.
    pub fn of(self, value: f64, reference: f64) -> f64 {
        match self {
            ErrorMeasure::Relative => ((value - reference) / reference).abs(),
            ErrorMeasure::Absolute => (value - reference).abs(),
        }
    }

    /// "relative" or "absolute".
    pub fn name(self) -> &'static str {
        match self {
            ErrorMeasure::Relative => "relative",
            ErrorMeasure::Absolute => "absolute",
        }
    }
}

/// One verification case: an example, what is measured from its run and
/// what it must agree with.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// Short name, for `--only` and the table's first column.
    pub name: &'static str,
    /// The scene file, in the examples folder.
    pub example: &'static str,
    /// One line: what the case is.
    pub description: &'static str,
    /// What is compared, with its unit.
    pub quantity: &'static str,
    pub measure: ErrorMeasure,
    /// The largest error that passes, in the measure's terms.
    pub tolerance: f64,
    /// In the `--quick` subset (a few seconds at most).
    pub quick: bool,
    /// The analytical answer, from the scene's parameters.
    pub reference: fn(&Scene) -> anyhow::Result<f64>,
    /// The run's answer, from its outputs.
    pub value: fn(&Ran) -> anyhow::Result<f64>,
}

/// A finished run of a case, for [`Case::value`].
pub struct Ran<'a> {
    pub scene: &'a Scene,
    /// The run's folder: `history.csv`, `contacts.csv` (when the scene asks
    /// for it) and `summary.json`.
    pub dir: &'a Path,
    pub summary: &'a Summary,
    /// Block sizes at the start and the end, which the files do not hold.
    pub measures: &'a Measures,
    rows: OnceCell<Vec<HistoryRow>>,
    rows_3d: OnceCell<Vec<HistoryRow3>>,
}

impl<'a> Ran<'a> {
    pub fn new(
        scene: &'a Scene,
        dir: &'a Path,
        summary: &'a Summary,
        measures: &'a Measures,
    ) -> Self {
        Self {
            scene,
            dir,
            summary,
            measures,
            rows: OnceCell::new(),
            rows_3d: OnceCell::new(),
        }
    }

    /// The 2D history, read once.
    pub fn history(&self) -> anyhow::Result<&[HistoryRow]> {
        if let Some(rows) = self.rows.get() {
            return Ok(rows);
        }
        let rows = crate::read_history(self.dir.join("history.csv"))?;
        Ok(self.rows.get_or_init(|| rows))
    }

    /// The 3D history, read once.
    pub fn history_3d(&self) -> anyhow::Result<&[HistoryRow3]> {
        if let Some(rows) = self.rows_3d.get() {
            return Ok(rows);
        }
        let rows = crate::read_history_3d(self.dir.join("history.csv"))?;
        Ok(self.rows_3d.get_or_init(|| rows))
    }
}

/// How `dda validate` runs.
#[derive(Debug, Clone)]
pub struct Options {
    /// Where each case's run goes (`DIR/<case>/`) and `DIR/validation.csv`.
    pub out: PathBuf,
    /// The folder of the shipped examples.
    pub examples: PathBuf,
    /// Runs at once; default one per core.
    pub jobs: Option<usize>,
}

/// The examples folder: `examples` under the current folder when there is
/// one, else the one this crate was built from.
pub fn default_examples() -> PathBuf {
    let here = PathBuf::from("examples");
    if here.is_dir() {
        here
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
    }
}

/// The cases to run: those named in `only` (in catalogue order), else the
/// quick ones with `quick`, else all.
pub fn select(cases: &[Case], quick: bool, only: &[String]) -> anyhow::Result<Vec<Case>> {
    if let Some(unknown) = only.iter().find(|n| !cases.iter().any(|c| c.name == *n)) {
        let names: Vec<&str> = cases.iter().map(|c| c.name).collect();
        anyhow::bail!(
            "no case `{unknown}` in the catalogue; the cases are {}",
            names.join(", ")
        );
    }
    Ok(cases
        .iter()
        .filter(|c| {
            if only.is_empty() {
                c.quick || !quick
            } else {
                only.iter().any(|n| n == c.name)
            }
        })
        .copied()
        .collect())
}

/// Runs `cases` and fails, naming them, if any case failed.
pub fn command(
    cases: &[Case],
    options: &Options,
    registry: &dda_contact::LawRegistry,
) -> anyhow::Result<Vec<Row>> {
    let rows = run_cases(cases, options, registry)?;
    let failed: Vec<&str> = rows
        .iter()
        .filter(|r| !r.passed)
        .map(|r| r.case.as_str())
        .collect();
    if !failed.is_empty() {
        anyhow::bail!(
            "{} of {} cases failed: {} (see {})",
            failed.len(),
            rows.len(),
            failed.join(", "),
            options.out.join("validation.csv").display()
        );
    }
    Ok(rows)
}
