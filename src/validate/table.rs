//! The table `dda validate` prints and the rows of `validation.csv`.

use std::path::Path;

use crate::output::CsvFile;

/// The columns of `validation.csv`.
pub const CSV_HEADER: &str =
    "case,example,quantity,reference,dda,error,measure,tolerance,wall_time_s,result,note";

/// One case's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub case: String,
    pub example: String,
    pub quantity: String,
    /// `None` when the case failed before there was one.
    pub reference: Option<f64>,
    pub dda: Option<f64>,
    pub error: Option<f64>,
    /// "relative" or "absolute".
    pub measure: &'static str,
    pub tolerance: f64,
    /// Wall-clock time of the run and its reading, s.
    pub wall_time: f64,
    pub passed: bool,
    /// Why the case failed when it could not be measured, else empty.
    pub note: String,
}

impl Row {
    /// "pass" or "FAIL".
    pub fn result(&self) -> &'static str {
        if self.passed {
            "pass"
        } else {
            "FAIL"
        }
    }
}

/// The first line of the printed table.
pub fn header() -> String {
    format!(
        "{:<26} {:>13} {:>13} {:>9} {:>9} {:>8}  {}",
        "case", "reference", "dda", "error", "tolerance", "wall s", "result"
    )
}

/// A row of the printed table; a case that could not be measured shows its
/// note after the result.
pub fn line(row: &Row) -> String {
    let number = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.6e}"));
    let error = row.error.map_or("-".to_string(), |e| format!("{e:.2e}"));
    let mut text = format!(
        "{:<26} {:>13} {:>13} {:>9} {:>9} {:>8.2}  {}",
        row.case,
        number(row.reference),
        number(row.dda),
        error,
        format!("{:e}", row.tolerance),
        row.wall_time,
        row.result()
    );
    if !row.note.is_empty() {
        text.push_str(&format!(": {}", row.note));
    }
    text
}

/// `validation.csv`, one row written as each case ends.
pub struct CsvTable {
    file: CsvFile,
}

impl CsvTable {
    pub fn create(path: &Path) -> anyhow::Result<Self> {
        Ok(Self {
            file: CsvFile::create(path, CSV_HEADER)?,
        })
    }

    pub fn write(&mut self, row: &Row) -> anyhow::Result<()> {
        let number = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
        self.file.write_batch(|w| {
            w.write_record([
                row.case.clone(),
                row.example.clone(),
                row.quantity.clone(),
                number(row.reference),
                number(row.dda),
                number(row.error),
                row.measure.to_string(),
                format!("{:e}", row.tolerance),
                format!("{:.3}", row.wall_time),
                row.result().to_string(),
                row.note.clone(),
            ])
        })
    }
}
