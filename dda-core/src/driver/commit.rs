//! An accepted step made permanent: contact records and law histories,
//! velocities, the blocks' motion, and the energy check.

use rayon::prelude::*;

use super::{block, split, Driver, Trial};
use crate::contact::ContactState;
use crate::system::BlockSystem;
use crate::{BLOCKS_PER_TASK, CONTACTS_PER_TASK};

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    pub(super) fn commit(&mut self, trial: Trial<T>, dt: f64) {
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
        self.recent.push(dt, &trial.d, trial.first_moves);
        self.finish_step(&trial.d, dt, spring_energy);
    }

    /// Moves the blocks by `d`, the time by `dt`, and checks the energy.
    pub(super) fn finish_step(&mut self, d: &[f64], dt: f64, spring_energy: f64) {
        if !self.settling {
            self.advance_time(dt);
        }
        self.system.commit(&split::<N>(d), dt, self.time);
        self.stats.steps += 1;
        self.check_energy(spring_energy);
    }

    /// Each contact's state, record and law history at the accepted trial;
    /// returns the energy the springs store.
    pub(super) fn commit_contacts(&mut self, trial: &Trial<T>, dt: f64) -> f64 {
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
        // Each block's on any core (a 3D block's mass matrix is some 8,000
        // instructions), summed in block order as one thread would.
        let system = &self.system;
        let kinetic: Vec<f64> = (self.velocity.par_iter().enumerate())
            .with_min_len(BLOCKS_PER_TASK)
            .map(|(i, v)| 0.5 * v.dot(&(system.mass(i) * v)))
            .collect();
        let kinetic: f64 = kinetic.iter().sum();
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
