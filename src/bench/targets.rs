//! `dda bench --targets`: the walls' speed targets measured in one run,
//! each with what was measured and its verdict, under the machine and the
//! date, as a Markdown table (and JSON). MuJoCo's time on the compared
//! wall comes from `benches/mujoco_wall.py`, run just before on the same
//! machine (`benches/targets.sh` runs both).

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use anyhow::Context;
use serde::{Deserialize, Serialize};

use super::largest_step;
use super::scaling::{exponent, kind_name};
use super::simulate::{simulate, SimulateOptions, SimulateRow};
use super::walls::{Stepping, FIXED_PENALTY};
use super::{bench, BenchOptions, BenchRow};
use crate::scene::BlockKind;
use dda_core::Solver;

/// The share of MuJoCo's wall time the compared wall may take (1/10).
const MUJOCO_SHARE: f64 = 0.1;
/// The compared wall's largest drift over its simulated second, m.
const DRIFT_LIMIT: f64 = 1.8e-4;
/// Doolin's DDA (ntdda) on the 20 × 20 wall (411 blocks), ms a step, and
/// the speed-up asked of it (10).
const NTDDA_MS: f64 = 28.0;
const NTDDA_SPEEDUP: f64 = 10.0;
/// The drift that counts a wall at rest as standing, m: it settles
/// micrometres (ntdda's 10 × 10 wall drifted 0.155 m within 0.2 s).
const STANDING_DRIFT: f64 = 1e-4;
/// Open-close passes the compared wall may take in any one step at dt 1
/// ms (2).
const FEW_PASSES: usize = 2;
/// The largest walls' time a step, ms, and the process's peak memory, MB.
const LARGEST_MS: f64 = 100.0;
const MEMORY_MB: f64 = 2000.0;
/// The largest exponent p of time a step ∝ N^p between the compared
/// wall and the largest.
const EXPONENT: f64 = 1.3;

/// The walls and runs of a targets run; [`TargetOptions::default`] is the
/// issue's.
#[derive(Debug, Clone)]
pub struct TargetOptions {
    /// Courses of the wall compared with MuJoCo, and the first wall of the
    /// exponent (40: 1,621 blocks).
    pub compared: usize,
    /// Courses of the wall compared with ntdda (20: 411 blocks).
    pub ntdda: usize,
    /// Courses of the wall ntdda blows up on at dt 1 ms (10).
    pub standing: usize,
    /// Courses of the largest walls, 2D and 3D (100: 10,051 blocks).
    pub largest: usize,
    /// Simulated time of the automatic-step and dt 1 ms runs, s (1).
    pub seconds: f64,
    /// Steps timed at dt 1 ms on the largest 2D and 3D walls (20 and 10).
    pub steps_2d: usize,
    pub steps_3d: usize,
    /// Wall-clock cap per simulated run, s (600).
    pub max_wall: f64,
    /// Runs of each timed wall, the median run by wall time reported (3):
    /// this machine's timings wander by a tenth or more from run to run.
    pub repeats: usize,
    /// MuJoCo's run of the compared wall, if measured.
    pub mujoco: Option<MujocoRun>,
}

impl Default for TargetOptions {
    fn default() -> Self {
        Self {
            compared: 40,
            ntdda: 20,
            standing: 10,
            largest: 100,
            seconds: 1.0,
            steps_2d: 20,
            steps_3d: 10,
            max_wall: 600.0,
            repeats: 3,
            mujoco: None,
        }
    }
}

/// What `benches/mujoco_wall.py` prints of its run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MujocoRun {
    pub engine: String,
    pub courses: usize,
    /// Seconds of `mj_step` over the run, and the largest drift, m.
    pub wall_s: f64,
    pub drift_m: f64,
}

impl MujocoRun {
    /// Reads `benches/mujoco_wall.py`'s JSON.
    pub fn load(path: &Path) -> anyhow::Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("--mujoco: cannot read {}", path.display()))?;
        serde_json::from_str(&text).with_context(|| {
            format!(
                "--mujoco {}: not the JSON of benches/mujoco_wall.py (engine, courses, wall_s, drift_m)",
                path.display()
            )
        })
    }
}

/// One target's reading.
#[derive(Debug, Clone, Serialize)]
pub struct Target {
    pub target: String,
    pub measured: String,
    /// Met, not met, or not measured (`None`).
    pub met: Option<bool>,
}

/// The whole run: where and when, and the targets.
#[derive(Debug, Clone, Serialize)]
pub struct TargetReport {
    pub date: String,
    pub machine: String,
    /// Runs of each timed wall; each row reads the median run.
    pub repeats: usize,
    pub targets: Vec<Target>,
}

/// `rows`' row of the wall of `courses` courses and this kind.
fn row_of<R>(
    rows: &[R],
    courses: usize,
    kind: BlockKind,
    key: impl Fn(&R) -> (usize, BlockKind),
) -> anyhow::Result<&R> {
    (rows.iter().find(|r| key(r) == (courses, kind)))
        .with_context(|| format!("no run of the {courses} × {courses} {kind:?} wall"))
}

/// The compared wall against MuJoCo (or dda's side alone), beside its
/// static settlement where read (m): a drift below it no solver of the
/// model can reach.
fn against_mujoco(row: &SimulateRow, mujoco: Option<&MujocoRun>, settled: Option<f64>) -> Target {
    let kind = kind_name(row.kind);
    let ours = format!(
        "{:.2} s for {:.2} s simulated, drift {:.2e} m{}",
        row.wall_s,
        row.reached,
        row.drift,
        settled.map_or(String::new(), |s| format!(
            " (its static settlement {s:.2e} m)"
        ))
    );
    let drift_met = row.completed && row.drift <= DRIFT_LIMIT;
    let (measured, met) = match mujoco {
        Some(m) => {
            let share = row.wall_s / m.wall_s;
            (
                format!(
                    "{ours}; {} {:.1} s, drift {:.2e} m: 1/{:.0} of its time",
                    m.engine,
                    m.wall_s,
                    m.drift_m,
                    1.0 / share
                ),
                Some(drift_met && share <= MUJOCO_SHARE),
            )
        }
        None => (
            format!("{ours}; MuJoCo not measured (--mujoco)"),
            (!drift_met).then_some(false),
        ),
    };
    Target {
        target: format!(
            "{0} × {0} wall, {kind}, {1} s simulated at the automatic dt and penalty: at most 1/10 of MuJoCo's wall time, drift at most {DRIFT_LIMIT:.1e} m",
            row.courses, row.seconds
        ),
        measured,
        met,
    }
}

/// The report as it is made: each target printed, and the JSON written
/// again, as it is added.
struct Writer<'a> {
    report: TargetReport,
    json: Option<&'a Path>,
}

impl Writer<'_> {
    fn add(&mut self, found: Target) -> anyhow::Result<()> {
        println!("{}", markdown_row(&found));
        self.report.targets.push(found);
        if let Some(path) = self.json {
            let text = serde_json::to_string_pretty(&self.report)?;
            crate::output::write_atomically(path, text.as_bytes())?;
        }
        Ok(())
    }
}

const KINDS: [BlockKind; 2] = [BlockKind::Rigid, BlockKind::Deformable];

fn sim_key(r: &SimulateRow) -> (usize, BlockKind) {
    (r.courses, r.kind)
}

fn steps_key(r: &BenchRow) -> (usize, BlockKind) {
    (r.courses, r.kind)
}

/// The 2D walls of `sizes`, both kinds, run for the options' simulated
/// time at the automatic step, or at each of `dts`.
fn simulated(
    options: &TargetOptions,
    sizes: Vec<usize>,
    dts: Vec<f64>,
) -> anyhow::Result<Vec<SimulateRow>> {
    simulate(&simulating(options, sizes, dts, false))
}

/// The runs of the walls of `sizes` in 2D, both kinds, for the targets'
/// simulated time at `dts` (the automatic step where empty), each wall
/// settled first where `settle`.
fn simulating(
    options: &TargetOptions,
    sizes: Vec<usize>,
    dts: Vec<f64>,
    settle: bool,
) -> SimulateOptions {
    SimulateOptions {
        sizes,
        kinds: KINDS.to_vec(),
        dimensions: vec![2],
        seconds: options.seconds,
        max_wall: options.max_wall,
        repeats: options.repeats,
        progress_every: Some(Duration::from_secs(5)),
        solver: Solver::Direct,
        dts,
        shake: None,
        settle,
        step_log: None,
    }
}

/// The walls of `sizes`, both kinds, `steps` steps timed at dt 1 ms,
/// each the median of `repeats` runs.
fn stepped(
    sizes: Vec<usize>,
    dimension: u32,
    steps: usize,
    repeats: usize,
) -> anyhow::Result<Vec<BenchRow>> {
    bench(&BenchOptions {
        sizes,
        steps,
        repeats,
        kinds: KINDS.to_vec(),
        dimensions: vec![dimension],
        solver: Solver::Direct,
    })
}

/// The ntdda wall at both steps, both kinds, against a tenth of ntdda's
/// time a step.
fn against_ntdda(
    options: &TargetOptions,
    automatic: &[SimulateRow],
    at_1ms: &[SimulateRow],
) -> anyhow::Result<Target> {
    let n = options.ntdda;
    let mut readings = Vec::new();
    let mut met = true;
    for (rows, how) in [(automatic, "automatic step"), (at_1ms, "dt 1 ms")] {
        for kind in KINDS {
            let r = row_of(rows, n, kind, sim_key)?;
            readings.push(format!(
                "{how}, {}: {:.2} ms ({:.1}×)",
                kind_name(kind),
                r.ms_per_step,
                NTDDA_MS / r.ms_per_step
            ));
            met &= r.completed && r.ms_per_step <= NTDDA_MS / NTDDA_SPEEDUP;
        }
    }
    Ok(Target {
        target: format!(
            "{n} × {n} wall at least {NTDDA_SPEEDUP}× faster a step than ntdda ({NTDDA_MS} ms), over {} s",
            options.seconds
        ),
        measured: readings.join("; "),
        met: Some(met),
    })
}

/// The wall ntdda blows up on, at dt 1 ms: no cut, no unconverged step,
/// standing.
fn standing(options: &TargetOptions, at_1ms: &[SimulateRow]) -> anyhow::Result<Target> {
    let s = options.standing;
    let mut readings = Vec::new();
    let mut met = true;
    for kind in KINDS {
        let r = row_of(at_1ms, s, kind, sim_key)?;
        readings.push(format!(
            "{}: {} cuts, {} unconverged steps, drift {:.2e} m",
            kind_name(kind),
            r.cuts,
            r.unconverged_steps,
            r.drift
        ));
        met &= r.completed && r.cuts == 0 && r.unconverged_steps == 0;
        met &= r.drift < STANDING_DRIFT;
    }
    Ok(Target {
        target: format!(
            "stable where ntdda blows up ({s} × {s}, dt 1 ms, {} s): no cut, no unconverged step, drift below {STANDING_DRIFT:.0e} m",
            options.seconds
        ),
        measured: readings.join("; "),
        met: Some(met),
    })
}

/// One run's open-close work: how it was stepped, its kind, passes a step
/// and the most one step took, unconverged steps and cuts, and whether it
/// ran its whole time.
struct Passes {
    how: String,
    kind: BlockKind,
    passes: f64,
    most: usize,
    unconverged: usize,
    cuts: usize,
    completed: bool,
}

impl Passes {
    /// A simulated run's, at its penalty, named by `how` it was stepped.
    fn of(how: &str, r: &SimulateRow) -> Self {
        Self {
            how: format!("{how} ({:.2e})", r.penalty),
            kind: r.kind,
            passes: r.per_step.passes_per_step,
            most: r.most_passes,
            unconverged: r.unconverged_steps,
            cuts: r.cuts,
            completed: r.completed,
        }
    }
}

/// The compared wall at dt 1 ms, both kinds, at the automatic penalty
/// (`at_1ms`) and at the bench's fixed one (`fixed`): its open-close
/// passes a step. The counts do not wander as times do, so `fixed` is
/// one run. Beside them, read but not judged, the same four walls
/// settled first (`analysis.settle`), one run each: whether the passes
/// beyond two come from the unstressed start.
fn few_passes(
    options: &TargetOptions,
    at_1ms: &[SimulateRow],
    fixed: &[BenchRow],
) -> anyhow::Result<Target> {
    let n = options.compared;
    let mut runs = Vec::new();
    for kind in KINDS {
        runs.push(Passes::of(
            "automatic penalty",
            row_of(at_1ms, n, kind, sim_key)?,
        ));
    }
    for kind in KINDS {
        let r = row_of(fixed, n, kind, steps_key)?;
        runs.push(Passes {
            how: format!("penalty {FIXED_PENALTY:.0e}"),
            kind,
            passes: r.per_step.passes_per_step,
            most: r.most_passes,
            unconverged: r.unconverged_steps,
            cuts: r.cuts,
            completed: true,
        });
    }
    let settle = simulating(options, vec![n], Vec::new(), true);
    let mut settled = Vec::new();
    for stepping in [Stepping::Given(1e-3), Stepping::Fixed] {
        for kind in KINDS {
            let r = super::simulate::run(n, 2, kind, stepping, &settle, 0)?;
            settled.push(Passes::of("settled, penalty", &r));
        }
    }
    Ok(few_passes_of(n, options.seconds, &runs, &settled))
}

/// [`few_passes`]' target from its runs: met where every run ran its
/// whole time with no step taking more than `FEW_PASSES` passes and left
/// no step unconverged. The `settled` runs are read beside them, not
/// judged: the most passes any of their steps took.
fn few_passes_of(n: usize, seconds: f64, runs: &[Passes], settled: &[Passes]) -> Target {
    let mut readings: Vec<String> = (runs.iter())
        .map(|r| {
            format!(
                "{}, {}: {:.2} passes a step, at most {} in one step, {} unconverged steps, {} cuts",
                r.how,
                kind_name(r.kind),
                r.passes,
                r.most,
                r.unconverged,
                r.cuts
            )
        })
        .collect();
    if let Some(most) = settled.iter().map(|r| r.most).max() {
        let unconverged: usize = settled.iter().map(|r| r.unconverged).sum();
        let whole = settled.iter().all(|r| r.completed);
        readings.push(format!(
            "the same {} walls settled first (analysis.settle), one run each, not judged: at most {most} {} in one step, {unconverged} unconverged steps{}",
            settled.len(),
            if most == 1 { "pass" } else { "passes" },
            if whole { "" } else { ", not all run to their end" }
        ));
    }
    let met = (runs.iter()).all(|r| r.completed && r.most <= FEW_PASSES && r.unconverged == 0);
    Target {
        target: format!(
            "{n} × {n} wall at dt 1 ms, {seconds} s, both kinds, at the automatic penalty and at {FIXED_PENALTY:.0e}: at most {FEW_PASSES} open-close passes in any step, no unconverged step"
        ),
        measured: readings.join("; "),
        met: Some(met),
    }
}

/// The compared wall's static settlement (m), each kind in `KINDS`' order.
fn settlements(options: &TargetOptions) -> anyhow::Result<Vec<f64>> {
    (KINDS.iter())
        .map(|&kind| largest_step::static_settlement(options.compared, options.max_wall, kind))
        .collect()
}

/// The compared wall at rest at steps of 5 and 10 ms, and the largest
/// step it stands at ([`largest_step`]), each kind.
pub fn standing_steps(options: &TargetOptions) -> anyhow::Result<Target> {
    standing_steps_from(options, &settlements(options)?)
}

/// [`standing_steps`] against the static settlements `settled` (m), each
/// kind in `KINDS`' order.
fn standing_steps_from(options: &TargetOptions, settled: &[f64]) -> anyhow::Result<Target> {
    let (n, seconds) = (options.compared, options.seconds);
    let mut readings = Vec::new();
    let mut met = true;
    for (&kind, &settled) in KINDS.iter().zip(settled) {
        let (reading, stands) = largest_step::reading(n, seconds, options.max_wall, kind, settled)?;
        readings.push(format!("{}: {reading}", kind_name(kind)));
        met &= stands;
    }
    Ok(Target {
        target: largest_step::asked(n, seconds),
        measured: readings.join("; "),
        met: Some(met),
    })
}

/// The largest walls: a step in 2D and 3D at dt 1 ms and in 2D at the
/// automatic step, each kind; then the process's peak memory.
fn largest(
    options: &TargetOptions,
    automatic: &[SimulateRow],
    steps_2d: &[BenchRow],
    steps_3d: &[BenchRow],
) -> anyhow::Result<Vec<Target>> {
    let l = options.largest;
    let blocks = thousands(row_of(steps_2d, l, BlockKind::Rigid, steps_key)?.blocks);
    let mut found = Vec::new();
    let mut peak: f64 = 0.0;
    for kind in KINDS {
        let name = kind_name(kind);
        let at_1ms = [
            (steps_2d, "2D", options.steps_2d),
            (steps_3d, "3D", options.steps_3d),
        ];
        for (rows, dimension, steps) in at_1ms {
            let r = row_of(rows, l, kind, steps_key)?;
            peak = peak.max(r.peak_memory_mb);
            found.push(Target {
                target: format!(
                    "{blocks} blocks, {dimension} at dt 1 ms and penalty 1e9, {name}: a step in at most {LARGEST_MS} ms"
                ),
                measured: format!(
                    "{:.1} ms a step over {steps} steps{}",
                    r.median_ms_per_step,
                    of_runs(r.runs)
                ),
                met: Some(r.median_ms_per_step <= LARGEST_MS),
            });
        }
        let r = row_of(automatic, l, kind, sim_key)?;
        peak = peak.max(r.peak_memory_mb);
        found.push(Target {
            target: format!(
                "{blocks} blocks, 2D at the automatic step, {name}: a step in at most {LARGEST_MS} ms"
            ),
            measured: format!(
                "{:.1} ms a step over {:.2} s simulated (dt {:.2e} s){}",
                r.ms_per_step,
                r.reached,
                r.dt,
                of_runs(r.runs)
            ),
            met: Some(r.completed && r.ms_per_step <= LARGEST_MS),
        });
    }
    found.push(Target {
        target: format!("{blocks} blocks: memory at most {MEMORY_MB} MB"),
        measured: format!(
            "the process's peak resident memory over all the runs above: {peak:.0} MB"
        ),
        met: Some(peak <= MEMORY_MB),
    });
    Ok(found)
}

/// How time a step grows from the compared wall to the largest: in 2D at
/// dt 1 ms and at the automatic step, and in 3D at dt 1 ms, each kind.
fn growth(
    options: &TargetOptions,
    automatic: &[SimulateRow],
    steps_2d: &[BenchRow],
    steps_3d: &[BenchRow],
) -> anyhow::Result<Vec<Target>> {
    let (c, l) = (options.compared, options.largest);
    let mut found = Vec::new();
    for kind in KINDS {
        let (a, b) = (
            row_of(steps_2d, c, kind, steps_key)?,
            row_of(steps_2d, l, kind, steps_key)?,
        );
        let (q, r) = (
            row_of(automatic, c, kind, sim_key)?,
            row_of(automatic, l, kind, sim_key)?,
        );
        let (u, v) = (
            row_of(steps_3d, c, kind, steps_key)?,
            row_of(steps_3d, l, kind, steps_key)?,
        );
        // Each with the runs its two walls' readings are medians of.
        let readings = [
            (
                "2D at dt 1 ms and penalty 1e9",
                a.median_ms_per_step,
                b.median_ms_per_step,
                a.runs.min(b.runs),
            ),
            (
                "2D at the automatic step",
                q.ms_per_step,
                r.ms_per_step,
                q.runs.min(r.runs),
            ),
            (
                "3D at dt 1 ms and penalty 1e9",
                u.median_ms_per_step,
                v.median_ms_per_step,
                u.runs.min(v.runs),
            ),
        ];
        for (how, from, to, runs) in readings {
            let p = exponent((a.blocks, from), (b.blocks, to));
            found.push(Target {
                target: format!(
                    "{how}, {}: time a step growing at most as N^{EXPONENT} from {} to {} blocks",
                    kind_name(kind),
                    thousands(a.blocks),
                    thousands(b.blocks)
                ),
                measured: format!("N^{p:.2} ({from:.1} → {to:.1} ms a step{})", of_runs(runs)),
                met: Some(p <= EXPONENT),
            });
        }
    }
    Ok(found)
}

/// Runs every target's walls and prints each target as it is measured;
/// with `json`, the report so far is written after each.
pub fn targets(options: &TargetOptions, json: Option<&Path>) -> anyhow::Result<TargetReport> {
    if let Some(m) = &options.mujoco {
        anyhow::ensure!(
            m.courses == options.compared,
            "--mujoco: MuJoCo ran the {0} × {0} wall, the targets compare the {1} × {1}; run benches/mujoco_wall.py {1}",
            m.courses,
            options.compared
        );
    }
    if let Some(path) = json {
        super::command::check_writable("--json", path)?;
    }
    let mut out = Writer {
        report: TargetReport {
            date: humantime::format_rfc3339_seconds(SystemTime::now()).to_string(),
            machine: machine(),
            repeats: options.repeats,
            targets: Vec::new(),
        },
        json,
    };
    println!(
        "Speed targets of the walls, measured in one run{}: {}, {}",
        of_runs(options.repeats),
        out.report.date,
        out.report.machine
    );
    println!("| target | measured | verdict |\n|---|---|---|");
    let (c, l) = (options.compared, options.largest);
    let automatic = simulated(options, vec![options.ntdda, c, l], Vec::new())?;
    let settled = settlements(options)?;
    for (&kind, &at) in KINDS.iter().zip(&settled) {
        let row = row_of(&automatic, c, kind, sim_key)?;
        out.add(against_mujoco(row, options.mujoco.as_ref(), Some(at)))?;
    }
    let at_1ms = simulated(
        options,
        vec![options.standing, options.ntdda, c],
        vec![1e-3],
    )?;
    out.add(against_ntdda(options, &automatic, &at_1ms)?)?;
    out.add(standing(options, &at_1ms)?)?;
    let fixed_steps = (options.seconds / 1e-3).round() as usize;
    out.add(few_passes(
        options,
        &at_1ms,
        &stepped(vec![c], 2, fixed_steps, 1)?,
    )?)?;
    out.add(standing_steps_from(options, &settled)?)?;
    let steps_2d = stepped(vec![c, l], 2, options.steps_2d, options.repeats)?;
    let steps_3d = stepped(vec![c, l], 3, options.steps_3d, options.repeats)?;
    for found in largest(options, &automatic, &steps_2d, &steps_3d)? {
        out.add(found)?;
    }
    for found in growth(options, &automatic, &steps_2d, &steps_3d)? {
        out.add(found)?;
    }
    Ok(out.report)
}

/// How a timed reading was taken, where more than one run: ", the median
/// of 3 runs".
fn of_runs(repeats: usize) -> String {
    if repeats > 1 {
        format!(", the median of {repeats} runs")
    } else {
        String::new()
    }
}

/// `n` with a comma between each three digits.
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A target as a row of the Markdown table.
pub fn markdown_row(t: &Target) -> String {
    let verdict = match t.met {
        Some(true) => "**met**",
        Some(false) => "not met",
        None => "not measured",
    };
    format!("| {} | {} | {verdict} |", t.target, t.measured)
}

/// The processor's model, its cores and the memory (Linux; less
/// elsewhere).
fn machine() -> String {
    let read = |path: &str| std::fs::read_to_string(path).unwrap_or_default();
    let field = |text: &str, name: &str| {
        (text.lines())
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split(':').nth(1))
            .map(|v| v.trim().to_string())
    };
    let cpu =
        field(&read("/proc/cpuinfo"), "model name").unwrap_or_else(|| "processor unknown".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let memory = field(&read("/proc/meminfo"), "MemTotal")
        .and_then(|v| v.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(String::new(), |kb| {
            format!(", {:.0} GiB", kb / 1024.0 / 1024.0)
        });
    format!("{cpu}, {cores} cores{memory}")
}

/// `dda bench --targets`: every target, then the report's JSON.
pub fn command(options: &TargetOptions, json: Option<PathBuf>) -> anyhow::Result<()> {
    let report = targets(options, json.as_deref())?;
    let met = report
        .targets
        .iter()
        .filter(|t| t.met == Some(true))
        .count();
    println!("{met} of {} targets met", report.targets.len());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The compared wall's run: `wall_s` s for a simulated second,
    /// drifting `drift` m.
    fn compared(wall_s: f64, drift: f64) -> SimulateRow {
        crate::bench::simulate::tests::row(wall_s, drift)
    }

    /// Met only within a tenth of MuJoCo's time and the drift's limit;
    /// without MuJoCo, not measured unless the drift alone fails it.
    #[test]
    fn the_compared_wall_needs_both_time_and_drift() {
        let mujoco = MujocoRun {
            engine: "mujoco 3".into(),
            courses: 40,
            wall_s: 50.0,
            drift_m: 0.02,
        };
        let verdict = |wall_s, drift, m: Option<&MujocoRun>| {
            against_mujoco(&compared(wall_s, drift), m, None).met
        };
        assert_eq!(verdict(4.9, 1.7e-4, Some(&mujoco)), Some(true));
        assert_eq!(verdict(5.1, 1.7e-4, Some(&mujoco)), Some(false));
        assert_eq!(verdict(4.9, 1.9e-4, Some(&mujoco)), Some(false));
        assert_eq!(verdict(4.9, 1.7e-4, None), None);
        assert_eq!(verdict(4.9, 1.9e-4, None), Some(false));
        let mut short = compared(1.0, 1e-5);
        short.completed = false;
        assert_eq!(against_mujoco(&short, Some(&mujoco), None).met, Some(false));
        // The static settlement is named beside the drift, which the
        // verdict still reads.
        let beside = against_mujoco(&compared(4.9, 1.7e-4), Some(&mujoco), Some(2.6e-4));
        assert!(
            beside
                .measured
                .contains("drift 1.70e-4 m (its static settlement 2.60e-4 m)"),
            "{beside:?}"
        );
        assert_eq!(beside.met, Some(true));
    }

    /// Met only where no step of any run takes more than two passes, no
    /// step is left unconverged and every run runs its whole time.
    #[test]
    fn the_compared_wall_at_1_ms_needs_few_passes_in_every_run() {
        let run = |passes, most, unconverged, completed| Passes {
            how: "penalty 1e9".into(),
            kind: BlockKind::Rigid,
            passes,
            most,
            unconverged,
            cuts: 0,
            completed,
        };
        let verdict = |runs: &[Passes]| few_passes_of(40, 1.0, runs, &[]).met;
        assert_eq!(
            verdict(&[run(1.0, 1, 0, true), run(2.0, 2, 0, true)]),
            Some(true)
        );
        // A mean within two passes does not hide one step that took more.
        assert_eq!(
            verdict(&[run(1.0, 1, 0, true), run(1.02, 6, 0, true)]),
            Some(false)
        );
        assert_eq!(
            verdict(&[run(1.0, 1, 0, true), run(2.055, 4, 0, true)]),
            Some(false)
        );
        assert_eq!(verdict(&[run(1.0, 1, 1, true)]), Some(false));
        assert_eq!(verdict(&[run(1.0, 1, 0, false)]), Some(false));
        let target = few_passes_of(40, 1.0, &[run(2.055, 4, 0, true)], &[]);
        assert!(
            target.measured
                == "penalty 1e9, rigid: 2.06 passes a step, at most 4 in one step, 0 unconverged steps, 0 cuts",
            "{target:?}"
        );
        // The settled walls are read beside the verdict, not judged.
        let settled = [run(1.0, 1, 0, true), run(1.0, 1, 0, true)];
        let beside = few_passes_of(40, 1.0, &[run(2.055, 4, 0, true)], &settled);
        assert_eq!(beside.met, Some(false));
        assert!(
            beside.measured.ends_with(
                "; the same 2 walls settled first (analysis.settle), one run each, not judged: at most 1 pass in one step, 0 unconverged steps"
            ),
            "{beside:?}"
        );
        let met = few_passes_of(40, 1.0, &[run(1.0, 2, 0, true)], &[run(1.5, 3, 0, true)]);
        assert_eq!(met.met, Some(true), "{met:?}");
        assert!(
            target.target.starts_with("40 × 40 wall at dt 1 ms, 1 s")
                && target
                    .target
                    .contains("at most 2 open-close passes in any step"),
            "{target:?}"
        );
    }

    #[test]
    fn exponents_and_thousands() {
        assert!((exponent((1000, 10.0), (10_000, 100.0)) - 1.0).abs() < 1e-12);
        assert!(
            (exponent(
                (1621, 10.0),
                (10_051, 10.0 * (10_051.0f64 / 1621.0).powf(1.3))
            ) - 1.3)
                .abs()
                < 1e-12
        );
        assert_eq!(thousands(10_051), "10,051");
        assert_eq!(thousands(1_621), "1,621");
        assert_eq!(thousands(411), "411");
        assert_eq!(thousands(1_000_000), "1,000,000");
    }
}
