//! Strength that falls with accumulated slip instead of at the first change
//! of contact state.
//!
//! * Displacement-dependent interface shear strength (after Wang et al.
//!   2013): cohesion, and optionally friction, fall from peak to residual as
//!   the joint's accumulated slip δ grows, so a joint that slips a fraction
//!   of a millimetre during settling keeps its cohesion.
//! * Displacement-dependent friction (after Tsesarsky et al. 2005): the same
//!   with friction only.
//!
//! `τ_max = tan φ(δ)·σ + c(δ)·L`, with φ(δ) and c(δ) between peak and residual
//! by a [`Weakening`] curve. δ is the slip of accepted steps (the elastic
//! stretch of the shear spring is not slip). Tensile strength, if any, is
//! lost for good the first time the joint opens.

use crate::strength::{angle, stiffnesses, strength};
#[cfg(test)]
use dda_core::ContactLaw;
use dda_core::DdaError;
use dda_core::{ContactState, LocalKinematics};
use serde::{Deserialize, Serialize};

use crate::springs::mohr_coulomb;
use crate::weakening::Weakening;
use crate::{Strength, StrengthLaw};

#[derive(Debug, Clone, PartialEq)]
pub struct SlipWeakening {
    /// Peak friction angle, degrees.
    pub peak_friction_angle: f64,
    /// Residual friction angle, degrees (equal to the peak: no friction loss).
    pub residual_friction_angle: f64,
    /// Peak cohesion (Pa); only joints in contact at the start have it.
    pub peak_cohesion: f64,
    /// Residual cohesion (Pa), usually 0.
    pub residual_cohesion: f64,
    /// Tensile strength (Pa) of the initial bond.
    pub tensile_strength: f64,
    /// How strength falls with slip.
    pub weakening: Weakening,
    pub normal_stiffness: Option<f64>,
    pub shear_stiffness: Option<f64>,
}

impl SlipWeakening {
    /// Friction only, from peak to residual angle (Tsesarsky-type).
    pub fn friction(peak: f64, residual: f64, weakening: Weakening) -> Self {
        Self {
            peak_friction_angle: peak,
            residual_friction_angle: residual,
            peak_cohesion: 0.0,
            residual_cohesion: 0.0,
            tensile_strength: 0.0,
            weakening,
            normal_stiffness: None,
            shear_stiffness: None,
        }
    }
}

/// Whether the joint had a bond at the start and still holds in tension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct SlipHistory {
    pub bonded: bool,
    pub intact_in_tension: bool,
}

impl StrengthLaw for SlipWeakening {
    type History = SlipHistory;

    fn check(&self) -> Result<(), DdaError> {
        let (peak, residual) = (self.peak_friction_angle, self.residual_friction_angle);
        angle("peak_friction_angle", "the peak friction angle", peak)?;
        angle(
            "residual_friction_angle",
            "the residual friction angle",
            residual,
        )?;
        strength("peak_cohesion", "the cohesion", self.peak_cohesion)?;
        strength(
            "residual_cohesion",
            "the residual cohesion",
            self.residual_cohesion,
        )?;
        strength(
            "tensile_strength",
            "the tensile strength",
            self.tensile_strength,
        )?;
        self.weakening.check()?;
        stiffnesses(self.normal_stiffness, self.shear_stiffness)
    }

    fn penalties(&self) -> (Option<f64>, Option<f64>) {
        (self.normal_stiffness, self.shear_stiffness)
    }

    fn new_history(&self, at_start: bool) -> SlipHistory {
        SlipHistory {
            bonded: at_start,
            intact_in_tension: at_start,
        }
    }

    fn strength(&self, normal: f64, kin: &LocalKinematics, history: &SlipHistory) -> Strength {
        let slip = kin.slip_path;
        let w = &self.weakening;
        let phi = w.between(self.peak_friction_angle, self.residual_friction_angle, slip);
        let cohesion = if history.bonded {
            w.between(self.peak_cohesion, self.residual_cohesion, slip)
        } else {
            0.0
        };
        let tension = if history.intact_in_tension {
            self.tensile_strength * kin.length
        } else {
            0.0
        };
        Strength {
            shear: mohr_coulomb(phi, cohesion, normal, kin),
            tension,
        }
    }

    fn update_history(&self, state: ContactState, _: &LocalKinematics, history: &mut SlipHistory) {
        if state == ContactState::Open {
            // A joint that opens loses its bond for good; slip alone does not.
            history.intact_in_tension = false;
            history.bonded = false;
        }
    }
}

crate::strength_law!(SlipWeakening);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::springs::kinematics;

    #[test]
    fn cohesion_survives_small_slip_and_fades_with_large_slip() {
        let law = SlipWeakening {
            peak_friction_angle: 30.0,
            residual_friction_angle: 20.0,
            peak_cohesion: 1e4,
            residual_cohesion: 0.0,
            tensile_strength: 0.0,
            weakening: Weakening::Step { at: 1e-3 },
            normal_stiffness: None,
            shear_stiffness: None,
        };
        let mut h = law.initial_history(true);
        let mut kin = kinematics(-1e-5, 0.0, 0.0); // normal force 1e4, L = 0.5
        law.commit(ContactState::Sliding, &kin, &mut h);
        assert!(h.bonded, "sliding does not break the bond");
        let peak = law.response(ContactState::Sliding, &kin, &h).shear_force;
        assert!((peak - (1e4 * 30f64.to_radians().tan() + 1e4 * 0.5)).abs() < 1e-6);
        kin.slip_path = 2e-3;
        let residual = law.response(ContactState::Sliding, &kin, &h).shear_force;
        assert!((residual - 1e4 * 20f64.to_radians().tan()).abs() < 1e-6);
        law.commit(ContactState::Open, &kin, &mut h);
        assert!(!h.bonded);
    }
}
