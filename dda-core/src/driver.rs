//! The Newmark (β = 1/2, γ = 1) time stepper with open-close iterations.
//!
//! One step: search contacts, then repeat open-close passes until no contact
//! changes state; each pass solves the step's equations by Newton-Raphson on
//! the residual with the contact states held fixed. A step that does not
//! settle within the open-close limit is cut to a third, recursively down to a
//! floor; a step that moves a point too far is cut; a step that penetrates too
//! deep raises the penalty. Nothing is changed until the step is accepted.

use std::time::Instant;

use nalgebra::{DMatrix, DVector, SVector};
use rayon::prelude::*;

use crate::assembly::{add_outer_into, BlockSparse};
use crate::contact::{ContactState, DynContactLaw};
use crate::contacts::{transfer_records, BlockVector, Contact, ContactKey, Entrance};
use crate::error::DdaError;
use crate::loads::Support;
use crate::settings::{Integrator, Settings};
use crate::solve::{solver_for, LinearSolver};
use crate::statistics::CYCLES_KEPT;
pub use crate::statistics::{Cycle, PhaseTimes, Statistics};
use crate::system::{BlockMatrix, BlockSystem};
use anderson::Anderson;
use predict::RecentSteps;
use terms::{ContactLoad, ContactTerms, Decision, Kept};
use touching::Touching;

mod anderson;
mod checkpoint;
mod explicit;
mod gmres;
mod impact;
mod predict;
mod terms;
mod touching;

/// The automatic step's ceiling is sqrt(block size / g) over this: a block
/// starting from rest moves 1/800 of its size in such a step.
const AUTO_STEPS_PER_MOTION_TIME: f64 = 20.0;

/// The automatic step keeps each block's points moving at most this share
/// of the median block size in a step: a rocking column's rebounds then stay
/// within about 1 % of Housner's, while a wall at rest steps at the ceiling.
const AUTO_MOTION_SHARE: f64 = 2.5e-4;

/// The automatic step never falls below this share of its ceiling.
const AUTO_FLOOR: f64 = 1e-4;

/// Couplings (sliding contacts) up to this many are applied by the
/// Sherman-Morrison-Woodbury formula, one back-substitution each; more, by
/// GMRES on the symmetric factor (`driver/gmres.rs`), one a product.
const SMW_COUPLINGS: usize = 64;

/// A step's first pass starts on the last step's factor where its matrix
/// changed by at most this share of its largest value. A rigid wall's
/// matrix changes by a spring or two a step (1.5e-4 of its largest value
/// on the 20 × 20 wall at its automatic step): a change of low rank, which
/// the mixed moves on the old factor remove, where a new factor of the
/// step's start served no better (at 1e-4 that wall factorised 95 times in
/// its first simulated second, with 345 moves; at 1e-3, 8 times with 284).
/// Where the old factor falls short, `STALE_FACTOR_MOVES` gives it up. A
/// large factor has its own limit, `LARGE_FACTOR_DRIFT`.
const FACTOR_DRIFT: f64 = 1e-3;

/// A step's first pass that started on an earlier step's factor and needed
/// more moves than this without a new one gives that factor up: the next
/// step factorises afresh. A change spread over the whole matrix (a
/// deformable wall's stresses as it settles) leaves the old factor a slow
/// one: kept for every later step, it cost the 20 × 20 deformable wall
/// 242 moves instead of 127 over its first 0.3 s.
const STALE_FACTOR_MOVES: usize = 5;

/// `FACTOR_DRIFT` for a factor of `LARGE_FACTOR_ENTRIES` or more, which
/// costs eight to ten moves and is kept through slower ones: there a
/// looser limit only kept slow factors longer (the 40 × 40 deformable
/// wall's simulated second: 510 moves and 20 factorisations at 1e-4, 790
/// and 24 at 1e-3), so such factors keep the limit they had, and are not
/// given up after `STALE_FACTOR_MOVES` (the 10,051-block walls take seven
/// moves a step on the last step's factor; giving it up after five made
/// the rigid one's step 95 → 165 ms).
const LARGE_FACTOR_DRIFT: f64 = 1e-4;

/// ... and by more than this: a matrix that changed only by round-off (a
/// free block's, turning) is factorised again, so its linear step is
/// solved to round-off as before; on the old factor each step kept an
/// error of the change's size, and a cube spinning for 6,283 steps ended
/// 1.4e-12 off its spin.
const FACTOR_ROUND_OFF: f64 = 1e-12;

/// With more sliding contacts than `SMW_COUPLINGS`, moves on fresh factors
/// that raise the residual this many times in a row end the symmetric
/// iteration, and the whole tangent takes over: there the symmetric one
/// climbs on to the iteration limit (a wall at a fine contact tolerance
/// spent 25 iterations and factorisations on each such pass). With fewer,
/// it runs to the limit, since its best iterate starts the whole-tangent
/// iteration, which on a wedge at its friction limit failed from an
/// earlier one.
const RISES_BEFORE_WHOLE_TANGENT: usize = 3;

/// The least reach of the matrix pattern, as a share of the median block
/// size: open contacts this near enter the pattern whatever the motion.
const PATTERN_REACH_SHARE: f64 = 0.05;

/// How many times the last step's largest displacement an open contact's
/// gap may be and still enter the pattern (both blocks may move toward each
/// other, and the next step may be faster).
const PATTERN_REACH_MOTION: f64 = 4.0;

/// The least displacement bound of a step, as a share of the median block
/// size, when Shi's g2·w0 (a share of the whole model) is larger: the
/// search range follows the blocks and their motion, not the model's
/// extent. Default 0.1: still 400 times what a block moves in an automatic
/// step. A quarter, as it was, put every feature of two neighbouring
/// bricks within range of the other's, so no test of the narrow phase
/// rejected early (at 10,051 3D blocks the narrow phase took a median 306
/// ms a step, against 219 at a tenth, finding the same contacts).
pub const BOUND_BLOCK_SHARE: f64 = 0.1;

/// The most halvings of a coupled Newton-Raphson step.
const LINE_SEARCH_HALVINGS: usize = 12;

/// Forces below this share of a contact's normal spring force at the
/// contact tolerance are round-off: a contact whose friction and shear
/// force both lie below it keeps its state between locked and sliding.
const ROUND_OFF_FORCE: f64 = 1e-9;

/// Block pairs a narrow-phase task takes at least: fewer would cost more
/// in scheduling than they save.
const PAIRS_PER_TASK: usize = 64;

/// Contacts an assembly task takes at least, for the same reason.
const CONTACTS_PER_TASK: usize = 256;

/// Blocks a residual-gathering task takes at least, for the same reason.
const BLOCKS_PER_TASK: usize = 128;

/// The largest share of the last residual that a Newton-Raphson move made
/// with an earlier iterate's factor may leave for the factor to be kept: a
/// factor costs several residual assemblies and solves, and between the
/// iterates of one pass the tangent changes only where a contact reaches
/// its strength. 0.3 kept one factor a pass on the 40 × 40 wall (0.1 took
/// two).
const KEPT_FACTOR_CONTRACTION: f64 = 0.3;

/// The same share for a factor of at least `LARGE_FACTOR_ENTRIES` entries,
/// which costs eight to ten moves (12 ms against 1.5 on the 40 × 40
/// deformable wall, 155 against 20 at 100 × 100): a kept factor that
/// contracts by 0.6 a move converges in fewer moves than that would buy.
/// Over the first ten steps at dt 1 ms, the 100 × 100 deformable wall
/// went from 0.8 factorisations and 6.9 moves a step to none and 7.8.
const KEPT_LARGE_FACTOR_CONTRACTION: f64 = 0.6;

/// Factor entries from which `KEPT_LARGE_FACTOR_CONTRACTION` applies: the
/// 40 × 40 deformable wall (1.3 million) and larger. Below it (the 40 × 40
/// rigid wall, 0.25 million) a factorisation costs two or three moves.
const LARGE_FACTOR_ENTRIES: usize = 1 << 20;

/// How a sliding contact's friction force changes with its normal gap:
/// the tangent gains `slope`·u·vᵀ, u the friction's rows along the slip
/// direction, v the gap's rows, on blocks `blocks`.
struct FrictionCoupling<const N: usize> {
    blocks: [usize; 2],
    u: [BlockVector<N>; 2],
    v: [BlockVector<N>; 2],
    slope: f64,
}

/// The trial solution of one step attempt.
struct Trial<const T: usize> {
    d: Vec<f64>,
    states: Vec<ContactState>,
    entrances: Vec<usize>,
    directions: Vec<SVector<f64, T>>,
    converged: bool,
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
    /// Contacts started in their foreseen state, until a pass turns one
    /// back.
    foreseen: Vec<usize>,
}

/// What [`Driver::load`] assembles.
#[derive(Clone, Copy)]
enum Motion<'a> {
    /// An implicit step's residual and its tangent matrix.
    Tangent,
    /// An implicit step's residual alone (the factor is kept).
    Implicit,
    /// An explicit step's forces, its dashpots on the displacement its
    /// start velocities make in dt.
    Explicit(&'a [f64]),
}

/// Runs a [`BlockSystem`] in time.
pub struct Driver<S, const N: usize, const T: usize> {
    pub system: S,
    laws: Vec<Box<dyn DynContactLaw>>,
    contacts: Vec<Contact<N, T>>,
    velocity: Vec<BlockVector<N>>,
    settings: Settings,
    solver: Box<dyn LinearSolver>,
    matrix: BlockSparse<N>,
    values: Vec<f64>,
    factored: Option<Vec<f64>>,
    /// Whether the solver holds the symbolic analysis of the matrix pattern.
    analysed: bool,
    /// Each contact's load at the last assembly (kept for its storage).
    contact_loads: Vec<Option<ContactLoad<N, T>>>,
    /// Each contact's open-close decision and what it keeps of an accepted
    /// step (kept for their storage).
    decisions: Vec<Decision<T>>,
    kept: Vec<Kept<T>>,
    /// Each contact's entrance in the current pass, side by side: a pass's
    /// iterations read them in order instead of through each contact.
    active: Vec<Entrance<N, T>>,
    /// The contacts of each block in the current pass, in contact order:
    /// a residual is gathered block by block, in parallel, adding each
    /// block's contact forces in the order one thread would.
    touching: Touching,
    /// Where each contact's block pair sits in the matrix pattern (`None`:
    /// not in it, so the contact must stay open).
    slots: Vec<Option<usize>>,
    /// Assemble contact by contact on one thread even within a pass (for
    /// tests: the two ways agree to the last bit).
    one_thread_assembly: bool,
    /// How near an open contact's blocks must be for their pair to enter
    /// the pattern: the reach of the last step's motion, at least
    /// `PATTERN_REACH_SHARE` of the median block size (m).
    pattern_reach: f64,
    /// The largest point displacement of the last accepted step (m).
    last_moved: f64,
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
    /// What rounding left out of `time` (a compensated sum, so thousands of
    /// steps of 0.001 s add up to 2 s, not 1.9999999999998905).
    time_carry: f64,
    dt: f64,
    dt_next: f64,
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
                    "time step automatic, at most {cap:.4e} s (1/{AUTO_STEPS_PER_MOTION_TIME} of sqrt(block size / g)): each step as long as keeps every block's points moving less than {AUTO_MOTION_SHARE:e} of the median block size; give dt to fix it"
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
            notes.push(
                "contact damping is off (Shi's undamped penalty springs): a block landing on, or released onto, its contacts bounces on them, and near its friction limit (a factor of safety below about 1.1) the bounces can start a slide of millimetres to metres; analysis.contact_damping: 1.0 ends impacts and holds such blocks (docs/limits.md)".into(),
            );
        }
        let dofs = (0..blocks).map(|i| system.dofs(i)).collect();
        let block_size = system.block_size();
        let solver = solver_for(settings.solver);
        Ok(Self {
            velocity: vec![BlockVector::<N>::zeros(); blocks],
            matrix: BlockSparse::new(dofs, []),
            system,
            laws,
            contacts: Vec::new(),
            settings,
            solver,
            values: Vec::new(),
            factored: None,
            analysed: false,
            contact_loads: Vec::new(),
            active: Vec::new(),
            touching: Touching::default(),
            decisions: Vec::new(),
            kept: Vec::new(),
            slots: Vec::new(),
            one_thread_assembly: false,
            pattern_reach: PATTERN_REACH_SHARE * block_size,
            last_moved: 0.0,
            block_size,
            inverse_masses: Vec::new(),
            supports: Vec::new(),
            struck: Vec::new(),
            struck_early: Vec::new(),
            striking: Vec::new(),
            sliding_impact: Vec::new(),
            time: 0.0,
            time_carry: 0.0,
            dt,
            dt_next: dt,
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
        }
        .explained())
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
    pub fn contacts(&self) -> &[Contact<N, T>] {
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
            self.step(time - self.time)?;
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
        // wall's step. Inside the pool, `scope` runs it in place.
        let result = rayon::scope(|_| self.try_step(dt_limit));
        self.stats.wall_time += started.elapsed();
        result
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
            if !trial.converged && dt / 3.0 >= floor {
                dt /= 3.0;
                cut = true;
                self.stats.open_close_cuts += 1;
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
        let committing = Instant::now();
        self.commit(trial, dt);
        self.stats.times.commit += committing.elapsed();
        self.last_moved = moved_by;
        self.pattern_reach =
            (PATTERN_REACH_MOTION * moved_by).max(PATTERN_REACH_SHARE * self.block_size);
        if let Some(cap) = self.dt_cap {
            // The automatic step: as long as keeps the motion per step
            // within its share of the block size, never above the ceiling.
            let target = AUTO_MOTION_SHARE * self.block_size;
            let allowed = if moved_by > 0.0 {
                dt * target / moved_by
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

    /// Finds the contacts within `range` (broad and narrow phase) and moves
    /// the last step's records onto them.
    fn search(&mut self, range: f64) {
        let started = Instant::now();
        let pairs = self.system.near_pairs(range);
        let searched = Instant::now();
        self.stats.times.broad_phase += searched - started;
        // Each pair's contacts on any thread, gathered in pair order.
        let system = &self.system;
        let mut fresh: Vec<Contact<N, T>> = pairs
            .par_iter()
            .with_min_len(PAIRS_PER_TASK)
            .flat_map_iter(|&(i, j)| system.pair_contacts(i, j, range))
            .collect();
        transfer_records(&mut self.contacts, &mut fresh);
        let at_start = self.stats.steps == 0;
        let touching = self.settings.contact_tolerance * self.length_scale;
        for c in &mut fresh {
            if c.record.history.is_none() {
                c.record.history = Some(self.laws[c.law].initial_history(at_start));
                // Joints closed in the initial geometry start locked, so
                // their bonds hold from the first step.
                if at_start && c.entrances.iter().all(|e| e.gap <= touching) {
                    c.record.state = ContactState::Locked;
                }
            }
        }
        // Freeing the last step's contacts (a heap block or two each: 4.6
        // ms at ten thousand blocks) is left to a thread that would idle.
        let last = std::mem::replace(&mut self.contacts, fresh);
        rayon::spawn(move || drop(last));
        self.stats.times.narrow_phase += searched.elapsed();
    }

    /// How far a point may move in a step (m); the contact search reaches
    /// 2.5 times as far, so no contact the step can close is missed. Shi's
    /// g2·w0, but in a model many blocks wide no more than a tenth of the
    /// median block size ([`BOUND_BLOCK_SHARE`]) or twice the last step's
    /// motion, whichever is larger: a step that moves farther is cut like
    /// one beyond g2·w0.
    fn displacement_bound(&self) -> f64 {
        let shi = self.settings.max_displacement_ratio * self.length_scale;
        shi.min((BOUND_BLOCK_SHARE * self.block_size).max(2.0 * self.last_moved))
    }

    /// Keeps the matrix pattern to the block pairs whose contacts can close
    /// in the step: closed ones, and open ones within the pattern's reach.
    /// The pattern changes (and the solver analyses it again) only when a
    /// pair within reach is missing, or when more than an eighth of its
    /// pairs have moved beyond twice the reach, so a standing wall keeps
    /// one analysis for thousands of steps.
    fn update_pattern(&mut self) {
        let reach = self.pattern_reach;
        self.find_slots();
        let mut missing = self.matrix.block_count() == 0;
        let mut held = vec![false; self.matrix.pairs().len()];
        for (c, slot) in self.contacts.iter().zip(&self.slots) {
            let (wanted, kept) = pattern_wants(c, reach);
            match slot {
                None => missing |= wanted,
                Some(s) => held[*s] |= kept,
            }
        }
        let stale = held.iter().filter(|h| !**h).count();
        if missing || 8 * stale > held.len() {
            let kept: Vec<(usize, usize)> = self
                .contacts
                .iter()
                .filter(|c| pattern_wants(c, reach).1)
                .map(|c| (c.blocks[0], c.blocks[1]))
                .collect();
            self.rebuild_pattern(kept);
            self.find_slots();
        }
    }

    /// A new matrix pattern with these block pairs.
    fn rebuild_pattern(&mut self, pairs: Vec<(usize, usize)>) {
        let dofs = (0..self.system.block_count())
            .map(|i| self.system.dofs(i))
            .collect();
        self.matrix = BlockSparse::new(dofs, pairs);
        self.factored = None;
        self.analysed = false;
    }

    fn find_slots(&mut self) {
        self.slots.clear();
        let matrix = &self.matrix;
        self.slots.par_extend(
            (self.contacts.par_iter())
                .with_min_len(CONTACTS_PER_TASK)
                .map(|c| matrix.slot(c.blocks[0], c.blocks[1])),
        );
    }

    /// Adds to the pattern the pairs of closed contacts it misses (a contact
    /// that closed from beyond the pattern's reach in this step).
    fn cover_closed(&mut self, states: &[ContactState]) {
        let missing: Vec<(usize, usize)> = self
            .contacts
            .iter()
            .zip(states)
            .zip(&self.slots)
            .filter(|((_, s), slot)| s.is_closed() && slot.is_none())
            .map(|((c, _), _)| (c.blocks[0], c.blocks[1]))
            .collect();
        if missing.is_empty() {
            return;
        }
        let started = Instant::now();
        let mut pairs = self.matrix.pairs().to_vec();
        pairs.extend(missing);
        self.rebuild_pattern(pairs);
        self.find_slots();
        self.stats.times.pattern += started.elapsed();
    }

    /// Solves one step of length `dt` with open-close iterations.
    fn attempt(&mut self, dt: f64) -> Result<Trial<T>, DdaError> {
        let nb = self.system.block_count();
        self.striking.clear();
        self.sliding_impact.clear();
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
            self.system.supports(self.time, self.time + dt)
        } else {
            Vec::new()
        };
        self.foresee_states(&mut trial, dt);
        // The states two passes back: a pass that returns to them is a
        // cycle, which more passes would only repeat.
        let mut before: Option<Vec<ContactState>> = None;
        for _ in 0..self.settings.open_close_limit {
            self.stats.open_close_iterations += 1;
            let struck = self.striking.len();
            self.strike(dt, &masses, &trial);
            if self.striking.len() != struck {
                // A new impulse makes a new step: states seen before it
                // are no cycle.
                before = None;
            }
            self.newton(dt, &masses, &mut trial)?;
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
                            time: self.time + dt,
                            key: self.contacts[i].key,
                            between: [other, *state],
                            kept,
                        });
                    }
                    *state = kept;
                }
                self.stats.open_close_iterations += 1;
                self.stats.cycle_breaks += 1;
                self.strike(dt, &masses, &trial);
                self.newton(dt, &masses, &mut trial)?;
                trial.converged = true;
                break;
            }
            before = Some(assumed);
        }
        Ok(trial)
    }

    /// Starts each contact that the foreseen motion carries across its
    /// open-close tolerance closed or open as that motion leaves it (see
    /// `predict`). With restitution only openings are foreseen: a contact
    /// struck in an attempt stays struck, and a foreseen closing may not
    /// come.
    fn foresee_states(&mut self, trial: &mut Trial<T>, dt: f64) {
        let Some(foreseen) = self.recent.foresee(dt) else {
            return;
        };
        let deciding = Instant::now();
        let at_rest = std::mem::replace(&mut trial.d, foreseen);
        let decisions = self.decisions_at(trial, dt, &trial.d);
        trial.d = at_rest;
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
    }

    /// Every contact's decision at the trial, in the kept buffer (give it
    /// back to `self.decisions`). Each reads the trial and writes nothing:
    /// they are made in parallel and come in contact order.
    fn decisions_at(&mut self, trial: &Trial<T>, dt: f64, moving: &[f64]) -> Vec<Decision<T>> {
        let mut decisions = std::mem::take(&mut self.decisions);
        let terms = self.terms();
        (0..self.contacts.len())
            .into_par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(|i| terms.decision(i, trial, dt, moving))
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
        let decisions = self.decisions_at(trial, dt, moving);
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

    /// Newton-Raphson on the step's residual with the contact states fixed.
    ///
    /// The symmetric tangent leaves out how a sliding contact's friction
    /// grows with its normal force; where springs are stiff against the
    /// blocks' inertia (large steps, stiff penalties) that iteration does
    /// not converge, and the step is solved again from its best iterate
    /// with the whole tangent.
    fn newton(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &mut Trial<T>,
    ) -> Result<(), DdaError> {
        self.cover_closed(&trial.states);
        // The entrances stay put until the pass's decision: its iterations
        // read them side by side, not each through its contact (at ten
        // thousand blocks, that pointer chase was a third of an assembly).
        let copying = Instant::now();
        self.active.clear();
        self.active.par_extend(
            (self.contacts.par_iter())
                .zip(&trial.entrances)
                .with_min_len(CONTACTS_PER_TASK)
                .map(|(c, &e)| c.entrances[e].clone()),
        );
        self.touching
            .fill(self.system.block_count(), &self.contacts);
        self.stats.times.assembly += copying.elapsed();
        let solved = self.solve_pass(dt, masses, trial);
        self.active.clear();
        self.touching.clear();
        solved
    }

    /// The pass's iterations: on the symmetric tangent, then, if those do
    /// not converge and few contacts slide, on the whole one.
    fn solve_pass(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &mut Trial<T>,
    ) -> Result<(), DdaError> {
        let sliding = (trial.states.iter())
            .filter(|s| **s == ContactState::Sliding)
            .count();
        let hand_over = sliding > SMW_COUPLINGS;
        if self.iterate(dt, masses, trial, false, hand_over)? {
            return Ok(());
        }
        if sliding > 0 && self.iterate(dt, masses, trial, true, false)? {
            self.stats.coupled_solves += 1;
            return Ok(());
        }
        self.stats.newton_failures += 1;
        Ok(())
    }

    /// Newton-Raphson iterations from `trial.d`; with `coupled`, the
    /// tangent includes friction's dependence on the normal gap (a rank-one
    /// term per sliding contact, solved by the Sherman-Morrison-Woodbury
    /// formula on the symmetric factor). Returns whether it converged;
    /// otherwise `trial.d` is left at the iterate with the smallest
    /// residual (the first one is Shi's explicit-friction solution).
    fn iterate(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &mut Trial<T>,
        coupled: bool,
        hand_over: bool,
    ) -> Result<bool, DdaError> {
        let mut first = 0.0;
        let mut residual = vec![0.0; self.matrix.dim()];
        let mut couplings = Vec::new();
        let mut best = (f64::INFINITY, trial.d.clone());
        let mut anderson = Anderson::default();
        let mut last = f64::INFINITY;
        // Whether the pass has a factor to move on; whether the last move
        // was made with an earlier iterate's factor; and whether the pass
        // still keeps factors. A step's first pass starts on the last
        // step's factor while the pattern stands and its matrix has barely
        // changed (`factor_fits`): with the same springs it carries the
        // iteration, and the test of a kept factor below refreshes it where
        // it does not (a checkpoint keeps its values, so a resumed run
        // starts on the same one). A later pass starts on its
        // own: the springs that came or went drive its first residual, and
        // an earlier pass's factor left 98-107 % of it.
        let mut factored =
            !coupled && trial.load_scale == 0.0 && self.analysed && self.factored.is_some();
        let mut kept = false;
        let mut keeping = true;
        let (give_way, stale, drift) = if self.solver.factor_entries() >= LARGE_FACTOR_ENTRIES {
            (
                KEPT_LARGE_FACTOR_CONTRACTION,
                usize::MAX,
                LARGE_FACTOR_DRIFT,
            )
        } else {
            (KEPT_FACTOR_CONTRACTION, STALE_FACTOR_MOVES, FACTOR_DRIFT)
        };
        let mut rises = 0;
        let mut moves = 0;
        // Whether the pass runs on an earlier step's factor (until it
        // factorises anew).
        let mut carried = false;
        for iteration in 0..=self.settings.newton_limit {
            couplings.clear();
            // The tangent is assembled where a new factor is sure to be
            // needed, and at a pass's start to weigh the last step's factor
            // against it; elsewhere only if the kept one falls short.
            let tangent = coupled || !keeping || !factored || iteration == 0;
            self.assemble(
                dt,
                masses,
                trial,
                &mut residual,
                coupled.then_some(&mut couplings),
                tangent,
            );
            if iteration == 0 && factored {
                factored = self.factor_fits(drift);
                carried = factored;
            }
            if residual.iter().any(|v| !v.is_finite()) {
                return Err(DdaError::NotFinite {
                    time: self.time + dt,
                });
            }
            let norm = residual.iter().map(|r| r * r).sum::<f64>().sqrt();
            if iteration == 0 {
                // A later pass starts from the last one's solution, so its
                // residual is only what the changed states add: measured
                // against that alone, it would be solved to many more
                // digits than the step's first pass was.
                trial.load_scale = trial.load_scale.max(norm);
                first = trial.load_scale;
            }
            if norm < best.0 {
                best.0 = norm;
                best.1.clone_from(&trial.d);
            }
            let converged = iteration > 0 && norm <= self.settings.residual_tolerance * first;
            rises = if !kept && norm > last { rises + 1 } else { 0 };
            let diverging = !kept
                && (norm > 1e3 * best.0 || (hand_over && rises >= RISES_BEFORE_WHOLE_TANGENT));
            if converged || diverging || iteration == self.settings.newton_limit {
                if carried && moves > stale {
                    self.factored = None;
                }
                if !converged {
                    trial.d = best.1;
                }
                return Ok(converged);
            }
            // A kept factor that does not carry the iteration (a contact's
            // force reached or left its strength) gives way to this
            // iterate's own tangent, and so does every later one of the
            // pass: where the tangent changes from one iterate to the next,
            // moves on an old one only spend the iteration limit. A kept
            // factor's move that raised the residual is undone: the next
            // move is Newton's from the best iterate.
            if kept && norm > give_way * last {
                // An earlier step's factor is replaced once, by this
                // iterate's; the pass's own falls short only where the
                // tangent changes from one iterate to the next.
                if carried {
                    factored = false;
                } else {
                    keeping = false;
                }
                if norm > last {
                    trial.d.clone_from(&best.1);
                    kept = false;
                    last = best.0;
                    anderson.restart();
                    continue;
                }
            }
            let refresh = coupled || !keeping || !factored;
            if norm > last || (kept && refresh) {
                // A mixed move that did not lower the residual (a contact
                // crossed its strength), or a new factor: mix again from
                // here.
                anderson.restart();
            }
            last = norm;
            self.stats.newton_iterations += 1;
            if refresh {
                if !tangent {
                    self.assemble(dt, masses, trial, &mut residual, None, true);
                }
                self.factorize()?;
                carried = false;
                factored = true;
            }
            kept = !refresh;
            let solving = Instant::now();
            // A pass's first move is solved exactly: where the equations
            // are linear it is the answer. Later ones correct an iterate of
            // a tangent that is itself approximate (explicit friction, a
            // kept factor), so single precision costs them nothing.
            if coupled || moves == 0 {
                self.solver.solve(&mut residual);
            } else {
                self.solver.solve_correction(&mut residual);
            }
            moves += 1;
            if !couplings.is_empty() {
                self.correct(&couplings, &mut residual);
            }
            self.stats.times.solve += solving.elapsed();
            self.stats.count_solves(self.solver.take_counts());
            // Convergence is read off the Newton move itself: a mixed or
            // shortened move can be tiny where the residual is not.
            let newton_move = residual.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
            if !coupled {
                anderson.mix(&mut residual);
            }
            if !couplings.is_empty() {
                // The friction's direction turns fast with the stretch, so
                // a full step can overshoot: halve it until the residual
                // falls (the exact tangent makes the step a descent one).
                let step = std::mem::take(&mut residual);
                let start = trial.d.clone();
                let mut scale = 1.0;
                let mut probe = vec![0.0; step.len()];
                for _ in 0..LINE_SEARCH_HALVINGS {
                    for (i, (d, d0)) in trial
                        .d
                        .chunks_exact_mut(N)
                        .zip(start.chunks_exact(N))
                        .enumerate()
                    {
                        let dd = self.matrix.block(&step, i);
                        for ((d, d0), dd) in d.iter_mut().zip(d0).zip(dd.iter()) {
                            *d = d0 + scale * dd;
                        }
                    }
                    self.assemble(dt, masses, trial, &mut probe, None, false);
                    let trial_norm = probe.iter().map(|r| r * r).sum::<f64>().sqrt();
                    if trial_norm < (1.0 - 1e-4 * scale) * norm {
                        break;
                    }
                    scale *= 0.5;
                }
                trial.d = start;
                residual = step.iter().map(|dd| dd * scale).collect();
            }
            let mut largest: f64 = 0.0;
            for (i, d) in trial.d.chunks_exact_mut(N).enumerate() {
                for (d, dd) in d.iter_mut().zip(self.matrix.block(&residual, i).iter()) {
                    *d += dd;
                    largest = largest.max(dd.abs());
                }
            }
            if !largest.is_finite() {
                return Err(DdaError::NotFinite {
                    time: self.time + dt,
                });
            }
            // A kept factor stiffer than the tangent makes short moves
            // that are no sign of convergence.
            if !kept && newton_move <= self.settings.increment_tolerance * self.length_scale {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Turns `y = K⁻¹r` (K the symmetric tangent) into the solution with
    /// K + Σ sⱼ uⱼvⱼᵀ: x = y − Z (I + S VᵀZ)⁻¹ S Vᵀy, with Z = K⁻¹U; beyond
    /// `SMW_COUPLINGS` couplings, by GMRES on x + K⁻¹U S Vᵀx = y.
    fn correct(&self, couplings: &[FrictionCoupling<N>], y: &mut [f64]) {
        let m = couplings.len();
        let size = y.len();
        let dot = |c: &FrictionCoupling<N>, x: &[f64]| {
            c.v[0].dot(&self.matrix.block(x, c.blocks[0]))
                + c.v[1].dot(&self.matrix.block(x, c.blocks[1]))
        };
        if m > SMW_COUPLINGS {
            // x + K⁻¹Σ sⱼuⱼ(vⱼᵀx) = y, from x = y.
            let apply = |v: &[f64], out: &mut [f64]| {
                out.iter_mut().for_each(|o| *o = 0.0);
                for c in couplings {
                    let w = c.slope * dot(c, v);
                    self.matrix.add_block(out, c.blocks[0], &(c.u[0] * w));
                    self.matrix.add_block(out, c.blocks[1], &(c.u[1] * w));
                }
                self.solver.solve(out);
                for (o, v) in out.iter_mut().zip(v) {
                    *o += v;
                }
            };
            let rhs = y.to_vec();
            gmres::gmres(apply, &rhs, y, 1e-6, 60);
            return;
        }
        let z: Vec<Vec<f64>> = couplings
            .iter()
            .map(|c| {
                let mut u = vec![0.0; size];
                self.matrix.add_block(&mut u, c.blocks[0], &c.u[0]);
                self.matrix.add_block(&mut u, c.blocks[1], &c.u[1]);
                self.solver.solve(&mut u);
                u
            })
            .collect();
        let system = DMatrix::from_fn(m, m, |i, j| {
            let identity = if i == j { 1.0 } else { 0.0 };
            identity + couplings[i].slope * dot(&couplings[i], &z[j])
        });
        let rhs = DVector::from_fn(m, |i, _| couplings[i].slope * dot(&couplings[i], y));
        let Some(c) = system.lu().solve(&rhs) else {
            return;
        };
        for (zj, cj) in z.iter().zip(c.iter()) {
            for (yi, zi) in y.iter_mut().zip(zj) {
                *yi -= cj * zi;
            }
        }
    }

    /// Whether the step may start on the last factor: its matrix changed
    /// (largest change against largest value) by more than round-off and
    /// at most `drift` (`FACTOR_DRIFT`, or `LARGE_FACTOR_DRIFT` for a large
    /// factor) from the one just assembled.
    fn factor_fits(&mut self, drift: f64) -> bool {
        self.matrix.values_into(&mut self.values);
        let Some(old) = &self.factored else {
            return false;
        };
        let scale = old.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let change = (old.iter().zip(&self.values)).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        change > FACTOR_ROUND_OFF * scale && change <= drift * scale
    }

    /// Factorizes the assembled matrix unless its values are unchanged.
    fn factorize(&mut self) -> Result<(), DdaError> {
        self.matrix.values_into(&mut self.values);
        if self.values.iter().any(|v| !v.is_finite()) {
            return Err(DdaError::NotFinite { time: self.time });
        }
        if !self.analysed {
            let started = Instant::now();
            self.solver.analyse(&self.matrix.pattern())?;
            self.analysed = true;
            self.factored = None;
            self.stats.symbolic_analyses += 1;
            self.stats.times.symbolic += started.elapsed();
        }
        if self.factored.as_ref() != Some(&self.values) {
            let started = Instant::now();
            self.solver.factorize(&self.values)?;
            self.stats.times.numeric += started.elapsed();
            self.stats.factorizations += 1;
            // The factored values swap places with the buffer the next
            // assembly fills: no copy, no allocation.
            let spare = self.factored.take().unwrap_or_default();
            self.factored = Some(std::mem::replace(&mut self.values, spare));
        }
        Ok(())
    }

    /// Fills `residual` with applied minus internal forces at the trial
    /// displacement and, with `tangent`, the matrix with the tangent.
    fn assemble(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &Trial<T>,
        residual: &mut [f64],
        couplings: Option<&mut Vec<FrictionCoupling<N>>>,
        tangent: bool,
    ) {
        let motion = if tangent {
            Motion::Tangent
        } else {
            Motion::Implicit
        };
        self.load(dt, masses, trial, residual, couplings, motion);
    }

    /// [`Driver::assemble`]; or, for [`Motion::Explicit`], the forces alone
    /// at the trial: no inertia, no matrix, dashpots on the start
    /// velocities.
    fn load(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &Trial<T>,
        residual: &mut [f64],
        mut couplings: Option<&mut Vec<FrictionCoupling<N>>>,
        motion: Motion<'_>,
    ) {
        let started = Instant::now();
        let (implicit, tangent, approach) = match motion {
            Motion::Tangent => (true, true, None),
            Motion::Implicit => (true, false, None),
            Motion::Explicit(approach) => (false, false, Some(approach)),
        };
        // Where the dashpots read the blocks' motion in the step.
        let moving = approach.unwrap_or(&trial.d);
        let mut matrix = std::mem::take(&mut self.matrix);
        if tangent {
            matrix.clear();
        }
        residual.fill(0.0);
        let end = self.time + dt;
        let ratio = self.settings.velocity_ratio;
        let alpha = self.settings.mass_damping;
        let (system, velocity, struck_early) = (&self.system, &self.velocity, &self.struck_early);
        let own_terms = |i: usize, m: &BlockMatrix<N>| {
            let d = block(&trial.d, i);
            let (mut k, mut r) = if implicit {
                let v0 = velocity[i] * ratio + struck_early[i];
                // Inertia of Newmark β = 1/2, γ = 1: a = 2(d − v0·dt)/dt²,
                // and mass-proportional damping −αM·v with v = 2d/dt − v0.
                (
                    m * (2.0 / (dt * dt) + 2.0 * alpha / dt),
                    m * (v0 * (2.0 / dt + alpha) - d * (2.0 / (dt * dt) + 2.0 * alpha / dt)),
                )
            } else {
                (BlockMatrix::<N>::zeros(), BlockVector::<N>::zeros())
            };
            system.block_terms(i, end, &d, &mut k, &mut r);
            (k, r)
        };
        // With the contacts of each block at hand (within a pass), the
        // residual and the matrix are gathered block by block (and the
        // matrix's off-diagonal blocks pair by pair) on every core; each
        // sum is made in the same order as below, so the two agree to the
        // last bit.
        let gather = couplings.is_none() && self.touching.is_filled() && !self.one_thread_assembly;
        if gather {
            let parts = matrix.split_blocks(residual);
            let (diagonal, _, _) = matrix.blocks_mut();
            (diagonal.par_iter_mut().zip(parts))
                .with_min_len(BLOCKS_PER_TASK)
                .enumerate()
                .for_each(|(i, (diagonal, part))| {
                    let (k, r) = own_terms(i, &masses[i]);
                    if tangent {
                        *diagonal += k;
                    }
                    part.iter_mut().zip(r.iter()).for_each(|(x, r)| *x += r);
                });
        } else {
            for (i, m) in masses.iter().enumerate() {
                let (k, r) = own_terms(i, m);
                if tangent {
                    matrix.add(i, i, &k);
                }
                matrix.add_block(residual, i, &r);
            }
        }
        for support in &self.supports {
            // A dashpot beside each fixed point's spring, as beside a
            // contact's: a supporting block does not ring on its springs.
            let (i, g) = (support.block, &support.row);
            let zero = BlockVector::<N>::zeros();
            let c = self.terms().dashpot(i, i, &[*g, zero], support.stiffness);
            let moved = g.dot(&block(moving, i)) - support.target_step;
            if tangent {
                matrix.add(i, i, &(g * g.transpose() * (c / dt)));
            }
            matrix.add_block(residual, i, &(g * (-c * moved / dt)));
        }
        let couple = couplings.is_some();
        let mut loads = std::mem::take(&mut self.contact_loads);
        let terms = self.terms();
        (0..self.contacts.len())
            .into_par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(|i| terms.load(i, trial, dt, moving, couple))
            .collect_into_vec(&mut loads);
        if gather {
            let (contacts, touching, active) = (&self.contacts, &self.touching, &self.active);
            let entrance = |i: usize| match active.get(i) {
                Some(entrance) => entrance,
                None => &contacts[i].entrances[trial.entrances[i]],
            };
            let (pairs, of_pair) = if tangent {
                contacts_by_slot(&loads, &self.slots, matrix.pairs().len())
            } else {
                (Vec::new(), Vec::new())
            };
            let parts = matrix.split_blocks(residual);
            let (diagonal, lower, dofs) = matrix.blocks_mut();
            (diagonal.par_iter_mut().zip(parts))
                .with_min_len(BLOCKS_PER_TASK)
                .enumerate()
                .for_each(|(x, (diagonal, part))| {
                    for &i in touching.of(x) {
                        if let Some(load) = &loads[i] {
                            let side = usize::from(contacts[i].blocks[0] != x);
                            if tangent {
                                let n = dofs[x];
                                spring_terms(load, entrance(i), |g, h, k| {
                                    add_outer_into(diagonal, (n, n), &g[side], &h[side], k, false);
                                });
                            }
                            let force = &load.force[side];
                            part.iter_mut().zip(force.iter()).for_each(|(p, f)| *p += f);
                        }
                    }
                });
            if tangent {
                (lower.par_iter_mut())
                    .with_min_len(BLOCKS_PER_TASK)
                    .enumerate()
                    .for_each(|(s, block)| {
                        for &i in &of_pair[pairs[s]..pairs[s + 1]] {
                            let load = loads[i].as_ref().expect("listed with a load");
                            let [a, b] = contacts[i].blocks;
                            spring_terms(load, entrance(i), |g, h, k| {
                                add_outer_into(block, (dofs[a], dofs[b]), &g[0], &h[1], k, a < b);
                            });
                        }
                    });
            }
            self.contact_loads = loads;
            self.matrix = matrix;
            self.stats.times.assembly += started.elapsed();
            return;
        }
        for (i, load) in loads.iter().enumerate() {
            let Some(load) = load else {
                continue;
            };
            let c = &self.contacts[i];
            let [a, b] = c.blocks;
            let entrance = match self.active.get(i) {
                Some(entrance) => entrance,
                None => &c.entrances[trial.entrances[i]],
            };
            let [na, nb] = &entrance.normal;
            if tangent {
                let slot = self.slots[i].expect("closed contacts are in the pattern");
                spring_terms(load, entrance, |g, h, k| {
                    add_coupling(&mut matrix, slot, a, b, (&g[0], &g[1]), (&h[0], &h[1]), k);
                });
            }
            if let (Some(couplings), true) = (couplings.as_deref_mut(), load.slope != 0.0) {
                let mut u = [BlockVector::<N>::zeros(), BlockVector::<N>::zeros()];
                for (k, [ta, tb]) in entrance.tangents.iter().enumerate() {
                    u[0] += ta * load.direction[k];
                    u[1] += tb * load.direction[k];
                }
                couplings.push(FrictionCoupling {
                    blocks: [a, b],
                    u,
                    v: [*na, *nb],
                    slope: load.slope,
                });
            }
            matrix.add_block(residual, a, &load.force[0]);
            matrix.add_block(residual, b, &load.force[1]);
        }
        self.contact_loads = loads;
        self.matrix = matrix;
        self.stats.times.assembly += started.elapsed();
    }

    /// The step's contacts as one contact's terms read them.
    fn terms(&self) -> ContactTerms<'_, N, T> {
        ContactTerms {
            contacts: &self.contacts,
            laws: &self.laws,
            inverse_masses: &self.inverse_masses,
            striking: &self.striking,
            damping: self.settings.contact_damping,
            tolerance: self.settings.contact_tolerance * self.length_scale,
            penalty: self.penalty,
            active: &self.active,
        }
    }

    /// The deepest penetration of the closed contacts at the trial, and the
    /// deepest among those that started the step within the `limit`.
    fn penetration(&self, trial: &Trial<T>, limit: f64) -> (f64, f64, Option<ContactKey>) {
        // Each closed contact's entrance and gap on any thread; the deepest
        // is then found in contact order, as one thread would.
        let gaps: Vec<Option<(f64, f64)>> = (self.contacts.par_iter().enumerate())
            .with_min_len(CONTACTS_PER_TASK)
            .map(|(i, c)| {
                trial.states[i].is_closed().then(|| {
                    let e = &c.entrances[trial.entrances[i]];
                    let (da, db) = (block(&trial.d, c.blocks[0]), block(&trial.d, c.blocks[1]));
                    (e.gap, e.gap_at(&da, &db))
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

    fn commit(&mut self, trial: Trial<T>, dt: f64) {
        let spring_energy = self.commit_contacts(&trial, dt);
        self.stats.impacts += self.striking.len();
        let ratio = self.settings.velocity_ratio;
        for (i, v) in self.velocity.iter_mut().enumerate() {
            // Newmark β = 1/2, γ = 1: v1 = 2d/dt − v0.
            // An impulse a share τ into the step: the motion took v0 +
            // (1 − τ)Δv, the velocity leaves with v0 + Δv.
            *v = block(&trial.d, i) * (2.0 / dt) - *v * ratio - self.struck_early[i] * 2.0
                + self.struck[i];
        }
        self.recent.push(dt, &trial.d);
        self.finish_step(&trial.d, dt, spring_energy);
    }

    /// Moves the blocks by `d`, the time by `dt`, and checks the energy.
    fn finish_step(&mut self, d: &[f64], dt: f64, spring_energy: f64) {
        self.advance_time(dt);
        self.system.commit(&split::<N>(d), dt, self.time);
        self.stats.steps += 1;
        self.check_energy(spring_energy);
    }

    /// Each contact's state, record and law history at the accepted trial;
    /// returns the energy the springs store.
    fn commit_contacts(&mut self, trial: &Trial<T>, dt: f64) -> f64 {
        // What each contact keeps is worked out in parallel from the old
        // records, then written into them; the springs' energy is summed
        // in contact order, as one thread would.
        let mut kept = std::mem::take(&mut self.kept);
        let terms = self.terms();
        (0..self.contacts.len())
            .into_par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(|i| terms.kept(i, trial, dt))
            .collect_into_vec(&mut kept);
        let mut spring_energy = 0.0;
        for k in &kept {
            spring_energy += k.energy[0];
            spring_energy += k.energy[1];
        }
        let laws = &self.laws;
        self.contacts
            .par_iter_mut()
            .with_min_len(CONTACTS_PER_TASK)
            .zip(kept.par_iter())
            .for_each(|(c, k)| {
                let law = &laws[c.law];
                law.commit(
                    k.state,
                    &k.kin,
                    c.record.history.as_mut().expect("history set at search"),
                );
                let record = &mut c.record;
                record.state = k.state;
                record.entrance = k.entrance;
                record.shear = k.shear;
                record.slip_direction = k.direction;
                if k.state == ContactState::Sliding {
                    record.slip_path += k.slip;
                    record.slip_rate = k.slip / dt;
                } else {
                    record.slip_rate = 0.0;
                }
                record.normal_force = k.normal_force;
                record.shear_force = k.shear_force;
            });
        self.kept = kept;
        spring_energy
    }

    /// Total energy after a step, and whether it rose: with no loads or
    /// driven supports doing work, Newmark (β = 1/2, γ = 1) and friction
    /// only dissipate, so a rise means the method misbehaved.
    fn check_energy(&mut self, spring_energy: f64) {
        let Some(potential) = self.system.potential_energy() else {
            return;
        };
        let kinetic: f64 = self
            .velocity
            .iter()
            .enumerate()
            .map(|(i, v)| 0.5 * v.dot(&(self.system.mass(i) * v)))
            .sum();
        let total = kinetic + potential + spring_energy;
        let first_potential = *self.first_potential.get_or_insert(potential);
        let stats = &mut self.stats;
        stats.energy = total;
        // The energy in play: what moves, what the springs hold, and what
        // gravity has released so far.
        stats.energy_scale = stats
            .energy_scale
            .max(kinetic + spring_energy + (potential - first_potential).abs());
        let floor = *self.energy_floor.get_or_insert(total);
        let rise = total - floor;
        // Contacts changing state exchange small amounts of energy; a rise
        // beyond a quarter of the energy in play is the method misbehaving.
        if rise > 0.25 * stats.energy_scale {
            stats.energy_growth_steps += 1;
            stats.energy_growth = stats.energy_growth.max(rise);
        }
        self.energy_floor = Some(floor.min(total));
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

/// Energy of a linear spring carrying `force` with stiffness `k`.
fn stored(force: f64, k: f64) -> f64 {
    if k > 0.0 {
        0.5 * force * force / k
    } else {
        0.0
    }
}

/// The loaded contacts of each of `count` off-diagonal blocks (by their
/// `slots`), in contact order: where each block's contacts start in the
/// list, then the list.
fn contacts_by_slot<L>(
    loads: &[Option<L>],
    slots: &[Option<usize>],
    count: usize,
) -> (Vec<usize>, Vec<usize>) {
    let loaded = || (0..loads.len()).filter(|&i| loads[i].is_some());
    let slot = |i: usize| slots[i].expect("closed contacts are in the pattern");
    let mut starts = vec![0; count + 1];
    for i in loaded() {
        starts[slot(i) + 1] += 1;
    }
    for s in 1..starts.len() {
        starts[s] += starts[s - 1];
    }
    let mut at = starts.clone();
    let mut list = vec![0; starts[count]];
    for i in loaded() {
        list[at[slot(i)]] = i;
        at[slot(i)] += 1;
    }
    (starts, list)
}

/// A contact's springs as terms k·g·hᵀ over its two blocks' rows (g = [ga,
/// gb]), in the order the matrix adds them: the normal spring, each shear
/// spring, then the turning of a sliding contact's friction (3D). Terms of
/// no stiffness are left out.
fn spring_terms<const N: usize, const T: usize>(
    load: &ContactLoad<N, T>,
    entrance: &Entrance<N, T>,
    mut term: impl FnMut(&[BlockVector<N>; 2], &[BlockVector<N>; 2], f64),
) {
    let mut add = |g: &[BlockVector<N>; 2], h: &[BlockVector<N>; 2], k: f64| {
        if k != 0.0 {
            term(g, h, k);
        }
    };
    add(&entrance.normal, &entrance.normal, load.normal_stiffness);
    for (k, rows) in entrance.tangents.iter().enumerate() {
        add(rows, rows, load.shear_stiffness[k]);
    }
    if load.turning != 0.0 {
        let direction = &load.direction;
        for (k, gk) in entrance.tangents.iter().enumerate() {
            for (l, gl) in entrance.tangents.iter().enumerate() {
                let identity = if k == l { 1.0 } else { 0.0 };
                let projector = identity - direction[k] * direction[l];
                add(gk, gl, load.turning * projector);
            }
        }
    }
}

/// Adds k·g·hᵀ with g = (ga, gb) and h = (ha, hb); called for (g, h) and
/// (h, g) with the same k, the sum is symmetric.
fn add_coupling<const N: usize>(
    matrix: &mut BlockSparse<N>,
    slot: usize,
    a: usize,
    b: usize,
    (ga, gb): (&BlockVector<N>, &BlockVector<N>),
    (ha, hb): (&BlockVector<N>, &BlockVector<N>),
    k: f64,
) {
    if k == 0.0 {
        return;
    }
    matrix.add_outer(slot, a, a, ga, ha, k);
    matrix.add_outer(slot, b, b, gb, hb, k);
    matrix.add_outer(slot, a, b, ga, hb, k);
}

/// Whether a contact's block pair must be in the matrix pattern (closed,
/// or open within `reach`), and whether a pattern holding it may keep it
/// (closed, or open within twice the reach).
fn pattern_wants<const N: usize, const T: usize>(c: &Contact<N, T>, reach: f64) -> (bool, bool) {
    let closed = c.record.state.is_closed();
    // Shi's contact closes through its widest entrance, so it is as far
    // from closing as that entrance's gap.
    let gap = c
        .entrances
        .iter()
        .map(|e| e.gap)
        .fold(f64::NEG_INFINITY, f64::max);
    (closed || gap <= reach, closed || gap <= 2.0 * reach)
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
fn widest_entrance<const N: usize, const T: usize>(
    c: &Contact<N, T>,
    d: &[f64],
    current: usize,
    tolerance: f64,
) -> usize {
    let da = block::<N>(d, c.blocks[0]);
    let db = block::<N>(d, c.blocks[1]);
    widest_of(
        c.entrances.iter().map(|e| e.gap_at(&da, &db)),
        current,
        tolerance,
    )
}

/// [`widest_entrance`] before the blocks move, where each entrance's gap is
/// the one it starts with: the same choice, reading a 3D group's gaps
/// alone instead of its rows too (a step starts with every contact's
/// choice, at ten thousand 3D blocks some 200 MB of rows).
fn widest_at_rest<const N: usize, const T: usize>(
    c: &Contact<N, T>,
    current: usize,
    tolerance: f64,
) -> usize {
    widest_of(c.entrances.iter().map(|e| e.gap), current, tolerance)
}

/// The entrance of the largest of `gaps`, or `current` if within
/// `tolerance` of it.
fn widest_of(gaps: impl Iterator<Item = f64> + Clone, current: usize, tolerance: f64) -> usize {
    let (best, widest) =
        gaps.clone()
            .enumerate()
            .fold((current, f64::NEG_INFINITY), |acc, (i, g)| {
                if g > acc.1 {
                    (i, g)
                } else {
                    acc
                }
            });
    match gaps.clone().nth(current) {
        Some(g) if widest - g <= tolerance => current,
        _ => best,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
