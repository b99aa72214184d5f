//! The cohesive bond in its threshold form (the chapter's "seemingly simple"
//! model): while bonded, a joint carries tension and shear in proportion to
//! its opening and shear displacement, with no strength limit, until the
//! opening passes `max_opening` or the shear displacement passes `max_shear`;
//! then the bond is deleted for good and the joint is frictional.
//!
//! Peak shear force of a bonded contact: `k_s · max_shear`; peak tension:
//! `k_n · max_opening`. After the break: Coulomb friction `tan φ · σ`.

use crate::strength::{angle, stiffnesses};
use dda_core::settings::positive;
#[cfg(test)]
use dda_core::ContactLaw;
use dda_core::DdaError;
use dda_core::{ContactState, LocalKinematics};
use serde::{Deserialize, Serialize};

use crate::springs::mohr_coulomb;
use crate::{Strength, StrengthLaw};

/// The threshold bond; a scene's `ThresholdBond(...)` joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThresholdBond {
    /// Friction angle φ after the bond breaks, degrees, in [0, 90); required.
    pub friction_angle: f64,
    /// Opening at which the bond breaks in tension, m; required (typically
    /// 1e-5–1e-3 m).
    pub max_opening: f64,
    /// Shear displacement at which the bond breaks in shear, m; required.
    pub max_shear: f64,
    /// Normal penalty per unit contact length (2D) or area (3D), N/m³;
    /// default `None`: the driver's.
    #[serde(default)]
    pub normal_stiffness: Option<f64>,
    /// Shear penalty, N/m³; default `None`: normal / 2.5.
    #[serde(default)]
    pub shear_stiffness: Option<f64>,
}

/// Whether the bond still holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BondHistory {
    pub bonded: bool,
}

impl StrengthLaw for ThresholdBond {
    type History = BondHistory;

    fn check(&self) -> Result<(), DdaError> {
        angle("friction_angle", "the friction angle", self.friction_angle)?;
        let hint = "it is the displacement (m) at which the bond breaks, like 1e-4";
        positive("max_opening", "max_opening", self.max_opening, hint)?;
        positive("max_shear", "max_shear", self.max_shear, hint)?;
        stiffnesses(self.normal_stiffness, self.shear_stiffness)
    }

    fn penalties(&self) -> (Option<f64>, Option<f64>) {
        (self.normal_stiffness, self.shear_stiffness)
    }

    fn new_history(&self, at_start: bool) -> BondHistory {
        BondHistory { bonded: at_start }
    }

    /// The strength once the bond is broken (a bonded contact has no limit).
    fn strength(&self, normal: f64, kin: &LocalKinematics, _: &BondHistory) -> Strength {
        Strength {
            shear: mohr_coulomb(self.friction_angle, 0.0, normal, kin),
            tension: 0.0,
        }
    }

    /// A bond holds past the friction, until its own thresholds.
    fn yields_at_strength(&self) -> bool {
        false
    }

    /// A bonded, locked contact holds until a threshold is passed.
    fn adjust_state(
        &self,
        from: ContactState,
        by_strength: ContactState,
        kin: &LocalKinematics,
        history: &BondHistory,
    ) -> ContactState {
        if !(history.bonded && from == ContactState::Locked) {
            by_strength
        } else if kin.gap > self.max_opening + kin.tolerance {
            ContactState::Open
        } else if kin.shear > self.max_shear {
            ContactState::Sliding
        } else {
            ContactState::Locked
        }
    }

    fn update_history(&self, state: ContactState, _: &LocalKinematics, history: &mut BondHistory) {
        if state != ContactState::Locked {
            history.bonded = false;
        }
    }
}

crate::strength_law!(ThresholdBond);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::springs::kinematics;

    #[test]
    fn bond_holds_tension_and_shear_up_to_its_thresholds_then_breaks() {
        let law = ThresholdBond {
            friction_angle: 30.0,
            max_opening: 1e-4,
            max_shear: 2e-4,
            normal_stiffness: None,
            shear_stiffness: None,
        };
        let mut h = law.initial_history(true);
        let locked = ContactState::Locked;
        assert_eq!(
            law.next_state(locked, &kinematics(0.9e-4, 0.0, 0.0), &h),
            locked
        );
        assert_eq!(
            law.next_state(locked, &kinematics(1.1e-4, 0.0, 0.0), &h),
            ContactState::Open
        );
        // Shear far beyond friction is held while bonded, released past max_shear.
        assert_eq!(
            law.next_state(locked, &kinematics(-1e-6, 1.9e-4, 0.0), &h),
            locked
        );
        assert_eq!(
            law.next_state(locked, &kinematics(-1e-6, 2.1e-4, 0.0), &h),
            ContactState::Sliding
        );
        law.commit(ContactState::Sliding, &kinematics(0.0, 0.0, 0.0), &mut h);
        // Broken: frictional, no tension.
        assert_eq!(
            law.next_state(locked, &kinematics(1e-6, 0.0, 0.0), &h),
            ContactState::Open
        );
        // Friction 577 N against a spring force of 800 N.
        assert_eq!(
            law.next_state(locked, &kinematics(-1e-6, 2e-6, 0.0), &h),
            ContactState::Sliding
        );
        assert!(!law.initial_history(false).bonded);
    }
}
