//! Impacts as events (`Settings::restitution`): a contact that closes in a
//! step strikes, and an impulse at the step's start turns its approach
//! speed u into a rebound of e·u before the step is solved.
//!
//! Penalty springs alone make each impact a short vibration whose rebound
//! follows dt and the penalty; the impulse gives the rigid-body answer
//! (Housner's, with e = 0) and leaves the springs only the load the contact
//! carries after it. The impulse acts on the struck blocks alone, each
//! answering through its mass and its own springs over the step
//! (M + dt²/2·K: a block held by fixed points hardly moves, strain barely
//! takes part when the step is long against its vibration); neighbours feel
//! it through their contact springs within the step.

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};

use super::{Driver, Trial};
use crate::contact::{ContactState, LocalKinematics};
use crate::system::{BlockMatrix, BlockSystem};
use crate::{BlockVector, EntranceRows};

/// One row of the impulse: a contact's normal or one of its tangents.
struct Row<const N: usize> {
    contact: usize,
    blocks: [usize; 2],
    g: [BlockVector<N>; 2],
    /// The speed along the row the impulse must leave.
    target: f64,
    normal: bool,
    /// When in the step the impulse acts, as a share of it.
    at: f64,
}

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// Translation and rotation lead a block's DOF (see `BlockKind::dofs`).
    const RIGID_DOFS: usize = N / 2;

    /// Sets `self.struck`, the start velocities' change that strikes the
    /// contacts this pass closes (open when the step began, approaching),
    /// with no struck contact pulled (a row whose impulse would pull is
    /// left out and the rest solved again).
    pub(super) fn strike(&mut self, dt: f64, masses: &[BlockMatrix<N>], trial: &Trial<T>) {
        let nb = self.system.block_count();
        for v in [&mut self.struck, &mut self.struck_early] {
            v.clear();
            v.resize(nb, BlockVector::<N>::zeros());
        }
        let Some(e) = self.settings.restitution else {
            return;
        };
        // A contact struck once in this attempt stays struck: its impulse
        // brings it to the surface by the step's end, where the next pass
        // may find it just open.
        for (i, c) in self.contacts.iter().enumerate() {
            if !c.record.state.is_closed()
                && trial.states[i].is_closed()
                && !self.striking.contains(&i)
            {
                self.striking.push(i);
            }
        }
        let ratio = self.settings.velocity_ratio;
        let v0 = |i: usize| self.velocity[i] * ratio;
        let mut rows = Vec::new();
        for &i in &self.striking {
            let c = &self.contacts[i];
            let entrance = &c.entrances[trial.entrances[i]];
            let [a, b] = c.blocks;
            // The rows' rigid part: the striking point's rigid motion.
            let rigid = |g: &[BlockVector<N>; 2]| {
                g.map(|g| g.map_with_location(|r, _, x| if r < Self::RIGID_DOFS { x } else { 0.0 }))
            };
            let speed = |g: &[BlockVector<N>; 2]| {
                let g = rigid(g);
                g[0].dot(&v0(a)) + g[1].dot(&v0(b))
            };
            let normal = entrance.normal();
            let approach = speed(&normal);
            if approach >= 0.0 {
                continue;
            }
            // The impact comes when the start gap has closed, this share
            // of the way through the step.
            let at = (entrance.gap().max(0.0) / (-approach * dt)).min(1.0);
            rows.push(Row {
                contact: i,
                blocks: c.blocks,
                g: rigid(&normal),
                target: -e * approach - approach,
                normal: true,
                at,
            });
            if !self.sliding_impact.contains(&i) {
                for g in (0..T).map(|k| entrance.tangent(k)) {
                    let g = &g;
                    rows.push(Row {
                        contact: i,
                        blocks: c.blocks,
                        g: rigid(g),
                        target: -speed(g),
                        normal: false,
                        at,
                    });
                }
            }
        }
        if rows.is_empty() {
            return;
        }
        let compliance = self.impulse_compliances(dt, masses, &rows);
        let response = |row: &Row<N>, side: usize| compliance[&row.blocks[side]] * row.g[side];
        loop {
            let n = rows.len();
            let mut w = DMatrix::<f64>::zeros(n, n);
            // W[r, s]: row r's speed change per unit impulse on row s.
            for (s, other) in rows.iter().enumerate() {
                let moved = [response(other, 0), response(other, 1)];
                for (r, row) in rows.iter().enumerate() {
                    for side in 0..2 {
                        for (block, moved) in other.blocks.iter().zip(&moved) {
                            if row.blocks[side] == *block {
                                w[(r, s)] += row.g[side].dot(moved);
                            }
                        }
                    }
                }
            }
            let target = DVector::from_iterator(n, rows.iter().map(|r| r.target));
            // Least norm: rows that say the same (a face's corners on a
            // rigid block) share the impulse instead of making W singular.
            let scale = w.diagonal().amax().max(f64::MIN_POSITIVE);
            let Ok(impulse) = w.svd(true, true).solve(&target, 1e-12 * scale) else {
                return;
            };
            let pulling: Vec<usize> = (rows.iter().zip(impulse.iter()))
                .filter(|(r, &p)| r.normal && p < 0.0)
                .map(|(r, _)| r.contact)
                .collect();
            let slipping = if pulling.is_empty() {
                self.slipping_impacts(dt, trial, &rows, impulse.as_slice())
            } else {
                Vec::new()
            };
            if !slipping.is_empty() {
                // Friction cannot stop these contacts' slip: they strike
                // along the normal only.
                rows.retain(|r| r.normal || !slipping.contains(&r.contact));
                self.sliding_impact.extend(slipping);
                continue;
            }
            if pulling.is_empty() {
                for (row, p) in rows.iter().zip(impulse.iter()) {
                    for side in 0..2 {
                        let change = response(row, side) * *p;
                        self.struck[row.blocks[side]] += change;
                        self.struck_early[row.blocks[side]] += change * (1.0 - row.at);
                    }
                }
                return;
            }
            rows.retain(|r| !pulling.contains(&r.contact));
            self.striking.retain(|i| !pulling.contains(i));
            if rows.is_empty() {
                return;
            }
        }
    }

    /// The struck contacts whose tangential impulse exceeds what friction
    /// carries: the law's strength at the normal impulse's mean force over
    /// the step, times dt.
    fn slipping_impacts(
        &self,
        dt: f64,
        trial: &Trial<T>,
        rows: &[Row<N>],
        impulse: &[f64],
    ) -> Vec<usize> {
        let mut slipping = Vec::new();
        for (r, row) in rows.iter().enumerate() {
            if !row.normal || slipping.contains(&row.contact) {
                continue;
            }
            let tangential: f64 = (rows.iter().zip(impulse))
                .filter(|(t, _)| !t.normal && t.contact == row.contact)
                .map(|(_, p)| p * p)
                .sum::<f64>()
                .sqrt();
            if tangential == 0.0 {
                continue;
            }
            let i = row.contact;
            let c = &self.contacts[i];
            let law = &self.laws[c.law];
            let history = c.record.history.as_ref().expect("history set at search");
            let kin = self.terms().kinematics(i, trial.entrances[i], trial, dt);
            let k = law
                .response(ContactState::Locked, &kin, history)
                .normal_stiffness;
            if k <= 0.0 {
                continue;
            }
            let pressed = LocalKinematics {
                gap: -impulse[r] / dt / k,
                ..kin
            };
            let strength = law
                .response(ContactState::Sliding, &pressed, history)
                .shear_force;
            if tangential > strength * dt {
                slipping.push(i);
            }
        }
        slipping
    }

    /// Each struck block's rigid velocity per unit impulse: the inverse of
    /// its mass over translation and rotation, with the directions its
    /// fixed or driven points hold taken out (a block held in place takes
    /// no impulse, a pinned one only turns).
    fn impulse_compliances(
        &self,
        dt: f64,
        masses: &[BlockMatrix<N>],
        rows: &[Row<N>],
    ) -> BTreeMap<usize, BlockMatrix<N>> {
        let rigid = Self::RIGID_DOFS;
        let supports = self.system.supports(self.time, self.load_time(dt));
        let mut compliance = BTreeMap::new();
        for block in rows.iter().flat_map(|r| r.blocks) {
            compliance.entry(block).or_insert_with(|| {
                let m = &masses[block];
                let kept = BlockMatrix::<N>::from_fn(|r, c| match (r < rigid, c < rigid) {
                    (true, true) => m[(r, c)],
                    _ if r == c => 1.0,
                    _ => 0.0,
                });
                let mut inverse = kept.try_inverse().unwrap_or_else(BlockMatrix::<N>::zeros);
                for r in 0..N {
                    for c in 0..N {
                        if r >= rigid || c >= rigid {
                            inverse[(r, c)] = 0.0;
                        }
                    }
                }
                let held: Vec<BlockVector<N>> = (supports.iter())
                    .filter(|s| s.block == block)
                    .map(|s| {
                        s.row
                            .map_with_location(|r, _, x| if r < rigid { x } else { 0.0 })
                    })
                    .collect();
                if held.is_empty() {
                    return inverse;
                }
                // C = A⁻¹ − A⁻¹Sᵀ(S A⁻¹ Sᵀ)⁺ S A⁻¹: the held rows S move
                // nothing.
                let k = held.len();
                let moved: Vec<BlockVector<N>> = held.iter().map(|s| inverse * s).collect();
                let schur = DMatrix::from_fn(k, k, |i, j| held[i].dot(&moved[j]));
                let scale = schur.diagonal().amax().max(f64::MIN_POSITIVE);
                let Ok(pinv) = schur.pseudo_inverse(1e-12 * scale) else {
                    return BlockMatrix::<N>::zeros();
                };
                let mut c = inverse;
                for i in 0..k {
                    for j in 0..k {
                        c -= moved[i] * moved[j].transpose() * pinv[(i, j)];
                    }
                }
                c
            });
        }
        compliance
    }
}
