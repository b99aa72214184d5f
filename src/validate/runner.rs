//! Running the cases: each into its own folder, in parallel, a row as each
//! ends.

use std::sync::Mutex;
use std::time::Instant;

use anyhow::Context;
use dda_contact::LawRegistry;
use rayon::prelude::*;

use super::table::{self, CsvTable, Row};
use super::{Case, Options, Ran};
use crate::scene::Scene;
use crate::study::execute::run_measured;

/// Runs `cases` (at most `options.jobs` at once), printing the table on
/// stdout and writing `validation.csv` as each ends; returns the rows in
/// the order of `cases`. A case that cannot run or be measured is a failed
/// row with the error as its note; `Err` only when the output folder or
/// the CSV file cannot be written.
pub fn run_cases(
    cases: &[Case],
    options: &Options,
    registry: &LawRegistry,
) -> anyhow::Result<Vec<Row>> {
    std::fs::create_dir_all(&options.out)
        .with_context(|| format!("cannot create {}", options.out.display()))?;
    let csv = Mutex::new(CsvTable::create(&options.out.join("validation.csv"))?);
    let jobs = options
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()?;
    println!("{}", table::header());
    let rows: Vec<anyhow::Result<Row>> = pool.install(|| {
        cases
            .par_iter()
            .map(|case| {
                let row = run_case(case, options, registry);
                // Print and write together, so the table and the file agree.
                let mut csv = csv.lock().unwrap_or_else(|e| e.into_inner());
                println!("{}", table::line(&row));
                csv.write(&row)?;
                Ok(row)
            })
            .collect()
    });
    let rows = rows.into_iter().collect::<anyhow::Result<Vec<Row>>>()?;
    let passed = rows.iter().filter(|r| r.passed).count();
    let wall: f64 = rows.iter().map(|r| r.wall_time).sum();
    println!(
        "{passed} of {} cases passed ({wall:.1} s of runs); {}",
        rows.len(),
        options.out.join("validation.csv").display()
    );
    Ok(rows)
}

/// Runs one case into `out/<name>`; never fails.
fn run_case(case: &Case, options: &Options, registry: &LawRegistry) -> Row {
    let started = Instant::now();
    let mut row = Row {
        case: case.name.to_string(),
        example: case.example.to_string(),
        quantity: case.quantity.to_string(),
        reference: None,
        dda: None,
        error: None,
        measure: case.measure.name(),
        tolerance: case.tolerance,
        wall_time: 0.0,
        passed: false,
        note: String::new(),
    };
    let measured = (|| -> anyhow::Result<(f64, f64)> {
        let scene = Scene::load(options.examples.join(case.example))?;
        let reference = (case.reference)(&scene).context("the reference")?;
        let dir = options.out.join(case.name);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        let (summary, measures) = run_measured(&scene, &dir, registry)?;
        if let Some(e) = &summary.error {
            anyhow::bail!("the run failed: {e}");
        }
        let ran = Ran::new(&scene, &dir, &summary, &measures);
        let value = (case.value)(&ran)?;
        Ok((reference, value))
    })();
    row.wall_time = started.elapsed().as_secs_f64();
    match measured {
        Ok((reference, value)) => {
            let error = case.measure.of(value, reference);
            row.reference = Some(reference);
            row.dda = Some(value);
            row.error = Some(error);
            // NaN never passes.
            row.passed = error <= case.tolerance;
        }
        Err(e) => row.note = format!("{e:#}").replace(['\n', '\r'], " "),
    }
    row
}
