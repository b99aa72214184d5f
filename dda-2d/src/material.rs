//! Isotropic linear elasticity in the plane.

use dda_core::ConstitutiveLaw;
use nalgebra::{Matrix3, Vector3};

/// Which plane idealisation the 2D block stands for (scene files name it
/// `Strain` or `Stress`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Plane {
    /// Long prism: εz = 0 (the usual choice for rock and masonry sections).
    #[default]
    Strain,
    /// Thin plate: σz = 0.
    Stress,
}

/// Linear elastic isotropic law in plane stress or plane strain, acting on
/// (εx, εy, γxy) with tension-positive stresses (σx, σy, τxy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneElastic {
    pub young: f64,
    pub poisson: f64,
    pub plane: Plane,
}

impl PlaneElastic {
    /// The elasticity matrix.
    pub fn matrix(&self) -> Matrix3<f64> {
        let (e, nu) = (self.young, self.poisson);
        match self.plane {
            Plane::Stress => {
                let c = e / (1.0 - nu * nu);
                Matrix3::new(
                    c,
                    c * nu,
                    0.0,
                    c * nu,
                    c,
                    0.0,
                    0.0,
                    0.0,
                    c * (1.0 - nu) / 2.0,
                )
            }
            Plane::Strain => {
                let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
                Matrix3::new(
                    c * (1.0 - nu),
                    c * nu,
                    0.0,
                    c * nu,
                    c * (1.0 - nu),
                    0.0,
                    0.0,
                    0.0,
                    c * (1.0 - 2.0 * nu) / 2.0,
                )
            }
        }
    }
}

impl ConstitutiveLaw<3> for PlaneElastic {
    fn stress(
        &self,
        committed: &Vector3<f64>,
        increment: &Vector3<f64>,
    ) -> (Vector3<f64>, Matrix3<f64>) {
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
        for plane in [Plane::Stress, Plane::Strain] {
            let law = PlaneElastic {
                young: e,
                poisson: nu,
                plane,
            };
            // σ = (0, −q, 0): strains from the compliance (inverse) matrix.
            let strain = law.matrix().try_inverse().unwrap() * Vector3::new(0.0, -q, 0.0);
            let (ex, ey) = match plane {
                Plane::Stress => (nu * q / e, -q / e),
                Plane::Strain => (nu * (1.0 + nu) * q / e, -(1.0 - nu * nu) * q / e),
            };
            assert!((strain.x - ex).abs() < 1e-12 * ex.abs());
            assert!((strain.y - ey).abs() < 1e-12 * ey.abs());
            assert!(strain.z.abs() < 1e-20);
            // Symmetric positive definite.
            let m = law.matrix();
            assert_eq!(m, m.transpose());
            assert!(m.cholesky().is_some());
        }
    }
}
