//! `steps.csv`: a row per accepted step saying what it cost, so a run's
//! slow stretches can be found and charted (`dda plot`): the step's
//! length, its open-close passes, Newton-Raphson moves, factorisations,
//! the attempts cut before it was accepted, whether it was accepted
//! unconverged, its moves on the whole tangent and their GMRES products,
//! the total energy after it, its wall time and how that time split
//! between the step's phases (as `dda bench`'s "where the time goes":
//! contact search, assembly, factorisation, substitutions, open-close
//! decisions and commit; the rest is the step's other work). Rows are
//! kept in memory between output times and written there, so a run
//! stopped at any point keeps every step up to its last output time.

use std::path::Path;

use anyhow::bail;
use dda_core::{PhaseTimes, Statistics};
use serde::Deserialize;

use crate::observe::{Cursor, Observer, RunView};
use crate::output::{first_line, num, read_rows, round_time, CsvFile};

/// The columns of `steps.csv`.
pub const STEPS_HEADER: &str = "step,time,dt,passes,moves,factorizations,cuts,unconverged,whole_tangent_moves,products,energy,wall_ms,search_ms,assembly_ms,factorization_ms,solve_ms,open_close_ms,commit_ms";

/// One row of `steps.csv`: the step numbered `step` ends at `time` (s)
/// after `dt` (s); the counts are the step's own, cuts included.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct StepRow {
    pub step: usize,
    pub time: f64,
    pub dt: f64,
    pub passes: usize,
    pub moves: usize,
    pub factorizations: usize,
    /// Attempts of this step cut to a third before one was accepted.
    pub cuts: usize,
    /// 1 if the step was accepted without open-close agreement.
    pub unconverged: usize,
    pub whole_tangent_moves: usize,
    /// GMRES's products in those moves (each a product with the matrix
    /// and a solve on the factor).
    pub products: usize,
    /// The total energy after the step, J (J/m in 2D).
    pub energy: f64,
    /// The driver's wall-clock time for the step, its cut attempts
    /// included, ms.
    pub wall_ms: f64,
    /// Of that, the contact search (broad and narrow phase, the matrix
    /// pattern), ms.
    pub search_ms: f64,
    /// Filling the matrix and the residuals, ms.
    pub assembly_ms: f64,
    /// Symbolic analysis and numeric factorisation, ms.
    pub factorization_ms: f64,
    /// Substitutions (GMRES's among them), ms.
    pub solve_ms: f64,
    /// The passes' open-close decisions and the foreseen states, ms.
    pub open_close_ms: f64,
    /// Committing the accepted step, ms.
    pub commit_ms: f64,
}

impl StepRow {
    /// The step's wall time outside its named phases, ms (at least 0:
    /// each column is rounded to a microsecond).
    pub fn other_ms(&self) -> f64 {
        let named = self.search_ms
            + self.assembly_ms
            + self.factorization_ms
            + self.solve_ms
            + self.open_close_ms
            + self.commit_ms;
        (self.wall_ms - named).max(0.0)
    }
}

/// The running totals a row is the difference of.
#[derive(Debug, Clone, Copy, Default)]
struct Totals {
    passes: usize,
    moves: usize,
    factorizations: usize,
    cuts: usize,
    unconverged: usize,
    whole_tangent_moves: usize,
    products: usize,
    wall_s: f64,
    phases: PhaseTimes,
}

impl Totals {
    fn of(s: &Statistics) -> Self {
        Self {
            passes: s.open_close_iterations,
            moves: s.newton_iterations,
            factorizations: s.factorizations,
            cuts: s.cuts(),
            unconverged: s.unconverged_steps,
            whole_tangent_moves: s.whole_tangent_moves,
            products: s.whole_tangent_products,
            wall_s: s.wall_time.as_secs_f64(),
            phases: s.times,
        }
    }
}

/// Writes `steps.csv` as the run goes.
pub struct StepsWriter {
    out: CsvFile,
    /// The totals and the time at the last step.
    last: Totals,
    last_time: f64,
    /// Rows of the steps since the last output time.
    pending: Vec<[String; 18]>,
}

impl StepsWriter {
    /// A new file, the steps counted from where `run` stands.
    pub fn create(path: &Path, run: &dyn RunView) -> anyhow::Result<Self> {
        Ok(Self::from(CsvFile::create(path, STEPS_HEADER)?, run))
    }

    /// Writes on after the first `length` bytes of `path` (a resumed run),
    /// a file of this version's columns.
    pub fn resume(path: &Path, length: u64, run: &dyn RunView) -> anyhow::Result<Self> {
        if first_line(path)? != STEPS_HEADER {
            bail!(
                "{}: its columns are not this version's ({STEPS_HEADER}), so an earlier version wrote it; run the scene again from the start",
                path.display()
            );
        }
        Ok(Self::from(CsvFile::resume(path, length)?, run))
    }

    fn from(out: CsvFile, run: &dyn RunView) -> Self {
        Self {
            out,
            last: Totals::of(run.statistics()),
            last_time: run.time(),
            pending: Vec::new(),
        }
    }

    /// Writes the rows kept since the last output time.
    fn flush(&mut self) -> anyhow::Result<()> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let rows = std::mem::take(&mut self.pending);
        self.out
            .write_batch(|w| rows.iter().try_for_each(|r| w.write_record(r)))
    }
}

impl Observer for StepsWriter {
    fn on_step(&mut self, run: &dyn RunView) {
        let s = run.statistics();
        let now = Totals::of(s);
        let last = std::mem::replace(&mut self.last, now);
        let time = run.time();
        let dt = time - std::mem::replace(&mut self.last_time, time);
        let p = now.phases.since(&last.phases);
        let ms = |d: std::time::Duration| format!("{:.3}", d.as_secs_f64() * 1e3);
        self.pending.push([
            s.steps.to_string(),
            num(round_time(time)),
            num(twelve_digits(dt)),
            (now.passes - last.passes).to_string(),
            (now.moves - last.moves).to_string(),
            (now.factorizations - last.factorizations).to_string(),
            (now.cuts - last.cuts).to_string(),
            (now.unconverged - last.unconverged).to_string(),
            (now.whole_tangent_moves - last.whole_tangent_moves).to_string(),
            (now.products - last.products).to_string(),
            num(s.energy),
            format!("{:.3}", (now.wall_s - last.wall_s) * 1e3),
            ms(p.broad_phase + p.narrow_phase + p.pattern),
            ms(p.assembly),
            ms(p.symbolic + p.numeric),
            ms(p.solve),
            ms(p.open_close),
            ms(p.commit),
        ]);
    }

    fn on_output(&mut self, _run: &dyn RunView) -> anyhow::Result<()> {
        self.flush()
    }

    fn cursor(&self) -> Option<Cursor> {
        Some(Cursor::File {
            name: "steps.csv".into(),
            length: self.out.len(),
        })
    }

    fn on_finish(
        &mut self,
        _run: &dyn RunView,
        _error: Option<&anyhow::Error>,
    ) -> anyhow::Result<()> {
        self.flush()
    }
}

/// A step's length to 12 digits: the difference of two times carries
/// their round-off (a step of 1 ms ending at 100 s is 0.0010000000000047748
/// of them), which a log has no use for.
fn twelve_digits(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// Reads a `steps.csv` written by [`StepsWriter`].
pub fn read_steps(path: impl AsRef<Path>) -> anyhow::Result<Vec<StepRow>> {
    read_rows(path.as_ref(), "steps", STEPS_HEADER)
}
