//! What a run counts and times, reported in the summary and by `dda bench`.

use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::contact::ContactState;
use crate::contacts::ContactKey;
use crate::solve::SolveCounts;

/// Counters of a run, reported in the summary.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Statistics {
    pub steps: usize,
    pub open_close_iterations: usize,
    pub newton_iterations: usize,
    pub factorizations: usize,
    /// Steps cut to a third because open-close iterations did not settle.
    pub open_close_cuts: usize,
    /// Steps cut because a point moved farther than the bound.
    pub displacement_cuts: usize,
    pub penalty_raises: usize,
    /// Steps cut because a contact penetrated too deep.
    pub penetration_cuts: usize,
    /// Steps cut to a third because the last pass's Newton-Raphson
    /// iteration stalled out of balance (`UNSOLVED_SHARE` in
    /// `driver/pass.rs`), and steps accepted so at the smallest step.
    #[serde(default)]
    pub newton_cuts: usize,
    #[serde(default)]
    pub unsolved_steps: usize,
    /// Steps accepted at the smallest time step without open-close agreement.
    pub unconverged_steps: usize,
    /// Steps whose open-close passes returned to the states of two passes
    /// before (a cycle), settled by keeping each cycling contact's sliding
    /// or closed state.
    pub cycle_breaks: usize,
    /// Contacts that started a step in the state its foreseen motion
    /// leads to (opening or closing), not the one they ended the last in.
    pub foreseen: usize,
    /// Open-close passes spent turning back a foreseen state: the motion
    /// did not carry the contact across after all.
    pub foresight_misses: usize,
    /// Contacts that struck (closed with an approach speed while
    /// `restitution` is set) and took an impulse.
    pub impacts: usize,
    /// The first contacts that cycled (at most 20), each with the two
    /// states it cycled between and the one it kept.
    pub cycles: Vec<Cycle>,
    /// Open-close passes whose Newton-Raphson iteration did not converge
    /// (the best iterate was kept).
    pub newton_failures: usize,
    /// Open-close passes solved again with friction's coupling to the
    /// normal force in the tangent, after the symmetric iteration failed.
    pub coupled_solves: usize,
    /// Newton-Raphson moves on the whole tangent, and the factorisations
    /// among them: a large factor preconditions several such moves.
    pub whole_tangent_moves: usize,
    pub whole_tangent_factorizations: usize,
    /// GMRES's products in the moves that take friction's coupling to the
    /// normal force in: each one a product with the matrix and a solve on
    /// the factor, what such a move costs.
    #[serde(default)]
    pub whole_tangent_products: usize,
    /// Residuals assembled by those moves' line searches, each a trial
    /// share of a move (`LINE_SEARCH_GROWTH`).
    #[serde(default)]
    pub line_search_residuals: usize,
    /// Open-close passes that moved on the factor at hand with the
    /// springs changed since it was made as rank-one terms, instead of a
    /// new factorisation.
    pub changed_spring_passes: usize,
    /// Steps whose first pass started on the kept factor without weighing
    /// it against the step's tangent.
    #[serde(default)]
    pub unweighed_starts: usize,
    /// Steps whose first pass started from the foreseen motion instead of
    /// at rest (`WARM_START_MISS`).
    #[serde(default)]
    pub warm_starts: usize,
    /// Open-close passes ended before their tolerance because a contact's
    /// decision read on the way would change (`EARLY_DECISION`).
    pub early_decisions: usize,
    /// Those among them ended in their moves on the whole tangent.
    #[serde(default)]
    pub whole_tangent_early_decisions: usize,
    /// Accepted steps that ended with a penetration deeper than the limit.
    pub deep_penetration_steps: usize,
    /// The deepest penetration of any accepted step.
    pub deepest_penetration: f64,
    /// The deepest contact of the last step accepted deeper than the limit,
    /// and its penetration (m).
    pub last_deep: Option<(ContactKey, f64)>,
    /// Contacts still changing state or entrance in the last step accepted
    /// without open-close agreement (at most `CYCLES_KEPT`).
    pub last_unsettled: Vec<ContactKey>,
    /// Total energy (kinetic, potential, elastic, contact springs) after
    /// the last step, when the system can tell it (no work done on it).
    pub energy: f64,
    /// The energy in play: the largest kinetic plus spring energy plus the
    /// potential energy released, seen so far.
    pub energy_scale: f64,
    /// The largest rise of the total energy above its lowest value so far,
    /// counted when above a quarter of the energy in play: a scene that
    /// should only lose energy gained some.
    pub energy_growth: f64,
    pub energy_growth_steps: usize,
    pub wall_time: Duration,
    /// Symbolic analyses of the step's matrix pattern (one per change of
    /// the contact graph).
    pub symbolic_analyses: usize,
    /// Where the wall time went.
    pub times: PhaseTimes,
    /// Explicit integration: the smallest critical time step bound seen,
    /// 2/ω_max from the penalty springs and the block masses (s).
    pub critical_dt: Option<f64>,
    /// Explicit integration: steps shortened below the nominal dt to stay
    /// under the critical one.
    pub critical_limited_steps: usize,
    /// Iterative solver (`Settings::solver`): systems solved,
    /// conjugate-gradient iterations over them, and systems that reached
    /// the iteration cap and were solved by sparse Cholesky instead.
    pub iterative_solves: usize,
    pub iterative_iterations: usize,
    pub iterative_fallbacks: usize,
}

impl Statistics {
    /// Steps cut, for any reason: open-close, displacement, penetration,
    /// a pass that stalled out of balance.
    pub fn cuts(&self) -> usize {
        self.open_close_cuts + self.displacement_cuts + self.penetration_cuts + self.newton_cuts
    }

    /// Adds an iterative solver's work.
    pub(crate) fn count_solves(&mut self, counts: SolveCounts) {
        self.iterative_solves += counts.solves;
        self.iterative_iterations += counts.iterations;
        self.iterative_fallbacks += counts.fallbacks;
    }
}

/// How many cycling contacts the statistics name.
pub(crate) const CYCLES_KEPT: usize = 20;

/// A contact whose open-close passes cycled between two states in a step
/// ending at `time`, and the state it kept.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Cycle {
    pub time: f64,
    pub key: ContactKey,
    pub between: [ContactState; 2],
    pub kept: ContactState,
}

/// Wall time of each phase of the step, summed over the run. Each phase
/// reads the clock once on entry and once on exit, so the timing costs
/// nothing next to the work it measures.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct PhaseTimes {
    /// Broad phase: pairs of blocks near enough to touch.
    pub broad_phase: Duration,
    /// Narrow phase: the contacts of each near pair, records carried over.
    pub narrow_phase: Duration,
    /// Building the step's matrix pattern from the contact graph.
    pub pattern: Duration,
    /// Filling the matrix and the residual (inertia, block terms, contacts).
    pub assembly: Duration,
    /// Symbolic analysis: fill-reducing ordering and the factor's structure.
    pub symbolic: Duration,
    /// Numeric Cholesky factorisation.
    pub numeric: Duration,
    /// Forward and back substitutions.
    pub solve: Duration,
    /// Each pass's open-close decisions, and the step's foreseen states.
    pub open_close: Duration,
    /// Committing the accepted step (laws, records, blocks).
    pub commit: Duration,
}

impl PhaseTimes {
    /// The phases with their names, in step order.
    pub fn phases(&self) -> [(&'static str, Duration); 9] {
        [
            ("broad_phase", self.broad_phase),
            ("narrow_phase", self.narrow_phase),
            ("pattern", self.pattern),
            ("assembly", self.assembly),
            ("symbolic", self.symbolic),
            ("numeric", self.numeric),
            ("solve", self.solve),
            ("open_close", self.open_close),
            ("commit", self.commit),
        ]
    }

    /// The time of each phase since `earlier`.
    pub fn since(&self, earlier: &PhaseTimes) -> PhaseTimes {
        let d = |a: Duration, b: Duration| a.saturating_sub(b);
        PhaseTimes {
            broad_phase: d(self.broad_phase, earlier.broad_phase),
            narrow_phase: d(self.narrow_phase, earlier.narrow_phase),
            pattern: d(self.pattern, earlier.pattern),
            assembly: d(self.assembly, earlier.assembly),
            symbolic: d(self.symbolic, earlier.symbolic),
            numeric: d(self.numeric, earlier.numeric),
            solve: d(self.solve, earlier.solve),
            open_close: d(self.open_close, earlier.open_close),
            commit: d(self.commit, earlier.commit),
        }
    }
}
