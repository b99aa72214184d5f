//! Steps to a requested time (an output time, the run's end) made equal.
//!
//! A stretch that whole steps of dt do not fill would end on a short step.
//! That step's inertia terms (2M/dt² in Newmark's matrix) differ from its
//! neighbours' by (dt/short)², so the factor kept from the steps before
//! fits neither it nor the step after it: two factorisations at every
//! output time. Split into equal steps of at most dt instead, the stretch
//! takes as many steps, all of one length to the bit, and every stretch
//! as long takes that length again. The 40 × 40 wall's first 2 s at its
//! automatic step (9.49 ms) with outputs every 0.05 s took 89
//! factorisations in 240 steps before, 14 now (13 in 212 steps with
//! outputs only at the end).

use super::Driver;
use crate::system::BlockSystem;

/// How far a stretch may fall short of a whole number of steps, or reach
/// past it, and still be taken in whole steps of dt, the last one that
/// hair shorter or a hair's step added (a share of a step): round-off in
/// an output time at a multiple of dt, or a run asked for n steps as n·dt
/// less a nanosecond. A hair's change to the last step's inertia terms
/// leaves its factor fitting.
const WHOLE_STEP_SLACK: f64 = 1e-4;

/// How closely a stretch's equal step must match the last one to take
/// its length to the bit (a share of it). What is left of a stretch
/// after each step, and output times k·interval, carry round-off of some
/// k·1e-16 of the interval; a step start may skip the kept factor's
/// weighing only at the same dt as the weighing (`driver/weighing.rs`).
const SAME_STEP: f64 = 1e-10;

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// The longest the next step may be on the way to a time `remaining`
    /// (s) ahead: all of it where whole steps of dt fill the stretch (the
    /// last one as long as what is left), else the stretch's share of its
    /// least number of equal steps of at most dt.
    pub(super) fn even_limit(&mut self, remaining: f64) -> f64 {
        let whole = remaining / self.dt;
        let steps = (whole - WHOLE_STEP_SLACK).ceil().max(1.0);
        if steps - whole <= WHOLE_STEP_SLACK {
            return remaining;
        }
        let even = remaining / steps;
        match self.even_step {
            Some(last) if (last - even).abs() <= SAME_STEP * even => last,
            _ => {
                self.even_step = Some(even);
                even
            }
        }
    }
}
