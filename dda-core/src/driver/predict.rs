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
}

impl RecentSteps {
    /// Keeps an accepted step's length and displacement.
    pub fn push(&mut self, dt: f64, d: &[f64]) {
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
        let (dt1, d1) = self.steps.last()?;
        let Some((dt0, d0)) = self.steps.len().checked_sub(2).map(|i| &self.steps[i]) else {
            return Some(d1.iter().map(|x| x * dt / dt1).collect());
        };
        // Mean velocities sit at the steps' midpoints.
        let reach = (dt1 + dt) / (dt0 + dt1);
        Some(
            d0.iter()
                .zip(d1)
                .map(|(x0, x1)| {
                    let (u0, u1) = (x0 / dt0, x1 / dt1);
                    (u1 + (u1 - u0) * reach) * dt
                })
                .collect(),
        )
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
        recent.push(0.1, &[0.01]);
        recent.push(0.2, &[0.09 - 0.01]);
        let next = recent.foresee(0.3).unwrap();
        assert!((next[0] - (0.36 - 0.09)).abs() < 1e-12, "{next:?}");
    }

    #[test]
    fn one_step_is_held_and_a_third_is_forgotten() {
        let mut recent = RecentSteps::default();
        recent.push(0.1, &[1.0]);
        assert_eq!(recent.foresee(0.05).unwrap(), vec![0.5]);
        recent.push(0.1, &[2.0]);
        recent.push(0.1, &[2.0]);
        // Two equal steps: the motion goes on as it was.
        assert_eq!(recent.foresee(0.1).unwrap(), vec![2.0]);
        assert!(recent.fits(1) && !recent.fits(2));
    }
}
