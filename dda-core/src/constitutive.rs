//! Constitutive laws of the blocks' uniform strain.
//!
//! `S` is the number of strain components (engineering shears) of the
//! dimension. The dimension crates provide the isotropic elastic laws.

use nalgebra::{SMatrix, SVector};

/// Stress from strain for a uniform-strain block. Stresses are tension
/// positive; strains use engineering shears.
pub trait ConstitutiveLaw<const S: usize>: Send + Sync {
    /// Stress after a strain increment from a committed stress, and the
    /// tangent d(stress)/d(strain increment). Linear laws return
    /// `stress + C·increment` and `C`.
    fn stress(
        &self,
        committed: &SVector<f64, S>,
        increment: &SVector<f64, S>,
    ) -> (SVector<f64, S>, SMatrix<f64, S, S>);

    /// The elastic stiffness scale (Young's modulus), used for automatic penalties.
    fn modulus(&self) -> f64;
}
