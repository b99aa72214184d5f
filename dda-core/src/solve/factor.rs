//! The numeric factorisation on two cores. A supernode's columns of L are
//! made from its own entries of the matrix and the supernodes below it in
//! the elimination tree (left-looking, as faer's own factorisation), so
//! the subtrees of a `Split` factorise side by side, each core its own,
//! and the top after them. Each column's sums are taken in the same order
//! on any number of cores.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::{Accum, MatMut, MatRef, Par};

use super::split::{pattern, supernode_of, FactorPiece, Split};

/// The factorisation's layout and each core's buffers, made with the
/// analysis.
pub(super) struct Numeric {
    layout: Layout,
    work: [Work; 2],
}

/// Where each entry of the matrix lands in the factor, and which
/// supernodes update which.
struct Layout {
    /// For each supernode, the matrix entries (their index in the given
    /// values) and where each lands in the supernode's columns: the
    /// supernode's are `entries[entries_at[s]..entries_at[s + 1]]`.
    entries_at: Vec<usize>,
    entries: Vec<(usize, usize)>,
    /// For each supernode, the supernodes below it whose rows reach its
    /// columns, in order.
    below_at: Vec<usize>,
    below: Vec<usize>,
    /// The core whose subtrees hold each supernode; 2 for the top.
    core: Vec<u8>,
}

impl Numeric {
    /// The layout for `split` and a matrix given by the lower triangle
    /// `col_ptr`, `row_idx` (in the matrix's own ordering) and the
    /// ordering's inverse permutation (`inverse[old] = new`).
    pub fn new(
        symbolic: &SymbolicSupernodalCholesky<usize>,
        split: &Split,
        col_ptr: &[usize],
        row_idx: &[usize],
        inverse: Option<&[usize]>,
    ) -> Self {
        let count = symbolic.n_supernodes();
        let supernode_of = supernode_of(symbolic);
        let (entries_at, entries) = entries(symbolic, &supernode_of, col_ptr, row_idx, inverse);
        // Supernode d's rows reach its ancestors' columns, each ancestor's
        // rows in one run.
        let mut lists = vec![Vec::new(); count];
        for d in 0..count {
            let mut last = None;
            for &r in pattern(symbolic, d) {
                let s = supernode_of[r];
                if last != Some(s) {
                    lists[s].push(d);
                    last = Some(s);
                }
            }
        }
        let mut below_at = vec![0];
        for list in &lists {
            below_at.push(below_at.last().unwrap() + list.len());
        }
        let (begin, end) = (symbolic.supernode_begin(), symbolic.supernode_end());
        let widest = (0..count).map(|s| end[s] - begin[s]).max().unwrap_or(0);
        let n = symbolic.nrows();
        Self {
            layout: Layout {
                entries_at,
                entries,
                below_at,
                below: lists.concat(),
                core: split.cores(count),
            },
            work: [Work::new(n, widest), Work::new(n, widest)],
        }
    }

    /// Factorises the matrix with `values` into `factor` (the symbolic
    /// analysis's layout): the subtrees of `split` on two cores, then its
    /// top, each top supernode taking the products of the supernodes below
    /// it on both cores, each those of its own subtrees. Fails with the
    /// supernode whose pivot is not positive.
    pub fn factorize(
        &mut self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
        split: &Split,
        values: &[f64],
        factor: &mut [f64],
    ) -> Result<(), usize> {
        let at = symbolic.col_ptr_for_val();
        let Self {
            layout,
            work: [w0, w1],
        } = self;
        let [p0, p1] = split.factor_pieces(symbolic, factor);
        let (r0, r1) = rayon::join(
            || layout.subtrees(symbolic, values, p0, w0),
            || layout.subtrees(symbolic, values, p1, w1),
        );
        r0.and(r1)?;
        for &s in split.top() {
            let (head, tail) = factor.split_at_mut(at[s]);
            let node = &mut tail[..at[s + 1] - at[s]];
            let mut theirs = std::mem::take(&mut w0.columns);
            let (below, len) = (layout.below(s), node.len());
            rayon::join(
                || {
                    theirs.clear();
                    theirs.resize(len, 0.0);
                    let mine = below.iter().filter(|&&d| layout.core[d] == 0);
                    layout.take_products(symbolic, s, mine, head, 0, &mut theirs, w0);
                },
                || {
                    layout.own_entries(s, values, node);
                    let mine = below.iter().filter(|&&d| layout.core[d] != 0);
                    layout.take_products(symbolic, s, mine, head, 0, node, w1);
                },
            );
            for (v, t) in node.iter_mut().zip(&theirs) {
                *v += t;
            }
            w0.columns = theirs;
            layout.finish(symbolic, s, node, w1)?;
        }
        Ok(())
    }
}

impl Layout {
    /// One core's subtrees: each the supernodes `first..=root` and their
    /// columns, from the factor's entry `offset` on.
    fn subtrees(
        &self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
        values: &[f64],
        pieces: Vec<FactorPiece<'_, f64>>,
        work: &mut Work,
    ) -> Result<(), usize> {
        let at = symbolic.col_ptr_for_val();
        for (supernodes, offset, columns) in pieces {
            for s in supernodes {
                let (head, tail) = columns.split_at_mut(at[s] - offset);
                let node = &mut tail[..at[s + 1] - at[s]];
                self.own_entries(s, values, node);
                let below = self.below(s).iter();
                self.take_products(symbolic, s, below, head, offset, node, work);
                self.finish(symbolic, s, node, work)?;
            }
        }
        Ok(())
    }

    /// The supernodes below `s` whose rows reach its columns.
    fn below(&self, s: usize) -> &[usize] {
        &self.below[self.below_at[s]..self.below_at[s + 1]]
    }

    /// Supernode `s`'s columns set to its entries of the matrix.
    fn own_entries(&self, s: usize, values: &[f64], node: &mut [f64]) {
        node.fill(0.0);
        for &(k, to) in &self.entries[self.entries_at[s]..self.entries_at[s + 1]] {
            node[to] += values[k];
        }
    }

    /// The products of the supernodes `below` (read from `head`, the
    /// factor's entries from `offset` up to `s`'s) subtracted from
    /// supernode `s`'s columns `node`.
    #[allow(clippy::too_many_arguments)]
    fn take_products<'d>(
        &self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
        s: usize,
        below: impl Iterator<Item = &'d usize>,
        head: &[f64],
        offset: usize,
        node: &mut [f64],
        work: &mut Work,
    ) {
        let at = symbolic.col_ptr_for_val();
        let (begin, end) = (symbolic.supernode_begin()[s], symbolic.supernode_end()[s]);
        let rows = pattern(symbolic, s);
        let width = end - begin;
        let height = width + rows.len();
        for (i, &r) in rows.iter().enumerate() {
            work.local[r] = width + i;
        }
        for &d in below {
            let d_rows = pattern(symbolic, d);
            let d_width = symbolic.supernode_end()[d] - symbolic.supernode_begin()[d];
            let ld = MatRef::from_column_major_slice(
                &head[at[d] - offset..at[d + 1] - offset],
                d_width + d_rows.len(),
                d_width,
            );
            let first = d_rows.partition_point(|&r| r < begin);
            let reach = &d_rows[first..];
            let mid = reach.partition_point(|&r| r < end);
            let m = reach.len();
            let lower = ld.subrows(d_width + first, m);
            work.product.resize(m * mid, 0.0);
            // Only the lower triangle of the rows within s's columns.
            let product = MatMut::from_column_major_slice_mut(&mut work.product, m, mid);
            let (within, beyond) = product.split_at_row_mut(mid);
            let (reach_within, reach_beyond) = lower.split_at_row(mid);
            triangular::matmul(
                within,
                BlockStructure::TriangularLower,
                Accum::Replace,
                reach_within,
                BlockStructure::Rectangular,
                reach_within.transpose(),
                BlockStructure::Rectangular,
                1.0,
                Par::Seq,
            );
            matmul(
                beyond,
                Accum::Replace,
                reach_beyond,
                reach_within.transpose(),
                1.0,
                Par::Seq,
            );
            for (j, &c) in reach[..mid].iter().enumerate() {
                let column = &mut node[(c - begin) * height..(c - begin + 1) * height];
                let products = &work.product[j * m..(j + 1) * m];
                for (&r, &p) in reach[j..mid].iter().zip(&products[j..mid]) {
                    column[r - begin] -= p;
                }
                for (&r, &p) in reach[mid..].iter().zip(&products[mid..]) {
                    column[work.local[r]] -= p;
                }
            }
        }
    }

    /// Supernode `s`'s columns of L from the matrix less the products: the
    /// dense Cholesky factor of its diagonal block, and the rows below it
    /// solved against that.
    fn finish(
        &self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
        s: usize,
        node: &mut [f64],
        work: &mut Work,
    ) -> Result<(), usize> {
        let width = symbolic.supernode_end()[s] - symbolic.supernode_begin()[s];
        let height = width + pattern(symbolic, s).len();
        let columns = MatMut::from_column_major_slice_mut(node, height, width);
        let (mut diagonal, mut lower) = columns.split_at_row_mut(width);
        cholesky_in_place(
            diagonal.rb_mut(),
            Default::default(),
            Par::Seq,
            MemStack::new(&mut work.stack),
            Default::default(),
        )
        .map_err(|_| s)?;
        solve_lower_triangular_in_place(diagonal.rb(), lower.rb_mut().transpose_mut(), Par::Seq);
        Ok(())
    }
}

/// Where each entry of the lower triangle `col_ptr`, `row_idx` (in the
/// matrix's own ordering, `inverse[old] = new`) lands in the factor: for
/// each supernode, its entries' indices and places in its columns, in
/// the entries' order (`Layout::entries`).
fn entries(
    symbolic: &SymbolicSupernodalCholesky<usize>,
    supernode_of: &[usize],
    col_ptr: &[usize],
    row_idx: &[usize],
    inverse: Option<&[usize]>,
) -> (Vec<usize>, Vec<(usize, usize)>) {
    let (begin, end) = (symbolic.supernode_begin(), symbolic.supernode_end());
    let new = |i: usize| inverse.map_or(i, |p| p[i]);
    let mut landing = Vec::with_capacity(row_idx.len());
    for j in 0..col_ptr.len() - 1 {
        for (k, &i) in row_idx
            .iter()
            .enumerate()
            .take(col_ptr[j + 1])
            .skip(col_ptr[j])
        {
            let (a, b) = (new(i), new(j));
            let (row, col) = (a.max(b), a.min(b));
            let s = supernode_of[col];
            let rows = pattern(symbolic, s);
            let width = end[s] - begin[s];
            let local = if row < end[s] {
                row - begin[s]
            } else {
                width + rows.partition_point(|&r| r < row)
            };
            landing.push((s, (k, (col - begin[s]) * (width + rows.len()) + local)));
        }
    }
    // Gathered by supernode: a counting sort.
    let mut at = vec![0; symbolic.n_supernodes() + 1];
    for &(s, _) in &landing {
        at[s + 1] += 1;
    }
    for s in 1..at.len() {
        at[s] += at[s - 1];
    }
    let mut next = at.clone();
    let mut entries = vec![(0, 0); landing.len()];
    for (s, entry) in landing {
        entries[next[s]] = entry;
        next[s] += 1;
    }
    (at, entries)
}

/// One core's buffers.
struct Work {
    /// Where each row lies in the supernode at hand.
    local: Vec<usize>,
    /// A supernode's products with one below it.
    product: Vec<f64>,
    /// A top supernode's products from this core's subtrees.
    columns: Vec<f64>,
    /// The dense factorisation's workspace.
    stack: MemBuffer,
}

impl Work {
    fn new(n: usize, widest: usize) -> Self {
        Self {
            local: vec![0; n],
            product: Vec::new(),
            columns: Vec::new(),
            stack: MemBuffer::new(cholesky_in_place_scratch::<f64>(
                widest,
                Par::Seq,
                Default::default(),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::solve::tests::{factored, grid};
    use crate::solve::{LinearSolver, SparseCholesky};

    fn on(threads: usize, make: impl FnOnce() -> SparseCholesky + Send) -> SparseCholesky {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(make)
    }

    /// The factor made subtree by subtree on two cores is faer's to
    /// round-off, and bit for bit the same on one core.
    #[test]
    fn the_split_factor_is_faers_on_any_number_of_cores() {
        // Blocks of 6 unknowns make supernodes of several blocks, with
        // rows below them both in their own subtree and in the top.
        let (pattern, values) = grid(30, 6);
        let faer = factored(&pattern, &values, usize::MAX);
        assert!(faer.numeric.is_none());
        let two = on(2, || factored(&pattern, &values, 0));
        assert!(two.numeric.is_some(), "a grid's tree splits");
        let top = two.split.as_ref().unwrap().top().len();
        assert!(top > 0);
        let largest = faer.factor.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (x, y) in two.factor.iter().zip(&faer.factor) {
            assert!((x - y).abs() <= 1e-13 * largest, "{x} against {y}");
        }
        assert_eq!(two.factor, on(1, || factored(&pattern, &values, 0)).factor);
    }

    /// A new analysis (another pattern, as when contacts come and go)
    /// makes a new layout: the factor of the new matrix solves it.
    #[test]
    fn a_new_pattern_is_factorised_on_its_own_layout() {
        let mut s = SparseCholesky {
            split_from: 0,
            ..Default::default()
        };
        for (g, b) in [(30, 6), (24, 3), (30, 6)] {
            let (pattern, values) = grid(g, b);
            s.analyse(&pattern).unwrap();
            s.factorize(&values).unwrap();
            let faer = factored(&pattern, &values, usize::MAX);
            let largest = faer.factor.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for (x, y) in s.factor.iter().zip(&faer.factor) {
                assert!(
                    (x - y).abs() <= 1e-13 * largest,
                    "{g} × {g}: {x} against {y}"
                );
            }
        }
    }

    /// An indefinite matrix is refused, as faer refuses it, and a
    /// definite one factorises again afterwards.
    #[test]
    fn the_split_factorisation_refuses_an_indefinite_matrix() {
        let (pattern, values) = grid(30, 6);
        let mut s = SparseCholesky {
            split_from: 0,
            ..Default::default()
        };
        s.analyse(&pattern).unwrap();
        assert!(s.numeric.is_some());
        for column in [0, pattern.dim / 2, pattern.dim - 1] {
            let mut bad = values.clone();
            bad[pattern.col_ptr[column]] = -1.0;
            assert!(s.factorize(&bad).is_err(), "column {column}");
        }
        s.factorize(&values).unwrap();
        let mut x = vec![1.0; pattern.dim];
        s.solve(&mut x);
        assert!(x.iter().all(|v| v.is_finite()));
    }
}
