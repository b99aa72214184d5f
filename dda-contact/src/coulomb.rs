//! Shi's penalty Coulomb joint: normal and shear penalty springs, friction,
//! cohesion and tensile strength.
//!
//! * Normal force `σ = −k_n·gap` while closed (compression positive).
//! * Locked: shear spring force `k_s·|shear|`; it slides once that exceeds the
//!   strength `tan φ·max(σ, 0) + c·L` (L: the boundary length, or area in 3D,
//!   the contact stands for).
//! * Sliding: friction force of that strength, opposing the slip; it locks
//!   again when the slip reverses.
//! * A closed contact opens once the gap exceeds `T0·L / k_n`, i.e. when its
//!   tension exceeds the tensile strength T0 (zero once the bond is broken).
//! * Bonds (cohesion c and tensile strength T0) exist only on joints in
//!   contact at the start, and break for good the first time the contact
//!   opens or slides (Shi's rule).

use crate::strength::{angle, stiffnesses, strength};
#[cfg(test)]
use dda_core::ContactLaw;
use dda_core::DdaError;
use dda_core::{ContactState, LocalKinematics};
use serde::{Deserialize, Serialize};

use crate::springs::mohr_coulomb;
use crate::{Strength, StrengthLaw};

/// The penalty Coulomb law; a scene's `Coulomb(...)` joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Coulomb {
    /// Friction angle φ, degrees, in [0, 90); required (rock joints 25–40°,
    /// dry masonry 30–40°).
    pub friction_angle: f64,
    /// Cohesion c, Pa; default 0 (dry joints); 0.1–1 MPa for mortar or
    /// cemented rock joints.
    #[serde(default)]
    pub cohesion: f64,
    /// Tensile strength T0, Pa; default 0 (dry joints).
    #[serde(default)]
    pub tensile_strength: f64,
    /// Normal penalty k_n per unit contact length (2D) or area (3D), N/m³;
    /// default `None`: the driver's penalty.
    #[serde(default)]
    pub normal_stiffness: Option<f64>,
    /// Shear penalty k_s, N/m³; default `None`: k_n / 2.5 (Shi's).
    #[serde(default)]
    pub shear_stiffness: Option<f64>,
}

impl Coulomb {
    /// A dry frictional joint with automatic penalties.
    pub fn frictional(friction_angle: f64) -> Self {
        Self {
            friction_angle,
            cohesion: 0.0,
            tensile_strength: 0.0,
            normal_stiffness: None,
            shear_stiffness: None,
        }
    }
}

/// Whether the joint's bond (cohesion and tensile strength) still holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct CoulombHistory {
    pub bonded: bool,
}

impl StrengthLaw for Coulomb {
    type History = CoulombHistory;

    fn check(&self) -> Result<(), DdaError> {
        angle("friction_angle", "the friction angle", self.friction_angle)?;
        strength("cohesion", "the cohesion", self.cohesion)?;
        strength(
            "tensile_strength",
            "the tensile strength",
            self.tensile_strength,
        )?;
        stiffnesses(self.normal_stiffness, self.shear_stiffness)
    }

    fn penalties(&self) -> (Option<f64>, Option<f64>) {
        (self.normal_stiffness, self.shear_stiffness)
    }

    fn new_history(&self, at_start: bool) -> CoulombHistory {
        CoulombHistory {
            bonded: at_start && (self.cohesion > 0.0 || self.tensile_strength > 0.0),
        }
    }

    fn strength(&self, normal: f64, kin: &LocalKinematics, history: &CoulombHistory) -> Strength {
        // A dry joint has no bond, so it reads no history: that read is a
        // cache miss a contact and move, on the 10,051-block deformable
        // wall two fifths of its assembly. The compiler would make it ahead
        // of the test (a reference may always be read), unless the
        // reference passes through `black_box` behind it.
        let bonds = self.cohesion > 0.0 || self.tensile_strength > 0.0;
        let (c, t0) = if bonds && std::hint::black_box(history).bonded {
            (self.cohesion, self.tensile_strength)
        } else {
            (0.0, 0.0)
        };
        Strength {
            shear: mohr_coulomb(self.friction_angle, c, normal, kin),
            tension: t0 * kin.length,
        }
    }

    fn update_history(
        &self,
        state: ContactState,
        _kin: &LocalKinematics,
        history: &mut CoulombHistory,
    ) {
        if state != ContactState::Locked {
            history.bonded = false;
        }
    }
}

crate::strength_law!(Coulomb);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::springs::{kinematics as kin, SHEAR_RATIO};

    #[test]
    fn locks_below_and_slides_above_the_coulomb_limit() {
        let law = Coulomb::frictional(30.0);
        let h = law.initial_history(true);
        let gap = -1e-5; // normal force 1e4
        let limit = 1e4 * 30f64.to_radians().tan();
        let ks = 1e9 / SHEAR_RATIO;
        let below = kin(gap, 0.99 * limit / ks, 0.0);
        let above = kin(gap, 1.01 * limit / ks, 0.0);
        assert_eq!(
            law.next_state(ContactState::Locked, &below, &h),
            ContactState::Locked
        );
        assert_eq!(
            law.next_state(ContactState::Locked, &above, &h),
            ContactState::Sliding
        );
        let r = law.response(ContactState::Sliding, &above, &h);
        assert!((r.shear_force - limit).abs() < 1e-9 * limit);
        assert!((r.normal_force - 1e4).abs() < 1e-9);
        assert_eq!(r.shear_stiffness, 0.0);
    }

    #[test]
    fn opens_in_tension_and_relocks_when_the_spring_unloads() {
        let law = Coulomb::frictional(30.0);
        let h = law.initial_history(true);
        assert_eq!(
            law.next_state(ContactState::Locked, &kin(1e-6, 0.0, 0.0), &h),
            ContactState::Open
        );
        assert_eq!(
            law.next_state(ContactState::Open, &kin(1e-6, 0.0, 0.0), &h),
            ContactState::Open
        );
        // A sliding contact locks once its trial spring force falls back
        // within the strength (the slip reversed), and slides on above it.
        let ks = 1e9 / SHEAR_RATIO;
        let limit = 1e4 * 30f64.to_radians().tan();
        assert_eq!(
            law.next_state(
                ContactState::Sliding,
                &kin(-1e-5, 0.99 * limit / ks, -1e-9),
                &h
            ),
            ContactState::Locked
        );
        assert_eq!(
            law.next_state(
                ContactState::Sliding,
                &kin(-1e-5, 1.01 * limit / ks, 1e-9),
                &h
            ),
            ContactState::Sliding
        );
    }

    #[test]
    fn the_bond_holds_tension_until_it_breaks_for_good() {
        let law = Coulomb {
            tensile_strength: 1e5,
            cohesion: 1e5,
            ..Coulomb::frictional(30.0)
        };
        let mut h = law.initial_history(true);
        assert!(h.bonded);
        assert!(
            !law.initial_history(false).bonded,
            "new contacts have no bond"
        );
        // Tension capacity T0·L = 5e4 N: a gap of 4e-5 (4e4 N) holds, 6e-5 opens.
        assert_eq!(
            law.next_state(ContactState::Locked, &kin(4e-5, 0.0, 0.0), &h),
            ContactState::Locked
        );
        assert_eq!(
            law.next_state(ContactState::Locked, &kin(6e-5, 0.0, 0.0), &h),
            ContactState::Open
        );
        law.commit(ContactState::Sliding, &kin(0.0, 0.0, 0.0), &mut h);
        assert!(!h.bonded);
        assert_eq!(
            law.next_state(ContactState::Locked, &kin(4e-5, 0.0, 0.0), &h),
            ContactState::Open
        );
    }

    #[test]
    fn spring_forces_are_the_gradient_of_the_spring_energy() {
        // Energy ½k_n·gap² + ½k_s·shear²: forces are −dE/dgap and dE/dshear.
        let law = Coulomb::frictional(30.0);
        let h = law.initial_history(true);
        let energy = |g: f64, s: f64| 0.5 * 1e9 * g * g + 0.5 * (1e9 / SHEAR_RATIO) * s * s;
        let (g, s, eps) = (-2e-5, 3e-6, 1e-9);
        let r = law.response(ContactState::Locked, &kin(g, s, 0.0), &h);
        let dn = (energy(g + eps, s) - energy(g - eps, s)) / (2.0 * eps);
        let ds = (energy(g, s + eps) - energy(g, s - eps)) / (2.0 * eps);
        assert!((r.normal_force + dn).abs() < 1e-6 * dn.abs());
        assert!((r.shear_force - ds).abs() < 1e-6 * ds.abs());
    }
}
