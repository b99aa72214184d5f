//! The driver's whole state as bytes, and back: what a checkpoint keeps so
//! a resumed run goes on bit for bit as if it had never stopped.
//!
//! Contacts keep their keys and records only: their entrances are found
//! again by the next step's search, which moves the records onto them. The
//! matrix pattern is kept as its block pairs, since another pattern would
//! order the factorisation, and so the round-off, differently.

use nalgebra::SVector;
use serde::{Deserialize, Serialize};

use super::predict::RecentSteps;
use super::weighing::Weighing;
use super::Driver;
use crate::contact::ContactState;
use crate::contacts::{BlockVector, Contact, ContactKey, ContactRecord};
use crate::error::DdaError;
use crate::statistics::Statistics;
use crate::system::{BlockSystem, SystemState};

/// The driver's state: every field that a step reads and an earlier step
/// wrote.
#[derive(Serialize, Deserialize)]
struct Saved {
    dofs: usize,
    tangents: usize,
    laws: usize,
    time: f64,
    time_carry: f64,
    dt: f64,
    dt_next: f64,
    even_step: Option<f64>,
    last_dt: Option<f64>,
    penalty: f64,
    last_moved: f64,
    passes_before: f64,
    slow_carried: usize,
    pattern_reach: f64,
    energy_floor: Option<f64>,
    first_potential: Option<f64>,
    velocity: Vec<Vec<f64>>,
    half_velocity: Vec<Vec<f64>>,
    recent: RecentSteps,
    contacts: Vec<SavedContact>,
    pattern: Vec<(usize, usize)>,
    /// The matrix values of the factor the next step starts on.
    factored: Option<Vec<f64>>,
    factor_change: Option<f64>,
    weighing: Option<Weighing>,
    statistics: Statistics,
    system: SystemState,
}

/// A contact's key and record; its law's history in the law's own form.
#[derive(Serialize, Deserialize)]
struct SavedContact {
    key: ContactKey,
    blocks: [usize; 2],
    law: usize,
    state: ContactState,
    shear: Vec<f64>,
    slip_direction: Vec<f64>,
    slip_path: f64,
    slip_rate: f64,
    entrance: usize,
    normal_force: f64,
    shear_force: f64,
    history: Option<Vec<u8>>,
}

fn broken(e: postcard::Error) -> DdaError {
    DdaError::Checkpoint(format!(
        "the checkpoint does not read ({e}): it is damaged or from another version"
    ))
}

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// The state after the last accepted step, as bytes for
    /// [`Driver::restore`].
    pub fn save(&self) -> Result<Vec<u8>, DdaError> {
        let contacts = self
            .contacts
            .iter()
            .map(|c| {
                let r = &c.record;
                let history = match &r.history {
                    Some(h) => Some(self.laws[c.law].save_history(h)?),
                    None => None,
                };
                Ok(SavedContact {
                    key: c.key,
                    blocks: c.blocks,
                    law: c.law,
                    state: r.state,
                    shear: r.shear.iter().copied().collect(),
                    slip_direction: r.slip_direction.iter().copied().collect(),
                    slip_path: r.slip_path,
                    slip_rate: r.slip_rate,
                    entrance: r.entrance,
                    normal_force: r.normal_force,
                    shear_force: r.shear_force,
                    history,
                })
            })
            .collect::<Result<Vec<_>, DdaError>>()?;
        let saved = Saved {
            dofs: N,
            tangents: T,
            laws: self.laws.len(),
            time: self.time,
            time_carry: self.time_carry,
            dt: self.dt,
            dt_next: self.dt_next,
            even_step: self.even_step,
            last_dt: self.last_dt,
            penalty: self.penalty,
            last_moved: self.last_moved,
            passes_before: self.passes_before,
            slow_carried: self.slow_carried,
            pattern_reach: self.pattern_reach,
            energy_floor: self.energy_floor,
            first_potential: self.first_potential,
            velocity: self
                .velocity
                .iter()
                .map(|v| v.iter().copied().collect())
                .collect(),
            half_velocity: (self.half_velocity.iter())
                .map(|v| v.iter().copied().collect())
                .collect(),
            recent: self.recent.clone(),
            contacts,
            pattern: self.matrix.pairs().to_vec(),
            factored: self.factored.clone(),
            factor_change: self.factor_change,
            weighing: self.weighing.clone(),
            statistics: self.stats.clone(),
            system: self.system.save_state()?,
        };
        postcard::to_stdvec(&saved)
            .map_err(|e| DdaError::Checkpoint(format!("cannot save the run: {e}")))
    }

    /// Puts a driver built from the same scene where [`Driver::save`] found
    /// its run. The wall-clock times in the statistics go on from the saved
    /// ones.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<(), DdaError> {
        let saved: Saved = postcard::from_bytes(bytes).map_err(broken)?;
        let blocks = self.system.block_count();
        let fits = saved.dofs == N
            && saved.tangents == T
            && saved.laws == self.laws.len()
            && saved.velocity.len() == blocks
            && saved.velocity.iter().all(|v| v.len() == N)
            && [0, blocks].contains(&saved.half_velocity.len())
            && saved.half_velocity.iter().all(|v| v.len() == N)
            && saved.recent.fits(blocks * N)
            && saved.pattern.iter().all(|&(a, b)| a < blocks && b < blocks)
            && saved.contacts.iter().all(|c| {
                c.law < self.laws.len()
                    && c.blocks.iter().all(|&b| b < blocks)
                    && c.shear.len() == T
                    && c.slip_direction.len() == T
            });
        if !fits {
            return Err(DdaError::Checkpoint(
                "the checkpoint's blocks, contacts or laws do not match the scene's: it was saved from another scene".into(),
            ));
        }
        self.system.restore_state(&saved.system)?;
        let mut contacts = Vec::with_capacity(saved.contacts.len());
        for c in saved.contacts {
            let history = match &c.history {
                Some(bytes) => Some(self.laws[c.law].load_history(bytes)?),
                None => None,
            };
            contacts.push(Contact {
                blocks: c.blocks,
                record: ContactRecord {
                    state: c.state,
                    shear: SVector::from_column_slice(&c.shear),
                    slip_direction: SVector::from_column_slice(&c.slip_direction),
                    slip_path: c.slip_path,
                    slip_rate: c.slip_rate,
                    entrance: c.entrance,
                    normal_force: c.normal_force,
                    shear_force: c.shear_force,
                    history,
                },
                ..Contact::new(c.key, c.law, (0.0, 0.0), Vec::new())
            });
        }
        self.contacts = contacts;
        self.searched = Default::default();
        self.chosen.clear();
        self.velocity = saved
            .velocity
            .iter()
            .map(|v| BlockVector::<N>::from_column_slice(v))
            .collect();
        self.half_velocity = (saved.half_velocity.iter())
            .map(|v| BlockVector::<N>::from_column_slice(v))
            .collect();
        self.recent = saved.recent;
        self.time = saved.time;
        self.time_carry = saved.time_carry;
        self.dt = saved.dt;
        self.dt_next = saved.dt_next;
        self.even_step = saved.even_step;
        self.last_dt = saved.last_dt;
        self.penalty = saved.penalty;
        self.last_moved = saved.last_moved;
        self.passes_before = saved.passes_before;
        self.slow_carried = saved.slow_carried;
        self.pattern_reach = saved.pattern_reach;
        self.energy_floor = saved.energy_floor;
        self.first_potential = saved.first_potential;
        self.factor_change = saved.factor_change;
        self.weighing = saved.weighing;
        self.stats = saved.statistics;
        self.rebuild_pattern(saved.pattern);
        self.find_slots();
        if let Some(values) = saved.factored {
            // The factor the next step starts on, made again from its
            // values (not counted: the run made it before it stopped).
            let pattern = self.matrix.pattern();
            if values.len() != pattern.row_idx.len() {
                return Err(DdaError::Checkpoint(
                    "the checkpoint's matrix does not match its contact pattern: it is damaged or from another version".into(),
                ));
            }
            self.solver.analyse(&pattern)?;
            self.solver.factorize(&values)?;
            self.analysed = true;
            self.factored = Some(values);
        }
        Ok(())
    }
}
