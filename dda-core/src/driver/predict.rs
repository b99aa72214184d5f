//! The step's motion foreseen from the last two accepted steps, so that a
//! contact it carries across the open-close tolerance starts the step in
//! the state it will end in.
//!
//! A settling wall opens a few head joints at every step; each opening
//! found only by a pass's decision costs another pass (at 1 ms, 40 × 40
//! rigid bricks took 2.5 passes a step). The start velocities foresee the
//! step badly where springs are stiff against the step: Newmark's
//! v₁ = 2d/dt − v₀ flips a stiff mode's velocity at every step, so at the
//! automatic step they would open joints that the step then closes. The
//! displacements themselves do not flip, so the step's mean velocity is
//! extrapolated from the last two steps' mean velocities instead.
//!
//! A foreseen state is only where the passes start: each pass still
//! decides every contact, and the step ends only when all agree.

use serde::{Deserialize, Serialize};

/// The last two accepted steps: each one's length (s) and displacement.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub(super) struct RecentSteps {
    /// Oldest first, at most two.
    steps: Vec<(f64, Vec<f64>)>,
    /// How far the last accepted step's motion lay from what was foreseen
    /// for it, as a share of the motion (`None` before one was foreseen).
    #[serde(default)]
    miss: Option<f64>,
    /// The Newton-Raphson moves of the last accepted step's first pass.
    #[serde(default)]
    first_moves: usize,
}

impl RecentSteps {
    /// Keeps an accepted step's length and displacement, and the moves of
    /// its first pass.
    pub fn push(&mut self, dt: f64, d: &[f64], first_moves: usize) {
        self.first_moves = first_moves;
        self.miss = self.foreseer(dt).map(|foreseen| {
            let (mut missed, mut moved) = (0.0, 0.0);
            for (k, x) in d.iter().enumerate() {
                missed += (x - foreseen(k)).powi(2);
                moved += x * x;
            }
            if missed == 0.0 {
                0.0
            } else {
                (missed / moved).sqrt()
            }
        });
        let mut oldest = if self.steps.len() == 2 {
            self.steps.remove(0)
        } else {
            (0.0, Vec::new())
        };
        oldest.0 = dt;
        oldest.1.clear();
        oldest.1.extend_from_slice(d);
        self.steps.push(oldest);
    }

    /// The displacement foreseen for a step of `dt`: the mean velocity
    /// extrapolated linearly in time from the last two steps' (from one
    /// step, held), times `dt`. `None` before the first step.
    pub fn foresee(&self, dt: f64) -> Option<Vec<f64>> {
        let foreseen = self.foreseer(dt)?;
        Some(
            (0..self.steps[self.steps.len() - 1].1.len())
                .map(foreseen)
                .collect(),
        )
    }

    /// [`RecentSteps::foresee`]'s entries, one at a time.
    fn foreseer(&self, dt: f64) -> Option<impl Fn(usize) -> f64 + '_> {
        let (dt1, d1) = self.steps.last()?;
        let older = self.steps.len().checked_sub(2).map(|i| &self.steps[i]);
        Some(move |k: usize| {
            let Some((dt0, d0)) = older else {
                return d1[k] * dt / dt1;
            };
            // Mean velocities sit at the steps' midpoints.
            let reach = (dt1 + dt) / (dt0 + dt1);
            let (u0, u1) = (d0[k] / dt0, d1[k] / dt1);
            (u1 + (u1 - u0) * reach) * dt
        })
    }

    /// How far the last accepted step's motion lay from its foresight, as
    /// a share of that motion (0 where foreseen exactly, `None` where none
    /// was foreseen).
    pub fn miss(&self) -> Option<f64> {
        self.miss
    }

    /// The Newton-Raphson moves of the last accepted step's first pass.
    pub fn first_moves(&self) -> usize {
        self.first_moves
    }

    /// Whether every kept step has `len` values (a checkpoint's check).
    pub fn fits(&self, len: usize) -> bool {
        self.steps.len() <= 2 && self.steps.iter().all(|(dt, d)| *dt > 0.0 && d.len() == len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_acceleration_is_foreseen_exactly() {
        // x(t) = t²: steps of 0.1 then 0.2 from t = 0; the next, of 0.3,
        // moves from 0.09 to 0.36.
        let mut recent = RecentSteps::default();
        assert!(recent.foresee(0.1).is_none());
        recent.push(0.1, &[0.01], 1);
        recent.push(0.2, &[0.09 - 0.01], 1);
        let next = recent.foresee(0.3).unwrap();
        assert!((next[0] - (0.36 - 0.09)).abs() < 1e-12, "{next:?}");
        // Taken, it was foreseen to round-off.
        recent.push(0.3, &[0.36 - 0.09], 1);
        assert!(recent.miss().unwrap() < 1e-12, "{:?}", recent.miss());
    }

    #[test]
    fn a_step_that_turns_back_misses_its_foresight_by_more_than_its_motion() {
        let mut recent = RecentSteps::default();
        recent.push(0.1, &[1.0, 0.0], 1);
        assert_eq!(recent.miss(), None);
        // Held: (1, 0) foreseen, (-1, 0) taken.
        recent.push(0.1, &[-1.0, 0.0], 1);
        assert_eq!(recent.miss(), Some(2.0));
        // At rest where rest was foreseen: no miss.
        let mut still = RecentSteps::default();
        still.push(0.1, &[0.0], 1);
        still.push(0.1, &[0.0], 1);
        assert_eq!(still.miss(), Some(0.0));
    }

    #[test]
    fn one_step_is_held_and_a_third_is_forgotten() {
        let mut recent = RecentSteps::default();
        recent.push(0.1, &[1.0], 1);
        assert_eq!(recent.foresee(0.05).unwrap(), vec![0.5]);
        recent.push(0.1, &[2.0], 1);
        recent.push(0.1, &[2.0], 1);
        // Two equal steps: the motion goes on as it was.
        assert_eq!(recent.foresee(0.1).unwrap(), vec![2.0]);
        assert!(recent.fits(1) && !recent.fits(2));
    }
}
