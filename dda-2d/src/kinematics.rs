//! Shi's 6-DOF uniform-strain kinematics: the T-matrix and the mass matrix.
//!
//! DOF order: (u0, v0, r0, εx, εy, γxy) about the block centroid.

use nalgebra::{Matrix2, Matrix2x6, Point2, Rotation2, SMatrix, Vector2, Vector6};

use crate::polygon::CentralMoments;

/// The 6×6 block matrix type.
pub type Matrix6 = SMatrix<f64, 6, 6>;

/// Displacement of point `p` of a block with centroid `c` is `t_matrix(p, c) · D`.
pub fn t_matrix(p: &Point2<f64>, c: &Point2<f64>) -> Matrix2x6<f64> {
    let (x, y) = (p.x - c.x, p.y - c.y);
    Matrix2x6::new(
        1.0,
        0.0,
        -y,
        x,
        0.0,
        y / 2.0, //
        0.0,
        1.0,
        x,
        0.0,
        y,
        x / 2.0,
    )
}

/// Mass matrix ρ∫TᵀT dA from the central moments (ρ = density).
pub fn mass_matrix(m: &CentralMoments, density: f64) -> Matrix6 {
    let (s, s1, s2, s3) = (m.area, m.xx, m.yy, m.xy);
    let mut k = Matrix6::zeros();
    k[(0, 0)] = s;
    k[(1, 1)] = s;
    k[(2, 2)] = s1 + s2;
    k[(2, 3)] = -s3;
    k[(2, 4)] = s3;
    k[(2, 5)] = (s1 - s2) / 2.0;
    k[(3, 3)] = s1;
    k[(3, 5)] = s3 / 2.0;
    k[(4, 4)] = s2;
    k[(4, 5)] = s3 / 2.0;
    k[(5, 5)] = (s1 + s2) / 4.0;
    let upper = k;
    (upper + upper.transpose() - Matrix6::from_diagonal(&upper.diagonal())) * density
}

pub use dda_core::RotationUpdate;

/// Where point `p` goes for step displacement `d` about centroid `c`.
pub fn move_point(
    p: &Point2<f64>,
    c: &Point2<f64>,
    d: &Vector6<f64>,
    update: RotationUpdate,
) -> Point2<f64> {
    match update {
        RotationUpdate::Linear => p + t_matrix(p, c) * d,
        RotationUpdate::Exact => {
            let arm = p - c;
            let strained = arm + strain_tensor(d) * arm;
            c + Vector2::new(d[0], d[1]) + Rotation2::new(d[2]) * strained
        }
    }
}

/// The small-strain tensor of the DOF vector.
pub fn strain_tensor(d: &Vector6<f64>) -> Matrix2<f64> {
    Matrix2::new(d[3], d[5] / 2.0, d[5] / 2.0, d[4])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polygon::central_moments;

    fn pentagon() -> Vec<Point2<f64>> {
        [(0.0, 0.0), (2.0, -0.3), (2.6, 1.1), (1.1, 2.0), (-0.4, 1.2)]
            .iter()
            .map(|&(x, y)| Point2::new(x + 10.0, y - 3.0))
            .collect()
    }

    #[test]
    fn mass_matrix_is_the_integral_of_t_transpose_t() {
        // Compare with ρ∫TᵀT dA by a fine quadrature over triangles of the fan.
        let poly = pentagon();
        let m = central_moments(&poly);
        let rho = 2.5;
        let exact = mass_matrix(&m, rho);
        let mut quad = Matrix6::zeros();
        let a = poly[0];
        // Degree-2 exact rule (edge midpoints) on each fan triangle.
        for w in poly[1..].windows(2) {
            let (b, c) = (w[0], w[1]);
            let area = ((b - a).perp(&(c - a))) / 2.0;
            for (p, q) in [(a, b), (b, c), (c, a)] {
                let mid = Point2::from((p.coords + q.coords) / 2.0);
                let t = t_matrix(&mid, &m.centroid);
                quad += t.transpose() * t * (area / 3.0) * rho;
            }
        }
        assert!((exact - quad).norm() < 1e-10 * exact.norm());
        assert_eq!(exact, exact.transpose());
        assert!(
            exact.cholesky().is_some(),
            "mass matrix must be positive definite"
        );
    }

    #[test]
    fn exact_update_preserves_lengths_for_a_rigid_rotation() {
        let c = Point2::new(1.0, 2.0);
        let p = Point2::new(1.7, 2.4);
        let d = Vector6::new(0.3, -0.2, 0.8, 0.0, 0.0, 0.0);
        let q = move_point(&p, &c, &d, RotationUpdate::Exact);
        let c2 = c + Vector2::new(0.3, -0.2);
        assert!(((q - c2).norm() - (p - c).norm()).abs() < 1e-15);
        let lin = move_point(&p, &c, &d, RotationUpdate::Linear);
        let stretch = (lin - c2).norm() / (p - c).norm();
        assert!(
            (stretch - (1.0f64 + 0.64).sqrt()).abs() < 1e-12,
            "linear update stretches by √(1+r²)"
        );
    }
}
