//! Velocity-dependent friction (after Bakun-Mazor et al. 2012): the friction
//! coefficient falls from its static to its dynamic value as the slip rate
//! grows,
//!
//! `μ(v) = μ_d + (μ_s − μ_d)·exp(−v / v_c)`,
//!
//! with v the slip rate of the last accepted step, so the open-close passes
//! of a step all see the same coefficient and do not chatter.

use crate::strength::{angle, stiffnesses};
use dda_core::settings::positive;
use dda_core::DdaError;
use dda_core::{ContactState, LocalKinematics};
use serde::{Deserialize, Serialize};

use crate::{Strength, StrengthLaw};

/// Rate-dependent friction; a scene's `RateFriction(...)` joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateFriction {
    /// Friction angle at rest, degrees, in [0, 90); required.
    pub static_friction_angle: f64,
    /// Friction angle at fast slip, degrees, in [0, 90); required.
    pub dynamic_friction_angle: f64,
    /// Slip rate v_c over which μ falls by 1/e of its drop, m/s; required
    /// (0.01–1 m/s for rock joints).
    pub characteristic_rate: f64,
    /// Normal penalty per unit contact length (2D) or area (3D), N/m³;
    /// default `None`: the driver's.
    #[serde(default)]
    pub normal_stiffness: Option<f64>,
    /// Shear penalty, N/m³; default `None`: normal / 2.5.
    #[serde(default)]
    pub shear_stiffness: Option<f64>,
}

impl RateFriction {
    /// The friction coefficient at slip rate `rate`.
    pub fn coefficient(&self, rate: f64) -> f64 {
        let (s, d) = (
            self.static_friction_angle.to_radians().tan(),
            self.dynamic_friction_angle.to_radians().tan(),
        );
        d + (s - d) * (-rate.abs() / self.characteristic_rate).exp()
    }
}

impl StrengthLaw for RateFriction {
    type History = ();

    fn check(&self) -> Result<(), DdaError> {
        let (fast, slow) = (self.static_friction_angle, self.dynamic_friction_angle);
        angle("static_friction_angle", "the static friction angle", fast)?;
        angle("dynamic_friction_angle", "the dynamic friction angle", slow)?;
        let hint = "it is the slip rate (m/s) over which friction falls, like 0.1";
        positive(
            "characteristic_rate",
            "the characteristic rate",
            self.characteristic_rate,
            hint,
        )?;
        stiffnesses(self.normal_stiffness, self.shear_stiffness)
    }

    fn penalties(&self) -> (Option<f64>, Option<f64>) {
        (self.normal_stiffness, self.shear_stiffness)
    }

    fn new_history(&self, _at_start: bool) {}

    fn strength(&self, normal: f64, kin: &LocalKinematics, _: &()) -> Strength {
        Strength {
            shear: self.coefficient(kin.slip_rate) * normal.max(0.0),
            tension: 0.0,
        }
    }

    /// A sliding contact keeps sliding until its slip reverses.
    fn yields_at_strength(&self) -> bool {
        false
    }

    // The coefficient is the last step's, so a sliding contact whose rate
    // dipped would see a higher strength and lock, then slip fast:
    // stick-slip of the explicit rate, not of the law. A sliding contact
    // keeps sliding until its slip reverses.
    fn adjust_state(
        &self,
        from: ContactState,
        by_strength: ContactState,
        kin: &LocalKinematics,
        _: &(),
    ) -> ContactState {
        if from == ContactState::Sliding && by_strength == ContactState::Locked && kin.slip >= 0.0 {
            ContactState::Sliding
        } else {
            by_strength
        }
    }
}

crate::strength_law!(RateFriction);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficient_falls_from_static_to_dynamic() {
        let law = RateFriction {
            static_friction_angle: 30.0,
            dynamic_friction_angle: 15.0,
            characteristic_rate: 0.1,
            normal_stiffness: None,
            shear_stiffness: None,
        };
        let (s, d) = (30f64.to_radians().tan(), 15f64.to_radians().tan());
        assert!((law.coefficient(0.0) - s).abs() < 1e-15);
        assert!((law.coefficient(0.1) - (d + (s - d) / std::f64::consts::E)).abs() < 1e-15);
        assert!((law.coefficient(100.0) - d).abs() < 1e-12);
    }
}
