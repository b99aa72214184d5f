//! A factored matrix plus a few rank-one terms, K + Σ sⱼuⱼvⱼᵀ with K = LLᵀ,
//! solved by the Sherman-Morrison-Woodbury formula between the two sweeps:
//!
//!   x = L⁻ᵀ (y − Wᵤ (I + S WᵥᵀWᵤ)⁻¹ S Wᵥᵀ y),  y = L⁻¹b,  W = L⁻¹U.
//!
//! A term's u and v lie on two blocks, so L⁻¹u is nonzero only on the
//! supernodes from those rows up to the root of the elimination tree: a
//! forward sweep over that path, a few percent of the factor, makes it.
//! Formed after the back sweep instead (K⁻¹U, dense), each term cost a
//! whole solve, and each move read every column.

use nalgebra::{DMatrix, DVector, LU};

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{Accum, MatMut, MatRef, Par};

use super::split::{pattern, solve_sequential, supernode_of, Scalar};
use super::SparseCholesky;

/// A rank-one term `slope`·u·vᵀ, u and v as (unknown, value) pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct UpdateTerm {
    pub u: Vec<(usize, f64)>,
    pub v: Vec<(usize, f64)>,
    pub slope: f64,
}

/// L⁻¹ of a sparse vector, on the unknowns of the supernodes it reaches.
#[derive(Debug, Default)]
struct Reached {
    /// Runs of unknowns (start, end), in the factor's ordering.
    runs: Vec<(usize, usize)>,
    /// Their values, run after run.
    values: Vec<f64>,
}

impl Reached {
    fn dot<T: Scalar>(&self, y: &[T]) -> f64 {
        let mut at = 0;
        let mut sum = 0.0;
        for &(start, end) in &self.runs {
            let values = &self.values[at..at + end - start];
            sum += (values.iter().zip(&y[start..end]))
                .map(|(w, y)| w * y.widen())
                .sum::<f64>();
            at += end - start;
        }
        sum
    }

    /// y −= c·self.
    fn subtract_from<T: Scalar>(&self, c: f64, y: &mut [T]) {
        let mut at = 0;
        for &(start, end) in &self.runs {
            let values = &self.values[at..at + end - start];
            for (y, w) in y[start..end].iter_mut().zip(values) {
                *y = T::narrow(y.widen() - c * w);
            }
            at += end - start;
        }
    }
}

/// The terms' forward sweeps and the LU factors of I + S WᵥᵀWᵤ, ready to
/// apply between a solve's sweeps (`LinearSolver::solve_updated`).
pub struct FactorUpdate {
    /// L⁻¹ of each distinct vector among the terms' u and v.
    reached: Vec<Reached>,
    /// Which of `reached` is each term's u, and its v.
    u: Vec<usize>,
    v: Vec<usize>,
    slopes: Vec<f64>,
    capacitance: LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    /// The most rows in a supernode, its diagonal block's and those
    /// below (a substitution's buffer).
    widest: usize,
}

impl FactorUpdate {
    /// Makes the terms' sweeps on the factor `values`, each core taking
    /// half of them; `inverse` maps an unknown to the factor's ordering.
    /// `None` where the tree is not laid out children first.
    pub(super) fn new(
        symbolic: &SymbolicSupernodalCholesky<usize>,
        values: &[f64],
        inverse: Option<&[usize]>,
        terms: &[UpdateTerm],
    ) -> Option<Self> {
        let tree = Tree::new(symbolic)?;
        // Distinct vectors: a spring's u is its v.
        let mut vectors: Vec<Vec<(usize, f64)>> = Vec::new();
        let mut u = Vec::with_capacity(terms.len());
        let mut v = Vec::with_capacity(terms.len());
        for t in terms {
            for (x, to) in [(&t.u, &mut u), (&t.v, &mut v)] {
                let at = vectors.iter().position(|w| w == x);
                to.push(at.unwrap_or_else(|| {
                    vectors.push(x.clone());
                    vectors.len() - 1
                }));
            }
        }
        // Into the factor's ordering.
        for (r, _) in vectors.iter_mut().flatten() {
            *r = inverse.map_or(*r, |p| p[*r]);
        }
        let factor = SupernodalLltRef::new(symbolic, values);
        let reached = tree.sweep_all(factor, &vectors);
        let slopes: Vec<f64> = terms.iter().map(|t| t.slope).collect();
        let capacitance = capacitance(&reached, &u, &v, &slopes, symbolic.nrows());
        Some(Self {
            reached,
            u,
            v,
            slopes,
            capacitance,
            widest: tree.widest,
        })
    }

    /// y − Wᵤ (I + S WᵥᵀWᵤ)⁻¹ S Wᵥᵀ y, in place; y is left where the
    /// capacitance matrix is singular.
    pub(super) fn apply<T: Scalar>(&self, y: &mut [T]) {
        let m = self.slopes.len();
        if m == 0 {
            // nalgebra's LU of an empty matrix does not solve.
            return;
        }
        let rhs = DVector::from_fn(m, |i, _| self.slopes[i] * self.reached[self.v[i]].dot(y));
        let Some(c) = self.capacitance.solve(&rhs) else {
            return;
        };
        for (j, c) in c.iter().enumerate() {
            self.reached[self.u[j]].subtract_from(*c, y);
        }
    }
}

/// The LU factors of I + S WᵥᵀWᵤ, with W's columns `reached` and `u`, `v`
/// each term's.
fn capacitance(
    reached: &[Reached],
    u: &[usize],
    v: &[usize],
    slopes: &[f64],
    n: usize,
) -> LU<f64, nalgebra::Dyn, nalgebra::Dyn> {
    let m = slopes.len();
    let mut dense = vec![0.0; n];
    let mut products = DMatrix::zeros(m, m);
    for j in 0..m {
        reached[u[j]].subtract_from(-1.0, &mut dense);
        for i in 0..m {
            products[(i, j)] = reached[v[i]].dot(&dense);
        }
        for &(start, end) in &reached[u[j]].runs {
            dense[start..end].fill(0.0);
        }
    }
    DMatrix::from_fn(m, m, |i, j| {
        let identity = if i == j { 1.0 } else { 0.0 };
        identity + slopes[i] * products[(i, j)]
    })
    .lu()
}

/// The supernodal elimination tree: each unknown's supernode and each
/// supernode's parent.
struct Tree {
    supernode_of: Vec<usize>,
    parent: Vec<Option<usize>>,
    /// The most rows in a supernode, its diagonal block's and those
    /// below (a substitution's buffer).
    widest: usize,
}

impl Tree {
    fn new(symbolic: &SymbolicSupernodalCholesky<usize>) -> Option<Self> {
        let count = symbolic.n_supernodes();
        let supernode_of = supernode_of(symbolic);
        let mut parent = vec![None; count];
        let mut widest = 0;
        let (begin, end) = (symbolic.supernode_begin(), symbolic.supernode_end());
        for (s, parent) in parent.iter_mut().enumerate() {
            let below = pattern(symbolic, s);
            widest = widest.max(end[s] - begin[s] + below.len());
            if let Some(&r) = below.first() {
                let p = supernode_of[r];
                if p <= s {
                    return None;
                }
                *parent = Some(p);
            }
        }
        Some(Self {
            supernode_of,
            parent,
            widest,
        })
    }

    /// L⁻¹ of each of `vectors` (in the factor's ordering). Vectors on the
    /// same unknowns (a contact's springs, the old and the new) share their
    /// path to the root: each such group is swept once, its vectors side
    /// by side, and the cores take half of the vectors each.
    fn sweep_all(
        &self,
        factor: SupernodalLltRef<'_, usize, f64>,
        vectors: &[Vec<(usize, f64)>],
    ) -> Vec<Reached> {
        let rows = |x: &[(usize, f64)]| x.iter().map(|e| e.0).collect::<Vec<_>>();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for (j, x) in vectors.iter().enumerate() {
            match groups.iter_mut().find(|g| rows(&vectors[g[0]]) == rows(x)) {
                Some(group) => group.push(j),
                None => groups.push(vec![j]),
            }
        }
        let widest_group = groups.iter().map(Vec::len).max().unwrap_or(0);
        let sweep = |part: &[Vec<usize>]| {
            let n = self.supernode_of.len();
            let mut x = vec![0.0; n * widest_group];
            let mut below = vec![0.0; self.widest * widest_group];
            let mut marked = vec![false; self.parent.len()];
            let mut made = Vec::new();
            for group in part {
                let seeds: Vec<&[(usize, f64)]> = group.iter().map(|&j| &vectors[j][..]).collect();
                let reached = self.forward(factor, &seeds, &mut x, &mut below, &mut marked);
                made.extend(group.iter().copied().zip(reached));
            }
            made
        };
        let (mut half, mut count) = (0, 0);
        while half < groups.len() && 2 * count < vectors.len() {
            count += groups[half].len();
            half += 1;
        }
        let (first, second) = groups.split_at(half);
        let (mut made, rest) = rayon::join(|| sweep(first), || sweep(second));
        made.extend(rest);
        made.sort_unstable_by_key(|(j, _)| *j);
        made.into_iter().map(|(_, r)| r).collect()
    }

    /// L⁻¹ of each of the vectors `seeds` (in the factor's ordering), all
    /// on the same unknowns: a forward sweep over the supernodes from
    /// theirs up to the root, children first, the vectors side by side in
    /// `x` (n unknowns each). `x` is zero on entry and left so; `marked`
    /// is all false.
    fn forward(
        &self,
        factor: SupernodalLltRef<'_, usize, f64>,
        seeds: &[&[(usize, f64)]],
        x: &mut [f64],
        below: &mut [f64],
        marked: &mut [bool],
    ) -> Vec<Reached> {
        let (n, k) = (self.supernode_of.len(), seeds.len());
        let mut path = Vec::new();
        for (c, seeds) in seeds.iter().enumerate() {
            for &(r, w) in seeds.iter() {
                x[c * n + r] += w;
                let mut s = Some(self.supernode_of[r]);
                while let Some(at) = s.filter(|&at| !marked[at]) {
                    marked[at] = true;
                    path.push(at);
                    s = self.parent[at];
                }
            }
        }
        path.sort_unstable();
        for &s in &path {
            let node = factor.supernode(s);
            let (start, width, rows) = (node.start(), node.val().ncols(), node.pattern());
            let (diagonal, lower) = node.val().split_at_row(width);
            solve_lower_triangular_in_place(
                diagonal,
                MatMut::from_column_major_slice_with_stride_mut(&mut x[start..], width, k, n),
                Par::Seq,
            );
            let below = &mut below[..rows.len() * k];
            matmul(
                MatMut::from_column_major_slice_mut(below, rows.len(), k),
                Accum::Replace,
                lower,
                MatRef::from_column_major_slice_with_stride(&x[start..], width, k, n),
                1.0,
                Par::Seq,
            );
            for (c, below) in below.chunks_exact(rows.len().max(1)).enumerate() {
                for (&r, v) in rows.iter().zip(below) {
                    x[c * n + r] -= v;
                }
            }
        }
        let mut reached: Vec<Reached> = (0..k).map(|_| Reached::default()).collect();
        for &s in &path {
            marked[s] = false;
            let node = factor.supernode(s);
            let (start, end) = (node.start(), node.start() + node.val().ncols());
            for (c, reached) in reached.iter_mut().enumerate() {
                let column = &mut x[c * n + start..c * n + end];
                reached.values.extend_from_slice(column);
                column.fill(0.0);
                match reached.runs.last_mut() {
                    Some(last) if last.1 == start => last.1 = end,
                    _ => reached.runs.push((start, end)),
                }
            }
        }
        reached
    }
}

impl SparseCholesky {
    /// [`LinearSolver::update`] on this factor.
    pub(super) fn make_update(&self, terms: &[UpdateTerm]) -> Option<FactorUpdate> {
        assert!(self.factored, "update before factorize");
        let symbolic = self.symbolic.as_ref()?;
        let SymbolicCholeskyRaw::Supernodal(tree) = symbolic.raw() else {
            return None;
        };
        let inverse = symbolic.perm().map(|p| p.arrays().1);
        FactorUpdate::new(tree, &self.factor, inverse, terms)
    }

    /// [`LinearSolver::solve_updated`] on this factor: exactly, or on its
    /// single-precision copy where it keeps one.
    pub(super) fn solve_with_update(&self, update: &FactorUpdate, rhs: &mut [f64], exact: bool) {
        assert!(self.factored, "solve before factorize");
        let symbolic = self.symbolic.as_ref().expect("analysed");
        let SymbolicCholeskyRaw::Supernodal(tree) = symbolic.raw() else {
            panic!("an update is made on a supernodal factor only");
        };
        let (forward, inverse) = symbolic.perm().map(|p| p.arrays()).unzip();
        let apply_f64 = |y: &mut [f64]| update.apply(y);
        let apply_f32 = |y: &mut [f32]| update.apply(y);
        let scale = rhs.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
        if exact || self.single.is_empty() || scale == 0.0 || !scale.is_finite() {
            let (x, work) = &mut *self.split_work.borrow_mut();
            permute_in(rhs, forward, x, |v| v);
            match &self.split {
                Some(split) => split.solve(tree, &self.factor, x, work, Some(&apply_f64)),
                None => {
                    let mut below = vec![0.0; update.widest];
                    solve_sequential(tree, &self.factor, x, &mut below, &apply_f64);
                }
            }
            permute_out(x, inverse, rhs, |v| v);
            return;
        }
        // Scaled to its largest entry, so no entry leaves f32's range.
        let (single, _) = &mut *self.single_scratch.borrow_mut();
        permute_in(rhs, forward, single, |v| (v / scale) as f32);
        match &self.split {
            Some(split) => {
                let work = &mut self.single_split_work.borrow_mut();
                split.solve(tree, &self.single, single, work, Some(&apply_f32));
            }
            None => {
                let mut below = vec![0.0; update.widest];
                solve_sequential(tree, &self.single, single, &mut below, &apply_f32);
            }
        }
        permute_out(single, inverse, rhs, |v| f64::from(v) * scale);
    }
}

/// x[i] = f(rhs[forward[i]]), into the factor's ordering.
fn permute_in<T>(rhs: &[f64], forward: Option<&[usize]>, x: &mut Vec<T>, f: impl Fn(f64) -> T) {
    x.clear();
    match forward {
        Some(forward) => x.extend(forward.iter().map(|&j| f(rhs[j]))),
        None => x.extend(rhs.iter().map(|&v| f(v))),
    }
}

/// rhs[j] = f(x[inverse[j]]), back from the factor's ordering.
fn permute_out<T: Copy>(x: &[T], inverse: Option<&[usize]>, rhs: &mut [f64], f: impl Fn(T) -> f64) {
    match inverse {
        Some(inverse) => (rhs.iter_mut().zip(inverse)).for_each(|(r, &i)| *r = f(x[i])),
        None => (rhs.iter_mut().zip(x)).for_each(|(r, &v)| *r = f(v)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::tests::{factored, grid};
    use crate::solve::LinearSolver;

    /// K x + Σ sⱼuⱼ(vⱼᵀx), K given by its lower triangle.
    fn multiply(
        pattern: &crate::assembly::CscPattern,
        values: &[f64],
        terms: &[UpdateTerm],
        x: &[f64],
    ) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        for c in 0..pattern.dim {
            let column = pattern.col_ptr[c]..pattern.col_ptr[c + 1];
            for (&r, &value) in pattern.row_idx[column.clone()].iter().zip(&values[column]) {
                y[r] += value * x[c];
                if r != c {
                    y[c] += value * x[r];
                }
            }
        }
        for t in terms {
            let w = t.slope * t.v.iter().map(|&(i, v)| v * x[i]).sum::<f64>();
            t.u.iter().for_each(|&(i, u)| y[i] += u * w);
        }
        y
    }

    /// Springs on pairs of blocks come and go (slopes of both signs, u = v,
    /// some on the same blocks), and one term has u ≠ v: the updated solve
    /// is the updated matrix's, to round-off exactly and to single
    /// precision's as a correction, split between two cores or not.
    #[test]
    fn an_updated_solve_solves_the_matrix_with_the_terms() {
        let (pattern, values) = grid(30, 3);
        let n = pattern.dim;
        let on = |a: usize, b: usize, phase: f64| -> Vec<(usize, f64)> {
            (0..3)
                .map(|k| (3 * a + k, (phase + k as f64).sin()))
                .chain((0..3).map(|k| (3 * b + k, -(phase + k as f64).cos())))
                .collect()
        };
        // Two pairs of terms on the same blocks, swept side by side.
        let mut terms: Vec<UpdateTerm> = [
            (0, 1, 2.0),
            (95, 125, -1.5),
            (400, 401, 3.0),
            (899, 869, 0.7),
            (95, 125, 0.8),
            (400, 401, -0.4),
        ]
        .iter()
        .enumerate()
        .map(|(j, &(a, b, slope))| {
            let u = on(a, b, j as f64);
            UpdateTerm {
                v: u.clone(),
                u,
                slope,
            }
        })
        .collect();
        terms.push(UpdateTerm {
            u: on(450, 451, 0.3),
            v: on(451, 481, 1.1),
            slope: 0.9,
        });
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for split_from in [0, usize::MAX] {
            let s = factored(&pattern, &values, split_from);
            assert_eq!(s.split.is_some(), split_from == 0);
            let update = s.update(&terms).expect("a supernodal factor");
            for (exact, tolerance) in [(true, 1e-12), (false, 1e-5)] {
                let mut x = b.clone();
                s.solve_updated(&update, &mut x, exact);
                let r: Vec<f64> = (multiply(&pattern, &values, &terms, &x).iter().zip(&b))
                    .map(|(y, b)| y - b)
                    .collect();
                let share = norm(&r) / norm(&b);
                assert!(
                    share < tolerance,
                    "split {split_from}, exact {exact}: {share:e}"
                );
            }
            // Without the terms the solve is K's alone, which leaves the
            // terms' share of the residual.
            let mut x = b.clone();
            s.solve(&mut x);
            let r: Vec<f64> = (multiply(&pattern, &values, &terms, &x).iter().zip(&b))
                .map(|(y, b)| y - b)
                .collect();
            assert!(norm(&r) / norm(&b) > 1e-3);
        }
    }
}
