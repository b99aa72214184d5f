//! A results CSV (`history.csv`, `contacts.csv`, `study.csv`) as columns
//! named by its header, so 2D and 3D histories and any later columns are
//! read alike.

use std::path::Path;

use anyhow::{bail, Context};

/// One column: integers, floats, or text when any cell is not a number.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    Int(Vec<i64>),
    Float(Vec<f64>),
    Text(Vec<String>),
}

/// The columns of a CSV file in header order.
pub fn read_columns(path: &Path) -> anyhow::Result<Vec<(String, Column)>> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .with_context(|| format!("cannot open {}", path.display()))?;
    let names: Vec<String> = reader
        .headers()
        .with_context(|| format!("{}: cannot read the header", path.display()))?
        .iter()
        .map(str::to_string)
        .collect();
    let mut cells: Vec<Vec<String>> = vec![Vec::new(); names.len()];
    for (k, record) in reader.records().enumerate() {
        // Line k + 2: the header is line 1.
        let record = record.with_context(|| format!("{}:{}: bad row", path.display(), k + 2))?;
        if record.len() != names.len() {
            bail!(
                "{}:{}: {} fields where the header has {}",
                path.display(),
                k + 2,
                record.len(),
                names.len()
            );
        }
        for (column, cell) in cells.iter_mut().zip(record.iter()) {
            column.push(cell.to_string());
        }
    }
    Ok(names
        .into_iter()
        .zip(cells)
        .map(|(name, cells)| {
            let column = typed(&name, cells);
            (name, column)
        })
        .collect())
}

/// Whether a column counts or numbers things (steps, blocks): integers.
/// Any other numeric column is float even when its cells are whole
/// numbers, so a column's type does not change from run to run.
fn is_count(name: &str) -> bool {
    matches!(
        name,
        "step"
            | "steps"
            | "block"
            | "block_a"
            | "block_b"
            | "point"
            | "index"
            | "case"
            | "run"
            // steps.csv's counts of a step's work.
            | "passes"
            | "moves"
            | "factorizations"
            | "cuts"
            | "unconverged"
            | "whole_tangent_moves"
            | "products"
    ) || name.ends_with("_id")
        || name.ends_with("_count")
}

/// The narrowest type every cell reads as.
fn typed(name: &str, cells: Vec<String>) -> Column {
    if is_count(name) {
        if let Ok(ints) = cells.iter().map(|c| c.parse::<i64>()).collect() {
            return Column::Int(ints);
        }
    }
    if let Ok(floats) = cells.iter().map(|c| c.parse::<f64>()).collect() {
        return Column::Float(floats);
    }
    Column::Text(cells)
}
