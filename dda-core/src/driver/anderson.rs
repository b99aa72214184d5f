//! Anderson acceleration of the Newton-Raphson iterations of a pass.
//!
//! With sliding contacts the symmetric tangent leaves out how friction grows
//! with the normal force, so a pass's iterations converge only linearly: on
//! a settling wall, whose head joints slide in thousands at almost no normal
//! force, one slow mode halves the residual per iteration for twenty
//! iterations. The iterations are a fixed-point map x → x + K⁻¹r(x); mixing
//! the last few steps (Walker & Ni 2011, "Anderson acceleration for
//! fixed-point iterations") removes such a mode in a few iterations, at the
//! cost of a few dot products on the same factor.

use nalgebra::{DMatrix, DVector};

/// Steps mixed: a few slow modes are what is left to remove.
const DEPTH: usize = 3;

/// The last steps of one pass's iterations.
#[derive(Debug, Default)]
pub(crate) struct Anderson {
    /// Newton steps K⁻¹r at the last iterates, oldest first.
    steps: Vec<Vec<f64>>,
    /// The moves made from each of those iterates to the next.
    moves: Vec<Vec<f64>>,
    /// The differences of successive steps (one fewer than the steps):
    /// each is made once and kept while both its steps are.
    differences: Vec<Vec<f64>>,
    /// Their dot products, `products[i][j]` = differencesᵢ·differencesⱼ for
    /// j ≤ i, each taken once, when the later one was made.
    products: [[f64; DEPTH]; DEPTH],
    /// Vectors no longer used, kept for their storage (a vector per
    /// unknown, several an iteration).
    spare: Vec<Vec<f64>>,
}

impl Anderson {
    /// Forgets the iterations so far (after a step that did not lower the
    /// residual).
    pub fn restart(&mut self) {
        self.spare.append(&mut self.steps);
        self.spare.append(&mut self.moves);
        self.spare.append(&mut self.differences);
    }

    /// Whether no iteration is kept: the next mix leaves its step as it is.
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// A copy of `x` in a kept vector.
    fn copy(&mut self, x: &[f64]) -> Vec<f64> {
        let mut v = self.spare.pop().unwrap_or_default();
        v.clear();
        v.extend_from_slice(x);
        v
    }

    /// Turns the Newton step `f` at the current iterate into the move to the
    /// next iterate, in place: f − (ΔX + ΔF)γ, with γ the least-squares fit
    /// of f by the differences ΔF of the last steps and ΔX of the last
    /// iterates. The first call (or the first after `restart`) leaves `f`
    /// as it is.
    pub fn mix(&mut self, f: &mut [f64]) {
        // The last m steps before this one, f_{k−m} … f_{k−1}; ΔF column j
        // is f_{k−m+j+1} − f_{k−m+j}, the last one ending at f itself.
        let m = self.steps.len();
        let step = self.copy(f);
        if let Some(last) = self.steps.last() {
            let mut newest = self.spare.pop().unwrap_or_default();
            newest.clear();
            newest.resize(f.len(), 0.0);
            // One sweep for the new difference and every dot product the
            // fit needs: each is summed entry by entry in order, as `dot`
            // sums it, but the sums run side by side instead of one after
            // another, each waiting on its own additions (on the
            // 10,051-block wall 0.36–0.39 ms a mix against 0.57–0.61).
            let earlier = &self.differences;
            let (products, mut rhs, own, to_newest) = match earlier.as_slice() {
                [] => sweep::<0>(f, last, &mut newest, []),
                [a] => sweep::<1>(f, last, &mut newest, [a]),
                [a, b] => sweep::<2>(f, last, &mut newest, [a, b]),
                _ => unreachable!("at most {DEPTH} steps kept"),
            };
            rhs[m - 1] = to_newest;
            self.products[m - 1][..m - 1].copy_from_slice(&products[..m - 1]);
            self.products[m - 1][m - 1] = own;
            self.differences.push(newest);
            let gram = DMatrix::from_fn(m, m, |i, j| self.products[i.max(j)][i.min(j)]);
            if let Some(gamma) = fit(gram, DVector::from_column_slice(&rhs[..m])) {
                for ((g, dx), df) in gamma.iter().zip(&self.moves).zip(&self.differences) {
                    for ((f, dx), df) in f.iter_mut().zip(dx).zip(df) {
                        *f -= g * (dx + df);
                    }
                }
            }
        }
        self.steps.push(step);
        let mixed = self.copy(f);
        self.moves.push(mixed);
        if self.steps.len() > DEPTH {
            for v in [
                self.steps.remove(0),
                self.moves.remove(0),
                self.differences.remove(0),
            ] {
                self.spare.push(v);
            }
            for i in 0..DEPTH - 1 {
                for j in 0..=i {
                    self.products[i][j] = self.products[i + 1][j + 1];
                }
            }
        }
    }
}

/// a·b, entry by entry in order.
#[cfg(test)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>()
}

/// Writes `newest` = f − last and returns, each summed entry by entry in
/// order: its products with the `earlier` differences, theirs with f (in
/// the first `E` places), its own square and its product with f.
#[inline(always)]
fn sweep<const E: usize>(
    f: &[f64],
    last: &[f64],
    newest: &mut [f64],
    earlier: [&Vec<f64>; E],
) -> ([f64; DEPTH], [f64; DEPTH], f64, f64) {
    let n = f.len();
    let (last, newest) = (&last[..n], &mut newest[..n]);
    let earlier = earlier.map(|e| &e[..n]);
    let (mut products, mut rhs) = ([-0.0; DEPTH], [-0.0; DEPTH]);
    let (mut own, mut to_newest) = (-0.0, -0.0);
    for k in 0..n {
        let x = f[k];
        let d = x - last[k];
        newest[k] = d;
        for j in 0..E {
            products[j] += d * earlier[j][k];
            rhs[j] += earlier[j][k] * x;
        }
        own += d * d;
        to_newest += d * x;
    }
    (products, rhs, own, to_newest)
}

/// γ minimising |f − Σ γⱼ dfⱼ| by the normal equations (`gram`, the
/// columns' dot products; `rhs`, theirs with f), which at this size are
/// cheaper than a QR;
/// `None` when the columns are (nearly) dependent.
fn fit(mut gram: DMatrix<f64>, rhs: DVector<f64>) -> Option<DVector<f64>> {
    let m = rhs.len();
    let scale = gram.diagonal().max();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    for i in 0..m {
        gram[(i, i)] += 1e-12 * scale;
    }
    let gamma = gram.cholesky()?.solve(&rhs);
    gamma.iter().all(|g| g.is_finite()).then_some(gamma)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Iterations x → x + ω(b − A x), the tangent ωA⁻¹ missing part of A,
    /// as a pass's with sliding contacts: the plain iteration converges at
    /// its slow rate, the mixed one in a few steps, to the same answer.
    #[test]
    fn mixing_speeds_up_a_linear_fixed_point_iteration() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0]);
        let b = DVector::from_vec(vec![1.0, 2.0, 3.0]);
        let exact = a.clone().lu().solve(&b).unwrap();
        let omega = 0.2;
        let run = |mixed: bool| {
            let mut x = DVector::<f64>::zeros(3);
            let mut anderson = Anderson::default();
            for k in 0..500 {
                let r = &b - &a * &x;
                if r.norm() < 1e-12 {
                    return (k, x);
                }
                let mut f: Vec<f64> = (r * omega).iter().copied().collect();
                if mixed {
                    anderson.mix(&mut f);
                }
                x += DVector::from_vec(f);
            }
            (500, x)
        };
        let (plain, xp) = run(false);
        let (mixed, xm) = run(true);
        println!("plain {plain} iterations, mixed {mixed}");
        assert!((xp - &exact).norm() < 1e-10 && (xm - &exact).norm() < 1e-10);
        assert!(mixed * 4 < plain, "mixed {mixed} against plain {plain}");
    }

    /// Mixes `f` by the last `DEPTH` (step, move) pairs of `history`,
    /// every difference and product taken anew: the mixing as written
    /// before the products were kept.
    fn mixed_anew(history: &[(Vec<f64>, Vec<f64>)], f: &mut [f64]) {
        let kept = &history[history.len().saturating_sub(DEPTH)..];
        let step = f.to_vec();
        let m = kept.len();
        if m == 0 {
            return;
        }
        let df: Vec<Vec<f64>> = (0..m)
            .map(|j| {
                let next = if j + 1 == m { &step } else { &kept[j + 1].0 };
                next.iter().zip(&kept[j].0).map(|(a, b)| a - b).collect()
            })
            .collect();
        let gram = DMatrix::from_fn(m, m, |i, j| dot(&df[i.max(j)], &df[i.min(j)]));
        let rhs = DVector::from_fn(m, |i, _| dot(&df[i], &step));
        if let Some(gamma) = fit(gram, rhs) {
            for (j, g) in gamma.iter().enumerate() {
                for ((f, dx), df) in f.iter_mut().zip(&kept[j].1).zip(&df[j]) {
                    *f -= g * (dx + df);
                }
            }
        }
    }

    /// The kept differences and products give the moves of differences and
    /// products taken anew, to the last bit, while the window fills, after
    /// it slides and after a restart.
    #[test]
    fn kept_products_mix_as_products_taken_anew() {
        let mut anderson = Anderson::default();
        let mut history: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
        for k in 0..12 {
            if k == 7 {
                anderson.restart();
                history.clear();
            }
            let step: Vec<f64> = (0..5)
                .map(|i| ((k * 5 + i) as f64 * 0.73).sin() * 0.5_f64.powi(k))
                .collect();
            let (mut kept, mut anew) = (step.clone(), step.clone());
            anderson.mix(&mut kept);
            mixed_anew(&history, &mut anew);
            assert_eq!(kept, anew, "move {k}");
            history.push((step, kept));
        }
    }

    #[test]
    fn a_restart_forgets_the_steps() {
        let mut anderson = Anderson::default();
        let mut f = vec![1.0, 2.0];
        anderson.mix(&mut f);
        anderson.restart();
        let mut g = vec![3.0, 4.0];
        anderson.mix(&mut g);
        assert_eq!(g, vec![3.0, 4.0]);
    }
}
