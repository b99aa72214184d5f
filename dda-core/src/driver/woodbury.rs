//! A factored matrix plus a few rank-one terms, solved by the
//! Sherman-Morrison-Woodbury formula: (K + Σ sⱼuⱼvⱼᵀ)⁻¹y = x − Z (I +
//! S VᵀZ)⁻¹ S Vᵀx, with x = K⁻¹y and Z = K⁻¹U made once for the terms.

use nalgebra::{DMatrix, DVector, LU};

use crate::assembly::BlockSparse;
use crate::contacts::BlockVector;
use crate::solve::{LinearSolver, UpdateTerm};

/// A rank-one term `slope`·u·vᵀ of the tangent, u and v on blocks `blocks`:
/// how a sliding contact's friction changes with its normal gap, or a
/// spring that came, went or changed since the factor was made.
#[derive(Clone)]
pub(super) struct RankOne<const N: usize> {
    pub(super) blocks: [usize; 2],
    pub(super) u: [BlockVector<N>; 2],
    pub(super) v: [BlockVector<N>; 2],
    pub(super) slope: f64,
}

impl<const N: usize> RankOne<N> {
    /// vᵀx.
    pub(super) fn dot(&self, matrix: &BlockSparse<N>, x: &[f64]) -> f64 {
        self.v[0].dot(&matrix.block(x, self.blocks[0]))
            + self.v[1].dot(&matrix.block(x, self.blocks[1]))
    }
}

/// The terms with Z = K⁻¹U and the LU factors of I + S VᵀZ.
pub(super) struct Woodbury<const N: usize> {
    terms: Vec<RankOne<N>>,
    /// Z's columns, one after another.
    z: Vec<f64>,
    capacitance: LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
}

impl<const N: usize> Woodbury<N> {
    /// Makes Z on the solver's factor, column by column.
    pub fn new(terms: Vec<RankOne<N>>, matrix: &BlockSparse<N>, solver: &dyn LinearSolver) -> Self {
        let (m, size) = (terms.len(), matrix.dim());
        let mut z = vec![0.0; m * size];
        for (t, column) in terms.iter().zip(z.chunks_exact_mut(size.max(1))) {
            matrix.add_block(column, t.blocks[0], &t.u[0]);
            matrix.add_block(column, t.blocks[1], &t.u[1]);
            solver.solve(column);
        }
        let column = |j: usize| &z[j * size..(j + 1) * size];
        let capacitance = DMatrix::from_fn(m, m, |i, j| {
            let identity = if i == j { 1.0 } else { 0.0 };
            identity + terms[i].slope * terms[i].dot(matrix, column(j))
        })
        .lu();
        Self {
            terms,
            z,
            capacitance,
        }
    }

    /// Turns `y = K⁻¹r` into (K + Σ sⱼuⱼvⱼᵀ)⁻¹r; leaves it where the
    /// capacitance matrix is singular.
    pub fn apply(&self, matrix: &BlockSparse<N>, y: &mut [f64]) {
        let m = self.terms.len();
        if m == 0 {
            // nalgebra's LU of an empty matrix does not solve.
            return;
        }
        let rhs = DVector::from_fn(m, |i, _| self.terms[i].slope * self.terms[i].dot(matrix, y));
        let Some(c) = self.capacitance.solve(&rhs) else {
            return;
        };
        for (zj, cj) in self.z.chunks_exact(y.len().max(1)).zip(c.iter()) {
            for (yi, zi) in y.iter_mut().zip(zj) {
                *yi -= cj * zi;
            }
        }
    }
}

/// The terms as the solver's updates of its factor
/// (`LinearSolver::update`), u and v over the unknowns.
pub(super) fn update_terms<const N: usize>(
    terms: &[RankOne<N>],
    matrix: &BlockSparse<N>,
) -> Vec<UpdateTerm> {
    let on = |blocks: [usize; 2], x: &[BlockVector<N>; 2]| -> Vec<(usize, f64)> {
        (matrix.entries(blocks[0], &x[0]))
            .chain(matrix.entries(blocks[1], &x[1]))
            .collect()
    };
    (terms.iter())
        .map(|t| UpdateTerm {
            u: on(t.blocks, &t.u),
            v: on(t.blocks, &t.v),
            slope: t.slope,
        })
        .collect()
}
