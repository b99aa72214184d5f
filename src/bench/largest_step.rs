//! The compared wall at rest at large given steps: whether it stands at
//! steps of 5 and 10 ms without drift, and the largest step it stands at
//! (`dda bench --targets`).
//!
//! A wall at rest settles onto its joints' springs (and, deformable, its
//! bricks' own shortening). Its static settlement is read off two steps
//! so long that the inertia terms (2M/dt²) vanish: Newmark's step is then
//! the static solve. A wall that stands moves at most twice that (the most
//! a load applied at once moves a linear system starting at rest) and
//! ends at it; one that creeps, or whose step fails, does not.

use std::time::Duration;

use super::simulate::{simulate, SimulateOptions, SimulateRow};
use crate::scene::BlockKind;
use dda_core::Solver;

/// The steps a standing wall must run at without drift, s (5 and 10 ms).
pub const STANDING_STEPS: [f64; 2] = [5e-3, 1e-2];
/// The step whose two steps give the static settlement, s (40.96): the
/// inertia terms are 1e-9 of a 1 ms step's.
pub const STATIC_STEP: f64 = 40.96;
/// The steps tried for the largest the wall stands at: 10 ms times
/// powers of 4, up to 10.24 s.
pub const TRIED_STEPS: [f64; 6] = [0.01, 0.04, 0.16, 0.64, 2.56, 10.24];
/// The most a standing wall may move, as a share of its static
/// settlement (2: a load applied at once).
pub const OVERSHOOT: f64 = 2.0;
/// How far from its static settlement a standing wall may end, as a
/// share of it (1 %).
pub const END_SHARE: f64 = 0.01;

/// Why a run does not stand, or `None` where it does, against the static
/// settlement `settled`, m.
pub fn fault(row: &SimulateRow, settled: f64) -> Option<String> {
    if !row.completed {
        Some(format!("stopped at {:.3} s", row.reached))
    } else if row.cuts > 0 || row.unconverged_steps > 0 {
        Some(format!(
            "{} cuts, {} unconverged steps",
            row.cuts, row.unconverged_steps
        ))
    } else if row.drift > OVERSHOOT * settled {
        Some(format!(
            "moved {:.2} times its static settlement",
            row.drift / settled
        ))
    } else if (row.end_drift - settled).abs() > END_SHARE * settled {
        Some(format!(
            "ended {:+.1} % from its static settlement",
            100.0 * (row.end_drift / settled - 1.0)
        ))
    } else {
        None
    }
}

/// The wall of `courses` courses and `kind` run at `dt` for `seconds` (at
/// least two steps), stopped after `max_wall` wall-clock seconds.
fn run(
    (courses, max_wall): (usize, f64),
    kind: BlockKind,
    dt: f64,
    seconds: f64,
) -> anyhow::Result<SimulateRow> {
    let rows = simulate(&SimulateOptions {
        sizes: vec![courses],
        kinds: vec![kind],
        dimensions: vec![2],
        seconds: seconds.max(2.0 * dt),
        max_wall,
        repeats: 1,
        progress_every: Some(Duration::from_secs(5)),
        solver: Solver::Direct,
        dts: vec![dt],
        shake: None,
        settle: false,
        step_log: None,
    })?;
    rows.into_iter()
        .next()
        .ok_or_else(|| anyhow::anyhow!("no run of the wall at dt {dt} s"))
}

/// The static settlement of the wall of `courses` courses and `kind`, m:
/// where two steps of `STATIC_STEP` leave it.
pub fn static_settlement(courses: usize, max_wall: f64, kind: BlockKind) -> anyhow::Result<f64> {
    Ok(run((courses, max_wall), kind, STATIC_STEP, 0.0)?.end_drift)
}

/// The wall of `courses` courses and `kind` at rest, each run `seconds`
/// long (each stopped after `max_wall` wall-clock seconds), against its
/// static settlement `settled` (m): what it read at the standing steps
/// and the largest step tried that it stands at, and whether it stands at
/// both standing steps.
pub fn reading(
    courses: usize,
    seconds: f64,
    max_wall: f64,
    kind: BlockKind,
    settled: f64,
) -> anyhow::Result<(String, bool)> {
    let wall = (courses, max_wall);
    let mut stands = true;
    let mut at = Vec::new();
    // The standing steps' runs, which the sweep reads again rather than
    // running them twice (10 ms is both).
    let mut done = Vec::new();
    for dt in STANDING_STEPS {
        let row = run(wall, kind, dt, seconds)?;
        let fault = fault(&row, settled);
        stands &= fault.is_none();
        at.push(format!(
            "{:.0} ms {:.2e} m ({:.2}×){}",
            dt * 1e3,
            row.drift,
            row.drift / settled,
            fault.map_or(String::new(), |f| format!(", {f}"))
        ));
        done.push((dt, row));
    }
    // The largest step tried before the first it does not stand at.
    let mut largest = None;
    let mut failed = None;
    for dt in TRIED_STEPS {
        let row = match done.iter().find(|(d, _)| *d == dt) {
            Some((_, row)) => row.clone(),
            None => run(wall, kind, dt, seconds)?,
        };
        match fault(&row, settled) {
            None => largest = Some(dt),
            Some(f) => {
                failed = Some(format!("not at {dt} s: {f}"));
                break;
            }
        }
    }
    let sweep = match (largest, failed) {
        (Some(dt), None) => format!("stands at every step tried, up to {dt} s"),
        (Some(dt), Some(f)) => format!("stands at steps up to {dt} s, {f}"),
        (None, Some(f)) => f,
        (None, None) => unreachable!("steps were tried"),
    };
    let text = format!(
        "{}; static settlement {settled:.2e} m; {sweep}",
        at.join(", ")
    );
    Ok((text, stands))
}

/// What the target asks of the wall of `courses` courses run `seconds`.
pub fn asked(courses: usize, seconds: f64) -> String {
    format!(
        "{courses} × {courses} wall at rest at dt 5 and 10 ms, {seconds} s, both kinds: no cut, no unconverged step, moving at most {OVERSHOOT} times its static settlement and ending within {:.0} % of it; the largest step it stands at ({}-{} s tried)",
        END_SHARE * 100.0,
        TRIED_STEPS[0],
        TRIED_STEPS[TRIED_STEPS.len() - 1]
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(drift: f64, end_drift: f64, cuts: usize, completed: bool) -> SimulateRow {
        let mut r = crate::bench::simulate::tests::row(1.0, drift);
        r.end_drift = end_drift;
        r.cuts = cuts;
        r.completed = completed;
        r
    }

    /// A run stands only when it finished without a cut, moved at most
    /// twice its static settlement and ended within 1 % of it.
    #[test]
    fn a_wall_stands_without_cuts_overshoot_or_creep() {
        let settled = 1e-4;
        assert_eq!(fault(&row(1.9e-4, 1.005e-4, 0, true), settled), None);
        assert_eq!(fault(&row(1e-4, 0.995e-4, 0, true), settled), None);
        let faults = [
            row(2.1e-4, 1e-4, 0, true),
            row(1.5e-4, 1.02e-4, 0, true),
            row(1.5e-4, 0.98e-4, 0, true),
            row(1.5e-4, 1e-4, 1, true),
            row(1.5e-4, 1e-4, 0, false),
        ];
        for r in &faults {
            assert!(fault(r, settled).is_some(), "{r:?}");
        }
    }
}
