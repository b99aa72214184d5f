//! The block system: what a dimension crate provides so the driver can run it.

use nalgebra::SMatrix;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::contacts::{BlockVector, Contact, EntranceRows};
use crate::error::DdaError;
use crate::loads::Support;
use crate::settings::finite;
use crate::PAIRS_PER_TASK;

/// One block's N×N matrix (mass, stiffness).
pub type BlockMatrix<const N: usize> = SMatrix<f64, N, N>;

/// What a block may do in a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum BlockKind {
    /// Translation and rotation only (3 DOF in 2D, 6 in 3D): it never
    /// strains and carries no stress.
    Rigid,
    /// Translation, rotation and uniform strain (Shi's 6 DOF in 2D, 12 in
    /// 3D).
    #[default]
    Deformable,
}

impl BlockKind {
    /// The DOF a block of this kind keeps of the `n` of a deformable one.
    /// The DOF order puts translation and rotation first and the strains
    /// after; in d dimensions there are d(d + 1)/2 of each, so a rigid block
    /// keeps the leading half.
    pub fn dofs(self, n: usize) -> usize {
        match self {
            BlockKind::Rigid => n / 2,
            BlockKind::Deformable => n,
        }
    }

    /// Checks a block's initial state: its `velocity` and `stress` are
    /// finite, and a rigid block, which never strains, carries no stress.
    /// The error names the field.
    pub fn check_state(self, velocity: &[f64], stress: &[f64]) -> Result<(), DdaError> {
        if self == BlockKind::Rigid && stress.iter().any(|s| *s != 0.0) {
            return Err(DdaError::Setting {
                field: "stress",
                message: "a rigid block carries no stress; remove the initial stress or make the block Deformable".into(),
            });
        }
        velocity
            .iter()
            .try_for_each(|v| finite("velocity", "the initial velocity", *v))?;
        stress
            .iter()
            .try_for_each(|s| finite("stress", "the initial stress", *s))
    }
}

/// A set of blocks with `N` DOF each and contacts with `T` tangential
/// directions. Everything is evaluated about the geometry at the start of the
/// step; nothing changes until [`BlockSystem::commit`], so a rejected step
/// leaves no trace. `Send`: a step runs on a thread of rayon's pool.
pub trait BlockSystem<const N: usize, const T: usize>: Send + Sync {
    /// How the system's contacts keep their entrances' rows.
    type Entrance: EntranceRows<N, T>;

    /// Number of blocks.
    fn block_count(&self) -> usize;

    /// Model length scale w0 (Shi): tolerances and bounds are fractions of it.
    fn length_scale(&self) -> f64;

    /// Stiffness scale for the automatic penalty: the largest Young's
    /// modulus (Pa).
    fn stiffness_scale(&self) -> f64;

    /// A typical block size (m): the median over the blocks of the square
    /// root of the area (2D) or the cube root of the volume (3D).
    fn block_size(&self) -> f64;

    /// The time (s) in which the scene's steady loads move a block by its
    /// own size from rest: sqrt(block size / |g|) under gravity; `None`
    /// where nothing but contacts and driven points moves the blocks. It
    /// bounds the automatic time step.
    fn motion_time(&self) -> Option<f64> {
        None
    }

    /// The automatic penalty per unit contact length (2D) or area (3D), in
    /// N/m³: twice the stiffest modulus over the typical block size, so a
    /// block's contacts are about as stiff as the block itself.
    fn automatic_penalty(&self) -> f64 {
        2.0 * self.stiffness_scale() / self.block_size()
    }

    /// How many of its N DOF block `i` moves by: the leading ones, the rest
    /// stay zero (see [`BlockKind::dofs`]). All N unless told otherwise.
    fn dofs(&self, block: usize) -> usize {
        let _ = block;
        N
    }

    /// Mass matrix of a block, ∫ρ TᵀT.
    fn mass(&self, block: usize) -> BlockMatrix<N>;

    /// Adds the block's own terms at the trial step displacement `d`, for a
    /// step ending at `time`: elastic stiffness, initial stress, body force,
    /// point loads, fixed points. Adds the tangent to `k` and the residual
    /// (applied minus internal generalised force) to `r`; only the DOF the
    /// block keeps ([`BlockSystem::dofs`]) need be right.
    fn block_terms(
        &self,
        block: usize,
        time: f64,
        d: &BlockVector<N>,
        k: &mut BlockMatrix<N>,
        r: &mut BlockVector<N>,
    );

    /// Broad phase: pairs (i, j), i < j, sorted, that hold every pair of
    /// blocks whose bounds come within `range` of each other (and may hold
    /// more: the narrow phase keeps only contacts within `range`).
    fn near_pairs(&self, range: f64) -> Vec<(usize, usize)>;

    /// Narrow phase: the contact candidates between blocks `i` < `j` within
    /// `range`, linearised about the current geometry, with fresh records and
    /// the pair's law index.
    fn pair_contacts(&self, i: usize, j: usize, range: f64) -> Vec<Contact<N, T, Self::Entrance>>;

    /// The narrow phase of `pairs` (as [`BlockSystem::near_pairs`] gave
    /// them for `range`), in their order, on every core.
    fn pairs_contacts(
        &self,
        pairs: &[(usize, usize)],
        range: f64,
    ) -> Vec<Contact<N, T, Self::Entrance>> {
        self.pairs_contacts_carried(pairs, range, &|_, _| {})
    }

    /// [`BlockSystem::pairs_contacts`], handing each pair's contacts to
    /// `carry` (with the pair's index in `pairs`) as they are made, before
    /// they join the others: the driver moves the last step's records onto
    /// them there, on the core that made them.
    fn pairs_contacts_carried(
        &self,
        pairs: &[(usize, usize)],
        range: f64,
        carry: &Carry<'_, N, T, Self::Entrance>,
    ) -> Vec<Contact<N, T, Self::Entrance>> {
        each_pair_contacts(self, pairs, range, carry)
    }

    /// Contact candidates within `range` of each other: the narrow phase of
    /// every near pair.
    fn find_contacts(&self, range: f64) -> Vec<Contact<N, T, Self::Entrance>> {
        let mut contacts = Vec::new();
        for (i, j) in self.near_pairs(range) {
            contacts.extend(self.pair_contacts(i, j, range));
        }
        contacts
    }

    /// The held directions of the fixed and driven points for a step from
    /// `start` to `end` (for the dashpots of contact damping).
    fn supports(&self, _start: f64, _end: f64) -> Vec<Support<N>> {
        Vec::new()
    }

    /// Largest displacement of any boundary point for step displacements `d`.
    fn max_displacement(&self, d: &[BlockVector<N>]) -> f64;

    /// Largest motion of a block's boundary points against each other (its
    /// turn and strain) for step displacements `d`, or a bound on it: twice
    /// the largest about its centroid, which a rectangle turning about a
    /// corner (a rocking column's pivot) reaches. For a block with
    /// `whole[i]` set, its points' whole displacement instead. The
    /// automatic step bounds it; the default counts every block whole.
    fn max_own_motion(&self, d: &[BlockVector<N>], whole: &[bool]) -> f64 {
        let _ = whole;
        self.max_displacement(d)
    }

    /// Potential energy of the blocks (gravity, strain, fixed-point
    /// springs), or `None` when loads or moving supports do work on them, so
    /// the driver's energy check does not apply.
    fn potential_energy(&self) -> Option<f64> {
        None
    }

    /// Applies an accepted step: moves the blocks, updates stresses and fixed
    /// point drifts. `time` is the end of the step.
    fn commit(&mut self, d: &[BlockVector<N>], dt: f64, time: f64);

    /// What the accepted steps have changed, for a checkpoint.
    fn save_state(&self) -> Result<SystemState, DdaError> {
        Err(DdaError::Checkpoint(
            "this block system cannot be saved in a checkpoint".into(),
        ))
    }

    /// Puts the system back as [`BlockSystem::save_state`] found it; the
    /// system must be built from the same scene.
    fn restore_state(&mut self, _state: &SystemState) -> Result<(), DdaError> {
        Err(DdaError::Checkpoint(
            "this block system cannot be restored from a checkpoint".into(),
        ))
    }
}

/// What a block's motion has changed since it was built: enough to put it
/// back where a checkpoint found it (its integrals follow from these).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BlockState {
    /// Vertex coordinates, one point after another.
    pub vertices: Vec<f64>,
    pub stress: Vec<f64>,
    pub strain: Vec<f64>,
    /// Accumulated rotation: the angle (2D) or the rotation vector (3D).
    pub rotation: Vec<f64>,
}

/// What a block system's accepted steps have changed: the blocks, and the
/// fixed, load and measured points that move with them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SystemState {
    pub blocks: Vec<BlockState>,
    /// Coordinates of each fixed, load and measured point, now.
    pub fixed_points: Vec<Vec<f64>>,
    pub load_points: Vec<Vec<f64>>,
    pub measured_points: Vec<Vec<f64>>,
}

/// Each pair's [`BlockSystem::pair_contacts`] on any thread, gathered in
/// pair order.
pub(crate) fn each_pair_contacts<S, const N: usize, const T: usize>(
    system: &S,
    pairs: &[(usize, usize)],
    range: f64,
    carry: &Carry<'_, N, T, S::Entrance>,
) -> Vec<Contact<N, T, S::Entrance>>
where
    S: BlockSystem<N, T> + ?Sized,
{
    (pairs.par_iter().enumerate())
        .with_min_len(PAIRS_PER_TASK)
        .flat_map_iter(|(k, &(i, j))| {
            let mut found = system.pair_contacts(i, j, range);
            carry(k, &mut found);
            found
        })
        .collect()
}

/// What [`BlockSystem::pairs_contacts_carried`] hands each pair's contacts
/// to: the pair's index and its contacts.
pub type Carry<'a, const N: usize, const T: usize, E> =
    dyn Fn(usize, &mut [Contact<N, T, E>]) + Sync + 'a;

#[cfg(test)]
mod tests {
    use super::*;

    fn field_of(e: DdaError) -> &'static str {
        match e {
            DdaError::Setting { field, .. } => field,
            e => panic!("{e}"),
        }
    }

    #[test]
    fn an_initial_state_is_finite_and_a_rigid_block_unstressed() {
        let (rigid, deformable) = (BlockKind::Rigid, BlockKind::Deformable);
        assert!(deformable
            .check_state(&[1.0, 0.0, 0.5], &[-1e5, 0.0, 0.0])
            .is_ok());
        assert!(rigid.check_state(&[1.0, 0.0, 0.5], &[0.0; 3]).is_ok());
        let e = rigid.check_state(&[0.0; 3], &[-1e5, 0.0, 0.0]).unwrap_err();
        assert!(e.to_string().contains("a rigid block carries no stress"));
        assert_eq!(field_of(e), "stress");
        let e = deformable
            .check_state(&[f64::NAN; 6], &[0.0; 6])
            .unwrap_err();
        assert!(e.to_string().contains("the initial velocity is NaN"));
        assert_eq!(field_of(e), "velocity");
        let e = deformable.check_state(&[0.0; 3], &[0.0, f64::INFINITY, 0.0]);
        assert_eq!(field_of(e.unwrap_err()), "stress");
    }
}
