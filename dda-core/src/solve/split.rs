//! Forward and back substitution on two cores. The elimination tree of a
//! supernodal factor splits into subtrees that share no unknown; each core
//! takes a set of them, and the supernodes above them (the top) are solved
//! on one core between the two sweeps. The split depends on the factor's
//! structure alone and the cores' sums are added in a fixed order, so an
//! answer does not depend on how many cores there are.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::traits::ComplexField;
use faer::{Accum, MatMut, MatRef, Par};

use super::subnormal::FlushSubnormals;

/// Subtrees opened into their children while looking for the best split.
const OPENINGS: usize = 1024;

/// The split stops opening subtrees once the heaviest holds less than
/// this share of the factor.
const SMALLEST_SHARE: f64 = 1.0 / 64.0;

/// A top supernode of at least this many entries is swept on both cores,
/// its rows shared between them: the top's widest (972 columns on the
/// 10,051-block 2D wall, 1,944 in 3D) would otherwise hold one core idle.
const SHARED_NODE_ENTRIES: usize = 1 << 15;

/// A shared supernode's triangle is halved down to this width, the halves'
/// products shared between the cores.
const SHARED_TRIANGLE: usize = 128;

/// Scalars of a substitution: `f64` for exact solves, `f32` for
/// corrections.
pub(crate) trait Scalar:
    ComplexField
    + Copy
    + Default
    + Send
    + Sync
    + std::ops::AddAssign
    + std::ops::SubAssign
    + std::ops::Neg<Output = Self>
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
{
    /// The value in double precision.
    fn widen(self) -> f64;
    /// A double-precision value rounded to this scalar.
    fn narrow(value: f64) -> Self;
    /// Whether its substitutions take subnormals as zero (`subnormal.rs`).
    const FLUSH: bool;
}
impl Scalar for f64 {
    const FLUSH: bool = false;
    fn widen(self) -> f64 {
        self
    }
    fn narrow(value: f64) -> Self {
        value
    }
}
impl Scalar for f32 {
    const FLUSH: bool = true;
    fn widen(self) -> f64 {
        f64::from(self)
    }
    fn narrow(value: f64) -> Self {
        value as f32
    }
}

/// What a solve applies to L⁻¹b between its two sweeps.
pub(super) type Between<'a, T> = &'a dyn Fn(&mut [T]);

/// Supernodes `first..=root`, whose unknowns are `begin..end`.
#[derive(Debug, Clone, Copy)]
struct Subtree {
    first: usize,
    root: usize,
    begin: usize,
    end: usize,
}

/// Which subtrees each core takes, and the supernodes above them.
#[derive(Debug, Clone)]
pub(crate) struct Split {
    cores: [Vec<Subtree>; 2],
    /// Supernodes in no subtree, children before parents.
    top: Vec<usize>,
    /// The most rows in a supernode, its diagonal block's and those below.
    widest: usize,
    /// Factor entries read one after another (the top and the busier
    /// core's), as a share of all: the split solve's time against one
    /// core's.
    pub share: f64,
}

impl Split {
    /// The best split of the factor's supernodes, if the tree has the
    /// layout faer gives it (every subtree's supernodes consecutive and
    /// each parent after its children).
    pub fn new(symbolic: &SymbolicSupernodalCholesky<usize>) -> Option<Self> {
        let count = symbolic.n_supernodes();
        let (begin, end) = (symbolic.supernode_begin(), symbolic.supernode_end());
        let supernode_of = supernode_of(symbolic);
        let rows = |s: usize| pattern(symbolic, s);
        // Each subtree's entries, first supernode, size and children; the
        // parent is the supernode of the first row below the diagonal.
        let mut entries = vec![0; count];
        let mut first: Vec<usize> = (0..count).collect();
        let mut size = vec![1; count];
        let mut children = vec![Vec::new(); count];
        let mut roots = Vec::new();
        let mut widest = 0;
        for s in 0..count {
            let width = end[s] - begin[s];
            widest = widest.max(width + rows(s).len());
            entries[s] += width * (width + rows(s).len());
            match rows(s).first() {
                None => roots.push(s),
                Some(&r) => {
                    let parent = supernode_of[r];
                    if parent <= s {
                        return None;
                    }
                    children[parent].push(s);
                    entries[parent] += entries[s];
                    size[parent] += size[s];
                    first[parent] = first[parent].min(first[s]);
                }
            }
        }
        if (0..count).any(|s| s + 1 - first[s] != size[s]) {
            return None;
        }
        let total: usize = roots.iter().map(|&s| entries[s]).sum();
        // Open the heaviest subtree into its children, its root going to
        // the top, and keep the split whose busier core and top read the
        // fewest entries.
        let balance = |subtrees: &[usize]| {
            let mut sorted = subtrees.to_vec();
            sorted.sort_by_key(|&s| (std::cmp::Reverse(entries[s]), s));
            let mut cores: [Vec<usize>; 2] = Default::default();
            let mut loads = [0; 2];
            for s in sorted {
                let lighter = usize::from(loads[1] < loads[0]);
                loads[lighter] += entries[s];
                cores[lighter].push(s);
            }
            (loads[0].max(loads[1]), cores)
        };
        let mut subtrees = roots;
        let mut top = Vec::new();
        let mut top_entries = 0;
        let mut best = (usize::MAX, Vec::new(), Vec::new());
        for _ in 0..OPENINGS {
            let (busier, _) = balance(&subtrees);
            if top_entries + busier < best.0 {
                best = (top_entries + busier, subtrees.clone(), top.clone());
            }
            let Some(at) = (0..subtrees.len()).max_by_key(|&k| (entries[subtrees[k]], subtrees[k]))
            else {
                break;
            };
            let heaviest = subtrees.swap_remove(at);
            if (entries[heaviest] as f64) < SMALLEST_SHARE * total as f64 {
                break;
            }
            let below: usize = children[heaviest].iter().map(|&c| entries[c]).sum();
            top_entries += entries[heaviest] - below;
            top.push(heaviest);
            subtrees.extend(&children[heaviest]);
        }
        let (read, subtrees, mut top) = best;
        let (_, cores) = balance(&subtrees);
        top.sort_unstable();
        let subtree = |s: usize| Subtree {
            first: first[s],
            root: s,
            begin: begin[first[s]],
            end: end[s],
        };
        Some(Self {
            cores: cores.map(|c| c.into_iter().map(subtree).collect()),
            top,
            widest,
            share: read as f64 / total.max(1) as f64,
        })
    }

    /// Solves L Lᵀ x = b in place, `x` in the factor's ordering; with
    /// `between`, applied to L⁻¹b between the two sweeps.
    pub fn solve<T: Scalar>(
        &self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
        values: &[T],
        x: &mut [T],
        work: &mut Work<T>,
        between: Option<Between<'_, T>>,
    ) {
        let _flush = FlushSubnormals::on(T::FLUSH);
        let factor = SupernodalLltRef::new(symbolic, values);
        let n = x.len();
        for gathered in &mut work.gathered {
            gathered.resize(n, T::default());
        }
        for below in &mut work.below {
            below.resize(self.widest, T::default());
        }
        // Forward: each core its subtrees, gathering what they take from
        // the top's unknowns; then the top.
        let [p0, p1] = self.pieces(x);
        let ([g0, g1], [b0, b1]) = (&mut work.gathered, &mut work.below);
        rayon::join(
            || forward_subtrees(factor, p0, g0, b0),
            || forward_subtrees(factor, p1, g1, b1),
        );
        for &s in &self.top {
            for r in begin_end(factor, s) {
                x[r] -= g0[r];
                x[r] -= g1[r];
                g0[r] = T::default();
                g1[r] = T::default();
            }
        }
        let mut all = Own {
            values: x,
            offset: 0,
            end: n,
        };
        for &s in &self.top {
            top_node(
                factor,
                s,
                &mut all,
                [&mut b0[..], &mut b1[..]],
                Sweep::Forward,
            );
        }
        if let Some(between) = between {
            between(all.values);
        }
        // Back: the top, then each core its subtrees, reading the top's
        // unknowns from a copy.
        for &s in self.top.iter().rev() {
            top_node(factor, s, &mut all, [&mut b0[..], &mut b1[..]], Sweep::Back);
        }
        work.top.clear();
        work.top.extend_from_slice(x);
        let top = &work.top;
        let [p0, p1] = self.pieces(x);
        let [b0, b1] = &mut work.below;
        rayon::join(
            || back_subtrees(factor, p0, top, b0),
            || back_subtrees(factor, p1, top, b1),
        );
    }

    /// Which core's subtrees hold each of the `count` supernodes; 2 for
    /// the top.
    pub fn cores(&self, count: usize) -> Vec<u8> {
        let mut core = vec![2; count];
        for (c, subtrees) in (0u8..).zip(&self.cores) {
            for t in subtrees {
                core[t.first..=t.root].fill(c);
            }
        }
        core
    }

    /// The supernodes in no subtree, children before parents.
    pub fn top(&self) -> &[usize] {
        &self.top
    }

    /// The top's supernodes swept on both cores (`SHARED_NODE_ENTRIES`).
    #[cfg(test)]
    pub fn shared(&self, symbolic: &SymbolicSupernodalCholesky<usize>) -> usize {
        let (begin, end) = (symbolic.supernode_begin(), symbolic.supernode_end());
        (self.top.iter())
            .filter(|&&s| {
                let width = end[s] - begin[s];
                is_shared(width, pattern(symbolic, s).len()) && width > SHARED_TRIANGLE
            })
            .count()
    }

    /// The factor's entries cut into each subtree's columns, by core: its
    /// supernodes, and where its columns start in the factor.
    pub fn factor_pieces<'f, T>(
        &self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
        factor: &'f mut [T],
    ) -> [Vec<FactorPiece<'f, T>>; 2] {
        let at = symbolic.col_ptr_for_val();
        let mut pieces: [Vec<_>; 2] = Default::default();
        let (mut rest, mut offset) = (factor, 0);
        for (core, t) in self.in_order() {
            let (_, tail) = rest.split_at_mut(at[t.first] - offset);
            let (columns, tail) = tail.split_at_mut(at[t.root + 1] - at[t.first]);
            pieces[core].push((t.first..=t.root, at[t.first], columns));
            (rest, offset) = (tail, at[t.root + 1]);
        }
        pieces
    }

    /// Every subtree with its core, in the factor's order (of their
    /// supernodes, so of their unknowns and entries too).
    fn in_order(&self) -> Vec<(usize, Subtree)> {
        let mut all: Vec<(usize, Subtree)> = (self.cores.iter().enumerate())
            .flat_map(|(core, subtrees)| subtrees.iter().map(move |t| (core, *t)))
            .collect();
        all.sort_by_key(|(_, t)| t.first);
        all
    }

    /// `x` cut into each subtree's unknowns, by core.
    fn pieces<'x, T>(&self, x: &'x mut [T]) -> [Vec<(Subtree, Own<'x, T>)>; 2] {
        let mut pieces: [Vec<_>; 2] = Default::default();
        let (mut rest, mut at) = (x, 0);
        for (core, t) in self.in_order() {
            let (_, tail) = rest.split_at_mut(t.begin - at);
            let (values, tail) = tail.split_at_mut(t.end - t.begin);
            let own = Own {
                values,
                offset: t.begin,
                end: t.end,
            };
            pieces[core].push((t, own));
            (rest, at) = (tail, t.end);
        }
        pieces
    }
}

/// A subtree's supernodes, the factor entry its columns start at, and
/// its columns.
pub(super) type FactorPiece<'f, T> = (std::ops::RangeInclusive<usize>, usize, &'f mut [T]);

/// A split solve's buffers, kept from one solve to the next.
#[derive(Debug, Default)]
pub(crate) struct Work<T> {
    /// Each core's updates of the top's unknowns (zero between solves).
    gathered: [Vec<T>; 2],
    /// Each core's product of a supernode's rows below its diagonal.
    below: [Vec<T>; 2],
    /// The unknowns once the top is solved, read by both cores.
    top: Vec<T>,
}

fn begin_end<T>(factor: SupernodalLltRef<'_, usize, T>, s: usize) -> std::ops::Range<usize> {
    let node = factor.supernode(s);
    node.start()..node.start() + node.val().ncols()
}

fn forward_subtrees<T: Scalar>(
    factor: SupernodalLltRef<'_, usize, T>,
    pieces: Vec<(Subtree, Own<'_, T>)>,
    gathered: &mut [T],
    below: &mut [T],
) {
    // Each core's sweep sets its own thread's mode.
    let _flush = FlushSubnormals::on(T::FLUSH);
    for (t, mut own) in pieces {
        for s in t.first..=t.root {
            forward_node(factor, s, &mut own, gathered, below);
        }
    }
}

fn back_subtrees<T: Scalar>(
    factor: SupernodalLltRef<'_, usize, T>,
    pieces: Vec<(Subtree, Own<'_, T>)>,
    top: &[T],
    below: &mut [T],
) {
    let _flush = FlushSubnormals::on(T::FLUSH);
    for (t, mut own) in pieces {
        for s in (t.first..=t.root).rev() {
            back_node(factor, s, &mut own, top, below);
        }
    }
}

/// Solves L Lᵀ x = b in place on one core, supernode by supernode, `x`
/// in the factor's ordering, with `between` applied to L⁻¹b between the
/// sweeps. `below` holds a supernode's rows below its diagonal.
pub(super) fn solve_sequential<T: Scalar>(
    symbolic: &SymbolicSupernodalCholesky<usize>,
    values: &[T],
    x: &mut [T],
    below: &mut [T],
    between: Between<'_, T>,
) {
    let _flush = FlushSubnormals::on(T::FLUSH);
    let factor = SupernodalLltRef::new(symbolic, values);
    let count = symbolic.n_supernodes();
    let mut all = Own::whole(x);
    for s in 0..count {
        forward_node(factor, s, &mut all, &mut [], below);
    }
    between(all.values);
    for s in (0..count).rev() {
        back_node(factor, s, &mut all, &[], below);
    }
}

/// Each unknown's supernode.
pub(super) fn supernode_of(symbolic: &SymbolicSupernodalCholesky<usize>) -> Vec<usize> {
    let (begin, end) = (symbolic.supernode_begin(), symbolic.supernode_end());
    let mut supernode_of = vec![0; symbolic.nrows()];
    for s in 0..symbolic.n_supernodes() {
        supernode_of[begin[s]..end[s]].fill(s);
    }
    supernode_of
}

/// The rows below supernode `s`'s diagonal block.
pub(super) fn pattern(symbolic: &SymbolicSupernodalCholesky<usize>, s: usize) -> &[usize] {
    let at = symbolic.col_ptr_for_row_idx();
    &symbolic.row_idx()[at[s]..at[s + 1]]
}

/// Unknowns `offset..end`, which a sweep over a subtree (or the top, with
/// all of them) writes.
struct Own<'a, T> {
    values: &'a mut [T],
    offset: usize,
    end: usize,
}

impl<'a, T> Own<'a, T> {
    /// All of the unknowns.
    fn whole(values: &'a mut [T]) -> Self {
        let end = values.len();
        Self {
            values,
            offset: 0,
            end,
        }
    }
}

/// Supernode `s`: its diagonal block, the rows below it and their indices,
/// and where its unknowns lie in `own`.
fn supernode<'f, T>(
    factor: SupernodalLltRef<'f, usize, T>,
    s: usize,
    own: &Own<'_, T>,
) -> (
    MatRef<'f, T>,
    MatRef<'f, T>,
    &'f [usize],
    std::ops::Range<usize>,
) {
    let node = factor.supernode(s);
    let width = node.val().ncols();
    let at = node.start() - own.offset;
    let (diagonal, lower) = node.val().split_at_row(width);
    (diagonal, lower, node.pattern(), at..at + width)
}

/// Supernode `s`'s values, column by column: each the diagonal block's
/// column, then the rows below it.
fn columns<'f, T>(factor: SupernodalLltRef<'f, usize, T>, s: usize) -> &'f [T] {
    let at = factor.symbolic().col_ptr_for_val();
    &factor.values()[at[s]..at[s + 1]]
}

/// Supernode `s`'s forward substitution: its unknowns solved, its products
/// subtracted from the rows below within `own` and added to `gathered`
/// beyond it. One pass down each column, triangle and rows below alike,
/// its products gathered in `below` (at least the supernode's rows long):
/// faer's triangular solve and product per supernode cost more in calls
/// than in arithmetic on the small supernodes that hold most entries.
fn forward_node<T: Scalar>(
    factor: SupernodalLltRef<'_, usize, T>,
    s: usize,
    own: &mut Own<'_, T>,
    gathered: &mut [T],
    below: &mut [T],
) {
    let node = factor.supernode(s);
    let (rows, width) = (node.pattern(), node.val().ncols());
    let n = width + rows.len();
    let at = node.start() - own.offset;
    let v = &mut below[..n];
    v[..width].copy_from_slice(&own.values[at..at + width]);
    v[width..].fill(T::default());
    for (j, column) in columns(factor, s).chunks_exact(n).enumerate() {
        // The reciprocal is made off the sweep's chain of dependences,
        // where a division would wait in it.
        let xj = v[j] * (T::one_impl() / column[j]);
        v[j] = xj;
        for (v, &l) in v[j + 1..].iter_mut().zip(&column[j + 1..]) {
            *v -= xj * l;
        }
    }
    own.values[at..at + width].copy_from_slice(&v[..width]);
    // The rows below hold minus their products.
    for (&r, &v) in rows.iter().zip(&v[width..]) {
        if r < own.end {
            own.values[r - own.offset] += v;
        } else {
            gathered[r] -= v;
        }
    }
}

/// Supernode `s`'s back substitution, reading the rows below within `own`
/// and from `top` beyond it. Every read runs down through memory: the
/// back sweep meets the supernodes last to first, and a sweep that read
/// each one upwards would leave the processor's prefetch running up into
/// the supernode just done instead of down into the next (it took about
/// twice the forward sweep's time). Each column's product with the rows
/// below is independent of the unknowns being solved, so it overlaps the
/// triangle's chain of dependences. `below`: at least the supernode's rows.
fn back_node<T: Scalar>(
    factor: SupernodalLltRef<'_, usize, T>,
    s: usize,
    own: &mut Own<'_, T>,
    top: &[T],
    below: &mut [T],
) {
    let node = factor.supernode(s);
    let (rows, width) = (node.pattern(), node.val().ncols());
    let n = width + rows.len();
    let at = node.start() - own.offset;
    let below = &mut below[..rows.len()];
    for (v, &r) in below.iter_mut().zip(rows).rev() {
        *v = if r < own.end {
            own.values[r - own.offset]
        } else {
            top[r]
        };
    }
    let x = &mut own.values[at..at + width];
    for (j, column) in columns(factor, s).chunks_exact(n).enumerate().rev() {
        let rectangle = dot(&column[width..], below);
        let triangle = dot(&column[j + 1..width], &x[j + 1..]);
        x[j] = (x[j] - rectangle - triangle) * (T::one_impl() / column[j]);
    }
}

/// Partial sums of a dot product: one register of single-precision lanes
/// (two of double) under AVX-512, which the compiler fills.
const LANES: usize = 16;

/// The dot product of `a` and `b` (as long as `a`), read from the end
/// (`back_node`), summed on `LANES` lanes and the lanes added pairwise:
/// in a back sweep's triangle each column's sum waits on the last unknown
/// solved, and a single running sum, or lanes added one after another,
/// would make that wait sixteen additions long instead of four.
#[inline(always)]
fn dot<T: Scalar>(a: &[T], b: &[T]) -> T {
    let mut lanes = [T::default(); LANES];
    let (a, b) = (a.rchunks_exact(LANES), b[..a.len()].rchunks_exact(LANES));
    let (first_a, first_b) = (a.remainder(), b.remainder());
    for (a, b) in a.zip(b) {
        for k in 0..LANES {
            lanes[k] += a[k] * b[k];
        }
    }
    for (k, (&a, &b)) in first_a.iter().zip(first_b).enumerate() {
        lanes[k] += a * b;
    }
    let mut half = LANES;
    while half > 1 {
        half /= 2;
        for k in 0..half {
            lanes[k] += lanes[k + half];
        }
    }
    lanes[0]
}

/// Whether a top supernode of `width` columns and `below` rows under its
/// diagonal block is swept on both cores (`SHARED_NODE_ENTRIES`).
fn is_shared(width: usize, below: usize) -> bool {
    width * (width + below) >= SHARED_NODE_ENTRIES
}

/// Which substitution a top supernode takes part in.
#[derive(Clone, Copy)]
enum Sweep {
    Forward,
    Back,
}

/// Top supernode `s`'s part of a sweep over every unknown (`forward_node`
/// or `back_node`), a large one's rows shared between the cores.
/// `buffers`: each `widest` long.
fn top_node<T: Scalar>(
    factor: SupernodalLltRef<'_, usize, T>,
    s: usize,
    own: &mut Own<'_, T>,
    [below, work]: [&mut [T]; 2],
    sweep: Sweep,
) {
    let (diagonal, lower, rows, at) = supernode(factor, s, own);
    if !is_shared(at.len(), rows.len()) {
        return match sweep {
            Sweep::Forward => forward_node(factor, s, own, &mut [], below),
            Sweep::Back => back_node(factor, s, own, &[], below),
        };
    }
    let below = &mut below[..rows.len()];
    match sweep {
        Sweep::Forward => {
            let x = &mut own.values[at];
            lower_shared(diagonal, x, work);
            product_shared(lower, x, below);
            for (&r, v) in rows.iter().zip(below.iter()) {
                own.values[r - own.offset] -= *v;
            }
        }
        Sweep::Back => {
            for (v, &r) in below.iter_mut().zip(rows) {
                *v = own.values[r - own.offset];
            }
            let x = &mut own.values[at];
            subtract_transposed_shared(lower, below, x, work);
            upper_shared(diagonal, x, work);
        }
    }
}

/// Solves L x = b in place (L lower triangular): the halves' triangles in
/// turn, the product between them shared. `work`: at least L's width
/// less half.
fn lower_shared<T: Scalar>(l: MatRef<'_, T>, x: &mut [T], work: &mut [T]) {
    let (width, half) = (l.nrows(), l.nrows() / 2);
    if width <= SHARED_TRIANGLE {
        let x = MatMut::from_column_major_slice_mut(x, width, 1);
        return solve_lower_triangular_in_place(l, x, Par::Seq);
    }
    let (x1, x2) = x.split_at_mut(half);
    lower_shared(l.submatrix(0, 0, half, half), x1, work);
    let taken = &mut work[..width - half];
    product_shared(l.submatrix(half, 0, width - half, half), x1, taken);
    for (x, t) in x2.iter_mut().zip(taken.iter()) {
        *x -= *t;
    }
    lower_shared(
        l.submatrix(half, half, width - half, width - half),
        x2,
        work,
    );
}

/// Solves Lᵀ x = b in place (L lower triangular), as `lower_shared`
/// backwards. `work`: at least half of L's width.
fn upper_shared<T: Scalar>(l: MatRef<'_, T>, x: &mut [T], work: &mut [T]) {
    let (width, half) = (l.nrows(), l.nrows() / 2);
    if width <= SHARED_TRIANGLE {
        let x = MatMut::from_column_major_slice_mut(x, width, 1);
        return solve_upper_triangular_in_place(l.transpose(), x, Par::Seq);
    }
    let (x1, x2) = x.split_at_mut(half);
    upper_shared(
        l.submatrix(half, half, width - half, width - half),
        x2,
        work,
    );
    subtract_transposed_shared(l.submatrix(half, 0, width - half, half), x2, x1, work);
    upper_shared(l.submatrix(0, 0, half, half), x1, work);
}

/// y = A x, each core taking half of A's rows.
fn product_shared<T: Scalar>(a: MatRef<'_, T>, x: &[T], y: &mut [T]) {
    let half = a.nrows() / 2;
    let (a1, a2) = a.split_at_row(half);
    let (y1, y2) = y.split_at_mut(half);
    let product = |a: MatRef<'_, T>, y: &mut [T]| {
        let _flush = FlushSubnormals::on(T::FLUSH);
        let y = MatMut::from_column_major_slice_mut(y, a.nrows(), 1);
        let x = MatRef::from_column_major_slice(x, a.ncols(), 1);
        matmul(y, Accum::Replace, a, x, T::one_impl(), Par::Seq);
    };
    rayon::join(|| product(a1, y1), || product(a2, y2));
}

/// x −= Aᵀ b, each core taking half of A's rows; the second half's sum,
/// made in `work` (x's length), is taken last.
fn subtract_transposed_shared<T: Scalar>(a: MatRef<'_, T>, b: &[T], x: &mut [T], work: &mut [T]) {
    let half = a.nrows() / 2;
    let (a1, a2) = a.split_at_row(half);
    let (b1, b2) = b.split_at(half);
    let sum = &mut work[..x.len()];
    let product = |a: MatRef<'_, T>, b: &[T], y: &mut [T], accum: Accum, sign: T| {
        let _flush = FlushSubnormals::on(T::FLUSH);
        let y = MatMut::from_column_major_slice_mut(y, a.ncols(), 1);
        let b = MatRef::from_column_major_slice(b, a.nrows(), 1);
        matmul(y, accum, a.transpose(), b, sign, Par::Seq);
    };
    rayon::join(
        || product(a1, b1, x, Accum::Add, -T::one_impl()),
        || product(a2, b2, sum, Accum::Replace, T::one_impl()),
    );
    for (x, s) in x.iter_mut().zip(sum.iter()) {
        *x -= *s;
    }
}
