//! Constitutive laws of the blocks' uniform strain.
//!
//! `S` is the number of strain components (engineering shears) of the
//! dimension. The dimension crates provide the isotropic elastic laws.

use nalgebra::{SMatrix, SVector};

use crate::error::DdaError;
use crate::settings::{finite, positive};

/// Stress from strain for a uniform-strain block. Stresses are tension
/// positive; strains use engineering shears.
pub trait ConstitutiveLaw<const S: usize>: Send + Sync {
    /// Stress after a strain increment from a committed stress, and the
    /// tangent d(stress)/d(strain increment). Linear laws return
    /// `stress + C·increment` and `C`.
    fn stress(
        &self,
        committed: &SVector<f64, S>,
        increment: &SVector<f64, S>,
    ) -> (SVector<f64, S>, SMatrix<f64, S, S>);

    /// The elastic stiffness scale (Young's modulus), used for automatic penalties.
    fn modulus(&self) -> f64;

    /// Whether the law's parameters make sense, checked before a run: a
    /// [`DdaError::Setting`] names the bad parameter and says what to give.
    fn check(&self) -> Result<(), DdaError> {
        Ok(())
    }
}

/// The checks of an isotropic elastic law, shared by the dimensions' laws:
/// Young's modulus of a solid (1 Pa or more) and Poisson's ratio in
/// [0, 0.5). Errors name the field, `young` or `poisson`.
pub fn check_elastic(young: f64, poisson: f64) -> Result<(), DdaError> {
    positive(
        "young",
        "Young's modulus",
        young,
        "give the elastic modulus (Pa)",
    )?;
    // Below 1 Pa a block's springs and the automatic penalty and dt lose
    // meaning (1e-300 once ran without a word).
    if young < 1.0 {
        return Err(DdaError::Setting {
            field: "young",
            message: format!(
                "Young's modulus {young:e} Pa is below 1 Pa, softer than any solid; give it in Pa (granite about 5e10, brick about 1e10)"
            ),
        });
    }
    finite("poisson", "Poisson's ratio", poisson)?;
    if !(0.0..0.5).contains(&poisson) {
        return Err(DdaError::Setting {
            field: "poisson",
            message: format!(
                "Poisson's ratio must lie in [0, 0.5), got {poisson}; rock is usually 0.2–0.3"
            ),
        });
    }
    Ok(())
}

/// The lightest density a material may have, kg/m³: the lightest aerogels
/// weigh about 0.16.
pub const LIGHTEST_DENSITY: f64 = 0.01;

/// The densest a material may be, kg/m³: osmium, the densest element, is
/// 22,590.
pub const DENSEST_DENSITY: f64 = 1e6;

/// The check of a material's mass density, which the blocks' mass matrices
/// scale by: finite, and from [`LIGHTEST_DENSITY`] to [`DENSEST_DENSITY`].
/// Beyond those a run failed with advice meant for real blocks (1e-300
/// read its springs' round-off as an energy rise and asked for the scene
/// to be reported; 1e300 overflowed and asked for a smaller step). Errors
/// name the field `density`.
pub fn check_density(density: f64) -> Result<(), DdaError> {
    positive(
        "density",
        "the density",
        density,
        "give the mass per unit volume (kg/m³)",
    )?;
    let beyond = if density < LIGHTEST_DENSITY {
        format!("below {LIGHTEST_DENSITY} kg/m³, lighter than any solid (the lightest aerogels weigh about 0.16)")
    } else if density > DENSEST_DENSITY {
        format!("above {DENSEST_DENSITY:e} kg/m³, denser than any material (osmium, the densest, 22,590: a point load adds weight)")
    } else {
        return Ok(());
    };
    Err(DdaError::Setting {
        field: "density",
        message: format!(
            "the density {density:e} kg/m³ is {beyond}; give it in kg/m³ (rock about 2,700, brick about 1,800)"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(result: Result<(), DdaError>) -> &'static str {
        match result {
            Err(DdaError::Setting { field, .. }) => field,
            other => panic!("expected a setting error, got {other:?}"),
        }
    }

    #[test]
    fn elastic_values_are_checked_and_named() {
        assert!(check_elastic(5e10, 0.25).is_ok());
        assert!(check_elastic(1.0, 0.0).is_ok());
        assert_eq!(field(check_elastic(0.0, 0.25)), "young");
        assert_eq!(field(check_elastic(1e-300, 0.25)), "young");
        assert_eq!(field(check_elastic(f64::NAN, 0.25)), "young");
        assert_eq!(field(check_elastic(5e10, 0.5)), "poisson");
        assert_eq!(field(check_elastic(5e10, -0.1)), "poisson");
        assert_eq!(field(check_elastic(5e10, f64::INFINITY)), "poisson");
        assert!(check_density(2700.0).is_ok());
        assert_eq!(field(check_density(0.0)), "density");
        assert_eq!(field(check_density(f64::NAN)), "density");
        // Its bounds are in, beyond them out.
        assert!(check_density(LIGHTEST_DENSITY).is_ok());
        assert!(check_density(DENSEST_DENSITY).is_ok());
        assert_eq!(field(check_density(1e-300)), "density");
        assert_eq!(field(check_density(0.009)), "density");
        assert_eq!(field(check_density(1.1e6)), "density");
        assert_eq!(field(check_density(1e300)), "density");
    }
}
