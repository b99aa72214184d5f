//! Contacts as the driver sees them: linearised gap and tangential
//! displacement in terms of the two blocks' step DOF, plus the record a
//! contact carries from step to step.
//!
//! `N` is the number of DOF per block, `T` the number of tangential directions
//! of the contact frame. The dimension crates fill these in; nothing here knows
//! what they are.

use std::collections::HashMap;

use nalgebra::SVector;

use crate::contact::{ContactState, History};

/// One block's step displacement (or any per-block DOF vector).
pub type BlockVector<const N: usize> = SVector<f64, N>;

/// Identifies a contact across steps so its state can be carried over.
///
/// `block_a`/`feature_a` is the entering feature (a vertex), `block_b`/`feature_b`
/// the feature it enters through (an edge or a face; for a contact with several
/// candidate entrances, a vertex). Meaning of the features is up to the
/// dimension crate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ContactKey {
    pub block_a: u32,
    pub feature_a: u32,
    pub block_b: u32,
    pub feature_b: u32,
}

impl ContactKey {
    /// The key without the entered feature, used when a vertex has moved onto
    /// a neighbouring edge or face: the contact keeps its state.
    fn coarse(&self) -> (u32, u32, u32) {
        (self.block_a, self.feature_a, self.block_b)
    }
}

/// A reference line (2D) or face (3D) through which the entering feature may
/// enter block `b`, linearised about the start of the step:
///
/// `gap(D) = gap + normal[0]·D_a + normal[1]·D_b`
/// `shear_k(D) = tangents[k][0]·D_a + tangents[k][1]·D_b` (this step's part)
#[derive(Debug, Clone, PartialEq)]
pub struct Entrance<const N: usize, const T: usize> {
    pub gap: f64,
    pub normal: [BlockVector<N>; 2],
    pub tangents: [[BlockVector<N>; 2]; T],
}

impl<const N: usize, const T: usize> Entrance<N, T> {
    /// Linearised gap at the step displacements of the two blocks.
    pub fn gap_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> f64 {
        self.gap + self.normal[0].dot(da) + self.normal[1].dot(db)
    }

    /// This step's relative tangential displacement.
    pub fn shear_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> SVector<f64, T> {
        SVector::<f64, T>::from_fn(|k, _| self.tangents[k][0].dot(da) + self.tangents[k][1].dot(db))
    }
}

/// What a contact remembers between steps. Owned by the driver; the dimension
/// crates only create contacts with a fresh record.
pub struct ContactRecord<const T: usize> {
    pub state: ContactState,
    /// Elastic shear displacement from the lock point, in the entrance's
    /// tangent basis (zero unless locked).
    pub shear: SVector<f64, T>,
    /// Unit slip direction of the last sliding step (zero if none).
    pub slip_direction: SVector<f64, T>,
    pub slip_path: f64,
    pub slip_rate: f64,
    /// Index of the entrance used in the last accepted step.
    pub entrance: usize,
    /// Normal and shear forces of the last accepted step (for output).
    pub normal_force: f64,
    pub shear_force: f64,
    /// The law's own history; `None` until the driver first sees the contact.
    pub history: Option<History>,
}

impl<const T: usize> Default for ContactRecord<T> {
    fn default() -> Self {
        Self {
            state: ContactState::Open,
            shear: SVector::zeros(),
            slip_direction: SVector::zeros(),
            slip_path: 0.0,
            slip_rate: 0.0,
            entrance: 0,
            normal_force: 0.0,
            shear_force: 0.0,
            history: None,
        }
    }
}

impl<const T: usize> std::fmt::Debug for ContactRecord<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactRecord")
            .field("state", &self.state)
            .field("shear", &self.shear)
            .field("slip_path", &self.slip_path)
            .finish_non_exhaustive()
    }
}

/// A contact candidate for one step: which blocks, which law, its entrances
/// (at least one; with several, the one with the largest gap at the trial
/// displacement is used: Shi's entrance-line choice), and its record.
#[derive(Debug)]
pub struct Contact<const N: usize, const T: usize> {
    pub key: ContactKey,
    pub blocks: [usize; 2],
    /// Index into the driver's law table.
    pub law: usize,
    /// Boundary length (2D) or area (3D) the contact stands for: what its
    /// cohesion and tensile strength act over (zero for a point contact).
    pub length: f64,
    /// Boundary length (2D, per unit thickness) or area (3D) the contact's
    /// springs stand for: `length` where the contact has one; for a corner
    /// touching a face (a rocking block's pivot), the entering vertex's share
    /// of its side that most nearly faces the entered one. Never zero, so the
    /// springs of every closed contact are the penalty times this.
    pub spring_length: f64,
    pub entrances: Vec<Entrance<N, T>>,
    pub record: ContactRecord<T>,
}

/// Moves the records of last step's contacts onto this step's, matching by
/// key, then by the coarse key (same vertex against the same block) when the
/// vertex has moved onto a neighbouring edge or face. A record only moves
/// between contacts of the same law.
pub fn transfer_records<const N: usize, const T: usize>(
    old: &mut [Contact<N, T>],
    new: &mut [Contact<N, T>],
) {
    let mut exact: HashMap<ContactKey, usize> = HashMap::with_capacity(old.len());
    let mut coarse: HashMap<(u32, u32, u32), usize> = HashMap::with_capacity(old.len());
    for (i, c) in old.iter().enumerate() {
        exact.insert(c.key, i);
        // Prefer a closed contact when several share the coarse key.
        let prefer = coarse
            .get(&c.key.coarse())
            .is_none_or(|&j| !old[j].record.state.is_closed());
        if prefer {
            coarse.insert(c.key.coarse(), i);
        }
    }
    let mut taken = vec![false; old.len()];
    // Exact matches first so a coarse match never steals an exact one.
    for c in new.iter_mut() {
        if let Some(&i) = exact.get(&c.key) {
            if !taken[i] && old[i].law == c.law {
                taken[i] = true;
                c.record = std::mem::take(&mut old[i].record);
            }
        }
    }
    for c in new.iter_mut().filter(|c| c.record.history.is_none()) {
        if let Some(&i) = coarse.get(&c.key.coarse()) {
            if !taken[i] && old[i].law == c.law && old[i].record.state.is_closed() {
                taken[i] = true;
                let mut record = std::mem::take(&mut old[i].record);
                // Another entrance set: its own indexing and tangent basis.
                record.entrance = 0;
                record.shear = SVector::zeros();
                c.record = record;
            }
        }
    }
}
