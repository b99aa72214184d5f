//! The contact springs in the factor's matrix, so that a later open-close
//! pass can move on that factor with the springs that came, went or
//! changed since (a few contacts opened or closed) as rank-one terms
//! (`woodbury.rs`), instead of factorising again.

use nalgebra::SVector;
use rayon::prelude::*;

use super::assemble::spring_terms;
use super::chosen::Chosen;
use super::terms::ContactLoad;
use super::woodbury::RankOne;
use crate::contacts::{BlockVector, Contact, EntranceRows};
use crate::CONTACTS_PER_TASK;

/// One closed contact's springs as a matrix holds them.
#[derive(Clone, Copy)]
struct Springs<const T: usize> {
    entrance: usize,
    normal: f64,
    shear: SVector<f64, T>,
    turning: f64,
    direction: SVector<f64, T>,
}

impl<const T: usize> Springs<T> {
    fn of<const N: usize>(load: &ContactLoad<N, T>, entrance: usize) -> Self {
        Self {
            entrance,
            normal: load.normal_stiffness,
            shear: load.shear_stiffness,
            turning: load.turning,
            direction: load.direction,
        }
    }

    /// Whether the two hold the same springs, but for changes that move no
    /// matrix entry by more than `floor` (on the entrance's rows `rows`):
    /// those are left to the moves, as on a carried factor.
    fn same<const N: usize>(
        &self,
        other: &Self,
        rows: &impl EntranceRows<N, T>,
        floor: f64,
    ) -> bool {
        let size = |g: &[BlockVector<N>; 2]| g[0].amax().max(g[1].amax()).powi(2);
        let near = |a: f64, b: f64, size: f64| (a - b).abs() * size <= floor;
        let tangents = (0..T).map(|k| size(&rows.tangent(k))).fold(0.0, f64::max);
        self.entrance == other.entrance
            && near(self.normal, other.normal, size(&rows.normal()))
            && (self.shear.iter().zip(&other.shear)).all(|(a, b)| near(*a, *b, tangents))
            && near(self.turning, other.turning, tangents)
    }

    /// The load that adds these terms.
    fn load<const N: usize>(&self) -> ContactLoad<N, T> {
        ContactLoad {
            force: [BlockVector::zeros(); 2],
            normal_stiffness: self.normal,
            shear_stiffness: self.shear,
            turning: self.turning,
            direction: self.direction,
            slope: 0.0,
            slipping: false,
        }
    }
}

/// Each contact's springs in the factor's matrix, within one step attempt
/// (the contacts and their entrances are the attempt's).
#[derive(Default)]
pub(super) struct FactorSprings<const T: usize> {
    held: Option<Vec<Option<Springs<T>>>>,
}

impl<const T: usize> FactorSprings<T> {
    /// The factor is now the matrix of these loads (the last tangent
    /// assembly's) at these entrances.
    pub fn record<const N: usize>(
        &mut self,
        loads: &[Option<ContactLoad<N, T>>],
        entrances: &[usize],
    ) {
        // On every core: a contact's load is some 200 bytes in 3D, and one
        // core walking 119,400 of them took 2.7 ms a step.
        let held = self.held.get_or_insert_with(Vec::new);
        (loads.par_iter().zip(entrances))
            .with_min_len(CONTACTS_PER_TASK)
            .map(|(load, &e)| load.as_ref().map(|l| Springs::of(l, e)))
            .collect_into_vec(held);
    }

    /// The factor's springs are unknown (a new attempt, a new factor made
    /// elsewhere).
    pub fn forget(&mut self) {
        self.held = None;
    }

    /// The terms by which the matrix of `loads` at `entrances` differs
    /// from the factor's, if known and at most `limit`: each contact whose
    /// springs changed a matrix entry by more than `floor`, its springs as
    /// the factor holds them taken away, and its springs now added.
    pub fn changed<const N: usize, E: EntranceRows<N, T>>(
        &self,
        loads: &[Option<ContactLoad<N, T>>],
        entrances: &[usize],
        contacts: &[Contact<N, T, E>],
        chosen: &Chosen<N, T, E>,
        limit: usize,
        floor: f64,
    ) -> Option<Vec<RankOne<N>>> {
        let held = self.held.as_ref().filter(|h| h.len() == loads.len())?;
        let mut terms = Vec::new();
        for (i, (was, load)) in held.iter().zip(loads).enumerate() {
            let now = load.as_ref().map(|l| Springs::of(l, entrances[i]));
            if match (was, &now) {
                (Some(a), Some(b)) => a.same(b, chosen.of(contacts, i, b.entrance), floor),
                (None, None) => true,
                _ => false,
            } {
                continue;
            }
            let blocks = contacts[i].blocks;
            let mut add = |springs: &Springs<T>, sign: f64| {
                let entrance = chosen.of(contacts, i, springs.entrance);
                spring_terms(&springs.load(), entrance, |g, h, k| {
                    terms.push(RankOne {
                        blocks,
                        u: *g,
                        v: *h,
                        slope: sign * k,
                    });
                });
            };
            if let Some(was) = was {
                add(was, -1.0);
            }
            if let Some(now) = &now {
                add(now, 1.0);
            }
            if terms.len() > limit {
                return None;
            }
        }
        Some(terms)
    }
}
