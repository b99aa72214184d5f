//! Block-sparse assembly of the step's system matrix.
//!
//! The matrix has one N×N block per block on the diagonal and one per pair of
//! blocks in contact. Only the lower triangle is stored (the matrix is
//! symmetric); the pattern is fixed for a step, since contacts are not searched
//! again inside the open-close loop, so the solver's symbolic analysis is reused
//! across passes.

use std::collections::HashMap;

use crate::contacts::BlockVector;
use crate::system::BlockMatrix;

/// Compressed sparse column pattern of the lower triangle.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CscPattern {
    pub dim: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

/// The lower triangle of a symmetric block-sparse matrix.
#[derive(Debug, Clone, Default)]
pub struct BlockSparse<const N: usize> {
    pub diagonal: Vec<BlockMatrix<N>>,
    /// Off-diagonal blocks (row block > column block).
    pub lower: Vec<BlockMatrix<N>>,
    /// (row block, column block) of each entry of `lower`.
    pairs: Vec<(usize, usize)>,
    index: HashMap<(usize, usize), usize>,
}

impl<const N: usize> BlockSparse<N> {
    /// A zero matrix with `blocks` diagonal blocks and one off-diagonal block
    /// for every distinct pair in `pairs`.
    pub fn new(blocks: usize, pairs: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let mut index = HashMap::new();
        let mut list = Vec::new();
        for (a, b) in pairs {
            if a == b {
                continue;
            }
            let key = (a.max(b), a.min(b));
            index.entry(key).or_insert_with(|| {
                list.push(key);
                list.len() - 1
            });
        }
        // Column-major order of blocks makes the CSC pattern easy to write.
        let mut order: Vec<usize> = (0..list.len()).collect();
        order.sort_by_key(|&i| (list[i].1, list[i].0));
        let pairs: Vec<(usize, usize)> = order.iter().map(|&i| list[i]).collect();
        let index = pairs.iter().enumerate().map(|(i, &p)| (p, i)).collect();
        Self {
            diagonal: vec![BlockMatrix::<N>::zeros(); blocks],
            lower: vec![BlockMatrix::<N>::zeros(); pairs.len()],
            pairs,
            index,
        }
    }

    pub fn block_count(&self) -> usize {
        self.diagonal.len()
    }

    pub fn clear(&mut self) {
        self.diagonal.iter_mut().for_each(|m| m.fill(0.0));
        self.lower.iter_mut().for_each(|m| m.fill(0.0));
    }

    /// Adds `m` to block (row, col) of the full symmetric matrix; the caller
    /// adds the transposed contribution to (col, row) only through this call.
    pub fn add(&mut self, row: usize, col: usize, m: &BlockMatrix<N>) {
        if row == col {
            self.diagonal[row] += m;
        } else if row > col {
            let i = self.index[&(row, col)];
            self.lower[i] += m;
        } else {
            let i = self.index[&(col, row)];
            self.lower[i] += m.transpose();
        }
    }

    /// The scalar CSC pattern of the lower triangle.
    pub fn pattern(&self) -> CscPattern {
        let blocks = self.block_count();
        let dim = blocks * N;
        let mut col_ptr = Vec::with_capacity(dim + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        let mut next = 0;
        for cb in 0..blocks {
            let start = next;
            while next < self.pairs.len() && self.pairs[next].1 == cb {
                next += 1;
            }
            for c in 0..N {
                for r in c..N {
                    row_idx.push(cb * N + r);
                }
                for &(rb, _) in &self.pairs[start..next] {
                    row_idx.extend((0..N).map(|r| rb * N + r));
                }
                col_ptr.push(row_idx.len());
            }
        }
        CscPattern {
            dim,
            col_ptr,
            row_idx,
        }
    }

    /// Values in the order of [`BlockSparse::pattern`].
    pub fn values_into(&self, values: &mut Vec<f64>) {
        values.clear();
        let mut next = 0;
        for cb in 0..self.block_count() {
            let start = next;
            while next < self.pairs.len() && self.pairs[next].1 == cb {
                next += 1;
            }
            let d = &self.diagonal[cb];
            for c in 0..N {
                values.extend((c..N).map(|r| d[(r, c)]));
                for m in &self.lower[start..next] {
                    values.extend((0..N).map(|r| m[(r, c)]));
                }
            }
        }
    }

    /// y = A x for the full symmetric matrix (used in tests and checks).
    pub fn multiply(&self, x: &[BlockVector<N>]) -> Vec<BlockVector<N>> {
        let mut y: Vec<BlockVector<N>> =
            self.diagonal.iter().zip(x).map(|(d, xi)| d * xi).collect();
        for (m, &(r, c)) in self.lower.iter().zip(&self.pairs) {
            y[r] += m * x[c];
            y[c] += m.transpose() * x[r];
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_and_values_match_the_dense_matrix() {
        const N: usize = 2;
        let mut a = BlockSparse::<N>::new(3, [(0, 2), (2, 0), (1, 2)]);
        let m = |s: f64| BlockMatrix::<N>::new(s, 1.0 + s, 2.0 + s, 3.0 + s);
        a.add(0, 0, &(m(10.0) + m(10.0).transpose()));
        a.add(1, 1, &(m(20.0) + m(20.0).transpose()));
        a.add(2, 2, &(m(30.0) + m(30.0).transpose()));
        a.add(0, 2, &m(1.0));
        a.add(2, 1, &m(2.0));
        let p = a.pattern();
        let mut v = Vec::new();
        a.values_into(&mut v);
        assert_eq!(p.row_idx.len(), v.len());
        assert_eq!(p.col_ptr.len(), p.dim + 1);
        // Rebuild the dense lower triangle and compare with multiply().
        let mut dense = vec![vec![0.0; p.dim]; p.dim];
        for (c, span) in p.col_ptr.windows(2).enumerate() {
            for (&r, &value) in p.row_idx[span[0]..span[1]].iter().zip(&v[span[0]..span[1]]) {
                assert!(r >= c, "only the lower triangle is stored");
                dense[r][c] = value;
                dense[c][r] = value;
            }
        }
        let x: Vec<BlockVector<N>> = (0..3)
            .map(|i| BlockVector::<N>::new(1.0 + i as f64, -0.5 * i as f64))
            .collect();
        let y = a.multiply(&x);
        for r in 0..p.dim {
            let expect: f64 = (0..p.dim).map(|c| dense[r][c] * x[c / N][c % N]).sum();
            assert!((y[r / N][r % N] - expect).abs() < 1e-12);
        }
        // Block (2, 0) holds m(1)ᵀ: entry (row 2*2+1, col 0) = m(1)[(0, 1)].
        assert_eq!(dense[5][0], m(1.0)[(0, 1)]);
    }
}
