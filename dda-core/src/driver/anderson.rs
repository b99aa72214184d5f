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
    /// The differences of successive steps, and vectors no longer used:
    /// kept for their storage (a vector per unknown, several an iteration).
    differences: Vec<Vec<f64>>,
    spare: Vec<Vec<f64>>,
}

impl Anderson {
    /// Forgets the iterations so far (after a step that did not lower the
    /// residual).
    pub fn restart(&mut self) {
        self.spare.append(&mut self.steps);
        self.spare.append(&mut self.moves);
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
        let step = self.copy(f);
        let m = self.moves.len().min(self.steps.len());
        if m > 0 {
            // The last m steps before this one, f_{k−m} … f_{k−1}; ΔF column
            // j is f_{k−m+j+1} − f_{k−m+j}, the last one ending at f itself.
            let first = self.steps.len() - m;
            self.differences.resize_with(m, Vec::new);
            for (j, df) in self.differences.iter_mut().enumerate() {
                let next = if j + 1 == m {
                    &step
                } else {
                    &self.steps[first + j + 1]
                };
                df.clear();
                df.extend(next.iter().zip(&self.steps[first + j]).map(|(a, b)| a - b));
            }
            let df = &self.differences[..m];
            if let Some(gamma) = fit(df, &step) {
                let moves = &self.moves[self.moves.len() - m..];
                for (j, g) in gamma.iter().enumerate() {
                    for ((f, dx), df) in f.iter_mut().zip(&moves[j]).zip(&df[j]) {
                        *f -= g * (dx + df);
                    }
                }
            }
        }
        self.steps.push(step);
        let mixed = self.copy(f);
        self.moves.push(mixed);
        if self.moves.len() > DEPTH {
            let oldest = self.moves.remove(0);
            self.spare.push(oldest);
        }
        if self.steps.len() > DEPTH {
            let oldest = self.steps.remove(0);
            self.spare.push(oldest);
        }
    }
}

/// γ minimising |f − Σ γⱼ dfⱼ| by the normal equations, which at this
/// size are cheaper than a QR; `None` when the columns are (nearly)
/// dependent.
fn fit(df: &[Vec<f64>], f: &[f64]) -> Option<DVector<f64>> {
    let m = df.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    // Symmetric: each product once (x·y and y·x round alike).
    let mut gram = DMatrix::zeros(m, m);
    for i in 0..m {
        for j in 0..=i {
            let g = dot(&df[i], &df[j]);
            gram[(i, j)] = g;
            gram[(j, i)] = g;
        }
    }
    let scale = gram.diagonal().max();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    for i in 0..m {
        gram[(i, i)] += 1e-12 * scale;
    }
    let rhs = DVector::from_fn(m, |i, _| dot(&df[i], f));
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
