//! The matrix times a vector: GMRES's product with the whole tangent's
//! symmetric part, row block by row block on every core.

use rayon::prelude::*;

use super::BlockSparse;
use crate::by_block::ByBlock;
use crate::contacts::BlockVector;
use crate::BLOCKS_PER_TASK;

impl<const N: usize> BlockSparse<N> {
    /// y = A x for the full symmetric matrix on the global vector of kept
    /// DOF.
    pub fn multiply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.dim()];
        self.multiply_into(x, &mut y);
        y
    }

    /// `y` = A x, as [`BlockSparse::multiply`], into `y` (the whole-tangent
    /// GMRES's product, several a move): row block by row block on every
    /// core. Each block's sum is made in the order of one sweep over the
    /// diagonal and then the pairs (its pairs as a row come before those
    /// as a column), so the product is the same to the last bit on any
    /// number of cores. On one core it took a fifth of a product on the
    /// 10,051-block deformable wall, its substitution the rest.
    pub fn multiply_into(&self, x: &[f64], y: &mut [f64]) {
        let rows = self.rows.get_or_init(|| {
            let mut rows = ByBlock::default();
            rows.fill(self.dofs.len(), self.pairs.iter().map(|&(r, _)| [r]));
            rows
        });
        let parts = self.split_blocks(y);
        (parts.into_par_iter().with_min_len(BLOCKS_PER_TASK))
            .enumerate()
            .for_each(|(i, part)| {
                let mut sum = BlockVector::<N>::zeros();
                sum += self.diagonal[i] * self.block(x, i);
                for &p in rows.of(i) {
                    sum += self.lower[p] * self.block(x, self.pairs[p].1);
                }
                for p in self.columns[i]..self.columns[i + 1] {
                    sum += self.lower[p].transpose() * self.block(x, self.pairs[p].0);
                }
                part.copy_from_slice(&sum.as_slice()[..part.len()]);
            });
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::dense;
    use super::*;
    use crate::system::BlockMatrix;

    /// The product row block by row block is one sweep's over the diagonal
    /// and then the pairs, to the last bit, on one core and on four, with
    /// blocks keeping all their DOF or some; and it is the dense product.
    #[test]
    fn the_product_by_rows_is_one_sweeps_to_the_last_bit() {
        let blocks = 600;
        let dofs: Vec<usize> = (0..blocks).map(|i| [6, 3, 6, 6, 2][i % 5]).collect();
        // Each block against a few near it and one far off, as contacts
        // pair blocks across a wall's courses.
        let pairs =
            (0..blocks).flat_map(|i| [1, 2, 17, 251].map(move |d| (i, (i * 7 + d) % blocks)));
        let mut a = BlockSparse::<6>::new(dofs.clone(), pairs);
        let value = |k: usize| ((k * 2_654_435_761) % 1_000) as f64 / 97.0 - 5.0;
        for i in 0..blocks {
            let m = BlockMatrix::<6>::from_fn(|r, c| value(i * 36 + r * 6 + c));
            a.add(i, i, &(m + m.transpose()));
        }
        for (k, &(r, c)) in a.pairs().to_vec().iter().enumerate() {
            a.add(
                r,
                c,
                &BlockMatrix::<6>::from_fn(|x, y| value(k * 31 + x * 6 + y)),
            );
        }
        let x: Vec<f64> = (0..a.dim()).map(|k| value(k * 13) * 1e-3).collect();
        // One sweep, block by block and then pair by pair.
        let mut sweep = vec![0.0; a.dim()];
        for (i, d) in a.diagonal.iter().enumerate() {
            a.add_block(&mut sweep, i, &(d * a.block(&x, i)));
        }
        for (m, &(r, c)) in a.lower.iter().zip(a.pairs()) {
            a.add_block(&mut sweep, r, &(m * a.block(&x, c)));
            a.add_block(&mut sweep, c, &(m.transpose() * a.block(&x, r)));
        }
        let bits = |y: &[f64]| y.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
            let y = pool.expect("a pool").install(|| a.multiply(&x));
            assert_eq!(bits(&y), bits(&sweep), "{threads} threads");
        }
        let p = a.pattern();
        let mut v = Vec::new();
        a.values_into(&mut v);
        let dense = dense(&p, &v);
        let y = a.multiply(&x);
        for r in 0..p.dim {
            let expect: f64 = (0..p.dim).map(|c| dense[r][c] * x[c]).sum();
            assert!(
                (y[r] - expect).abs() < 1e-9 * (1.0 + expect.abs()),
                "row {r}"
            );
        }
    }
}
