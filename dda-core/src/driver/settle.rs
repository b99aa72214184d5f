//! Settling before the run: static steps that take no time bring the model
//! to rest under its loads where the run starts, as a structure stands under
//! its own weight before it is shaken. Without it, gravity comes on at once
//! at t = 0 and the model rings about its settlement (up to twice it) while
//! the run's own loads begin.
//!
//! A settling step starts at rest (velocity ratio 0) and is long against
//! every period of the blocks on their springs, so its inertia is round-off
//! beside the springs and it solves the static equations; the open-close
//! passes find the contacts' states as in any step, and the displacement
//! bound still cuts a step in which a block falls or slides far. With no
//! inertia such a step takes the block wherever that bound lets it, so a
//! settling that moves a block so far, or whose steps agree on no contact
//! states, gives up and is undone: the run starts from the model as it was.
//! One whose steps stall, moving nothing while their Newton iterations
//! stop out of balance, ends there: the model is at rest to within that.

use std::time::{Duration, Instant};

use super::predict::RecentSteps;
use super::{Driver, BOUND_BLOCK_SHARE};
use crate::error::DdaError;
use crate::settings::Integrator;
use crate::statistics::Statistics;
use crate::system::BlockSystem;

/// The length of a settling step, s (40.96): a wall of 0.25 m bricks rings
/// at some 10 ms, a 100 m block on soft joints at a second or two, so the
/// inertia term 2M/dt² is at least 1e-6 of the springs' in any model built
/// of rock or masonry.
pub const SETTLE_STEP: f64 = 40.96;

/// A settling step that moves no point more than this share of the
/// largest point displacement of the settling so far ends it (1e-3).
pub const SETTLED_SHARE: f64 = 1e-3;

/// A settling step ends it only where its last residual is at most this
/// share of the loads the model started out of balance by (1e-6; the
/// Newton iteration leaves 1e-8–1e-10). It tells a model at rest from one
/// whose contacts were accepted at a state within round-off of the last
/// pass's (a block just past its friction limit, whose last pass locked it
/// and whose step then barely moved).
pub const SETTLED_BALANCE: f64 = 1e-6;

/// A settling step whose Newton iterations failed, that moved no point
/// farther than the open-close tolerance and took less than this share
/// off its first residual has stalled (1e-3); two in a row end the
/// settling. Contacts held exactly at their friction strength with no
/// slip, their friction's direction set by round-off, stall a static
/// step's iterations (a tilted wall of deformable bricks at a factor of
/// safety of 3 stopped at 3.4e-4 of its loads, its steps moving nothing,
/// for all 20 of its steps), where a dynamic step's inertia carries them.
pub const STALLED_SHARE: f64 = 1e-3;

/// What a settling did.
#[derive(Debug, Clone, PartialEq)]
pub struct Settling {
    /// Settling steps taken (cut steps count once).
    pub steps: usize,
    /// The largest point displacement of any step, m.
    pub largest_step: f64,
    /// The largest point displacement of the last step, m.
    pub last_step: f64,
    /// The last step's residual against the loads the first step started
    /// out of balance by.
    pub balance: f64,
    /// Whether the last step was whole (neither cut nor unconverged, its
    /// Newton iterations all converged), moved no more than
    /// [`SETTLED_SHARE`] of `largest_step` (or the open-close tolerance)
    /// and ended in balance ([`SETTLED_BALANCE`]).
    pub settled: bool,
    /// Whether the settling, not settled, was undone: a step of it moved a
    /// block farther than a tenth of the median block size, as one falls,
    /// slides or topples, or it gave up after two steps in a row that did
    /// so or ended unconverged; the run starts from the model as it was.
    pub undone: bool,
    /// Whether, not settled, it stalled: two steps in a row whose Newton
    /// iterations failed moved nothing and barely cut their residual
    /// ([`STALLED_SHARE`]). The model is at rest to within `balance` of
    /// its loads; the run starts there and shows whether it stands.
    pub stalled: bool,
    /// The counters of its steps, which the run's own leave out.
    pub statistics: Statistics,
    pub wall_time: Duration,
}

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// The time at which a step of `dt` reads its loads and supports: its
    /// end, or the run's start while the model settles.
    pub(super) fn load_time(&self, dt: f64) -> f64 {
        if self.settling {
            self.time
        } else {
            self.time + dt
        }
    }

    /// Brings the model to rest under its loads at the present time, in at
    /// most `most_steps` static steps of [`SETTLE_STEP`] that take no time;
    /// the blocks then start the run at rest where the settling left them,
    /// with the contacts' states and springs it found. A settling that does
    /// not settle, having moved a block as one falls, slides or topples, is
    /// undone (`Settling::undone`): the run starts from the model as it
    /// was, at rest. It gives up after two such steps in a row, or two
    /// whose open-close passes did not agree, and is undone too. Two steps
    /// in a row that stall ([`STALLED_SHARE`]) end it where they are. The
    /// run's counters and energy check start after it. Implicit integrator
    /// only.
    pub fn settle(&mut self, most_steps: usize) -> Result<Settling, DdaError> {
        if self.settings.integrator == Integrator::Explicit {
            return Err(DdaError::Setting {
                field: "settle",
                message: "settling takes implicit steps; with the explicit integrator, relax the model to rest with local_damping: 0.8 in a run of its own".into(),
            });
        }
        let started = Instant::now();
        // Where a settling fails after moving a block as one falls, slides
        // or topples, the run starts from the model as it was: static
        // steps with no inertia take a model that cannot stand anywhere
        // the displacement bound lets them (a toppling brick 2.8 mm into
        // its neighbour), and from there the run failed at once where the
        // same model unsettled collapses as it should. One that barely
        // moved (a block just past its friction limit) starts where it
        // was left, its springs loaded, as a released block would.
        // (A block system that cannot be saved keeps its settling's end.)
        let unsettled = self.save().ok();
        let run_stats = std::mem::take(&mut self.stats);
        let kept = (
            self.settings.velocity_ratio,
            self.dt,
            self.dt_next,
            self.dt_cap,
        );
        self.settings.velocity_ratio = 0.0;
        self.dt = SETTLE_STEP;
        self.dt_cap = None;
        self.settling = true;
        let tolerance = self.settings.contact_tolerance * self.length_scale;
        let mut settling = Settling {
            steps: 0,
            largest_step: 0.0,
            last_step: 0.0,
            balance: f64::NAN,
            settled: false,
            undone: false,
            stalled: false,
            statistics: Statistics::default(),
            wall_time: Duration::ZERO,
        };
        let mut result = Ok(());
        let mut loads = 0.0;
        let falling = BOUND_BLOCK_SHARE * self.block_size;
        let mut fell = false;
        let mut gave_up = false;
        let mut stuck = false;
        let failed = |s: &Statistics| (s.cuts(), s.unconverged_steps, s.newton_failures);
        while settling.steps < most_steps.max(1) {
            self.dt_next = SETTLE_STEP;
            let before = failed(&self.stats);
            result = self.step(SETTLE_STEP);
            if result.is_err() {
                break;
            }
            settling.steps += 1;
            settling.last_step = self.last_moved;
            settling.largest_step = settling.largest_step.max(self.last_moved);
            let (start, end) = self.residuals;
            if settling.steps == 1 {
                loads = start;
            }
            // With no loads at all nothing is out of balance (and 0/0
            // would write null into summary.json).
            settling.balance = if loads > 0.0 { end / loads } else { 0.0 };
            // A cut step moves less for being short, not for being at rest
            // (a block sliding off is cut to the displacement bound), and
            // an unconverged one is not at rest either.
            let whole = failed(&self.stats) == before;
            let still = self.last_moved <= (SETTLED_SHARE * settling.largest_step).max(tolerance);
            let balanced = end <= SETTLED_BALANCE * loads;
            if whole && still && balanced {
                settling.settled = true;
                break;
            }
            let failed_newton = self.stats.newton_failures > before.2;
            let stalled = failed_newton && still && end > (1.0 - STALLED_SHARE) * start;
            if stalled && stuck {
                settling.stalled = true;
                break;
            }
            stuck = stalled;
            // Two static steps in a row that moved a block as one falls,
            // slides or topples, or whose contacts found no states they
            // agree on even at the smallest step: the model does not stand,
            // and further steps (hundreds of passes each, as contacts open
            // and close with no inertia) would be undone.
            let unconverged = self.stats.unconverged_steps > before.1;
            let failing = self.last_moved > falling || unconverged;
            if failing && fell {
                gave_up = true;
                break;
            }
            fell = failing;
        }
        self.settling = false;
        (
            self.settings.velocity_ratio,
            self.dt,
            self.dt_next,
            self.dt_cap,
        ) = kept;
        settling.statistics = std::mem::replace(&mut self.stats, run_stats);
        result?;
        if let Some(unsettled) = unsettled.filter(|_| !settling.settled) {
            if gave_up || settling.largest_step > falling {
                self.restore(&unsettled)?;
                settling.undone = true;
            }
        }
        // The run starts at rest from the settled state: its energy check,
        // its foreseen motion and its factor are its own.
        self.velocity.iter_mut().for_each(|v| v.fill(0.0));
        self.energy_floor = None;
        self.first_potential = None;
        self.recent = RecentSteps::default();
        self.warm_start = None;
        self.factored = None;
        self.factor_change = None;
        self.weighing = None;
        self.even_step = None;
        if settling.settled {
            for note in self.notes.iter_mut().filter(|n| *n == super::UNDAMPED_NOTE) {
                *note = super::UNDAMPED_SETTLED_NOTE.into();
            }
        }
        settling.wall_time = started.elapsed();
        Ok(settling)
    }
}
