//! Element kinematics: how a block's DOF move its points.

use nalgebra::{SMatrix, SVector};

/// A block with `N` DOF in a space of `D` dimensions.
pub trait ElementKinematics<const N: usize, const D: usize> {
    /// The reference point the DOF are taken about (the centroid).
    fn reference_point(&self) -> SVector<f64, D>;

    /// The T-matrix: the displacement of point `p` is `T(p)·d` to first order.
    fn t_matrix(&self, p: &SVector<f64, D>) -> SMatrix<f64, D, N>;

    /// ∫ρTᵀT over the block.
    fn mass_matrix(&self) -> SMatrix<f64, N, N>;

    /// Where point `p` goes when a step `d` is committed. Its derivative at
    /// `d = 0` is the T-matrix; unlike `p + T(p)·d` it may rotate exactly.
    fn displaced(&self, p: &SVector<f64, D>, d: &SVector<f64, N>) -> SVector<f64, D>;
}
