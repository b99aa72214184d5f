//! The step's linear solve: sparse direct (the only module that names
//! faer) or preconditioned conjugate gradients (`pcg`).

use std::cell::RefCell;

use rayon::prelude::*;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SymbolicSupernodalCholesky, CholeskySymbolicParams,
    LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::assembly::CscPattern;
use crate::error::DdaError;
use crate::settings::Solver;

mod factor;
mod huge_pages;
mod pcg;
mod split;
mod subnormal;
mod update;

pub use pcg::ConjugateGradient;
pub use update::{FactorUpdate, UpdateTerm};

use subnormal::FlushSubnormals;

/// Solves symmetric positive definite systems given by their lower triangle.
pub trait LinearSolver: Send {
    /// Symbolic analysis of a pattern: kept for every factorisation until
    /// the next analysis.
    fn analyse(&mut self, pattern: &CscPattern) -> Result<(), DdaError>;

    /// Factorises the matrix with the analysed pattern and these values.
    fn factorize(&mut self, values: &[f64]) -> Result<(), DdaError>;

    /// Solves in place with the last factorization.
    fn solve(&self, rhs: &mut [f64]);

    /// Solves in place for a correction to an iterate whose tangent is
    /// itself approximate (a later Newton-Raphson move of a pass): the
    /// answer need only be as exact as that tangent, so a direct solver
    /// may use a single-precision copy of its factor. Default: `solve`.
    fn solve_correction(&self, rhs: &mut [f64]) {
        self.solve(rhs);
    }

    /// Whether `solve_correction` solves less exactly than `solve` on the
    /// same factor (a single-precision copy), so a correction that falls
    /// short may be the copy's and not the factor's. Default: no.
    fn corrections_inexact(&self) -> bool {
        false
    }

    /// A new step begins: forget what earlier systems left behind (an
    /// iterative solver's start), so a step solves the same whether the
    /// run went on or was resumed from a checkpoint before it.
    fn start_step(&mut self) {}

    /// What an iterative solver did since it was last asked (nothing for
    /// a direct one).
    fn take_counts(&self) -> SolveCounts {
        SolveCounts::default()
    }

    /// The factored matrix plus the terms Σ sⱼuⱼvⱼᵀ, made ready to solve
    /// with (`solve_updated`): `None` where the solver cannot.
    fn update(&self, _terms: &[UpdateTerm]) -> Option<FactorUpdate> {
        None
    }

    /// `solve` (with `exact`) or `solve_correction` of the factored matrix
    /// plus `update`'s terms. Only the solver that made `update` (or one
    /// that passes it on) solves with it.
    fn solve_updated(&self, _update: &FactorUpdate, _rhs: &mut [f64], _exact: bool) {
        unreachable!("solve_updated without update");
    }

    /// Entries of the factor a factorisation makes, the measure of its cost
    /// against a solve's; 0 where there is none to speak of (an iterative
    /// solver's block inverses).
    fn factor_entries(&self) -> usize {
        0
    }
}

/// Work of an iterative solver.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolveCounts {
    /// Systems solved.
    pub solves: usize,
    /// Conjugate-gradient iterations over them.
    pub iterations: usize,
    /// Systems that reached the iteration cap and were solved directly.
    pub fallbacks: usize,
}

/// The solver a scene's settings ask for.
pub fn solver_for(solver: Solver) -> Box<dyn LinearSolver> {
    match solver {
        Solver::Direct => Box::new(SparseCholesky::default()),
        Solver::Iterative {
            tolerance,
            max_iterations,
        } => Box::new(ConjugateGradient::new(tolerance, max_iterations)),
    }
}

/// Factor entries from which a factor also keeps a single-precision copy
/// for [`LinearSolver::solve_correction`]; default 2²⁰ (8 MB of `f64`).
/// Past the caches a triangular solve is bound by the memory it reads, and
/// half the bytes take little more than half the time; a smaller factor
/// gains little, and its runs keep their answers to the last bit.
pub const SINGLE_PRECISION_ENTRIES: usize = 1 << 20;

/// Factor entries from which the substitutions run on two cores (see
/// `split`); default 2¹⁸. A 20 × 20 wall's factor, ten times smaller,
/// solves no faster on two: the cores would wait on each other.
pub const SPLIT_ENTRIES: usize = 1 << 18;

/// Right-hand side entries a core takes at a time where a correction's
/// are scaled and permuted (a large factor's only: its right-hand sides
/// have tens of thousands).
const ENTRIES_PER_TASK: usize = 4096;

/// A split solve is kept only if it reads at most this share of the
/// factor one entry after another.
const SPLIT_SHARE: f64 = 0.8;

/// Sparse Cholesky (LLᵀ) from faer with a fill-reducing ordering. The
/// factor's storage and the workspaces are kept from one factorisation to
/// the next, so the hot path allocates nothing.
pub struct SparseCholesky {
    structure: Option<SymbolicSparseColMat<usize>>,
    symbolic: Option<SymbolicCholesky<usize>>,
    /// The values of L, in the symbolic analysis's layout.
    factor: Vec<f64>,
    /// The same rounded to `f32`, for correction solves; empty below
    /// `single_from` entries.
    single: Vec<f32>,
    /// Factor entries from which `single` is kept; default
    /// [`SINGLE_PRECISION_ENTRIES`].
    pub single_from: usize,
    factored: bool,
    /// Workspace of the factorisation and of the solves.
    scratch: RefCell<MemBuffer>,
    /// A correction's right-hand side in single precision, and the
    /// workspace of its solve.
    single_scratch: RefCell<(Vec<f32>, MemBuffer)>,
    /// How many symbolic analyses were done (for statistics and tests).
    pub analyses: usize,
    /// Factor entries from which the substitutions are split between two
    /// cores; default [`SPLIT_ENTRIES`].
    pub split_from: usize,
    /// The split of the analysed factor's tree, if it has one.
    split: Option<split::Split>,
    /// Where the factor is made on two cores, its layout (with `split`).
    numeric: Option<factor::Numeric>,
    /// A split solve's unknowns in the factor's ordering, and its buffers.
    split_work: RefCell<(Vec<f64>, split::Work<f64>)>,
    /// The same for a correction's.
    single_split_work: RefCell<split::Work<f32>>,
}

impl Default for SparseCholesky {
    fn default() -> Self {
        Self {
            structure: None,
            symbolic: None,
            factor: Vec::new(),
            single: Vec::new(),
            single_from: SINGLE_PRECISION_ENTRIES,
            factored: false,
            scratch: RefCell::new(MemBuffer::new(StackReq::EMPTY)),
            single_scratch: RefCell::new((Vec::new(), MemBuffer::new(StackReq::EMPTY))),
            analyses: 0,
            split_from: SPLIT_ENTRIES,
            split: None,
            numeric: None,
            split_work: RefCell::default(),
            single_split_work: RefCell::default(),
        }
    }
}

impl SparseCholesky {
    /// Where the substitutions run on two cores: the split, the tree it
    /// splits, and the ordering's forward and inverse permutations.
    fn split_parts(&self) -> Option<SplitParts<'_>> {
        let symbolic = self.symbolic.as_ref()?;
        let SymbolicCholeskyRaw::Supernodal(tree) = symbolic.raw() else {
            return None;
        };
        let (forward, inverse) = symbolic.perm()?.arrays();
        Some((self.split.as_ref()?, tree, forward, inverse))
    }
}

type SplitParts<'a> = (
    &'a split::Split,
    &'a SymbolicSupernodalCholesky<usize>,
    &'a [usize],
    &'a [usize],
);

impl LinearSolver for SparseCholesky {
    fn analyse(&mut self, pattern: &CscPattern) -> Result<(), DdaError> {
        let structure = SymbolicSparseColMat::new_checked(
            pattern.dim,
            pattern.dim,
            pattern.col_ptr.clone(),
            None,
            pattern.row_idx.clone(),
        );
        let symbolic = factorize_symbolic_cholesky(
            structure.as_ref(),
            Side::Lower,
            Default::default(),
            // Supernodal always: the blocks' dense 3 × 3 to 12 × 12
            // couplings make supernodes at every size, and faer's own
            // choice (by flops per factor entry) took the simplicial
            // factorisation for rigid walls to 20 × 20 and deformable ones
            // to 10 × 10, at 1.6-2.9 times the time (0.46 against 1.1-1.4
            // ms at 1,233 unknowns).
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(|e| DdaError::not_positive_definite(format!("{e:?}")))?;
        let need = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        self.scratch = RefCell::new(MemBuffer::new(need));
        self.factor = huge_pages::filled(symbolic.len_val(), 0.0);
        self.single = Vec::new();
        if symbolic.len_val() >= self.single_from {
            let need = symbolic.solve_in_place_scratch::<f32>(1, Par::Seq);
            self.single_scratch = RefCell::new((vec![0.0; pattern.dim], MemBuffer::new(need)));
        }
        self.split = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(tree) if symbolic.len_val() >= self.split_from => {
                split::Split::new(tree).filter(|s| s.share <= SPLIT_SHARE)
            }
            _ => None,
        };
        self.numeric = match (symbolic.raw(), &self.split) {
            (SymbolicCholeskyRaw::Supernodal(tree), Some(split)) => Some(factor::Numeric::new(
                tree,
                split,
                &pattern.col_ptr,
                &pattern.row_idx,
                symbolic.perm().map(|p| p.arrays().1),
            )),
            _ => None,
        };
        self.symbolic = Some(symbolic);
        self.structure = Some(structure);
        self.factored = false;
        self.analyses += 1;
        Ok(())
    }

    fn factorize(&mut self, values: &[f64]) -> Result<(), DdaError> {
        let (Some(structure), Some(symbolic)) = (&self.structure, &self.symbolic) else {
            panic!("factorize before analyse");
        };
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
        self.factored = false;
        if let (SymbolicCholeskyRaw::Supernodal(tree), Some(split), Some(numeric)) =
            (symbolic.raw(), &self.split, &mut self.numeric)
        {
            numeric
                .factorize(tree, split, values, &mut self.factor)
                .map_err(|s| {
                    DdaError::not_positive_definite(format!("NonPositivePivot in supernode {s}"))
                })?;
        } else {
            self.factor.fill(0.0);
            symbolic
                .factorize_numeric_llt::<f64>(
                    &mut self.factor,
                    matrix,
                    Side::Lower,
                    Default::default(),
                    Par::Seq,
                    MemStack::new(self.scratch.get_mut()),
                    Default::default(),
                )
                .map_err(|e| DdaError::not_positive_definite(format!("{e:?}")))?;
        }
        if self.factor.len() >= self.single_from {
            // On both cores: a large factor's copy reads 8 bytes an entry.
            const CHUNK: usize = 1 << 16;
            if self.single.len() != self.factor.len() {
                self.single = huge_pages::filled(self.factor.len(), 0.0);
            }
            (self
                .single
                .par_chunks_mut(CHUNK)
                .zip(self.factor.par_chunks(CHUNK)))
            .for_each(|(s, f)| s.iter_mut().zip(f).for_each(|(s, &f)| *s = f as f32));
        }
        self.factored = true;
        Ok(())
    }

    fn solve(&self, rhs: &mut [f64]) {
        assert!(self.factored, "solve before factorize");
        let symbolic = self.symbolic.as_ref().expect("analysed");
        if let Some((split, tree, forward, inverse)) = self.split_parts() {
            let (x, work) = &mut *self.split_work.borrow_mut();
            let rhs_in: &[f64] = rhs;
            (forward.par_iter())
                .with_min_len(ENTRIES_PER_TASK)
                .map(|&f| rhs_in[f])
                .collect_into_vec(x);
            split.solve(tree, &self.factor, x, work, None);
            let x: &[f64] = x;
            (rhs.par_iter_mut().zip(inverse))
                .with_min_len(ENTRIES_PER_TASK)
                .for_each(|(r, &i)| *r = x[i]);
            return;
        }
        let n = rhs.len();
        let col = MatMut::from_column_major_slice_mut(rhs, n, 1);
        LltRef::new(symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            col,
            Par::Seq,
            MemStack::new(&mut self.scratch.borrow_mut()),
        );
    }

    fn factor_entries(&self) -> usize {
        self.factor.len()
    }

    fn corrections_inexact(&self) -> bool {
        !self.single.is_empty()
    }

    fn update(&self, terms: &[UpdateTerm]) -> Option<FactorUpdate> {
        self.make_update(terms)
    }

    fn solve_updated(&self, update: &FactorUpdate, rhs: &mut [f64], exact: bool) {
        self.solve_with_update(update, rhs, exact);
    }

    fn solve_correction(&self, rhs: &mut [f64]) {
        if self.single.is_empty() {
            return self.solve(rhs);
        }
        assert!(self.factored, "solve before factorize");
        let symbolic = self.symbolic.as_ref().expect("analysed");
        // Scaled to its largest entry, so no entry leaves f32's range.
        let scale = (rhs.par_iter())
            .with_min_len(ENTRIES_PER_TASK)
            .fold(|| 0.0_f64, |m, r| m.max(r.abs()))
            .reduce(|| 0.0, f64::max);
        if scale == 0.0 || !scale.is_finite() {
            return self.solve(rhs);
        }
        let (single, stack) = &mut *self.single_scratch.borrow_mut();
        if let Some((split, tree, forward, inverse)) = self.split_parts() {
            // The permutations on every core: on one, the scaling and the
            // permutations of both precisions took 3.3 ms a step of the
            // 10,051-block 3D wall's moves.
            let rhs_in: &[f64] = rhs;
            (single.par_iter_mut().zip(forward))
                .with_min_len(ENTRIES_PER_TASK)
                .for_each(|(s, &f)| *s = (rhs_in[f] / scale) as f32);
            let work = &mut self.single_split_work.borrow_mut();
            split.solve(tree, &self.single, single, work, None);
            let single: &[f32] = single;
            (rhs.par_iter_mut().zip(inverse))
                .with_min_len(ENTRIES_PER_TASK)
                .for_each(|(r, &i)| *r = f64::from(single[i]) * scale);
            return;
        }
        for (s, r) in single.iter_mut().zip(rhs.iter()) {
            *s = (r / scale) as f32;
        }
        let n = single.len();
        let _flush = FlushSubnormals::on(true);
        LltRef::new(symbolic, &self.single).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(single, n, 1),
            Par::Seq,
            MemStack::new(stack),
        );
        for (r, s) in rhs.iter_mut().zip(single.iter()) {
            *r = f64::from(*s) * scale;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [4 1 0; 1 3 1; 0 1 2]'s lower triangle in CSC.
    fn tridiagonal() -> CscPattern {
        CscPattern {
            dim: 3,
            col_ptr: vec![0, 2, 4, 5],
            row_idx: vec![0, 1, 1, 2, 2],
            blocks: Vec::new(),
        }
    }

    #[test]
    fn solves_a_small_spd_system_and_reuses_the_analysis() {
        let pattern = tridiagonal();
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
    fn corrections_use_the_single_precision_copy_of_a_large_factor_only() {
        let pattern = tridiagonal();
        let values = [4.0, 1.0, 3.0, 1.0, 2.0];
        let mut single = SparseCholesky {
            single_from: 0,
            ..Default::default()
        };
        let mut double = SparseCholesky::default();
        for s in [&mut single, &mut double] {
            s.analyse(&pattern).unwrap();
            s.factorize(&values).unwrap();
        }
        // x = (1, 1, 1) at every scale, far beyond f32's range too: the
        // right-hand side is scaled to its largest entry.
        for scale in [1.0, 1e-300, 1e300] {
            let b: Vec<f64> = [5.0, 5.0, 3.0].iter().map(|v| v * scale).collect();
            let mut x = b.clone();
            single.solve_correction(&mut x);
            for x in &x {
                let error = (x / scale - 1.0).abs();
                assert!(error < 1e-6 && error > 0.0, "{error}");
            }
            // A small factor keeps no copy: its corrections are exact.
            let (mut y, mut z) = (b.clone(), b.clone());
            double.solve_correction(&mut y);
            double.solve(&mut z);
            assert_eq!(y, z);
        }
        let mut zero = vec![0.0; 3];
        single.solve_correction(&mut zero);
        assert_eq!(zero, [0.0; 3]);
    }

    #[test]
    fn factorises_supernodally_where_faer_would_choose_simplicial() {
        // One flop per factor entry, far below faer's own threshold for
        // supernodes.
        let pattern = tridiagonal();
        let mut s = SparseCholesky::default();
        s.analyse(&pattern).unwrap();
        let symbolic = s.symbolic.as_ref().unwrap();
        assert!(matches!(
            symbolic.raw(),
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(_)
        ));
    }

    #[test]
    fn reports_an_indefinite_matrix() {
        let pattern = CscPattern {
            dim: 2,
            col_ptr: vec![0, 2, 3],
            row_idx: vec![0, 1, 1],
            blocks: Vec::new(),
        };
        let mut s = SparseCholesky::default();
        s.analyse(&pattern).unwrap();
        assert!(s.factorize(&[1.0, 2.0, 1.0]).is_err());
    }

    /// `values` factorised, with a single-precision copy, split between
    /// the cores from `split_from` entries.
    pub(super) fn factored(
        pattern: &CscPattern,
        values: &[f64],
        split_from: usize,
    ) -> SparseCholesky {
        let mut s = SparseCholesky {
            split_from,
            single_from: 0,
            ..Default::default()
        };
        s.analyse(pattern).unwrap();
        s.factorize(values).unwrap();
        s
    }

    /// A g × g grid of blocks of `b` unknowns, each coupled to its right
    /// and upper neighbours, diagonally dominant: the lower triangle's
    /// pattern and values.
    pub(super) fn grid(g: usize, b: usize) -> (CscPattern, Vec<f64>) {
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for block in 0..g * g {
            for k in 0..b {
                let column = block * b + k;
                let mut rows: Vec<usize> = (column..(block + 1) * b).collect();
                for next in [block + 1, block + g] {
                    let beside = next == block + g || next % g != 0;
                    if next < g * g && beside {
                        rows.extend(next * b..(next + 1) * b);
                    }
                }
                for r in rows {
                    row_idx.push(r);
                    let v = if r == column {
                        5.0 * b as f64 + 1.0
                    } else {
                        ((r * 7919 + column * 104_729) as f64).sin()
                    };
                    values.push(v);
                }
                col_ptr.push(row_idx.len());
            }
        }
        let blocks = (0..=g * g).map(|i| i * b).collect();
        let dim = g * g * b;
        (
            CscPattern {
                dim,
                col_ptr,
                row_idx,
                blocks,
            },
            values,
        )
    }

    /// A single-precision correction takes a subnormal share of its
    /// scaled right-hand side as zero, split or not, on one core or two;
    /// an exact solve keeps it.
    #[test]
    fn corrections_take_subnormal_shares_as_zero() {
        // The grid and one unknown of its own, whose right-hand side is
        // 1e-40 of the largest (a subnormal in f32).
        let (mut pattern, mut values) = grid(40, 3);
        let lone = pattern.dim;
        pattern.dim += 1;
        pattern.row_idx.push(lone);
        pattern.col_ptr.push(pattern.row_idx.len());
        pattern.blocks.push(lone + 1);
        values.push(2.0);
        let mut b: Vec<f64> = (0..lone).map(|i| (i as f64 * 0.37).cos()).collect();
        b.push(1e-40);
        for split_from in [0, usize::MAX] {
            for threads in [1, 2] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let (exact, correction) = pool.install(|| {
                    let s = factored(&pattern, &values, split_from);
                    let (mut exact, mut correction) = (b.clone(), b.clone());
                    s.solve(&mut exact);
                    s.solve_correction(&mut correction);
                    (exact, correction)
                });
                assert!((exact[lone] / 5e-41 - 1.0).abs() < 1e-12, "{}", exact[lone]);
                // Flushed on x86-64 only (`subnormal.rs`).
                if cfg!(target_arch = "x86_64") {
                    assert_eq!(
                        correction[lone], 0.0,
                        "split from {split_from}, {threads} cores"
                    );
                }
                for (x, y) in correction[..lone].iter().zip(&exact) {
                    assert!((x - y).abs() <= 1e-5, "{x} against {y}");
                }
            }
        }
    }

    /// `b` solved on the grid `(pattern, values)` with the split from
    /// `split_from` entries on, on `threads` cores, exactly or as a
    /// correction; with what `read` reads off the solver.
    fn solved_on<R: Send>(
        (pattern, values): &(CscPattern, Vec<f64>),
        b: &[f64],
        (split_from, threads, correction): (usize, usize, bool),
        read: impl Fn(&SparseCholesky) -> R + Send + Sync,
    ) -> (Vec<f64>, R) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let s = factored(pattern, values, split_from);
            let mut x = b.to_vec();
            if correction {
                s.solve_correction(&mut x);
            } else {
                s.solve(&mut x);
            }
            (x, read(&s))
        })
    }

    #[test]
    fn split_substitutions_agree_with_one_core_and_on_any_number_of_cores() {
        let grid = grid(40, 3);
        let b: Vec<f64> = (0..grid.0.dim).map(|i| (i as f64 * 0.37).cos()).collect();
        // With the split's share.
        let solved = |split_from: usize, threads: usize, correction: bool| {
            let share = |s: &SparseCholesky| s.split.as_ref().map(|s| s.share);
            solved_on(&grid, &b, (split_from, threads, correction), share)
        };
        let (expected, none) = solved(usize::MAX, 2, false);
        assert_eq!(none, None);
        let (exact, share) = solved(0, 2, false);
        let share = share.expect("a grid's tree splits");
        assert!(share < 0.7, "{share}");
        let largest = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (x, y) in exact.iter().zip(&expected) {
            assert!((x - y).abs() <= 1e-13 * largest, "{x} against {y}");
        }
        assert_eq!(exact, solved(0, 1, false).0);
        // Corrections: single precision, split or not.
        let (correction, _) = solved(0, 2, true);
        let (single, _) = solved(usize::MAX, 2, true);
        for (x, (y, z)) in correction.iter().zip(expected.iter().zip(&single)) {
            assert!((x - y).abs() <= 1e-5 * largest, "{x} against {y}");
            assert!((x - z).abs() <= 1e-5 * largest, "{x} against {z}");
        }
        assert_eq!(correction, solved(0, 1, true).0);
    }

    /// The top's widest supernodes, their rows shared between the cores
    /// and their triangles halved, solve as one core does unsplit.
    #[test]
    fn shared_top_supernodes_agree_with_one_core() {
        // The top separator: 48 blocks of 6 unknowns, 288 columns.
        let grid = grid(48, 6);
        let b: Vec<f64> = (0..grid.0.dim).map(|i| (i as f64 * 0.37).cos()).collect();
        // With the count of supernodes shared.
        let solved = |split_from: usize, threads: usize, correction: bool| {
            let shared = |s: &SparseCholesky| {
                (s.split_parts()).map(|(split, tree, _, _)| split.shared(tree))
            };
            solved_on(&grid, &b, (split_from, threads, correction), shared)
        };
        let (expected, _) = solved(usize::MAX, 2, false);
        let largest = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let (exact, shared) = solved(0, 2, false);
        assert!(shared.is_some_and(|s| s >= 1), "{shared:?}");
        for (x, y) in exact.iter().zip(&expected) {
            assert!((x - y).abs() <= 1e-13 * largest, "{x} against {y}");
        }
        assert_eq!(exact, solved(0, 1, false).0);
        let (correction, _) = solved(0, 2, true);
        for (x, y) in correction.iter().zip(&expected) {
            assert!((x - y).abs() <= 1e-5 * largest, "{x} against {y}");
        }
        assert_eq!(correction, solved(0, 1, true).0);
    }
}
