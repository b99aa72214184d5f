//! The explicit integrator: central differences on the same blocks,
//! contacts and laws as the implicit step, for comparing the two methods
//! honestly (3DEC and UDEC integrate this way).
//!
//! Velocities sit at half steps: v(n+½) = v(n−½) + h·M⁻¹f(n), with h the
//! mean of the two step lengths (half the first step, so a constant force
//! gives the exact parabola), and the step's displacement is dt·v(n+½).
//! The forces f(n) are those of the implicit step's residual at zero
//! displacement: block stresses, loads, fixed-point springs and contact
//! springs at the start of the step, the states decided there. The states
//! at the end of the step are decided once (the return map of each shear
//! spring), with no repeat: stability comes from the step, not iteration.
//!
//! The step stays below the critical one, 2/ω_max. ω_max² is bounded at
//! every step by the largest, over blocks, of the block's own ω² (its
//! elastic and fixed-point springs against its mass) plus, for each contact
//! found near it, k·(gₐᵀMₐ⁻¹gₐ + g_bᵀM_b⁻¹g_b) of each spring row g: a
//! Gershgorin bound on the mass-scaled stiffness (by Cauchy-Schwarz on each
//! rank-one spring), so it never underestimates ω_max.

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::{widest_at_rest, Driver, Motion, Trial};
use crate::contact::ContactState;
use crate::error::DdaError;
use crate::settings::Integrator;
use crate::system::{BlockMatrix, BlockSystem};
use crate::{BlockVector, EntranceRows, CONTACTS_PER_TASK};

/// The share of the critical step an explicit step may take: the bound is
/// already above ω_max, this leaves room for springs that stiffen within
/// the step.
pub(crate) const CRITICAL_SHARE: f64 = 0.9;

/// Velocities at the half step and at the end of a step.
type HalfAndEnd<const N: usize> = (Vec<BlockVector<N>>, Vec<BlockVector<N>>);

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// For the explicit integrator, the critical step at the start as a
    /// note, and the nominal step from it when the scene gives none.
    pub(super) fn explained(mut self) -> Self {
        if self.settings.integrator != Integrator::Explicit {
            return self;
        }
        self.search(2.5 * self.displacement_bound());
        let masses: Vec<BlockMatrix<N>> = (0..self.system.block_count())
            .map(|i| self.system.mass(i))
            .collect();
        self.invert(&masses);
        let (critical, limiting) = self.critical_step(&masses, &self.at_rest());
        let share = CRITICAL_SHARE;
        let mut note = "explicit integration (central differences): ".to_string();
        if critical.is_finite() {
            note += &format!(
                "critical time step {critical:.4e} s at the start (2/ω_max from the penalty springs and block masses, limited by block {limiting}); "
            );
        } else {
            note += "no springs at the start to limit the step; ";
        }
        match self.settings.dt {
            None if critical.is_finite() => {
                self.dt = share * critical;
                self.dt_next = self.dt;
                self.notes.retain(|n| !n.starts_with("time step "));
                note += &format!("time step {:.4e} s, {share} of it", self.dt);
            }
            Some(dt) if dt > share * critical => {
                note += &format!(
                    "dt {dt} s is above {share} of it, so steps are shortened to stay below the critical step (bounded again at every step); a smaller penalty or heavier blocks allow longer steps"
                );
            }
            _ => {
                note +=
                    "each step stays below 0.9 of the critical step, bounded again at every step"
            }
        }
        self.notes.push(note);
        self
    }

    /// One explicit step of at most `dt_limit`.
    pub(super) fn explicit_step(&mut self, dt_limit: f64) -> Result<(), DdaError> {
        let bound = self.displacement_bound();
        self.search(2.5 * bound);
        let nb = self.system.block_count();
        let masses: Vec<BlockMatrix<N>> = (0..nb).map(|i| self.system.mass(i)).collect();
        self.invert(&masses);
        let mut trial = self.at_rest();
        let (critical, _) = self.critical_step(&masses, &trial);
        let stats = &mut self.stats;
        stats.critical_dt = Some(stats.critical_dt.map_or(critical, |c| c.min(critical)));
        let mut dt = self.dt.min(dt_limit);
        if dt > CRITICAL_SHARE * critical {
            dt = CRITICAL_SHARE * critical;
            stats.critical_limited_steps += 1;
        }
        // The states at the start of the step, where the forces act.
        let approach = self.approach(dt);
        self.decide(&mut trial, dt, Some(&approach));
        let (d, velocity) = loop {
            let (d, velocity) = self.central_difference(dt, &masses, &trial);
            let moved = self.system.max_displacement(&super::split::<N>(&d));
            if moved > bound && dt > self.dt * self.settings.min_dt_ratio {
                dt *= 0.9 * bound / moved;
                self.stats.displacement_cuts += 1;
                continue;
            }
            self.last_moved = moved;
            break (d, velocity);
        };
        // The states at its end: one return map, no repeat.
        trial.d = d;
        self.decide(&mut trial, dt, None);
        let limit = self.settings.max_penetration_ratio * self.length_scale;
        let (deepest, _, key) = self.penetration(&trial, limit);
        if deepest > limit {
            self.stats.deep_penetration_steps += 1;
            self.stats.deepest_penetration = self.stats.deepest_penetration.max(deepest);
            self.stats.last_deep = key.map(|k| (k, deepest));
        }
        let committing = std::time::Instant::now();
        let spring_energy = self.commit_contacts(&trial, dt);
        (self.half_velocity, self.velocity) = velocity;
        self.last_dt = Some(dt);
        self.finish_step(&trial.d, dt, spring_energy);
        self.stats.times.commit += committing.elapsed();
        Ok(())
    }

    /// The step's displacement and its velocities, at the half step and
    /// at the end (v(n+½) + dt/2·a(n): exact for a constant force), by
    /// central differences with the forces at the start (`trial.d` zero)
    /// in `trial.states`.
    fn central_difference(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &Trial<T>,
    ) -> (Vec<f64>, HalfAndEnd<N>) {
        self.supports = if self.settings.contact_damping > 0.0 {
            self.system.supports(self.time, self.load_time(dt))
        } else {
            Vec::new()
        };
        let approach = self.approach(dt);
        let mut force = vec![0.0; self.matrix.dim()];
        self.load(
            dt,
            masses,
            trial,
            &mut force,
            None,
            Motion::Explicit(&approach),
        );
        let h = self.last_dt.map_or(0.5 * dt, |last| 0.5 * (last + dt));
        let alpha = self.settings.mass_damping;
        let local = self.settings.local_damping;
        let mut d = vec![0.0; trial.d.len()];
        let mut half = Vec::with_capacity(self.velocity.len());
        let mut end = Vec::with_capacity(self.velocity.len());
        for (i, v) in self.carried().into_iter().enumerate() {
            let mut f = self.matrix.block(&force, i);
            // Local damping: each DOF's unbalanced force loses a share of
            // its size against that DOF's motion (none while at rest).
            for k in 0..N {
                if v[k] != 0.0 {
                    f[k] -= local * f[k].abs() * v[k].signum();
                }
            }
            let a = self.inverse_masses[i] * f;
            // Mass damping −αv, at the mean of the two half-step velocities.
            let next = (v * (1.0 - 0.5 * alpha * h) + a * h) / (1.0 + 0.5 * alpha * h);
            d[i * N..(i + 1) * N].copy_from_slice((next * dt).as_slice());
            half.push(next);
            end.push(next + a * (0.5 * dt));
        }
        (d, (half, end))
    }

    /// The trial of a step that has not moved the blocks: the records'
    /// states, slip directions and widest entrances.
    pub(super) fn at_rest(&self) -> Trial<T> {
        let d = vec![0.0; self.system.block_count() * N];
        let tolerance = self.settings.contact_tolerance * self.length_scale;
        // Each contact read once, on every core: its record lies a cache
        // line or more from the next one's.
        let contacts = self.contacts.par_iter().with_min_len(CONTACTS_PER_TASK);
        let (states, (entrances, directions)) = contacts
            .map(|c| {
                let r = &c.record;
                (
                    r.state,
                    (widest_at_rest(c, r.entrance, tolerance), r.slip_direction),
                )
            })
            .unzip();
        Trial {
            states,
            entrances,
            directions,
            d,
            converged: true,
            solved: true,
            unsettled: Vec::new(),
            pulled: vec![false; self.contacts.len()],
            within: vec![false; self.contacts.len()],
            load_scale: 0.0,
            rest_norm: 0.0,
            end_norm: 0.0,
            foreseen: Vec::new(),
            first_moves: 0,
        }
    }

    /// The velocities a step starts from: the last half step's, or the
    /// initial ones before the first step; times the velocity ratio.
    fn carried(&self) -> Vec<BlockVector<N>> {
        let from = if self.last_dt.is_some() {
            &self.half_velocity
        } else {
            &self.velocity
        };
        let ratio = self.settings.velocity_ratio;
        from.iter().map(|v| v * ratio).collect()
    }

    /// The motion the step's start velocities make in `dt`, on which the
    /// dashpots act.
    fn approach(&self, dt: f64) -> Vec<f64> {
        (self.carried().iter())
            .flat_map(|v| (v * dt).iter().copied().collect::<Vec<_>>())
            .collect()
    }

    fn invert(&mut self, masses: &[BlockMatrix<N>]) {
        self.inverse_masses = (masses.iter().enumerate())
            .map(|(i, m)| self.matrix.kept_inverse(i, m))
            .collect();
    }

    /// The critical step 2/ω_max (with the contact dashpots' shortening)
    /// from the bound in the module's note, and the block that sets it.
    fn critical_step(&mut self, masses: &[BlockMatrix<N>], rest: &Trial<T>) -> (f64, usize) {
        if self.block_rates.len() != masses.len() {
            self.block_rates = (0..masses.len())
                .map(|i| self.own_rate(i, &masses[i]))
                .collect();
        }
        // Per block, the bounds of ω² (springs) and β (dashpots, 1/s).
        let mut rates = self.block_rates.clone();
        let mut dampers = vec![0.0; rates.len()];
        let damped = self.settings.contact_damping > 0.0;
        let compliance = |a: usize, b: usize, [ga, gb]: &[BlockVector<N>; 2]| {
            ga.dot(&(self.inverse_masses[a] * ga)) + gb.dot(&(self.inverse_masses[b] * gb))
        };
        for (i, c) in self.contacts.iter().enumerate() {
            let history = c.record.history.as_ref().expect("history set at search");
            let [a, b] = c.blocks;
            let (mut spring, mut damper): (f64, f64) = (0.0, 0.0);
            for (entrance, e) in c.entrances.iter().enumerate() {
                let kin = self.terms().kinematics(i, entrance, rest, self.dt);
                let springs = self.laws[c.law].response(ContactState::Locked, &kin, history);
                let rows = std::iter::once((e.normal(), springs.normal_stiffness))
                    .chain((0..T).map(|k| (e.tangent(k), springs.shear_stiffness)));
                let (mut k_sum, mut c_sum) = (0.0, 0.0);
                for (g, k) in rows {
                    let g = &g;
                    let k = k.max(0.0);
                    k_sum += k * compliance(a, b, g);
                    if damped {
                        c_sum += self.terms().dashpot(a, b, g, k) * compliance(a, b, g);
                    }
                }
                spring = spring.max(k_sum);
                damper = damper.max(c_sum);
            }
            rates[a] += spring;
            rates[b] += spring;
            dampers[a] += damper;
            dampers[b] += damper;
        }
        if damped {
            for support in self.system.supports(self.time, self.time + self.dt) {
                let i = support.block;
                let g = [support.row, BlockVector::<N>::zeros()];
                dampers[i] +=
                    self.terms().dashpot(i, i, &g, support.stiffness) * compliance(i, i, &g);
            }
        }
        let (limiting, highest) =
            rates
                .iter()
                .copied()
                .enumerate()
                .fold(
                    (0, 0.0),
                    |best, (i, r)| if r > best.1 { (i, r) } else { best },
                );
        if highest <= 0.0 {
            return (f64::INFINITY, limiting);
        }
        // A mode x'' = −ω²x − βx' stepped with a share r of the velocity
        // carried and the dashpots on it: x(n+1) − x(n) = q·(x(n) −
        // x(n−1)) − ω²dt²·x(n), q = r(1 − β·dt), is stable while ω²dt² ≤
        // 2(1 + q). Local damping α acts as a stiffness (1 + α)ω² in a mode
        // whose velocity turns every step (it pushes along the new one).
        let beta = self.settings.velocity_ratio * dampers.iter().copied().fold(0.0, f64::max);
        let w = (1.0 + self.settings.local_damping) * highest;
        let r = self.settings.velocity_ratio;
        let critical = ((beta * beta + 2.0 * (1.0 + r) * w).sqrt() - beta) / w;
        (critical, limiting)
    }

    /// λ_max(M⁻¹K) of block `i` on its own springs (elastic stiffness,
    /// fixed points), over the DOF it moves by.
    fn own_rate(&self, i: usize, mass: &BlockMatrix<N>) -> f64 {
        let n = self.system.dofs(i);
        let mut k = BlockMatrix::<N>::zeros();
        let mut r = BlockVector::<N>::zeros();
        self.system
            .block_terms(i, self.time, &BlockVector::<N>::zeros(), &mut k, &mut r);
        let m = DMatrix::from_fn(n, n, |r, c| mass[(r, c)]);
        let k = DMatrix::from_fn(n, n, |r, c| 0.5 * (k[(r, c)] + k[(c, r)]));
        let Some(l) = m.cholesky().and_then(|c| c.l().try_inverse()) else {
            return 0.0;
        };
        let scaled = &l * k * l.transpose();
        scaled
            .symmetric_eigenvalues()
            .iter()
            .copied()
            .fold(0.0, f64::max)
    }
}
