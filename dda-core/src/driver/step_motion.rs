//! The motion the automatic step bounds.
//!
//! What a step must resolve is how blocks move against each other and
//! about themselves, not where the whole assembly goes: Newmark's step
//! carries a translation shared by touching blocks exactly under constant
//! loads. A 70-course deformable wall released from rest rings in its
//! first vertical mode (period about 50 ms), its top course moving 0.08
//! m/s: bounded by that whole motion the step fell to 1 ms, though no
//! joint opened or slid more than a fiftieth of what the bound allows.

use rayon::prelude::*;

use super::{Driver, Trial};
use crate::contacts::{BlockVector, EntranceRows};
use crate::system::BlockSystem;
use crate::CONTACTS_PER_TASK;

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// The largest of: each listed contact's relative motion over the step
    /// (its change of gap and its slip, open or closed), each block's
    /// points' motion about its centroid (turn and strain), and the whole
    /// motion of a block no closed contact holds (in flight, whose landing
    /// the step must find), in m.
    pub(super) fn step_motion(&self, trial: &Trial<T>, d: &[BlockVector<N>]) -> f64 {
        let mut free = vec![true; self.system.block_count()];
        for (c, state) in self.contacts.iter().zip(&trial.states) {
            if state.is_closed() {
                free[c.blocks[0]] = false;
                free[c.blocks[1]] = false;
            }
        }
        let own = self.system.max_own_motion(d, &free);
        let (chosen, contacts) = (&self.chosen, &self.contacts);
        let relative = (contacts.par_iter().enumerate())
            .with_min_len(CONTACTS_PER_TASK)
            .map(|(i, c)| {
                let e = chosen.of(contacts, i, trial.entrances[i]);
                let (gap, shear) = e.gap_and_shear_at(&d[c.blocks[0]], &d[c.blocks[1]]);
                ((gap - e.gap()).powi(2) + shear.norm_squared()).sqrt()
            })
            .reduce(|| 0.0, f64::max);
        own.max(relative)
    }
}
