//! Isotropic linear elasticity in 3D (A9.4).

use dda_core::ConstitutiveLaw;
use nalgebra::{Matrix6, Vector6};

/// Linear elastic isotropic law on (εx, εy, εz, γyz, γzx, γxy) with
/// tension-positive stresses (σx, σy, σz, τyz, τzx, τxy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsotropicElastic {
    pub young: f64,
    pub poisson: f64,
}

impl IsotropicElastic {
    /// The elasticity matrix: λ + 2G on the normal diagonal, λ between
    /// normal strains, G on the engineering shears.
    pub fn matrix(&self) -> Matrix6<f64> {
        let (e, nu) = (self.young, self.poisson);
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let g = e / (2.0 * (1.0 + nu));
        let mut c = Matrix6::zeros();
        for i in 0..3 {
            for j in 0..3 {
                c[(i, j)] = lambda;
            }
            c[(i, i)] += 2.0 * g;
            c[(i + 3, i + 3)] = g;
        }
        c
    }
}

impl ConstitutiveLaw<6> for IsotropicElastic {
    fn stress(
        &self,
        committed: &Vector6<f64>,
        increment: &Vector6<f64>,
    ) -> (Vector6<f64>, Matrix6<f64>) {
        let c = self.matrix();
        (committed + c * increment, c)
    }

    fn modulus(&self) -> f64 {
        self.young
    }

    fn check(&self) -> Result<(), dda_core::DdaError> {
        dda_core::constitutive::check_elastic(self.young, self.poisson)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniaxial_stress_gives_the_textbook_strains() {
        let (e, nu, q) = (2e10, 0.25, 1e6);
        let law = IsotropicElastic {
            young: e,
            poisson: nu,
        };
        let c = law.matrix();
        let strain = c.try_inverse().unwrap() * Vector6::new(0.0, 0.0, -q, 0.0, 0.0, 0.0);
        assert!((strain[2] + q / e).abs() < 1e-12 * q / e);
        assert!((strain[0] - nu * q / e).abs() < 1e-12 * q / e);
        assert!((strain[1] - nu * q / e).abs() < 1e-12 * q / e);
        for k in 3..6 {
            assert!(strain[k].abs() < 1e-20);
        }
        // Pure shear: τ = G γ.
        let shear = c * Vector6::new(0.0, 0.0, 0.0, 1e-4, 0.0, 0.0);
        assert!((shear[3] - e / (2.0 * (1.0 + nu)) * 1e-4).abs() < 1e-6);
        assert_eq!(c, c.transpose());
        assert!(c.cholesky().is_some(), "symmetric positive definite");
    }
}
