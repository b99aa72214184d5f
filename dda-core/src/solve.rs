//! Sparse direct solve. The only module that names faer.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{MatMut, Side};

use crate::assembly::CscPattern;
use crate::error::DdaError;

/// Solves symmetric positive definite systems given by their lower triangle.
pub trait LinearSolver: Send {
    /// Symbolic analysis of a pattern: kept for every factorisation until
    /// the next analysis.
    fn analyse(&mut self, pattern: &CscPattern) -> Result<(), DdaError>;

    /// Factorises the matrix with the analysed pattern and these values.
    fn factorize(&mut self, values: &[f64]) -> Result<(), DdaError>;

    /// Solves in place with the last factorization.
    fn solve(&self, rhs: &mut [f64]);
}

/// Sparse Cholesky (LLᵀ) from faer with a fill-reducing ordering.
#[derive(Default)]
pub struct SparseCholesky {
    symbolic: Option<(SymbolicSparseColMat<usize>, SymbolicLlt<usize>)>,
    factor: Option<Llt<usize, f64>>,
    /// How many symbolic analyses were done (for statistics and tests).
    pub analyses: usize,
}

impl LinearSolver for SparseCholesky {
    fn analyse(&mut self, pattern: &CscPattern) -> Result<(), DdaError> {
        let structure = SymbolicSparseColMat::new_checked(
            pattern.dim,
            pattern.dim,
            pattern.col_ptr.clone(),
            None,
            pattern.row_idx.clone(),
        );
        let llt = SymbolicLlt::try_new(structure.as_ref(), Side::Lower)
            .map_err(|e| DdaError::Factorization(format!("{e:?}")))?;
        self.symbolic = Some((structure, llt));
        self.factor = None;
        self.analyses += 1;
        Ok(())
    }

    fn factorize(&mut self, values: &[f64]) -> Result<(), DdaError> {
        let (structure, symbolic) = self.symbolic.as_ref().expect("factorize before analyse");
        let dim = structure.nrows();
        let matrix = SparseColMatRef::<'_, usize, f64>::new(
            SymbolicSparseColMatRef::new_checked(
                dim,
                dim,
                structure.col_ptr(),
                None,
                structure.row_idx(),
            ),
            values,
        );
        let factor = Llt::try_new_with_symbolic(symbolic.clone(), matrix, Side::Lower)
            .map_err(|e| DdaError::Factorization(format!("{e:?}")))?;
        self.factor = Some(factor);
        Ok(())
    }

    fn solve(&self, rhs: &mut [f64]) {
        let factor = self.factor.as_ref().expect("solve before factorize");
        let n = rhs.len();
        let col = MatMut::from_column_major_slice_mut(rhs, n, 1);
        factor.solve_in_place(col);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_spd_system_and_reuses_the_analysis() {
        // [4 1 0; 1 3 1; 0 1 2] lower triangle in CSC.
        let pattern = CscPattern {
            dim: 3,
            col_ptr: vec![0, 2, 4, 5],
            row_idx: vec![0, 1, 1, 2, 2],
        };
        let mut s = SparseCholesky::default();
        s.analyse(&pattern).unwrap();
        s.factorize(&[4.0, 1.0, 3.0, 1.0, 2.0]).unwrap();
        let mut b = vec![5.0, 5.0, 3.0]; // x = (1, 1, 1)
        s.solve(&mut b);
        for x in &b {
            assert!((x - 1.0).abs() < 1e-14);
        }
        s.factorize(&[8.0, 2.0, 6.0, 2.0, 4.0]).unwrap();
        let mut b = vec![5.0, 5.0, 3.0];
        s.solve(&mut b);
        for x in &b {
            assert!((x - 0.5).abs() < 1e-14);
        }
        assert_eq!(s.analyses, 1);
    }

    #[test]
    fn reports_an_indefinite_matrix() {
        let pattern = CscPattern {
            dim: 2,
            col_ptr: vec![0, 2, 3],
            row_idx: vec![0, 1, 1],
        };
        let mut s = SparseCholesky::default();
        s.analyse(&pattern).unwrap();
        assert!(s.factorize(&[1.0, 2.0, 1.0]).is_err());
    }
}
