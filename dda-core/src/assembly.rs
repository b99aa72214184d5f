//! Block-sparse assembly of the step's system matrix.
//!
//! The matrix has one block per block on the diagonal and one per pair of
//! blocks in contact. Block i takes the leading `dofs[i]` of its N DOF (a
//! rigid block its translation and rotation): the rest never enter the
//! matrix, so they stay exactly zero, and a system of rigid blocks is
//! factorised at the size of its rigid DOF. Only the lower triangle is stored
//! (the matrix is symmetric). The driver chooses the pairs: those whose
//! contacts can close in the step, kept with hysteresis, so the solver's
//! symbolic analysis is reused across passes and steps.

use rayon::prelude::*;

use crate::contacts::BlockVector;
use crate::system::BlockMatrix;
use crate::BLOCKS_PER_TASK;

mod product;

/// Compressed sparse column pattern of the lower triangle.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CscPattern {
    pub dim: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// Where each block's DOF start, then `dim`: block i's diagonal block
    /// spans `blocks[i]..blocks[i + 1]` (empty when not known).
    pub blocks: Vec<usize>,
}

/// Adds k·g·hᵀ over the first `rows` × `cols` entries of `m`, or its
/// transpose: the one sum of [`BlockSparse::add_outer`], for a caller that
/// holds the block itself.
pub fn add_outer_into<const N: usize>(
    m: &mut BlockMatrix<N>,
    (rows, cols): (usize, usize),
    g: &BlockVector<N>,
    h: &BlockVector<N>,
    k: f64,
    transposed: bool,
) {
    let (g, h) = (&g.as_slice()[..rows], &h.as_slice()[..cols]);
    // Column-major: entry (r, c) is at r + c·N. Each entry takes one
    // product, (g_r·h_c)·k, so the loops' order changes no sum.
    let m = m.as_mut_slice();
    let (outer, inner) = if transposed { (g, h) } else { (h, g) };
    for (j, &a) in outer.iter().enumerate() {
        let column = &mut m[j * N..j * N + inner.len()];
        match inner.len() {
            3 => scaled_add::<3>(column, inner, a, k),
            6 => scaled_add::<6>(column, inner, a, k),
            12 => scaled_add::<12>(column, inner, a, k),
            _ => scaled_add_any(column, inner, a, k),
        }
    }
}

/// Zeroes the first `rows` × `cols` entries of `m`, the DOF its blocks
/// keep: the others are zero from the start and nothing writes them
/// ([`add_outer_into`] writes kept ones only), so a rigid 3D block's
/// off-diagonal block is cleared in a quarter of its entries.
pub fn zero_kept<const N: usize>(m: &mut BlockMatrix<N>, (rows, cols): (usize, usize)) {
    let m = m.as_mut_slice();
    for j in 0..cols {
        m[j * N..j * N + rows].fill(0.0);
    }
}

/// x += (b·a)·k entry by entry, over a length the compiler knows.
#[inline(always)]
fn scaled_add<const L: usize>(x: &mut [f64], b: &[f64], a: f64, k: f64) {
    let x: &mut [f64; L] = x.try_into().expect("a column of L entries");
    let b: &[f64; L] = b.try_into().expect("L entries");
    for i in 0..L {
        x[i] += b[i] * a * k;
    }
}

fn scaled_add_any(x: &mut [f64], b: &[f64], a: f64, k: f64) {
    x.iter_mut().zip(b).for_each(|(x, &b)| *x += b * a * k);
}

/// How a matrix's values differ from earlier ones
/// ([`BlockSparse::change_from`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Change {
    /// The largest |v| of the earlier values.
    pub scale: f64,
    /// The largest |v − m|, m this matrix's value.
    pub largest: f64,
    /// Σ |v − m|.
    pub total: f64,
}

/// The lower triangle of a symmetric block-sparse matrix.
#[derive(Debug, Clone, Default)]
pub struct BlockSparse<const N: usize> {
    pub diagonal: Vec<BlockMatrix<N>>,
    /// Off-diagonal blocks (row block > column block).
    pub lower: Vec<BlockMatrix<N>>,
    /// (row block, column block) of each entry of `lower`.
    pairs: Vec<(usize, usize)>,
    /// Where each column block's pairs start in `pairs` (sorted by column,
    /// then row), and one past the last: a pair is found by bisecting its
    /// column's few rows, with no hashing (a lookup per contact per step).
    columns: Vec<usize>,
    /// The DOF each block keeps, and where they start in the global vector.
    dofs: Vec<usize>,
    offsets: Vec<usize>,
    /// Each row block's pairs, in `pairs` order: made at the first
    /// product, for [`BlockSparse::multiply_into`]'s rows.
    rows: std::sync::OnceLock<crate::by_block::ByBlock>,
}

impl<const N: usize> BlockSparse<N> {
    /// A zero matrix with one diagonal block per entry of `dofs` (how many
    /// of its N DOF the block keeps) and one off-diagonal block for every
    /// distinct pair in `pairs`.
    pub fn new(dofs: Vec<usize>, pairs: impl IntoIterator<Item = (usize, usize)>) -> Self {
        assert!(dofs.iter().all(|&n| n <= N), "a block keeps at most N DOF");
        let mut pairs: Vec<(usize, usize)> = pairs
            .into_iter()
            .filter(|(a, b)| a != b)
            .map(|(a, b)| (a.max(b), a.min(b)))
            .collect();
        // Column-major order of blocks makes the CSC pattern easy to write.
        pairs.sort_unstable_by_key(|&(row, col)| (col, row));
        pairs.dedup();
        let mut columns = vec![0; dofs.len() + 1];
        for &(_, col) in &pairs {
            columns[col + 1] += 1;
        }
        for c in 0..dofs.len() {
            columns[c + 1] += columns[c];
        }
        let mut offsets = Vec::with_capacity(dofs.len() + 1);
        offsets.push(0);
        for n in &dofs {
            offsets.push(offsets.last().copied().unwrap_or(0) + n);
        }
        Self {
            diagonal: vec![BlockMatrix::<N>::zeros(); dofs.len()],
            lower: vec![BlockMatrix::<N>::zeros(); pairs.len()],
            pairs,
            columns,
            dofs,
            offsets,
            rows: std::sync::OnceLock::new(),
        }
    }

    pub fn block_count(&self) -> usize {
        self.diagonal.len()
    }

    /// The number of unknowns: the DOF the blocks keep.
    pub fn dim(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0)
    }

    /// How many of its N DOF block `i` keeps.
    pub fn dofs(&self, i: usize) -> usize {
        self.dofs[i]
    }

    /// Adds the kept DOF of block `i`'s vector `v` to the global vector `x`.
    pub fn add_block(&self, x: &mut [f64], i: usize, v: &BlockVector<N>) {
        let kept = &mut x[self.offsets[i]..self.offsets[i + 1]];
        for (x, v) in kept.iter_mut().zip(v.iter()) {
            *x += v;
        }
    }

    /// Block `i`'s vector `v` over the DOF the block keeps, as (global
    /// unknown, value) pairs.
    pub fn entries<'a>(
        &'a self,
        i: usize,
        v: &'a BlockVector<N>,
    ) -> impl Iterator<Item = (usize, f64)> + 'a {
        (self.offsets[i]..self.offsets[i + 1]).zip(v.iter().copied())
    }

    /// The global vector `x` cut into each block's kept DOF, block by
    /// block (so blocks can be filled in parallel).
    pub fn split_blocks<'a>(&self, mut x: &'a mut [f64]) -> Vec<&'a mut [f64]> {
        let mut parts = Vec::with_capacity(self.dofs.len());
        for &n in &self.dofs {
            let (part, rest) = x.split_at_mut(n);
            parts.push(part);
            x = rest;
        }
        parts
    }

    /// Block `i`'s N-vector from the global vector `x`, zero beyond the DOF
    /// it keeps.
    pub fn block(&self, x: &[f64], i: usize) -> BlockVector<N> {
        let kept = &x[self.offsets[i]..self.offsets[i + 1]];
        BlockVector::<N>::from_fn(|r, _| kept.get(r).copied().unwrap_or(0.0))
    }

    /// The inverse of a block's matrix over the DOF the block keeps, zero
    /// elsewhere (zero too when singular).
    pub fn kept_inverse(&self, i: usize, m: &BlockMatrix<N>) -> BlockMatrix<N> {
        let n = self.dofs[i];
        let kept = BlockMatrix::<N>::from_fn(|r, c| match (r < n, c < n) {
            (true, true) => m[(r, c)],
            _ if r == c => 1.0,
            _ => 0.0,
        });
        let inverse = kept.try_inverse().unwrap_or_else(BlockMatrix::<N>::zeros);
        BlockMatrix::<N>::from_fn(|r, c| if r < n && c < n { inverse[(r, c)] } else { 0.0 })
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
            let i = self.slot(row, col).expect("the pattern holds the pair");
            self.lower[i] += m;
        } else {
            let i = self.slot(row, col).expect("the pattern holds the pair");
            self.lower[i] += m.transpose();
        }
    }

    /// Adds k·g·hᵀ to block (`row`, `col`), stored at `slot` when they
    /// differ, over the DOF the two blocks keep only: a rigid 3D block's
    /// spring is a quarter of the products of its whole block, and no
    /// product is made whole first.
    pub fn add_outer(
        &mut self,
        slot: usize,
        row: usize,
        col: usize,
        g: &BlockVector<N>,
        h: &BlockVector<N>,
        k: f64,
    ) {
        let (rows, cols) = (self.dofs[row], self.dofs[col]);
        let (m, transposed) = match row.cmp(&col) {
            std::cmp::Ordering::Equal => (&mut self.diagonal[row], false),
            std::cmp::Ordering::Greater => (&mut self.lower[slot], false),
            std::cmp::Ordering::Less => (&mut self.lower[slot], true),
        };
        debug_assert!(row == col || self.pairs[slot] == (row.max(col), row.min(col)));
        add_outer_into(m, (rows, cols), g, h, k, transposed);
    }

    /// The diagonal blocks, the off-diagonal ones, the DOF each block
    /// keeps and the off-diagonal ones' block pairs, to fill blocks on
    /// several threads at once.
    #[allow(clippy::type_complexity)]
    pub fn blocks_mut(
        &mut self,
    ) -> (
        &mut [BlockMatrix<N>],
        &mut [BlockMatrix<N>],
        &[usize],
        &[(usize, usize)],
    ) {
        (&mut self.diagonal, &mut self.lower, &self.dofs, &self.pairs)
    }

    /// Where block pair (a, b), a ≠ b, is stored, if the pattern holds it.
    pub fn slot(&self, a: usize, b: usize) -> Option<usize> {
        let (row, col) = (a.max(b), a.min(b));
        let (start, end) = (*self.columns.get(col)?, *self.columns.get(col + 1)?);
        let rows = &self.pairs[start..end];
        rows.binary_search_by_key(&row, |p| p.0)
            .ok()
            .map(|i| start + i)
    }

    /// The off-diagonal pairs (row block > column block) of the pattern.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// [`BlockSparse::add`] for `row` ≠ `col` stored at `slot` (from
    /// [`BlockSparse::slot`]), without looking the pair up.
    pub fn add_at(&mut self, slot: usize, row: usize, col: usize, m: &BlockMatrix<N>) {
        debug_assert_eq!(self.pairs[slot], (row.max(col), row.min(col)));
        if row > col {
            self.lower[slot] += m;
        } else {
            self.lower[slot] += m.transpose();
        }
    }

    /// The scalar CSC pattern of the lower triangle.
    pub fn pattern(&self) -> CscPattern {
        let (dofs, offsets) = (&self.dofs, &self.offsets);
        let mut col_ptr = Vec::with_capacity(self.dim() + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        let mut next = 0;
        for cb in 0..self.block_count() {
            let start = next;
            while next < self.pairs.len() && self.pairs[next].1 == cb {
                next += 1;
            }
            for c in 0..dofs[cb] {
                row_idx.extend((c..dofs[cb]).map(|r| offsets[cb] + r));
                for &(rb, _) in &self.pairs[start..next] {
                    row_idx.extend((0..dofs[rb]).map(|r| offsets[rb] + r));
                }
                col_ptr.push(row_idx.len());
            }
        }
        CscPattern {
            dim: self.dim(),
            col_ptr,
            row_idx,
            blocks: offsets.clone(),
        }
    }

    /// Values in the order of [`BlockSparse::pattern`]: column block by
    /// column block, each filled on any core into its own part (the same
    /// values in the same places as one thread's; at ten thousand blocks
    /// one thread took 3.5 ms, once a pass and at every factorisation).
    pub fn values_into(&self, values: &mut Vec<f64>) {
        let starts = self.value_starts();
        values.resize(starts[self.block_count()], 0.0);
        let mut parts = Vec::with_capacity(self.block_count());
        let mut rest = values.as_mut_slice();
        for cb in 0..self.block_count() {
            let (part, tail) = rest.split_at_mut(starts[cb + 1] - starts[cb]);
            parts.push(part);
            rest = tail;
        }
        (parts.into_par_iter().enumerate())
            .with_min_len(BLOCKS_PER_TASK)
            .for_each(|(cb, part)| {
                let mut at = part.iter_mut();
                self.column_values(cb, |v| *at.next().expect("sized by the count") = v);
            });
    }

    /// How this matrix's values differ from `old` (values in the order of
    /// [`BlockSparse::values_into`]), read on every core without gathering
    /// them; the total is summed column block by column block in order, so
    /// it is the same to the last bit however the work was shared. `None`
    /// where `old` has another length (another pattern).
    pub fn change_from(&self, old: &[f64]) -> Option<Change> {
        let starts = self.value_starts();
        if old.len() != starts[self.block_count()] {
            return None;
        }
        let columns: Vec<Change> = (0..self.block_count())
            .into_par_iter()
            .with_min_len(BLOCKS_PER_TASK)
            .map(|cb| {
                let mut was = old[starts[cb]..starts[cb + 1]].iter();
                let mut found = Change::default();
                self.column_values(cb, |v| {
                    let w = *was.next().expect("sized by the count");
                    found.scale = found.scale.max(w.abs());
                    found.largest = found.largest.max((w - v).abs());
                    found.total += (w - v).abs();
                });
                found
            })
            .collect();
        Some(columns.iter().fold(Change::default(), |a, b| Change {
            scale: a.scale.max(b.scale),
            largest: a.largest.max(b.largest),
            total: a.total + b.total,
        }))
    }

    /// Where each column block's values start in [`BlockSparse::values_into`]'s
    /// order, then their count.
    fn value_starts(&self) -> Vec<usize> {
        let dofs = &self.dofs;
        let mut starts = Vec::with_capacity(self.block_count() + 1);
        starts.push(0);
        for cb in 0..self.block_count() {
            let n = dofs[cb];
            let below: usize = (self.pairs[self.columns[cb]..self.columns[cb + 1]].iter())
                .map(|&(rb, _)| dofs[rb])
                .sum();
            starts.push(starts[cb] + n * (n + 1) / 2 + n * below);
        }
        starts
    }

    /// Column block cb's values, in order: the lower triangle of its
    /// diagonal block, then, column by column, the rows of its
    /// off-diagonal blocks.
    #[inline(always)]
    fn column_values(&self, cb: usize, mut put: impl FnMut(f64)) {
        let dofs = &self.dofs;
        let range = self.columns[cb]..self.columns[cb + 1];
        let (lower, pairs) = (&self.lower[range.clone()], &self.pairs[range]);
        let d = &self.diagonal[cb];
        for c in 0..dofs[cb] {
            (c..dofs[cb]).for_each(|r| put(d[(r, c)]));
            for (m, &(rb, _)) in lower.iter().zip(pairs) {
                (0..dofs[rb]).for_each(|r| put(m[(r, c)]));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense symmetric matrix of the stored lower triangle.
    pub(super) fn dense(p: &CscPattern, v: &[f64]) -> Vec<Vec<f64>> {
        let mut dense = vec![vec![0.0; p.dim]; p.dim];
        for (c, span) in p.col_ptr.windows(2).enumerate() {
            for (&r, &value) in p.row_idx[span[0]..span[1]].iter().zip(&v[span[0]..span[1]]) {
                assert!(r >= c, "only the lower triangle is stored");
                dense[r][c] = value;
                dense[c][r] = value;
            }
        }
        dense
    }

    fn filled<const N: usize>(dofs: Vec<usize>) -> BlockSparse<N> {
        let mut a = BlockSparse::<N>::new(dofs, [(0, 2), (2, 0), (1, 2)]);
        let m = |s: f64| BlockMatrix::<N>::from_fn(|r, c| s + (N * r + c) as f64);
        a.add(0, 0, &(m(10.0) + m(10.0).transpose()));
        a.add(1, 1, &(m(20.0) + m(20.0).transpose()));
        a.add(2, 2, &(m(30.0) + m(30.0).transpose()));
        a.add(0, 2, &m(1.0));
        a.add(2, 1, &m(2.0));
        a
    }

    /// Every pair is found in either order, once however often it was
    /// given, in column-major order; a pair the pattern lacks, a diagonal
    /// block and a block beyond the last are not.
    #[test]
    fn slots_find_the_pairs_the_pattern_holds() {
        let pairs = [(4, 1), (1, 4), (2, 0), (3, 1), (4, 0), (1, 0), (3, 1)];
        let a = BlockSparse::<3>::new(vec![3; 5], pairs);
        assert_eq!(a.pairs(), &[(1, 0), (2, 0), (4, 0), (3, 1), (4, 1)]);
        for (k, &(row, col)) in a.pairs().iter().enumerate() {
            assert_eq!(a.slot(row, col), Some(k));
            assert_eq!(a.slot(col, row), Some(k));
        }
        for (x, y) in [(2, 1), (4, 3), (3, 0), (2, 2), (5, 0), (0, 7)] {
            assert_eq!(a.slot(x, y), None, "({x}, {y})");
        }
    }

    #[test]
    fn pattern_and_values_match_the_dense_matrix() {
        let a = filled::<3>(vec![3, 3, 3]);
        let p = a.pattern();
        let mut v = Vec::new();
        a.values_into(&mut v);
        assert_eq!(p.row_idx.len(), v.len());
        assert_eq!((p.dim, p.col_ptr.len()), (9, 10));
        let dense = dense(&p, &v);
        let x: Vec<f64> = (0..9).map(|i| 1.0 + 0.3 * i as f64).collect();
        let y = a.multiply(&x);
        for r in 0..p.dim {
            let expect: f64 = (0..p.dim).map(|c| dense[r][c] * x[c]).sum();
            assert!((y[r] - expect).abs() < 1e-12);
        }
        // Block (2, 0) holds m(1)ᵀ: entry (row 2·3 + 1, col 0) = m(1)[(0, 1)].
        assert_eq!(dense[7][0], 1.0 + 1.0);
    }

    /// The largest value and change, and the total change, read off the
    /// blocks are those of the gathered values, at every kept width;
    /// another pattern's values give none.
    #[test]
    fn the_largest_change_is_read_off_the_blocks_as_off_the_values() {
        for dofs in [vec![3, 3, 3], vec![3, 2, 1]] {
            let a = filled::<3>(dofs.clone());
            let mut b = filled::<3>(dofs);
            b.add(
                2,
                1,
                &BlockMatrix::<3>::from_fn(|r, c| 0.25 * r as f64 - 0.5 * c as f64),
            );
            b.add(1, 1, &(BlockMatrix::<3>::identity() * -7.0));
            let (mut va, mut vb) = (Vec::new(), Vec::new());
            a.values_into(&mut va);
            b.values_into(&mut vb);
            let scale = va.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let change = (va.iter().zip(&vb)).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(change > 0.0);
            let total: f64 = (va.iter().zip(&vb)).map(|(x, y)| (x - y).abs()).sum();
            let found = b.change_from(&va).unwrap();
            assert_eq!((found.scale, found.largest), (scale, change));
            assert!(
                (found.total - total).abs() <= 1e-12 * total,
                "{found:?}, {total}"
            );
            let none = Change {
                scale,
                largest: 0.0,
                total: 0.0,
            };
            assert_eq!(a.change_from(&va), Some(none));
            assert_eq!(a.change_from(&va[1..]), None);
        }
    }

    /// k·g·hᵀ added over the kept DOF of blocks keeping `dofs`, and the
    /// whole product added block by block, on either side of the diagonal
    /// and on it: the stored values of the two.
    fn kept_and_whole<const N: usize>(
        dofs: Vec<usize>,
        g: &BlockVector<N>,
        h: &BlockVector<N>,
        k: f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let (mut whole, mut kept) = (filled::<N>(dofs.clone()), filled::<N>(dofs));
        for (row, col) in [(0, 0), (1, 1), (2, 2), (0, 2), (2, 0), (1, 2), (2, 1)] {
            let slot = kept.slot(row, col).unwrap_or(0);
            kept.add_outer(slot, row, col, g, h, k);
            whole.add(row, col, &(g * h.transpose() * k));
        }
        let (mut v, mut w) = (Vec::new(), Vec::new());
        kept.values_into(&mut v);
        whole.values_into(&mut w);
        (v, w)
    }

    /// A spring's k·g·hᵀ added over the kept DOF gives the values of the
    /// whole product added block by block.
    #[test]
    fn outer_products_fill_the_kept_dofs_as_whole_products_do() {
        let g = BlockVector::<3>::new(0.3, -1.2, 0.7);
        let h = BlockVector::<3>::new(-0.4, 0.9, 2.5);
        let (kept, whole) = kept_and_whole(vec![3, 2, 1], &g, &h, 1.7e9);
        assert_eq!(kept, whole);
    }

    /// The same at the widths with their own loops (12 and 6) and one
    /// without (4), to the last bit.
    #[test]
    fn outer_products_of_every_width_match_whole_products_to_the_bit() {
        let g = BlockVector::<12>::from_fn(|i, _| (i as f64 * 0.37 - 1.3).sin());
        let h = BlockVector::<12>::from_fn(|i, _| (i as f64 * 0.71 + 0.2).cos() * 3.1);
        let (kept, whole) = kept_and_whole(vec![12, 6, 4], &g, &h, 2.3e9);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&kept), bits(&whole));
    }

    #[test]
    fn blocks_keep_their_leading_dofs_only() {
        // Block 1 keeps 2 of 3 DOF, block 2 only 1.
        let full = filled::<3>(vec![3, 3, 3]);
        let a = filled(vec![3, 2, 1]);
        assert_eq!(a.dim(), 6);
        let (p, pf) = (a.pattern(), full.pattern());
        let (mut v, mut vf) = (Vec::new(), Vec::new());
        a.values_into(&mut v);
        full.values_into(&mut vf);
        let (d, df) = (dense(&p, &v), dense(&pf, &vf));
        // The kept matrix is the full one without the dropped rows and columns.
        let kept = [0, 1, 2, 3, 4, 6];
        for (r, &fr) in kept.iter().enumerate() {
            for (c, &fc) in kept.iter().enumerate() {
                assert_eq!(d[r][c], df[fr][fc], "({r}, {c})");
            }
        }
        // Vectors go in and out at the blocks' offsets, dropped DOF as zero.
        let mut x = vec![0.0; a.dim()];
        a.add_block(&mut x, 1, &BlockVector::<3>::new(1.0, 2.0, 3.0));
        a.add_block(&mut x, 2, &BlockVector::<3>::new(4.0, 5.0, 6.0));
        assert_eq!(x, [0.0, 0.0, 0.0, 1.0, 2.0, 4.0]);
        assert_eq!(a.block(&x, 1), BlockVector::<3>::new(1.0, 2.0, 0.0));
        assert_eq!(a.block(&x, 2), BlockVector::<3>::new(4.0, 0.0, 0.0));
        // The kept inverse inverts the kept part only.
        let m = BlockMatrix::<3>::new(4.0, 1.0, 9.0, 1.0, 3.0, 9.0, 9.0, 9.0, 0.0);
        let inv = a.kept_inverse(1, &m);
        let two = nalgebra::Matrix2::new(4.0, 1.0, 1.0, 3.0)
            .try_inverse()
            .unwrap();
        assert!((inv.fixed_view::<2, 2>(0, 0) - two).norm() < 1e-15);
        assert!(inv
            .row(2)
            .iter()
            .chain(inv.column(2).iter())
            .all(|&x| x == 0.0));
    }
}
