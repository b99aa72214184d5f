//! `summary.json`: what a run did, written by an [`Observer`] at its start,
//! every few seconds while it runs (status "running") and at its end, so a
//! killed run still says how far it got.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::observe::{Observer, RunView};
use crate::output::{round_time, write_json};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Still running, or killed: `time` says how far it got.
    Running,
    Finished,
    Failed,
}

/// Wall-clock time between updates of a running run's `summary.json`.
pub const SUMMARY_EVERY: std::time::Duration = std::time::Duration::from_secs(2);

/// What `summary.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub scene: String,
    /// 2 or 3.
    #[serde(default = "two")]
    pub dimension: u32,
    pub status: Status,
    /// Why the run stopped early (failed runs only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    pub blocks: usize,
    pub steps: usize,
    /// Simulated time reached, seconds.
    #[serde(default, skip_serializing_if = "not_finite")]
    pub time: f64,
    /// Simulated time asked for, seconds.
    pub duration: f64,
    /// Seconds of wall-clock time for the run.
    pub wall_time: f64,
    pub open_close_iterations: usize,
    pub newton_iterations: usize,
    pub factorizations: usize,
    pub open_close_cuts: usize,
    pub displacement_cuts: usize,
    pub penalty_raises: usize,
    /// Steps cut because a contact penetrated too deep.
    #[serde(default)]
    pub penetration_cuts: usize,
    /// Steps cut because their last pass's Newton-Raphson iteration
    /// stalled out of balance, and steps accepted so at the smallest step.
    #[serde(default)]
    pub newton_cuts: usize,
    #[serde(default)]
    pub unsolved_steps: usize,
    /// Steps accepted at the smallest time step without open-close agreement.
    pub unconverged_steps: usize,
    /// Steps whose open-close passes cycled between two sets of states,
    /// settled by keeping each cycling contact sliding or closed.
    #[serde(default)]
    pub cycle_breaks: usize,
    /// Contacts that started a step opened or closed by its foreseen
    /// motion, and the passes spent turning such a state back.
    #[serde(default)]
    pub foreseen: usize,
    #[serde(default)]
    pub foresight_misses: usize,
    /// Contacts that struck and took an impulse (`analysis.restitution`).
    #[serde(default)]
    pub impacts: usize,
    /// The first contacts that cycled: when, which, between which states,
    /// and the state kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cycles: Vec<CycleReport>,
    /// Open-close passes solved again with friction's coupling to the
    /// normal force in the tangent after the symmetric iteration failed.
    #[serde(default)]
    pub coupled_solves: usize,
    /// Open-close passes whose Newton iteration kept its best, unconverged iterate.
    #[serde(default)]
    pub newton_failures: usize,
    /// Accepted steps ending with a penetration deeper than the limit, and the deepest (m).
    #[serde(default)]
    pub deep_penetration_steps: usize,
    #[serde(default, skip_serializing_if = "not_finite")]
    pub deepest_penetration: f64,
    /// Total energy at the end (J, per unit thickness in 2D) when nothing
    /// works on the blocks, and how far it rose above its lowest value in
    /// the steps where it rose beyond a quarter of the energy in play.
    #[serde(default, skip_serializing_if = "not_finite")]
    pub energy: f64,
    #[serde(default)]
    pub energy_growth_steps: usize,
    #[serde(default, skip_serializing_if = "not_finite")]
    pub energy_growth: f64,
    /// What went wrong in the run that the results depend on; also printed.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// Normal penalty at the end (after any raises).
    #[serde(default, skip_serializing_if = "not_finite")]
    pub penalty: f64,
    /// Nominal time step.
    pub dt: f64,
    /// Explicit integration: the smallest critical time step bound seen
    /// (s), and the steps shortened below `dt` to stay under it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub critical_dt: Option<f64>,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub critical_limited_steps: usize,
    /// Iterative solver (`analysis.solver`): systems solved, conjugate-
    /// gradient iterations, and systems solved directly at the cap.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub iterative_solves: usize,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub iterative_iterations: usize,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub iterative_fallbacks: usize,
    /// Wall-clock seconds of each phase of the steps, summed over the
    /// run (the phases of `dda bench`'s "where the time goes"); the rest
    /// of `wall_time` is the steps' other work and the outputs.
    /// Named as `dda_core::PhaseTimes::phases` names them.
    #[serde(default)]
    pub phases: BTreeMap<String, f64>,
    /// Why automatic values were chosen.
    pub notes: Vec<String>,
    /// The settling before the run (`analysis.settle`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settling: Option<SettleReport>,
    /// The files written in the output directory, this one included.
    #[serde(default)]
    pub outputs: Vec<String>,
}

/// What the settling before the run did (`analysis.settle`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SettleReport {
    /// Static steps taken.
    pub steps: usize,
    /// Whether its last step, whole, moved no more than
    /// [`dda_core::driver::settle::SETTLED_SHARE`] of its largest, out of balance
    /// by no more than [`dda_core::driver::settle::SETTLED_BALANCE`].
    pub settled: bool,
    /// Whether, not settled, it was undone: a step moved a block farther
    /// than a tenth of the median block size (as one falls, slides or
    /// topples), or it gave up after two steps in a row that did so or
    /// ended unconverged; the run started from the model as it was.
    #[serde(default)]
    pub undone: bool,
    /// Whether, not settled, it stalled: two steps in a row whose Newton
    /// iterations failed moved nothing and barely cut their residual; the
    /// model is at rest to within `balance` of its loads.
    #[serde(default)]
    pub stalled: bool,
    /// The largest point displacement of a step, and of the last, m.
    pub largest_step: f64,
    pub last_step: f64,
    /// The last step's residual over the loads the first started out of
    /// balance by (settled at most [`dda_core::driver::settle::SETTLED_BALANCE`]).
    pub balance: f64,
    /// Open-close passes and factorisations of its steps.
    pub open_close_iterations: usize,
    pub factorizations: usize,
    /// Wall-clock seconds, which `wall_time` includes.
    pub wall_time: f64,
}

impl From<&dda_core::Settling> for SettleReport {
    fn from(s: &dda_core::Settling) -> Self {
        Self {
            steps: s.steps,
            settled: s.settled,
            undone: s.undone,
            stalled: s.stalled,
            largest_step: s.largest_step,
            last_step: s.last_step,
            balance: s.balance,
            open_close_iterations: s.statistics.open_close_iterations,
            factorizations: s.statistics.factorizations,
            wall_time: s.wall_time.as_secs_f64(),
        }
    }
}

impl SettleReport {
    /// The warning of a settling that did not settle, if it did not.
    pub fn warning(&self) -> Option<String> {
        // One that moved a block far before it stalled was undone: the
        // run starts from the model as it was, which the message below says.
        if self.stalled && !self.undone {
            return Some(format!(
                "the model's settling stalled after {} static steps (analysis.settle): its last two moved it no farther than the contact tolerance (the last {:.3e} m, the largest {:.3e} m) and their Newton iterations stopped {:.1e} of the loads out of balance, as contacts held exactly at their friction strength can stop a static step's; the model is at rest to within that, and the run starts there and shows whether it stands",
                self.steps, self.last_step, self.largest_step, self.balance
            ));
        }
        (!self.settled).then(|| {
            format!(
                "the model did not settle in {} static steps (analysis.settle): each step still moved it (the last {:.3e} m, the largest {:.3e} m) or ended out of balance; a model that stands settles in a few, so this one may not stand under its loads at t = 0 (a block sliding or toppling). {}",
                self.steps,
                self.last_step,
                self.largest_step,
                if self.undone {
                    "Its steps moved a block as one falls, slides or topples, or found no contact states they agree on, so the settling was undone: the run starts from the model as it was, at rest, as an unsettled one does"
                } else {
                    "The run starts where the steps left the blocks"
                }
            )
        })
    }
}

impl Summary {
    /// Steps cut, for any reason, as `Statistics::cuts` counts them.
    pub fn cuts(&self) -> usize {
        self.open_close_cuts + self.displacement_cuts + self.penetration_cuts + self.newton_cuts
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn two() -> u32 {
    2
}

/// Numbers JSON cannot hold are left out rather than written as null.
fn not_finite(v: &f64) -> bool {
    !v.is_finite()
}

/// Writes `summary.json` at the end of a run and keeps what it wrote.
pub struct SummaryWriter {
    path: PathBuf,
    scene: String,
    dimension: u32,
    duration: f64,
    /// The scene's notes, after the driver's.
    notes: Vec<String>,
    outputs: Vec<String>,
    started: Instant,
    /// Wall-clock seconds of the run before it was resumed.
    pub earlier_wall_time: f64,
    /// Whether the warnings also go to stderr at the end (default true).
    pub print_warnings: bool,
    /// When `summary.json` was last written.
    written: Option<Instant>,
    /// The last finite value of each number of the summary that a blown-up
    /// run can lose, as of the last output time.
    known: Known,
    /// What was written, once the run has finished.
    pub summary: Option<Summary>,
    /// The settling before the run, if any.
    pub settling: Option<SettleReport>,
}

impl SummaryWriter {
    /// A summary of a run starting now; `outputs` lists the files written,
    /// `summary.json` last.
    pub fn new(
        path: PathBuf,
        scene: String,
        dimension: u32,
        duration: f64,
        notes: Vec<String>,
        outputs: Vec<String>,
    ) -> Self {
        Self {
            path,
            scene,
            dimension,
            duration,
            notes,
            outputs,
            started: Instant::now(),
            written: None,
            earlier_wall_time: 0.0,
            print_warnings: true,
            known: Known::default(),
            summary: None,
            settling: None,
        }
    }
}

impl Observer for SummaryWriter {
    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.known.update(run);
        if self.written.is_none_or(|t| t.elapsed() >= SUMMARY_EVERY) {
            let summary = self.snapshot(run, None, Status::Running);
            write_json(&self.path, &summary)?;
            self.written = Some(Instant::now());
        }
        Ok(())
    }

    fn on_finish(
        &mut self,
        run: &dyn RunView,
        error: Option<&anyhow::Error>,
    ) -> anyhow::Result<()> {
        let status = if error.is_none() {
            Status::Finished
        } else {
            Status::Failed
        };
        let summary = self.snapshot(run, error, status);
        write_json(&self.path, &summary)?;
        if self.print_warnings {
            for warning in &summary.warnings {
                eprintln!("warning: {warning}");
            }
        }
        self.summary = Some(summary);
        Ok(())
    }
}

impl SummaryWriter {
    /// The summary of the run as it is now.
    fn snapshot(
        &self,
        run: &dyn RunView,
        error: Option<&anyhow::Error>,
        status: Status,
    ) -> Summary {
        let driver = run;
        let mut stats = driver.statistics().clone();
        let (mut time, mut penalty) = (driver.time(), driver.penalty());
        // The automatic penalty sorts the blocks' sizes: read only where
        // an energy rise needs its advice.
        let stiff = (stats.energy_growth_steps > 0)
            .then(|| dda_core::error::stiff_penalty(penalty, driver.automatic_penalty()))
            .flatten();
        let mut warnings = warnings(&stats, stiff);
        warnings.extend(self.settling.as_ref().and_then(SettleReport::warning));
        // A run that blew up may leave numbers JSON cannot hold (they would be
        // null); their last finite values stand in, said so.
        let known = &self.known;
        let mut replaced = Vec::new();
        let mut keep = |name: &str, value: &mut f64, good: Option<f64>| {
            if !value.is_finite() {
                match good {
                    Some(good) => {
                        replaced.push(format!("{name} ({value}; {good} given)"));
                        *value = good;
                    }
                    None => replaced.push(format!("{name} ({value}; left out)")),
                }
            }
        };
        keep("time", &mut time, known.time);
        keep("penalty", &mut penalty, known.penalty);
        keep("energy", &mut stats.energy, known.energy);
        keep(
            "energy_growth",
            &mut stats.energy_growth,
            known.energy_growth,
        );
        keep(
            "deepest_penetration",
            &mut stats.deepest_penetration,
            known.deepest_penetration,
        );
        if !replaced.is_empty() {
            warnings.push(format!(
                "not finite when the run stopped: {}; the values given are the last finite ones written, at an output time",
                replaced.join(", ")
            ));
        }
        Summary {
            scene: self.scene.clone(),
            dimension: self.dimension,
            status,
            error: error.map(|e| format!("{e:#}")),
            blocks: driver.block_count(),
            steps: stats.steps,
            time: round_time(time),
            duration: self.duration,
            wall_time: self.earlier_wall_time + self.started.elapsed().as_secs_f64(),
            open_close_iterations: stats.open_close_iterations,
            newton_iterations: stats.newton_iterations,
            factorizations: stats.factorizations,
            open_close_cuts: stats.open_close_cuts,
            displacement_cuts: stats.displacement_cuts,
            penalty_raises: stats.penalty_raises,
            penetration_cuts: stats.penetration_cuts,
            newton_cuts: stats.newton_cuts,
            unsolved_steps: stats.unsolved_steps,
            unconverged_steps: stats.unconverged_steps,
            cycle_breaks: stats.cycle_breaks,
            foreseen: stats.foreseen,
            foresight_misses: stats.foresight_misses,
            impacts: stats.impacts,
            cycles: stats.cycles.iter().map(CycleReport::from).collect(),
            coupled_solves: stats.coupled_solves,
            newton_failures: stats.newton_failures,
            deep_penetration_steps: stats.deep_penetration_steps,
            deepest_penetration: stats.deepest_penetration,
            energy: stats.energy,
            energy_growth_steps: stats.energy_growth_steps,
            energy_growth: stats.energy_growth,
            warnings,
            penalty,
            dt: driver.dt(),
            critical_dt: stats.critical_dt.filter(|c| c.is_finite()),
            critical_limited_steps: stats.critical_limited_steps,
            iterative_solves: stats.iterative_solves,
            iterative_iterations: stats.iterative_iterations,
            iterative_fallbacks: stats.iterative_fallbacks,
            phases: (stats.times.phases().iter())
                .map(|(name, time)| (name.to_string(), time.as_secs_f64()))
                .collect(),
            notes: driver.notes().iter().chain(&self.notes).cloned().collect(),
            settling: self.settling.clone(),
            outputs: self.outputs.clone(),
        }
    }
}

/// A contact whose open-close state cycled in a step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CycleReport {
    /// End of the step (s).
    pub time: f64,
    /// The entering block and the block it touches.
    pub blocks: [u32; 2],
    /// The entering vertex and the feature (edge, face or vertex) entered.
    pub features: [u32; 2],
    /// The two states the passes alternated between, and the one kept.
    pub between: [String; 2],
    pub kept: String,
}

impl From<&dda_core::Cycle> for CycleReport {
    fn from(c: &dda_core::Cycle) -> Self {
        let name = |s: dda_core::ContactState| format!("{s:?}").to_lowercase();
        Self {
            time: round_time(c.time),
            blocks: [c.key.block_a, c.key.block_b],
            features: [c.key.feature_a, c.key.feature_b],
            between: [name(c.between[0]), name(c.between[1])],
            kept: name(c.kept),
        }
    }
}

/// The driver's reports of steps it could not do well.
fn warnings(stats: &dda_core::Statistics, stiff: Option<String>) -> Vec<String> {
    let mut out = Vec::new();
    if stats.unconverged_steps > 0 {
        out.push(format!(
            "{} steps could not converge even at the smallest time step and were accepted without \
             open-close agreement; their contact states may be wrong (try a smaller dt, a softer penalty \
             or a larger open_close_limit)",
            stats.unconverged_steps
        ));
    }
    if stats.unsolved_steps > 0 {
        out.push(format!(
            "{} steps could not solve their equations even at the smallest time step (Newton-Raphson \
             stalled out of balance) and were accepted at their best iterate; the blocks may be out of \
             balance there (a smaller dt, or a softer penalty, makes the springs less stiff against the \
             blocks' inertia)",
            stats.unsolved_steps
        ));
    }
    if stats.deep_penetration_steps > 0 {
        out.push(format!(
            "{} steps ended with a contact penetrating beyond the allowed bound (deepest {:.3e} m); \
             blocks overlap more than the penalty method allows (try a stiffer penalty or a smaller dt)",
            stats.deep_penetration_steps, stats.deepest_penetration
        ));
    }
    if let Some(first) = stats.cycles.first() {
        let c = CycleReport::from(first);
        out.push(format!(
            "in {} steps some contacts' open-close passes alternated between two states; each was \
             settled by keeping the state that stores less work (sliding over locked, closed over open). \
             The first: at t = {} s, the contact of block {} on block {}, {} and {}, kept {} \
             (summary.json lists up to 20 under \"cycles\")",
            stats.cycle_breaks, c.time, c.blocks[0], c.blocks[1], c.between[0], c.between[1], c.kept
        ));
    }
    if stats.energy_growth_steps > 0 {
        let advice = energy_advice(stats, stiff);
        out.push(format!(
            "the total energy rose by up to {:.3e} J in {} steps although nothing did work on the blocks; \
             the method added energy and the results are suspect ({advice})",
            stats.energy_growth, stats.energy_growth_steps
        ));
    }
    out
}

/// Why the energy rose, from what the run saw: friction itself never adds
/// energy, so a rise comes from raised penalties, unsolved passes or steps
/// accepted without agreement.
/// `stiff`: the penalty named where it is far above the automatic one
/// (`dda_core::error::stiff_penalty`), the cause left where the run saw
/// no other.
pub(crate) fn energy_advice(stats: &dda_core::Statistics, stiff: Option<String>) -> String {
    let mut causes = Vec::new();
    if stats.penalty_raises > 0 {
        causes.push(format!(
            "the penalty was raised {} times, which multiplies the force of every existing overlap: leave raise_penalty off",
            stats.penalty_raises
        ));
    }
    if stats.newton_failures > 0 {
        causes.push(format!(
            "{} passes kept an unconverged Newton-Raphson iterate: a softer penalty or a smaller dt makes the springs less stiff against the blocks' inertia",
            stats.newton_failures
        ));
    }
    if stats.unconverged_steps > 0 {
        causes.push("steps were accepted without open-close agreement (see above)".into());
    }
    if stats.critical_dt.is_some() {
        causes.push(
            "explicit steps apply a contact's force from where the step starts, so a contact that closes within a step gains a little energy at each impact: a smaller dt reduces it, analysis.contact_damping: 1.0 removes it"
                .into(),
        );
    }
    if causes.is_empty() {
        match stiff {
            // A spring's energy, half its stiffness times its gap squared,
            // carries the gap's round-off times that stiffness.
            Some(stiff) => format!(
                "{stiff}: a spring's energy carries its gap's round-off times its stiffness, so at that penalty the check can read round-off as a rise; a penalty nearer the automatic one (analysis.penalty left out) keeps it below the check"
            ),
            None => "no cut, raise or unconverged pass explains it; please report the scene".to_string(),
        }
    } else {
        causes.join("; ")
    }
}

/// The last finite values, at an output time, of the summary's numbers.
#[derive(Debug, Clone, Default)]
struct Known {
    time: Option<f64>,
    penalty: Option<f64>,
    energy: Option<f64>,
    energy_growth: Option<f64>,
    deepest_penetration: Option<f64>,
}

impl Known {
    fn update(&mut self, driver: &dyn RunView) {
        let stats = driver.statistics();
        let pairs = [
            (&mut self.time, driver.time()),
            (&mut self.penalty, driver.penalty()),
            (&mut self.energy, stats.energy),
            (&mut self.energy_growth, stats.energy_growth),
            (&mut self.deepest_penetration, stats.deepest_penetration),
        ];
        for (slot, value) in pairs {
            if value.is_finite() {
                *slot = Some(value);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::SettleReport;

    fn report(stalled: bool, undone: bool) -> SettleReport {
        SettleReport {
            steps: 5,
            settled: false,
            undone,
            stalled,
            largest_step: if undone { 0.05 } else { 6.9e-6 },
            last_step: 0.0,
            balance: 3.4e-4,
            open_close_iterations: 5,
            factorizations: 13,
            wall_time: 0.05,
        }
    }

    /// A stalled settling says the model is at rest to within its
    /// balance; one undone as well (it moved a block far before it
    /// stalled) says the run starts from the model as it was.
    #[test]
    fn a_stalled_settling_warns_of_its_stall_unless_it_was_undone() {
        let stalled = report(true, false).warning().unwrap();
        assert!(
            stalled.contains("stalled") && stalled.contains("3.4e-4"),
            "{stalled}"
        );
        let undone = report(true, true).warning().unwrap();
        assert!(
            undone.contains("undone") && !undone.contains("stalled"),
            "{undone}"
        );
        assert!(report(false, false)
            .warning()
            .unwrap()
            .contains("may not stand"));
    }
}
