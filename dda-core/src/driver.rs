//! The Newmark (β = 1/2, γ = 1) time stepper with open-close iterations.
//!
//! One step: search contacts, then repeat open-close passes until no contact
//! changes state; each pass solves the step's equations by Newton-Raphson on
//! the residual with the contact states held fixed. A step that does not
//! settle within the open-close limit is cut to a third, recursively down to a
//! floor; a step that moves a point too far is cut; a step that penetrates too
//! deep raises the penalty. Nothing is changed until the step is accepted.
//!
//! This file holds the step and its open-close passes; the parts of a step
//! live beside it: the search and the matrix pattern (`pattern`), a pass's
//! Newton-Raphson iterations (`pass`), the residual and tangent
//! (`assemble`), one contact's terms (`terms`), and the accepted step's
//! commit (`commit`).

use std::time::Instant;

use nalgebra::SVector;
use rayon::prelude::*;

use crate::assembly::BlockSparse;
use crate::by_block::ByBlock;
use crate::contact::{ContactState, DynContactLaw};
use crate::contacts::{BlockVector, Contact, ContactKey, EntranceRows, SearchedPairs};
use crate::error::DdaError;
use crate::loads::Support;
use crate::settings::{Integrator, Settings};
use crate::solve::{solver_for, LinearSolver};
use crate::statistics::CYCLES_KEPT;
pub use crate::statistics::{Cycle, PhaseTimes, Statistics};
use crate::system::{BlockMatrix, BlockSystem};
use crate::{BLOCKS_PER_TASK, CONTACTS_PER_TASK};
use chosen::Chosen;
use predict::RecentSteps;
use terms::{ContactLoad, ContactTerms, Decision, Kept};
use touching::Touching;

mod anderson;
mod assemble;
mod checkpoint;
mod chosen;
mod commit;
mod even_steps;
mod explicit;
mod gmres;
mod impact;
mod pass;
mod pattern;
mod predict;
pub mod settle;
mod springs;
mod step_motion;
mod terms;
mod touching;
mod weighing;
mod woodbury;

/// The automatic step's ceiling is sqrt(block size / g) over this: a block
/// starting from rest moves 1/800 of its size in such a step.
const AUTO_STEPS_PER_MOTION_TIME: f64 = 20.0;

/// The automatic step keeps the motion it bounds (`step_motion`: each
/// contact's relative motion, each block's points' motion against each
/// other, a block in flight's whole motion) at most this share of the
/// median block size in a step: a rocking column's rebounds then stay
/// within about 1 % of Housner's, while a wall at rest steps at the
/// ceiling.
const AUTO_MOTION_SHARE: f64 = 2.5e-4;

/// A step starts its Newton-Raphson moves from its foreseen motion
/// (`predict.rs`) instead of at rest where the last step's motion lay
/// within this share of its own foresight. A standing wall at dt 1 ms is
/// foreseen within 0.3-1.2 %, and its first residual there is 0.3-4 % of
/// the one at rest: the 10,051-block walls then take a move less a step
/// (2D 7.75 → 7.00 rigid, 8.10 → 7.25 deformable; 3D 7.80 → 6.80 and
/// 7.60 → 6.60). A settling wall at its automatic step misses its
/// foresight by 40-230 %, and started from it took more moves and GMRES
/// products, not fewer. The step's first assembly is still made at rest
/// (the factor is weighed there, and the step's tolerance is a share of
/// its residual); the residual at the foreseen motion costs one more
/// assembly of the forces alone.
const WARM_START_MISS: f64 = 0.1;

/// A step starts from its foreseen motion only where the last step's first
/// pass took at least this many moves: a pass solved in one move (a
/// linear step on a factor of its own) has none to save, and would pay the
/// extra assembly. A block held on an incline at dt 0.2 ms (1.02 moves
/// a step) started warm in 1,154 of 10,000 steps for 91 moves fewer.
const WARM_START_MOVES: usize = 3;

/// The automatic step never falls below this share of its ceiling.
const AUTO_FLOOR: f64 = 1e-4;

/// The least displacement bound of a step, as a share of the median block
/// size, when Shi's g2·w0 (a share of the whole model) is larger: the
/// search range follows the blocks and their motion, not the model's
/// extent. Default 0.1: still 400 times what a block moves in an automatic
/// step. A quarter, as it was, put every feature of two neighbouring
/// bricks within range of the other's, so no test of the narrow phase
/// rejected early (at 10,051 3D blocks the narrow phase took a median 306
/// ms a step, against 219 at a tenth, finding the same contacts).
pub const BOUND_BLOCK_SHARE: f64 = 0.1;

/// How much of the passes an earlier step attempt took still counts, an
/// attempt later, in the passes the recent ones took: a pass reads its
/// decisions early (`EARLY_DECISION`) where those went on past it, or
/// where it is slow. After two passes a step, a wall taking one goes on
/// reading them for 13 steps. A read costs about a quarter of a move on
/// the 10,051-block 2D wall and half of one in 3D: read in every pass,
/// the 3D rigid wall (one pass a step) took 3 % longer.
const RECENT_PASSES_DECAY: f64 = 0.95;

/// Forces below this share of a contact's normal spring force at the
/// contact tolerance are round-off: a contact whose friction and shear
/// force both lie below it keeps its state between locked and sliding.
const ROUND_OFF_FORCE: f64 = 1e-9;

/// A step whose contacts times N² (its loops' work) is below this runs on
/// one core: there waking the other core costs more than it takes over.
/// Two cores against one, at dt 1 ms: the 10 × 10 walls (570 contacts,
/// 20,520) over their first second took 0.57–0.59 and 0.72–0.74 ms a step
/// rigid and deformable on two, 0.43 and 0.58–0.59 on one; the 20 × 20
/// deformable wall (2,340 contacts, 84,240) 2.93–3.00 against 2.71–2.78;
/// the 30 × 30 walls (5,310 contacts, 191,160) over 0.5 s 4.1–4.4 and
/// 11.4 on two against 4.7–4.9 and 14.2–14.6 on one; the 3D 10-course
/// walls (1,140 contacts of 12 DOF, 164,160) over 0.1 s 3.7 and 4.7
/// against 3.8–3.9 and 5.2–5.3. Before the first search has found any
/// contact, the blocks stand for them: the 10,051-block walls' first
/// step (the whole search, the ordering and the first factorisation) took
/// 4.9 s in 3D and 0.80–0.88 s in 2D on one core, 2.7 and 0.60–0.76 on
/// two.
pub const ONE_CORE_WORK: usize = 100_000;

/// The trial solution of one step attempt.
struct Trial<const T: usize> {
    d: Vec<f64>,
    states: Vec<ContactState>,
    entrances: Vec<usize>,
    directions: Vec<SVector<f64, T>>,
    converged: bool,
    /// Whether the last pass solved the step: its Newton-Raphson iteration
    /// converged, or stalled within `UNSOLVED_SHARE` of the loads.
    solved: bool,
    /// Contacts whose state or entrance the last pass changed.
    unsettled: Vec<usize>,
    /// Contacts this step has opened because their dashpot pulled (the
    /// spring alone still pushed): if they cycle, they stay open.
    pulled: Vec<bool>,
    /// Contacts that slid in an earlier pass and are now within their
    /// strength: they stay sliding for the passes (whose return map gives
    /// them the locked spring's force and tangent) and commit locked.
    within: Vec<bool>,
    /// The residual at the step's start (its first pass's first), N: the
    /// scale every pass's residual is measured against.
    load_scale: f64,
    /// The first pass's first residual and the last one reckoned, N:
    /// how far from balance the step starts and ends (`settle.rs` reads
    /// them; a later pass's first residual can raise `load_scale` far
    /// above the first where the pass before it moved far).
    rest_norm: f64,
    end_norm: f64,
    /// Contacts started in their foreseen state, until a pass turns one
    /// back.
    foreseen: Vec<usize>,
    /// The Newton-Raphson moves of the attempt's first pass.
    first_moves: usize,
}

/// What [`Driver::load`] assembles.
#[derive(Clone, Copy)]
enum Motion<'a> {
    /// An implicit step's residual and its tangent matrix.
    Tangent,
    /// An implicit step's residual alone (the factor is kept).
    Implicit,
    /// The same, each contact's load kept whole, its springs with its
    /// force, for `FactorSprings::record` (a kept factor not weighed).
    Springs,
    /// An explicit step's forces, its dashpots on the displacement its
    /// start velocities make in dt.
    Explicit(&'a [f64]),
}

/// The note on a model run without contact damping.
pub const UNDAMPED_NOTE: &str = "contact damping is off (Shi's undamped penalty springs): a block landing on, or released onto, its contacts bounces on them, and near its friction limit (a factor of safety below about 1.1) the bounces can start a slide of millimetres to metres; analysis.contact_damping: 1.0 ends impacts and holds such blocks, and analysis.settle starts a model released onto its contacts at rest (docs/limits.md)";

/// [`UNDAMPED_NOTE`] once the model has settled: nothing is released onto
/// its contacts any more.
pub const UNDAMPED_SETTLED_NOTE: &str = "contact damping is off (Shi's undamped penalty springs): the model starts settled on its contacts, but a block that lands on them in the run bounces, and near its friction limit (a factor of safety below about 1.1) the bounces can start a slide of millimetres to metres; analysis.contact_damping: 1.0 ends impacts and holds such blocks (docs/limits.md)";

/// Runs a [`BlockSystem`] in time.
pub struct Driver<S: BlockSystem<N, T>, const N: usize, const T: usize> {
    pub system: S,
    laws: Vec<Box<dyn DynContactLaw>>,
    contacts: Vec<Contact<N, T, S::Entrance>>,
    /// Where the last search's pairs lie in `contacts` (none where the
    /// contacts came from elsewhere: a checkpoint).
    searched: SearchedPairs,
    velocity: Vec<BlockVector<N>>,
    settings: Settings,
    solver: Box<dyn LinearSolver>,
    matrix: BlockSparse<N>,
    values: Vec<f64>,
    factored: Option<Vec<f64>>,
    /// How far the last step's matrix had moved from the factor's (the sum
    /// of its values' changes), where it started on it: the matrix stands
    /// still where the next step's is the same (`Driver::factor_fits`).
    factor_change: Option<f64>,
    /// The last weighing of the kept factor against a step's tangent, and
    /// the steps started on it unweighed since (`weighing.rs`).
    weighing: Option<weighing::Weighing>,
    /// The most steps in a row that start on a large factor unweighed
    /// (`weighing::UNWEIGHED_STEPS`).
    unweighed_steps: usize,
    /// The contact springs in the factor's matrix, within a step attempt.
    factor_springs: springs::FactorSprings<T>,
    /// The most rank-one terms a later pass applies to a large factor for
    /// the springs changed since it was made (`pass::CHANGED_SPRINGS`).
    changed_springs: usize,
    /// See `EARLY_DECISION`; 0 reads the decisions only after a pass.
    early_decision: f64,
    /// Whether a step whose motion the last one foresaw well starts from
    /// it (`WARM_START_MISS`).
    warm_starts: bool,
    /// Where the step attempt's first pass starts, if not at rest.
    warm_start: Option<Vec<f64>>,
    /// Whether the solver holds the symbolic analysis of the matrix pattern.
    analysed: bool,
    /// Each contact's load at the last assembly (kept for its storage).
    contact_loads: Vec<Option<ContactLoad<N, T>>>,
    /// Each contact's forces at the last move on a kept factor (kept for
    /// its storage).
    contact_forces: Vec<Option<[BlockVector<N>; 2]>>,
    /// Each contact's open-close decision and what it keeps of an accepted
    /// step (kept for their storage).
    decisions: Vec<Decision<T>>,
    kept: Vec<Kept<T>>,
    /// Each contact's chosen entrance, side by side, for the step's sweeps.
    chosen: Chosen<N, T, S::Entrance>,
    /// The contacts of each block in the current pass, in contact order:
    /// a residual is gathered block by block, in parallel, adding each
    /// block's contact forces in the order one thread would.
    touching: Touching,
    /// Where each contact's block pair sits in the matrix pattern (`None`:
    /// not in it, so the contact must stay open).
    slots: Vec<Option<usize>>,
    /// The contacts under each slot, in contact order: the tangent's
    /// off-diagonal blocks are gathered slot by slot on every core.
    slot_contacts: ByBlock,
    /// Assemble contact by contact on one thread even within a pass (for
    /// tests: the two ways agree to the last bit).
    one_thread_assembly: bool,
    /// A small model's pool of one thread (`ONE_CORE_WORK`), once made
    /// (`None` within if it could not be).
    one_core: Option<Option<std::sync::Arc<rayon::ThreadPool>>>,
    /// How near an open contact's blocks must be for their pair to enter
    /// the pattern: the reach of the last step's motion, at least
    /// `PATTERN_REACH_SHARE` of the median block size (m).
    pattern_reach: f64,
    /// The largest point displacement of the last accepted step (m).
    last_moved: f64,
    /// Open-close passes the recent step attempts took (the most, each
    /// attempt's older count weighed down by `RECENT_PASSES_DECAY`).
    passes_before: f64,
    /// Slow passes in a row on an earlier step's factor
    /// (`pass::STALE_FACTOR_MOVES`).
    slow_carried: usize,
    /// Whether the pass at hand reads its decisions early.
    decide_early: pass::EarlyDecision,
    /// Whether `decisions` holds those read early at the trial where the
    /// pass ended, for the `decide` that follows.
    decisions_read: bool,
    /// The median block size (m).
    block_size: f64,
    /// Inverse mass matrices of the blocks in the current step.
    inverse_masses: Vec<BlockMatrix<N>>,
    /// The held directions of fixed and driven points in the current step
    /// (only with contact damping).
    supports: Vec<Support<N>>,
    /// The impulse's change to each block's start velocity in the current
    /// pass (zero unless a contact strikes with `restitution` set).
    struck: Vec<BlockVector<N>>,
    /// The share of `struck` the step's motion feels: an impulse a share
    /// τ into the step moves the blocks for the remaining 1 − τ.
    struck_early: Vec<BlockVector<N>>,
    /// The contacts struck in the current attempt.
    striking: Vec<usize>,
    /// The struck contacts friction cannot stop in the current attempt.
    sliding_impact: Vec<usize>,
    /// The automatic step's ceiling, with `dt` left out of the settings
    /// (implicit integrator, scene under gravity): the nominal step then
    /// follows the blocks' motion (see [`AUTO_MOTION_SHARE`]).
    dt_cap: Option<f64>,
    time: f64,
    /// Whether the model is settling (`settle.rs`): its steps take no
    /// time, and read the loads and supports where the run starts.
    settling: bool,
    /// The last accepted step's residual at its start and at its end, N
    /// (`Trial::rest_norm`, `Trial::end_norm`).
    residuals: (f64, f64),
    /// What rounding left out of `time` (a compensated sum, so thousands of
    /// steps of 0.001 s add up to 2 s, not 1.9999999999998905).
    time_carry: f64,
    dt: f64,
    dt_next: f64,
    /// The equal step the last stretch to a requested time was split into
    /// (`driver/even_steps.rs`), s; `None` before any.
    even_step: Option<f64>,
    penalty: f64,
    length_scale: f64,
    stats: Statistics,
    notes: Vec<String>,
    /// The lowest total energy so far and the first potential energy
    /// (energy check).
    energy_floor: Option<f64>,
    first_potential: Option<f64>,
    /// Explicit integration: the last step's length, since velocities sit
    /// at half steps (`None` before the first step).
    last_dt: Option<f64>,
    /// Explicit integration: the velocities at the last half step (empty
    /// before the first step); `velocity` is their estimate at its end.
    half_velocity: Vec<BlockVector<N>>,
    /// Explicit integration: each block's ω² bound on its own springs
    /// (elastic, fixed points), found at the first step.
    block_rates: Vec<f64>,
    /// The last accepted steps, from which the next one's motion is
    /// foreseen (implicit integration).
    recent: RecentSteps,
}

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// A driver at time zero with the blocks at rest.
    pub fn new(
        system: S,
        laws: Vec<Box<dyn DynContactLaw>>,
        settings: Settings,
    ) -> Result<Self, DdaError> {
        settings.validate()?;
        let blocks = system.block_count();
        let mut notes = Vec::new();
        let length_scale = settings
            .length_scale
            .unwrap_or_else(|| system.length_scale());
        let penalty = match settings.penalty {
            Some(p) => p,
            None => {
                let p = system.automatic_penalty();
                notes.push(format!(
                    "penalty {p:.4e} N/m³ per unit contact length or area: twice the stiffest block's Young's modulus over the median block size"
                ));
                p
            }
        };
        if !(penalty.is_finite() && penalty > 0.0) {
            return Err(DdaError::Settings(format!(
                "the automatic penalty is {penalty}: give the blocks a positive Young's modulus or set a penalty"
            )));
        }
        let motion_time = (settings.integrator == Integrator::Implicit)
            .then(|| system.motion_time())
            .flatten();
        let (dt, dt_cap) = match (settings.dt, motion_time) {
            (Some(dt), _) => (dt, None),
            (None, Some(t)) => {
                let cap = t / AUTO_STEPS_PER_MOTION_TIME;
                notes.push(format!(
                    "time step automatic, at most {cap:.4e} s (1/{AUTO_STEPS_PER_MOTION_TIME} of sqrt(block size / g)): each step as long as keeps each contact's relative motion, each block's points' motion against each other and a block in flight's whole motion less than {AUTO_MOTION_SHARE:e} of the median block size; give dt to fix it"
                ));
                (cap, Some(cap))
            }
            (None, None) => {
                let lightest = (0..blocks)
                    .map(|i| system.mass(i)[(0, 0)])
                    .fold(f64::INFINITY, f64::min);
                let dt = if lightest.is_finite() {
                    0.2 * (lightest / penalty).sqrt()
                } else {
                    1e-3
                };
                notes.push(format!(
                    "time step {dt:.4e} s: 0.2 / sqrt(penalty / lightest block mass), so contact oscillations are resolved"
                ));
                (dt, None)
            }
        };
        if settings.contact_damping == 0.0 && system.block_count() > 1 {
            notes.push(UNDAMPED_NOTE.into());
        }
        let dofs = (0..blocks).map(|i| system.dofs(i)).collect();
        let block_size = system.block_size();
        let solver = solver_for(settings.solver);
        let mut driver = Self {
            velocity: vec![BlockVector::<N>::zeros(); blocks],
            matrix: BlockSparse::new(dofs, []),
            system,
            laws,
            contacts: Vec::new(),
            searched: SearchedPairs::default(),
            settings,
            solver,
            values: Vec::new(),
            factored: None,
            factor_change: None,
            weighing: None,
            unweighed_steps: weighing::UNWEIGHED_STEPS,
            factor_springs: Default::default(),
            changed_springs: pass::CHANGED_SPRINGS,
            early_decision: pass::EARLY_DECISION,
            warm_starts: true,
            warm_start: None,
            analysed: false,
            contact_loads: Vec::new(),
            contact_forces: Vec::new(),
            chosen: Chosen::default(),
            touching: Touching::default(),
            decisions: Vec::new(),
            kept: Vec::new(),
            slots: Vec::new(),
            slot_contacts: ByBlock::default(),
            one_thread_assembly: false,
            one_core: None,
            pattern_reach: 0.0,
            last_moved: 0.0,
            passes_before: 0.0,
            slow_carried: 0,
            decide_early: pass::EarlyDecision::Never,
            decisions_read: false,
            block_size,
            inverse_masses: Vec::new(),
            supports: Vec::new(),
            struck: Vec::new(),
            struck_early: Vec::new(),
            striking: Vec::new(),
            sliding_impact: Vec::new(),
            time: 0.0,
            settling: false,
            residuals: (0.0, 0.0),
            time_carry: 0.0,
            dt,
            dt_next: dt,
            even_step: None,
            dt_cap,
            penalty,
            length_scale,
            stats: Statistics::default(),
            notes,
            energy_floor: None,
            first_potential: None,
            last_dt: None,
            half_velocity: Vec::new(),
            block_rates: Vec::new(),
            recent: RecentSteps::default(),
        };
        driver.reach_pattern(0.0);
        Ok(driver.explained())
    }

    /// Replaces the linear solver.
    pub fn with_solver(mut self, solver: Box<dyn LinearSolver>) -> Self {
        self.solver = solver;
        self.factored = None;
        self.analysed = false;
        self
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    /// The nominal time step.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The current normal penalty (after any raises).
    pub fn penalty(&self) -> f64 {
        self.penalty
    }

    pub fn length_scale(&self) -> f64 {
        self.length_scale
    }

    /// Assembles contact by contact on one thread, as outside a pass,
    /// instead of block by block on every core. The two agree to the last
    /// bit; tests compare them.
    #[doc(hidden)]
    pub fn assemble_on_one_thread(&mut self, on: bool) {
        self.one_thread_assembly = on;
    }

    /// The most rank-one terms a later open-close pass applies to a large
    /// factor for the springs changed since it was made, instead of
    /// factorising (default 64); 0 factorises at every later pass. For
    /// tests and studies of the solve.
    #[doc(hidden)]
    pub fn set_changed_springs(&mut self, limit: usize) {
        self.changed_springs = limit;
    }

    /// The most steps in a row whose first pass may start on a large kept
    /// factor without weighing it against the step's tangent (default 3);
    /// 0 weighs it at every step. For tests and studies of the solve.
    #[doc(hidden)]
    pub fn set_unweighed_steps(&mut self, steps: usize) {
        self.unweighed_steps = steps;
    }

    /// The share of the step's first residual at which a pass reads its
    /// contacts' decisions and ends if any would change (default 1e-5);
    /// 0 reads them only once the pass has converged. For tests and
    /// studies of the solve.
    #[doc(hidden)]
    pub fn set_early_decision(&mut self, share: f64) {
        self.early_decision = share;
    }

    /// Whether a step whose motion the last step foresaw within
    /// `WARM_START_MISS` starts its Newton-Raphson moves from that motion
    /// (default true) instead of at rest. For tests and studies of the
    /// solve.
    #[doc(hidden)]
    pub fn set_warm_starts(&mut self, on: bool) {
        self.warm_starts = on;
    }

    pub fn statistics(&self) -> &Statistics {
        &self.stats
    }

    /// The shortest nominal step the run may take: `dt`, or with the
    /// automatic step following the motion, its floor.
    pub fn shortest_dt(&self) -> f64 {
        self.dt_cap.map_or(self.dt, |cap| cap * AUTO_FLOOR)
    }

    /// Why automatic values were chosen, for the user.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Generalised velocities at the end of the last step.
    pub fn velocities(&self) -> &[BlockVector<N>] {
        &self.velocity
    }

    /// Sets a block's generalised velocity (initial conditions); a block
    /// with fewer DOF keeps the leading ones only.
    pub fn set_velocity(&mut self, block: usize, v: BlockVector<N>) {
        let n = self.system.dofs(block);
        self.velocity[block] = v.map_with_location(|r, _, x| if r < n { x } else { 0.0 });
    }

    /// The number of unknowns of the step's system: the DOF the blocks move
    /// by.
    pub fn unknowns(&self) -> usize {
        self.matrix.dim()
    }

    /// Contacts of the last step, with their records.
    pub fn contacts(&self) -> &[Contact<N, T, S::Entrance>] {
        &self.contacts
    }

    /// Steps until `time` is reached exactly.
    pub fn advance_to(&mut self, time: f64) -> Result<(), DdaError> {
        self.advance_observed(time, |_| {})
    }

    /// [`Driver::advance_to`], showing each accepted step to `observe`.
    pub fn advance_observed(
        &mut self,
        time: f64,
        mut observe: impl FnMut(&Self),
    ) -> Result<(), DdaError> {
        self.advance_while(time, |d| {
            observe(d);
            true
        })?;
        Ok(())
    }

    /// [`Driver::advance_observed`] that stops after a step where `go_on`
    /// says false; returns whether `time` was reached.
    pub fn advance_while(
        &mut self,
        time: f64,
        mut go_on: impl FnMut(&Self) -> bool,
    ) -> Result<bool, DdaError> {
        while time - self.time > 1e-9 * self.dt {
            let limit = self.even_limit(time - self.time);
            self.step(limit)?;
            if (time - self.time).abs() <= 1e-9 * self.dt {
                // Land on the requested time, not on a sum of rounded steps.
                self.time = time;
                self.time_carry = 0.0;
            }
            if !go_on(self) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Adds `dt` to the time by Kahan's compensated summation.
    fn advance_time(&mut self, dt: f64) {
        let y = dt - self.time_carry;
        let t = self.time + y;
        self.time_carry = (t - self.time) - y;
        self.time = t;
    }

    /// One accepted step of at most `dt_limit`.
    pub fn step(&mut self, dt_limit: f64) -> Result<(), DdaError> {
        let started = Instant::now();
        // The step runs on a thread of rayon's pool, so the contacts'
        // parallel loops split from a worker. Called from outside the pool,
        // each loop would hand its work over to the pool and sleep until it
        // came back: a dozen hand-overs a step, a fifth of a 411-block
        // wall's step. Inside the pool, `scope` runs it in place. A small
        // model's step runs on a pool of one thread of its own
        // (`ONE_CORE_WORK`); the answer is the same on any number.
        let one_core = self.steps_on_one_core().then(|| self.one_core()).flatten();
        let result = match one_core {
            Some(pool) => pool.install(|| self.try_step(dt_limit)),
            None => rayon::scope(|_| self.try_step(dt_limit)),
        };
        self.stats.wall_time += started.elapsed();
        result.map_err(|e| self.with_advice(e))
    }

    /// The automatic penalty of this model (N/m³), whatever the one in use.
    pub fn automatic_penalty(&self) -> f64 {
        self.system.automatic_penalty()
    }

    /// `e` with the advice this model's settings make right: a failed
    /// factorisation names a penalty far above the automatic one as its
    /// cause, since it is the one setting that can swamp the blocks' terms
    /// (scene validation keeps masses and moduli positive).
    fn with_advice(&self, e: DdaError) -> DdaError {
        match e {
            DdaError::Factorization { detail, advice } => {
                let advice = crate::error::stiff_penalty(self.penalty, self.automatic_penalty())
                    .map_or(advice, |stiff| {
                        format!(
                            "{stiff}: springs that much stiffer than the blocks leave the factorisation to round-off; a penalty nearer the automatic one (analysis.penalty left out) keeps the matrix positive definite"
                        )
                    });
                DdaError::Factorization { detail, advice }
            }
            e => e,
        }
    }

    /// Whether the next step runs on a pool of one thread
    /// (`ONE_CORE_WORK`): its work read off the contacts found so far, or
    /// off the blocks while none is.
    pub fn steps_on_one_core(&self) -> bool {
        let found = match self.contacts.len() {
            0 => self.system.block_count(),
            found => found,
        };
        found * N * N < ONE_CORE_WORK
    }

    /// The driver's pool of one thread, made at its first use; `None` if
    /// it could not be made (the step then runs on the shared pool).
    fn one_core(&mut self) -> Option<std::sync::Arc<rayon::ThreadPool>> {
        let pool = self.one_core.get_or_insert_with(|| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build();
            pool.ok().map(std::sync::Arc::new)
        });
        pool.clone()
    }

    fn try_step(&mut self, dt_limit: f64) -> Result<(), DdaError> {
        if self.settings.integrator == Integrator::Explicit {
            return self.explicit_step(dt_limit);
        }
        self.solver.start_step();
        let bound = self.displacement_bound();
        self.search(2.5 * bound);
        let found = Instant::now();
        self.update_pattern();
        self.stats.times.pattern += found.elapsed();

        let floor = self.dt * self.settings.min_dt_ratio;
        let mut dt = self.dt_next.min(dt_limit);
        let mut cut = false;
        let mut moved_by;
        let trial = loop {
            let trial = self.attempt(dt)?;
            // A settling step out of balance is not cut: the next one goes
            // on from it, and the settling ends only in balance.
            let unsolved = !trial.solved && !self.settling;
            if (!trial.converged || unsolved) && dt / 3.0 >= floor {
                dt /= 3.0;
                cut = true;
                if trial.converged {
                    self.stats.newton_cuts += 1;
                } else {
                    self.stats.open_close_cuts += 1;
                }
                continue;
            }
            let d = split::<N>(&trial.d);
            let moved = self.system.max_displacement(&d);
            moved_by = moved;
            if moved > bound && dt > floor {
                dt = (0.9 * dt * bound / moved).max(floor);
                cut = true;
                self.stats.displacement_cuts += 1;
                continue;
            }
            // Too deep a penetration made in this step: a stiffer penalty
            // (Shi) or, by default, a shorter step. A contact that starts the
            // step deep is left alone: either remedy would throw it out harder.
            let limit = self.settings.max_penetration_ratio * self.length_scale;
            let (deepest, deepened, deepest_key) = self.penetration(&trial, limit);
            if deepened > limit {
                if self.settings.raise_penalty && self.stats.penalty_raises < 6 {
                    self.penalty *= 10.0;
                    self.factored = None;
                    self.stats.penalty_raises += 1;
                    continue;
                }
                if dt / 3.0 >= floor {
                    dt /= 3.0;
                    cut = true;
                    self.stats.penetration_cuts += 1;
                    continue;
                }
            }
            if unsolved {
                self.stats.unsolved_steps += 1;
            }
            if !trial.converged {
                self.stats.unconverged_steps += 1;
                self.stats.last_unsettled = (trial.unsettled.iter())
                    .take(CYCLES_KEPT)
                    .map(|&i| self.contacts[i].key)
                    .collect();
            }
            if deepest > limit {
                self.stats.deep_penetration_steps += 1;
                self.stats.deepest_penetration = self.stats.deepest_penetration.max(deepest);
                self.stats.last_deep = deepest_key.map(|k| (k, deepest));
            }
            break trial;
        };
        self.residuals = (trial.rest_norm, trial.end_norm);
        // What the automatic step bounds, read before the blocks move.
        let motion =
            (self.dt_cap.is_some()).then(|| self.step_motion(&trial, &split::<N>(&trial.d)));
        let committing = Instant::now();
        self.commit(trial, dt);
        self.stats.times.commit += committing.elapsed();
        self.last_moved = moved_by;
        self.reach_pattern(moved_by);
        if let Some(cap) = self.dt_cap {
            // The automatic step: as long as keeps the motion per step
            // within its share of the block size, never above the ceiling.
            let target = AUTO_MOTION_SHARE * self.block_size;
            let motion = motion.unwrap_or(moved_by);
            let allowed = if motion > 0.0 {
                dt * target / motion
            } else {
                cap
            };
            self.dt = allowed.clamp(cap * AUTO_FLOOR, cap);
            self.dt_next = self.dt_next.min(self.dt);
        }
        if cut {
            self.dt_next = (dt * 1.5).min(self.dt);
        } else if dt >= self.dt_next {
            self.dt_next = (self.dt_next * 1.5).min(self.dt);
        }
        Ok(())
    }

    /// Solves one step of length `dt` with open-close iterations.
    fn attempt(&mut self, dt: f64) -> Result<Trial<T>, DdaError> {
        let nb = self.system.block_count();
        self.striking.clear();
        self.sliding_impact.clear();
        self.factor_springs.forget();
        self.decisions_read = false;
        let mut trial = Trial {
            converged: false,
            ..self.at_rest()
        };
        let masses: Vec<BlockMatrix<N>> = (0..nb)
            .into_par_iter()
            .with_min_len(BLOCKS_PER_TASK)
            .map(|i| self.system.mass(i))
            .collect();
        // Only the contacts' dashpots read the inverse masses here.
        self.inverse_masses = if self.settings.contact_damping > 0.0 {
            (masses.iter().enumerate())
                .map(|(i, m)| self.matrix.kept_inverse(i, m))
                .collect()
        } else {
            Vec::new()
        };
        self.supports = if self.settings.contact_damping > 0.0 {
            self.system.supports(self.time, self.load_time(dt))
        } else {
            Vec::new()
        };
        let foreseen = self.foresee_states(&mut trial, dt);
        let foreseen_well = self.recent.miss().is_some_and(|m| m <= WARM_START_MISS);
        let several = self.recent.first_moves() >= WARM_START_MOVES;
        self.warm_start = foreseen.filter(|_| self.warm_starts && foreseen_well && several);
        // The states two passes back: a pass that returns to them is a
        // cycle, which more passes would only repeat.
        let mut before: Option<Vec<ContactState>> = None;
        let passes = self.stats.open_close_iterations;
        let limit = self.settings.open_close_limit;
        for pass in 0..limit {
            self.decide_early = if pass + 1 == limit {
                pass::EarlyDecision::Never
            } else if ((pass + 1) as f64) < self.passes_before {
                pass::EarlyDecision::Always
            } else {
                pass::EarlyDecision::IfSlow
            };
            self.stats.open_close_iterations += 1;
            let struck = self.striking.len();
            self.strike(dt, &masses, &trial);
            if self.striking.len() != struck {
                // A new impulse makes a new step: states seen before it
                // are no cycle.
                before = None;
            }
            let moved = self.stats.newton_iterations;
            self.newton(dt, &masses, &mut trial)?;
            if pass == 0 {
                trial.first_moves = self.stats.newton_iterations - moved;
            }
            let assumed = trial.states.clone();
            let changed = self.decide(&mut trial, dt, None);
            let contacts = &self.contacts;
            let missed =
                |&i: &usize| trial.states[i].is_closed() == contacts[i].record.state.is_closed();
            if trial.foreseen.iter().any(missed) {
                self.stats.foresight_misses += 1;
                trial.foreseen.clear();
            }
            if !changed {
                trial.converged = true;
                break;
            }
            if before.as_ref() == Some(&trial.states) {
                // Each cycling contact takes the state that stores less
                // elastic work (sliding rather than locked, closed rather
                // than open, so nothing passes through), and one more pass
                // solves the step with it.
                // A contact that opens only because its dashpot pulls, and
                // closes again without it, stays open: it carries no force
                // either way, and held closed its dashpot would pull.
                for (i, (state, &other)) in trial.states.iter_mut().zip(&assumed).enumerate() {
                    let kept = if trial.pulled[i]
                        && (*state == ContactState::Open || other == ContactState::Open)
                    {
                        ContactState::Open
                    } else {
                        break_cycle(*state, other)
                    };
                    if *state != other && self.stats.cycles.len() < CYCLES_KEPT {
                        self.stats.cycles.push(Cycle {
                            time: self.load_time(dt),
                            key: self.contacts[i].key,
                            between: [other, *state],
                            kept,
                        });
                    }
                    *state = kept;
                }
                self.stats.open_close_iterations += 1;
                self.decide_early = pass::EarlyDecision::Never;
                self.stats.cycle_breaks += 1;
                self.strike(dt, &masses, &trial);
                self.newton(dt, &masses, &mut trial)?;
                trial.converged = true;
                break;
            }
            before = Some(assumed);
        }
        let took = (self.stats.open_close_iterations - passes) as f64;
        self.passes_before = took.max(RECENT_PASSES_DECAY * self.passes_before);
        Ok(trial)
    }

    /// Starts each contact that the foreseen motion carries across its
    /// open-close tolerance closed or open as that motion leaves it (see
    /// `predict`). With restitution only openings are foreseen: a contact
    /// struck in an attempt stays struck, and a foreseen closing may not
    /// come. Returns the foreseen motion (`None` before the first step).
    fn foresee_states(&mut self, trial: &mut Trial<T>, dt: f64) -> Option<Vec<f64>> {
        let foreseen = self.recent.foresee(dt)?;
        let deciding = Instant::now();
        let at_rest = std::mem::replace(&mut trial.d, foreseen);
        let decisions = self.decisions_at(trial, dt, &trial.d);
        let foreseen = std::mem::replace(&mut trial.d, at_rest);
        self.stats.times.open_close += deciding.elapsed();
        let closings = self.settings.restitution.is_none();
        for (i, decision) in decisions.iter().enumerate() {
            let closed = decision.state.is_closed();
            if closed != trial.states[i].is_closed() && (closings || !closed) {
                trial.states[i] = decision.state;
                if let Some(direction) = decision.direction {
                    trial.directions[i] = direction;
                }
                trial.foreseen.push(i);
            }
        }
        self.stats.foreseen += trial.foreseen.len();
        self.decisions = decisions;
        Some(foreseen)
    }

    /// Every contact's decision at the trial, in the kept buffer (give it
    /// back to `self.decisions`). Each reads the trial and writes nothing:
    /// they are made in parallel and come in contact order.
    fn decisions_at(&mut self, trial: &Trial<T>, dt: f64, moving: &[f64]) -> Vec<Decision<T>> {
        let mut decisions = std::mem::take(&mut self.decisions);
        let terms = self.terms();
        let contacts = &self.contacts;
        (0..self.contacts.len())
            .into_par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(|i| {
                if let Some(c) = contacts.get(i + PREFETCH_AHEAD) {
                    prefetch_contact(c);
                }
                terms.decision(i, trial, dt, moving)
            })
            .collect_into_vec(&mut decisions);
        decisions
    }

    /// One open-close decision at the trial: each contact's next state,
    /// slip direction and entrance; returns whether any changed (listed in
    /// `trial.unsettled`). The shear dashpots act on the step's motion, or
    /// on `approach` where given (an explicit step's start velocities × dt).
    fn decide(&mut self, trial: &mut Trial<T>, dt: f64, approach: Option<&[f64]>) -> bool {
        let moving = approach.unwrap_or(&trial.d);
        let deciding = Instant::now();
        let decisions = if std::mem::take(&mut self.decisions_read) && approach.is_none() {
            std::mem::take(&mut self.decisions)
        } else {
            self.decisions_at(trial, dt, moving)
        };
        let mut changed = false;
        trial.unsettled.clear();
        for (i, decision) in decisions.iter().enumerate() {
            if decision.changed {
                changed = true;
                trial.unsettled.push(i);
            }
            if let Some(direction) = decision.direction {
                trial.directions[i] = direction;
            }
            trial.pulled[i] |= decision.pulled;
            trial.within[i] = decision.within;
            trial.states[i] = decision.state;
            trial.entrances[i] = decision.entrance;
        }
        self.decisions = decisions;
        self.stats.times.open_close += deciding.elapsed();
        changed
    }

    /// The step's contacts as one contact's terms read them.
    fn terms(&self) -> ContactTerms<'_, N, T, S::Entrance> {
        ContactTerms {
            contacts: &self.contacts,
            laws: &self.laws,
            inverse_masses: &self.inverse_masses,
            striking: &self.striking,
            damping: self.settings.contact_damping,
            tolerance: self.settings.contact_tolerance * self.length_scale,
            // A settling keeps the band: its static steps have no inertia
            // to carry a block across a contact opened between them, so
            // they would open and close it by turns and never end still.
            commit_open: self.settings.open_at_strength
                && self.settings.integrator == Integrator::Implicit
                && !self.settling,
            penalty: self.penalty,
            chosen: &self.chosen,
        }
    }

    /// The deepest penetration of the closed contacts at the trial, and the
    /// deepest among those that started the step within the `limit`.
    fn penetration(&self, trial: &Trial<T>, limit: f64) -> (f64, f64, Option<ContactKey>) {
        // Each closed contact's entrance and gap on any thread; the deepest
        // is then found in contact order, as one thread would.
        let (chosen, contacts) = (&self.chosen, &self.contacts);
        let gaps: Vec<Option<(f64, f64)>> = (self.contacts.par_iter().enumerate())
            .with_min_len(CONTACTS_PER_TASK)
            .map(|(i, c)| {
                trial.states[i].is_closed().then(|| {
                    let e = chosen.of(contacts, i, trial.entrances[i]);
                    let (da, db) = (block(&trial.d, c.blocks[0]), block(&trial.d, c.blocks[1]));
                    (e.gap(), e.gap_at(&da, &db))
                })
            })
            .collect();
        let mut deepest: f64 = 0.0;
        let mut deepened: f64 = 0.0;
        let mut key = None;
        for (c, gaps) in self.contacts.iter().zip(&gaps) {
            let Some((start, gap)) = *gaps else {
                continue;
            };
            if -gap > deepest {
                deepest = -gap;
                key = Some(c.key);
            }
            if -start <= limit {
                deepened = deepened.max(-gap);
            }
        }
        (deepest, deepened, key)
    }
}

/// The state a contact cycling between `a` and `b` keeps: sliding over
/// locked (the friction force at its limit stores less than the spring),
/// closed over open (so blocks do not pass through each other).
fn break_cycle(a: ContactState, b: ContactState) -> ContactState {
    use ContactState::{Locked, Open, Sliding};
    match (a, b) {
        (Open, other) | (other, Open) => other,
        (Locked, Sliding) | (Sliding, Locked) => Sliding,
        (same, _) => same,
    }
}

fn block<const N: usize>(d: &[f64], i: usize) -> BlockVector<N> {
    BlockVector::<N>::from_column_slice(&d[i * N..(i + 1) * N])
}

fn split<const N: usize>(d: &[f64]) -> Vec<BlockVector<N>> {
    d.chunks_exact(N)
        .map(BlockVector::<N>::from_column_slice)
        .collect()
}

/// Shi's entrance choice: the entrance with the largest gap at the trial
/// displacement (the line the vertex would cross first). The current one is
/// kept unless another is wider by more than `tolerance`, so entrances with
/// nearly equal gaps (corners meeting corners) do not flip between passes.
/// A lone entrance is chosen without reading it (most contacts have one,
/// each in its own allocation).
fn widest_entrance<const N: usize, const T: usize, E: EntranceRows<N, T>>(
    c: &Contact<N, T, E>,
    d: &[f64],
    current: usize,
    tolerance: f64,
) -> usize {
    if c.entrances.len() == 1 {
        return 0;
    }
    let da = block::<N>(d, c.blocks[0]);
    let db = block::<N>(d, c.blocks[1]);
    widest_of(
        c.entrances.iter().map(|e| e.gap_at(&da, &db)),
        current,
        tolerance,
    )
}

/// How many contacts ahead a sweep asks for a contact's own allocations.
const PREFETCH_AHEAD: usize = 8;

/// Asks for contact `c`'s entrances and its law's history, each in an
/// allocation of its own, ahead of a sweep's read of them.
#[inline(always)]
fn prefetch_contact<const N: usize, const T: usize, E>(c: &Contact<N, T, E>) {
    prefetch(&c.entrances[..]);
    if let Some(history) = &c.record.history {
        prefetch(&**history);
    }
}

/// Asks for the cache lines `value` spans, a hint only.
#[inline(always)]
fn prefetch<V: ?Sized>(value: &V) {
    #[cfg(target_arch = "x86_64")]
    {
        let start = (value as *const V).cast::<i8>();
        for offset in (0..std::mem::size_of_val(value)).step_by(64) {
            // SAFETY: a prefetch is a hint that never faults; the address
            // lies within a live reference's value.
            unsafe {
                std::arch::x86_64::_mm_prefetch(start.add(offset), std::arch::x86_64::_MM_HINT_T0);
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// [`widest_entrance`] before the blocks move, where each entrance's gap is
/// the one it starts with: the same choice, read off the widest the
/// contact keeps from its making ([`Contact::new`]) and the current
/// entrance, instead of every entrance's gap (at ten thousand 3D blocks
/// some 320,000 a step).
fn widest_at_rest<const N: usize, const T: usize, E: EntranceRows<N, T>>(
    c: &Contact<N, T, E>,
    current: usize,
    tolerance: f64,
) -> usize {
    if c.entrances.len() == 1 {
        return 0;
    }
    let (first, widest) = c.widest_at_start();
    match c.entrances.get(current) {
        Some(e) if widest - e.gap() <= tolerance => current,
        _ => first.unwrap_or(current),
    }
}

/// The entrance of the largest of `gaps`, or `current` if within
/// `tolerance` of it.
fn widest_of(gaps: impl Iterator<Item = f64>, current: usize, tolerance: f64) -> usize {
    // One sweep: each gap (in 3D two dot products of 12 entries) made once.
    let (mut best, mut widest, mut at_current) = (current, f64::NEG_INFINITY, None);
    for (i, g) in gaps.enumerate() {
        if g > widest {
            (best, widest) = (i, g);
        }
        if i == current {
            at_current = Some(g);
        }
    }
    match at_current {
        Some(g) if widest - g <= tolerance => current,
        _ => best,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contacts::Entrance;

    /// A contact between blocks 0 and 1 with entrances of these gaps, rows
    /// of every sign (so the zero motion's products are +0 and −0).
    fn contact(gaps: &[f64]) -> Contact<3, 1> {
        let row = |k: f64| BlockVector::<3>::new(k, -2.0 * k, 0.5);
        Contact::between_first_two(
            (gaps.iter().enumerate())
                .map(|(i, &gap)| Entrance {
                    gap,
                    normal: [row(i as f64 + 1.0), row(-3.0)],
                    tangents: [[row(2.0), row(-1.0)]],
                })
                .collect(),
        )
    }

    /// Before the blocks move the choice reads the gaps alone, and it is
    /// the choice made at a zero displacement: the widest, unless the
    /// current one is within the tolerance of it; ties keep the first.
    #[test]
    fn the_entrance_chosen_at_rest_is_the_one_chosen_at_zero_motion() {
        let zero = vec![0.0; 6];
        let cases: [(&[f64], usize, usize); 7] = [
            (&[-1e-3, 2e-3, 1e-3], 0, 1),
            (&[-1e-3, 2e-3, 1e-3], 2, 2),
            (&[-1e-3, 2e-3, 1.5e-3], 2, 2),
            (&[-0.0, 0.0, -0.0], 2, 2),
            (&[-0.0, 0.0, -0.0], 5, 0),
            (&[4e-3, 4e-3], 1, 1),
            (&[-5e-3, -4e-3, -6e-3], 2, 1),
        ];
        for (gaps, current, chosen) in cases {
            let c = contact(gaps);
            let tolerance = 1e-3;
            assert_eq!(
                widest_at_rest(&c, current, tolerance),
                chosen,
                "{gaps:?} from {current}"
            );
            assert_eq!(
                widest_entrance(&c, &zero, current, tolerance),
                chosen,
                "{gaps:?} from {current}"
            );
        }
    }
}
