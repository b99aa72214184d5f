//! The step's residual and tangent at a trial: inertia, the blocks' own
//! terms and the contacts' springs, gathered block by block on every core.

use std::time::Instant;

use rayon::prelude::*;

use super::terms::ContactLoad;
use super::woodbury::RankOne;
use super::{block, Driver, Motion, Trial};
use crate::assembly::{add_outer_into, zero_kept, BlockSparse};
use crate::contacts::{BlockVector, EntranceRows};
use crate::system::{BlockMatrix, BlockSystem};
use crate::{BLOCKS_PER_TASK, CONTACTS_PER_TASK};

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// Fills `residual` with applied minus internal forces at the trial
    /// displacement and, with `tangent`, the matrix with the tangent.
    pub(super) fn assemble(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &Trial<T>,
        residual: &mut [f64],
        couplings: Option<&mut Vec<RankOne<N>>>,
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
    pub(super) fn load(
        &mut self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        trial: &Trial<T>,
        residual: &mut [f64],
        mut couplings: Option<&mut Vec<RankOne<N>>>,
        motion: Motion<'_>,
    ) {
        let started = Instant::now();
        let (implicit, tangent, approach) = match motion {
            Motion::Tangent => (true, true, None),
            Motion::Implicit | Motion::Springs => (true, false, None),
            Motion::Explicit(approach) => (false, false, Some(approach)),
        };
        // Where the dashpots read the blocks' motion in the step.
        let moving = approach.unwrap_or(&trial.d);
        let mut matrix = std::mem::take(&mut self.matrix);
        residual.fill(0.0);
        let end = self.load_time(dt);
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
        let gather = self.touching.is_filled() && !self.one_thread_assembly;
        if tangent && !gather {
            matrix.clear();
        }
        if gather {
            let parts = matrix.split_blocks(residual);
            let (diagonal, _, _, _) = matrix.blocks_mut();
            (diagonal.par_iter_mut().zip(parts))
                .with_min_len(BLOCKS_PER_TASK)
                .enumerate()
                .for_each(|(i, (diagonal, part))| {
                    let (k, r) = own_terms(i, &masses[i]);
                    if tangent {
                        // Written over the last pass's terms: 0 + k is k
                        // (a zero's sign too), so no serial sweep clears
                        // the matrix first (up to 16 ms a pass at 10,051
                        // blocks in 3D).
                        *diagonal = k.add_scalar(0.0);
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
        // A move on a kept factor, gathered, needs the contacts' forces
        // alone: a quarter less to write and read again than their loads
        // (104 bytes a contact against 144 in 2D, 200 against 256 in 3D).
        let forces_only = gather && !tangent && !matches!(motion, Motion::Springs);
        let mut loads = std::mem::take(&mut self.contact_loads);
        let mut forces = std::mem::take(&mut self.contact_forces);
        let terms = self.terms();
        let contacts = (0..self.contacts.len()).into_par_iter();
        let contacts = contacts.with_min_len(CONTACTS_PER_TASK);
        if forces_only {
            // Written in place: collected, each force went through a copy
            // (200 bytes a contact in 3D).
            forces.resize(self.contacts.len(), None);
            (forces.par_iter_mut().enumerate())
                .with_min_len(CONTACTS_PER_TASK)
                .for_each(|(i, f)| *f = terms.force(i, trial, dt, moving));
        } else {
            (contacts.map(|i| terms.load(i, trial, dt, moving, couple)))
                .collect_into_vec(&mut loads);
        }
        if gather {
            let (contacts, touching, chosen) = (&self.contacts, &self.touching, &self.chosen);
            let entrance = |i: usize| chosen.of(contacts, i, trial.entrances[i]);
            let slot_contacts = &self.slot_contacts;
            let parts = matrix.split_blocks(residual);
            let (diagonal, lower, dofs, pairs) = matrix.blocks_mut();
            (diagonal.par_iter_mut().zip(parts))
                .with_min_len(BLOCKS_PER_TASK)
                .enumerate()
                .for_each(|(x, (diagonal, part))| {
                    for (i, side) in touching.of(x) {
                        let force = if forces_only {
                            let Some(force) = &forces[i] else { continue };
                            force
                        } else {
                            let Some(load) = &loads[i] else { continue };
                            if tangent {
                                let n = dofs[x];
                                side_terms(load, entrance(i), side, |g, h, k| {
                                    add_outer_into(diagonal, (n, n), g, h, k, false);
                                });
                            }
                            &load.force
                        };
                        part.iter_mut()
                            .zip(force[side].iter())
                            .for_each(|(p, f)| *p += f);
                    }
                });
            if tangent {
                (lower.par_iter_mut())
                    .with_min_len(BLOCKS_PER_TASK)
                    .enumerate()
                    .for_each(|(s, block)| {
                        let (row, col) = pairs[s];
                        zero_kept(block, (dofs[row], dofs[col]));
                        for &i in slot_contacts.of(s) {
                            let Some(load) = &loads[i] else { continue };
                            let [a, b] = contacts[i].blocks;
                            spring_terms(load, entrance(i), |g, h, k| {
                                add_outer_into(block, (dofs[a], dofs[b]), &g[0], &h[1], k, a < b);
                            });
                        }
                    });
            }
            if let Some(couplings) = couplings {
                // In the contacts' order, as below.
                let (contacts, chosen) = (&self.contacts, &self.chosen);
                let found = (loads.par_iter().enumerate()).filter_map(|(i, load)| {
                    let entrance = chosen.of(contacts, i, trial.entrances[i]);
                    coupling(load.as_ref()?, entrance, contacts[i].blocks)
                });
                couplings.par_extend(found);
            }
            self.contact_loads = loads;
            self.contact_forces = forces;
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
            let entrance = self.chosen.of(&self.contacts, i, trial.entrances[i]);
            if tangent {
                let slot = self.slots[i].expect("closed contacts are in the pattern");
                spring_terms(load, entrance, |g, h, k| {
                    add_coupling(&mut matrix, slot, a, b, (&g[0], &g[1]), (&h[0], &h[1]), k);
                });
            }
            if let Some(couplings) = couplings.as_deref_mut() {
                couplings.extend(coupling(load, entrance, [a, b]));
            }
            matrix.add_block(residual, a, &load.force[0]);
            matrix.add_block(residual, b, &load.force[1]);
        }
        self.contact_loads = loads;
        self.contact_forces = forces;
        self.matrix = matrix;
        self.stats.times.assembly += started.elapsed();
    }
}

/// A sliding contact's friction coupled to its normal gap, as a rank-one
/// term of the whole tangent (none where its slope is zero).
fn coupling<const N: usize, const T: usize>(
    load: &ContactLoad<N, T>,
    entrance: &impl EntranceRows<N, T>,
    blocks: [usize; 2],
) -> Option<RankOne<N>> {
    if load.slope == 0.0 {
        return None;
    }
    let mut u = [BlockVector::<N>::zeros(), BlockVector::<N>::zeros()];
    for k in 0..T {
        let [ta, tb] = entrance.tangent(k);
        u[0] += ta * load.direction[k];
        u[1] += tb * load.direction[k];
    }
    let [na, nb] = entrance.normal();
    Some(RankOne {
        blocks,
        u,
        v: [na, nb],
        slope: load.slope,
    })
}

/// A contact's springs as terms k·g·hᵀ over its two blocks' rows (g = [ga,
/// gb]), in the order the matrix adds them: the normal spring, each shear
/// spring, then the turning of a sliding contact's friction (3D). Terms of
/// no stiffness are left out.
pub(super) fn spring_terms<const N: usize, const T: usize>(
    load: &ContactLoad<N, T>,
    entrance: &impl EntranceRows<N, T>,
    term: impl FnMut(&[BlockVector<N>; 2], &[BlockVector<N>; 2], f64),
) {
    let tangents = std::array::from_fn(|k| entrance.tangent(k));
    springs(load, entrance.normal(), tangents, term);
}

/// [`spring_terms`] over one block's rows alone (`side` 0 or 1): the
/// terms of its diagonal block, the same to the last bit.
fn side_terms<const N: usize, const T: usize>(
    load: &ContactLoad<N, T>,
    entrance: &impl EntranceRows<N, T>,
    side: usize,
    term: impl FnMut(&BlockVector<N>, &BlockVector<N>, f64),
) {
    let tangents = std::array::from_fn(|k| entrance.tangent_of(k, side));
    springs(load, entrance.normal_of(side), tangents, term);
}

/// The springs' terms over rows `normal` and `tangents` (both blocks'
/// or one block's), in [`spring_terms`]'s order.
#[inline(always)]
fn springs<R, const N: usize, const T: usize>(
    load: &ContactLoad<N, T>,
    normal: R,
    tangents: [R; T],
    mut term: impl FnMut(&R, &R, f64),
) {
    let mut add = |g: &R, h: &R, k: f64| {
        if k != 0.0 {
            term(g, h, k);
        }
    };
    add(&normal, &normal, load.normal_stiffness);
    for (k, rows) in tangents.iter().enumerate() {
        add(rows, rows, load.shear_stiffness[k]);
    }
    if load.turning != 0.0 {
        let direction = &load.direction;
        for (k, gk) in tangents.iter().enumerate() {
            for (l, gl) in tangents.iter().enumerate() {
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
