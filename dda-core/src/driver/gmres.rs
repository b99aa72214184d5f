//! Restarted GMRES (Saad & Schultz 1986) for the whole tangent of a pass
//! with many sliding contacts: the operator is the symmetric factor's
//! inverse applied to the whole tangent, I + K⁻¹Σ sⱼuⱼvⱼᵀ, so each
//! iteration costs one solve on the factor and a rank-one product per
//! contact, where the Sherman-Morrison-Woodbury formula would cost one
//! solve per contact up front.

/// Krylov vectors kept before a restart.
const RESTART: usize = 30;

/// Solves A x = b for `apply(v, out)`: out = A v, from x = 0, until
/// ‖b − A x‖ ≤ `tolerance`·‖b‖ or `limit` products; returns whether it got
/// there (`x` holds the last iterate either way).
///
/// From zero the first Krylov vector is b itself, so k products search all
/// of span{b, …, Aᵏ⁻¹b}; a start from a guess spends one on the guess's
/// residual and searches a smaller space with the rest. A cycle that ends
/// on the tolerance returns on the rotated right-hand side's last entry,
/// which is that residual's norm, without a product to read it again; only
/// a restart reads the true residual.
pub(super) fn gmres(
    mut apply: impl FnMut(&[f64], &mut [f64]),
    b: &[f64],
    x: &mut [f64],
    tolerance: f64,
    limit: usize,
) -> bool {
    let n = b.len();
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let target = tolerance * norm(b);
    x.iter_mut().for_each(|v| *v = 0.0);
    let mut products = 0;
    let mut w = vec![0.0; n];
    let mut r = b.to_vec();
    loop {
        let beta = norm(&r);
        if beta <= target {
            return true;
        }
        if products >= limit {
            return false;
        }
        let mut basis = vec![r.iter().map(|v| v / beta).collect::<Vec<f64>>()];
        // The Hessenberg columns, turned upper triangular by the rotations
        // as they come; g is the rotated right-hand side β·e₁.
        let mut h: Vec<Vec<f64>> = Vec::new();
        let mut rotations: Vec<(f64, f64)> = Vec::new();
        let mut g = vec![beta];
        for j in 0..RESTART {
            apply(&basis[j], &mut w);
            products += 1;
            let mut column = vec![0.0; j + 2];
            for (i, v) in basis.iter().enumerate() {
                column[i] = dot(&w, v);
                for (w, v) in w.iter_mut().zip(v) {
                    *w -= column[i] * v;
                }
            }
            let length = norm(&w);
            column[j + 1] = length;
            // A breakdown (w = 0) means the space holds the solution.
            let next: Vec<f64> = if length > 0.0 {
                w.iter().map(|v| v / length).collect()
            } else {
                Vec::new()
            };
            for (i, &(c, s)) in rotations.iter().enumerate() {
                let (a, b) = (column[i], column[i + 1]);
                column[i] = c * a + s * b;
                column[i + 1] = -s * a + c * b;
            }
            let (a, b) = (column[j], column[j + 1]);
            let r = a.hypot(b);
            let (c, s) = if r == 0.0 { (1.0, 0.0) } else { (a / r, b / r) };
            column[j] = r;
            column[j + 1] = 0.0;
            rotations.push((c, s));
            g.push(-s * g[j]);
            g[j] *= c;
            h.push(column);
            let reached = g[j + 1].abs() <= target || next.is_empty();
            if reached || products >= limit || j + 1 == RESTART {
                // Back substitution for the coefficients, then the update.
                let k = h.len();
                let mut y = vec![0.0; k];
                for i in (0..k).rev() {
                    let sum: f64 = (i + 1..k).map(|l| h[l][i] * y[l]).sum();
                    y[i] = (g[i] - sum) / h[i][i];
                }
                for (v, y) in basis.iter().zip(&y) {
                    for (x, v) in x.iter_mut().zip(v) {
                        *x += y * v;
                    }
                }
                if reached || products >= limit {
                    return reached;
                }
                break;
            }
            basis.push(next);
        }
        // A restart: the true residual, read with one product.
        apply(x, &mut w);
        products += 1;
        for ((r, b), w) in r.iter_mut().zip(b).zip(&w) {
            *r = b - w;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// A non-symmetric system, the identity plus a few rank-one terms, as
    /// a pass's preconditioned whole tangent: solved to the tolerance.
    #[test]
    fn solves_the_identity_plus_low_rank_terms() {
        let n = 40;
        let mut a = DMatrix::<f64>::identity(n, n);
        for j in 0..5 {
            let u = DVector::from_fn(n, |i, _| ((i * (j + 2)) % 7) as f64 - 3.0);
            let v = DVector::from_fn(n, |i, _| ((i + 3 * j) % 5) as f64 * 0.1);
            a += &u * v.transpose() * 0.05;
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x = b.clone();
        let apply = |v: &[f64], out: &mut [f64]| {
            let r = &a * DVector::from_column_slice(v);
            out.copy_from_slice(r.as_slice());
        };
        assert!(gmres(apply, &b, &mut x, 1e-12, 100));
        let exact = a
            .clone()
            .lu()
            .solve(&DVector::from_column_slice(&b))
            .unwrap();
        let error = (DVector::from_column_slice(&x) - &exact).norm() / exact.norm();
        assert!(error < 1e-10, "{error}");
    }

    /// The identity plus r rank-one terms has a minimal polynomial of
    /// degree at most r + 1, so from zero GMRES needs that many products
    /// and no more: none goes to a starting residual or to reading the
    /// last one again (a start from b took two more). The rotated
    /// residual it stops on is the true one.
    #[test]
    fn needs_no_product_beyond_the_krylov_space() {
        let (n, rank) = (60, 4);
        let mut a = DMatrix::<f64>::identity(n, n);
        for j in 0..rank {
            let u = DVector::from_fn(n, |i, _| ((i * (j + 3)) % 11) as f64 - 5.0);
            let v = DVector::from_fn(n, |i, _| ((2 * i + j) % 7) as f64 * 0.02);
            a += &u * v.transpose() * 0.1;
        }
        let b: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos() + 0.1).collect();
        let mut x = vec![1.0; n];
        let mut products = 0;
        let apply = |v: &[f64], out: &mut [f64]| {
            products += 1;
            let r = &a * DVector::from_column_slice(v);
            out.copy_from_slice(r.as_slice());
        };
        let tolerance = 1e-10;
        assert!(gmres(apply, &b, &mut x, tolerance, 100));
        assert!(products <= rank + 1, "{products} products");
        let b = DVector::from_column_slice(&b);
        let r = &b - &a * DVector::from_column_slice(&x);
        assert!(r.norm() <= tolerance * b.norm(), "{}", r.norm() / b.norm());
    }

    /// Restarts carry on from the last iterate: a system needing more
    /// than one cycle still converges.
    #[test]
    fn restarts_converge_on_a_general_system() {
        let n = 80;
        let a = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                4.0 + i as f64 * 0.05
            } else if i + 1 == j {
                -1.3
            } else if j + 1 == i {
                -0.7
            } else {
                0.0
            }
        });
        let b = vec![1.0; n];
        let mut x = vec![0.0; n];
        let apply = |v: &[f64], out: &mut [f64]| {
            let r = &a * DVector::from_column_slice(v);
            out.copy_from_slice(r.as_slice());
        };
        assert!(gmres(apply, &b, &mut x, 1e-11, 1000));
        let r = DVector::from_column_slice(&b) - &a * DVector::from_column_slice(&x);
        assert!(
            r.norm() <= 1e-11 * (n as f64).sqrt() * 1.0001,
            "{}",
            r.norm()
        );
    }
}
