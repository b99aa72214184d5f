//! The penalty springs every law here shares: a normal spring, a shear
//! spring while locked and a friction force while sliding. A law supplies
//! only its shear strength and tensile capacity; these functions turn them
//! into forces and open-close decisions.

use dda_core::{ContactResponse, ContactState, LocalKinematics};

/// Shi's ratio of normal to shear penalty.
pub const SHEAR_RATIO: f64 = 2.5;

/// Normal and shear spring stiffnesses of one contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Springs {
    pub normal: f64,
    pub shear: f64,
}

impl Springs {
    /// The law's own stiffnesses where set, otherwise the driver's penalty
    /// and a shear spring 2.5 times softer (Shi's default); both per unit
    /// contact length (2D) or area (3D), times what the contact stands for.
    pub fn new(normal: Option<f64>, shear: Option<f64>, kin: &LocalKinematics) -> Self {
        let normal = normal.unwrap_or(kin.penalty);
        let shear = shear.unwrap_or(normal / SHEAR_RATIO);
        Self {
            normal: normal * kin.spring_length,
            shear: shear * kin.spring_length,
        }
    }

    /// Normal force at the trial gap (compression positive).
    pub fn normal_force(&self, kin: &LocalKinematics) -> f64 {
        -self.normal * kin.gap
    }

    /// Forces and stiffnesses in `state`; `strength` is the friction force
    /// a sliding contact carries.
    pub fn response(
        &self,
        state: ContactState,
        kin: &LocalKinematics,
        strength: f64,
    ) -> ContactResponse {
        let normal_force = self.normal_force(kin);
        match state {
            ContactState::Open => ContactResponse::default(),
            ContactState::Locked => ContactResponse {
                normal_force,
                normal_stiffness: self.normal,
                shear_force: self.shear * kin.shear,
                shear_stiffness: self.shear,
            },
            ContactState::Sliding => ContactResponse {
                normal_force,
                normal_stiffness: self.normal,
                shear_force: strength,
                shear_stiffness: 0.0,
            },
        }
    }

    /// Shi's open-close rules, with the lock/slide decision made as an
    /// elastoplastic return map: an open contact closes when it penetrates;
    /// a closed one opens when its tension passes `tension` (a force);
    /// otherwise it is locked while its trial spring force (the carried
    /// stretch plus this step's tangential motion, times k_s) is within
    /// `strength`, and sliding beyond it.
    ///
    /// The same test for a locked and a sliding contact makes the two states
    /// complementary (a sliding contact whose plastic slip would be negative
    /// locks), so a contact at its limit cannot cycle between them, and a
    /// slip that reverses by less than the open-close tolerance still locks:
    /// friction never pushes a block the way it is moving.
    pub fn next_state(
        &self,
        state: ContactState,
        kin: &LocalKinematics,
        strength: f64,
        tension: f64,
    ) -> ContactState {
        let locked_or_sliding = if self.shear * kin.shear <= strength {
            ContactState::Locked
        } else {
            ContactState::Sliding
        };
        match state {
            ContactState::Open if kin.gap < -kin.tolerance => locked_or_sliding,
            ContactState::Open => ContactState::Open,
            _ if kin.gap > tension / self.normal + kin.tolerance => ContactState::Open,
            _ => locked_or_sliding,
        }
    }
}

/// Mohr-Coulomb shear strength: tan φ times the compressive normal force
/// plus cohesion times the contact's length (or area).
pub fn mohr_coulomb(
    friction_angle: f64,
    cohesion: f64,
    normal_force: f64,
    kin: &LocalKinematics,
) -> f64 {
    let friction = if normal_force > 0.0 {
        tan_degrees(friction_angle) * normal_force
    } else {
        0.0
    };
    friction + cohesion * kin.length
}

/// tan of an angle in degrees. The laws ask it for every contact at every
/// iteration, nearly always of the same angle, and a tangent costs as much
/// as the rest of a contact's strength: each thread keeps its last one.
fn tan_degrees(angle: f64) -> f64 {
    thread_local! {
        static LAST: std::cell::Cell<(f64, f64)> = const { std::cell::Cell::new((0.0, 0.0)) };
    }
    LAST.with(|last| {
        let (a, t) = last.get();
        if a == angle {
            t
        } else {
            let t = angle.to_radians().tan();
            last.set((angle, t));
            t
        }
    })
}

#[cfg(test)]
pub(crate) fn kinematics(gap: f64, shear: f64, slip: f64) -> LocalKinematics {
    LocalKinematics {
        gap,
        gap_start: 0.0,
        shear,
        slip,
        slip_path: 0.0,
        slip_rate: 0.0,
        length: 0.5,
        spring_length: 1.0,
        penalty: 1e9,
        tolerance: 1e-9,
        dt: 1e-3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kept tangent is the angle asked for, however the angles
    /// alternate, and tension carries no friction.
    #[test]
    fn mohr_coulomb_strength_as_the_angles_change() {
        let kin = kinematics(-1e-5, 0.0, 0.0);
        for angle in [30.0, 30.0, 20.0, 0.0, 35.5, 30.0] {
            let expected = f64::tan(angle * std::f64::consts::PI / 180.0) * 1e4 + 2.0 * kin.length;
            let got = mohr_coulomb(angle, 2.0, 1e4, &kin);
            assert!(
                (got - expected).abs() <= 1e-12 * expected.abs().max(1.0),
                "{angle}°: {got} against {expected}"
            );
        }
        assert_eq!(mohr_coulomb(30.0, 2.0, -5.0, &kin), 2.0 * kin.length);
    }
}
