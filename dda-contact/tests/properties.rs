//! Every built-in law over random closed and open kinematics: friction never
//! exceeds its limit, friction opposes the slip, an open contact carries
//! nothing, the normal spring is elastic (its force is the stiffness times
//! the penetration, so a closing and opening cycle gives back what it took)
//! and tension never exceeds the tensile strength.

use dda_contact::{LawRegistry, Params};
use dda_core::{ContactState, DynContactLaw, LocalKinematics};
use proptest::prelude::*;

const PENALTY: f64 = 2e10;
/// The largest friction angle and cohesion the laws below are given.
const MAX_ANGLE: f64 = 35.0;
const MAX_COHESION: f64 = 1e5;
const TENSILE: f64 = 5e4;

fn laws() -> Vec<(&'static str, Box<dyn DynContactLaw>)> {
    let registry = LawRegistry::with_builtin();
    let table: [(&str, &[(&str, f64)]); 6] = [
        ("coulomb", &[("friction_angle", 30.0)]),
        (
            "coulomb",
            &[
                ("friction_angle", 35.0),
                ("cohesion", MAX_COHESION),
                ("tensile_strength", TENSILE),
            ],
        ),
        (
            "threshold_bond",
            &[
                ("friction_angle", 30.0),
                ("max_opening", 1e-4),
                ("max_shear", 1e-3),
            ],
        ),
        (
            "displacement_strength",
            &[
                ("friction_angle", 35.0),
                ("residual_friction_angle", 25.0),
                ("cohesion", MAX_COHESION),
                ("tensile_strength", TENSILE),
                ("weakening_length", 0.01),
            ],
        ),
        (
            "slip_friction",
            &[
                ("peak_friction_angle", 35.0),
                ("residual_friction_angle", 20.0),
                ("weakening_step", 0.05),
            ],
        ),
        (
            "rate_friction",
            &[
                ("static_friction_angle", 35.0),
                ("dynamic_friction_angle", 25.0),
                ("characteristic_rate", 0.1),
            ],
        ),
    ];
    table
        .iter()
        .map(|(name, params)| {
            let map: std::collections::BTreeMap<String, f64> =
                params.iter().map(|(k, v)| (k.to_string(), *v)).collect();
            let mut p = Params::from(map);
            (*name, registry.build(name, &mut p).unwrap())
        })
        .collect()
}

fn kinematics(gap: f64, shear: f64, slip: f64, slip_path: f64, slip_rate: f64) -> LocalKinematics {
    LocalKinematics {
        gap,
        gap_start: gap,
        shear,
        slip,
        slip_path,
        slip_rate,
        length: 0.5,
        spring_length: 0.5,
        penalty: PENALTY,
        tolerance: 1e-7,
        dt: 1e-3,
    }
}

proptest! {
    #[test]
    fn no_law_exceeds_friction_or_creates_energy(
        gap in -1e-4..-1e-9f64,
        shear in 0.0..1e-3f64,
        slip in -1e-4..1e-3f64,
        slip_path in 0.0..0.2f64,
        slip_rate in 0.0..1.0f64,
        at_start in any::<bool>(),
        from_sliding in any::<bool>(),
    ) {
        let kin = kinematics(gap, shear, slip, slip_path, slip_rate);
        let assumed = if from_sliding { ContactState::Sliding } else { ContactState::Locked };
        for (name, law) in laws() {
            let h = law.initial_history(at_start);
            let state = law.next_state(assumed, &kin, &h);
            let r = law.response(state, &kin, &h);
            if !state.is_closed() {
                prop_assert_eq!(r.normal_force, 0.0, "{} open but pushing", name);
                prop_assert_eq!(r.shear_force, 0.0, "{} open but shearing", name);
                continue;
            }
            // Elastic normal spring: force = stiffness × penetration.
            prop_assert!(
                (r.normal_force - r.normal_stiffness * -gap).abs() <= 1e-9 * r.normal_force.abs(),
                "{}: force {} stiffness {} gap {}", name, r.normal_force, r.normal_stiffness, gap
            );
            let mut limit = r.normal_force.max(0.0) * MAX_ANGLE.to_radians().tan() + MAX_COHESION * kin.length;
            if name == "threshold_bond" && at_start {
                // Its bond holds to a shear displacement (max_shear), not a stress.
                let k_s = law.response(ContactState::Locked, &kin, &h).shear_stiffness;
                limit = limit.max(k_s * 1e-3);
            }
            prop_assert!(r.shear_force >= 0.0, "{}: friction must oppose the slip", name);
            prop_assert!(
                r.shear_force <= limit * (1.0 + 1e-9),
                "{} {:?}: shear force {} beyond its limit {}", name, state, r.shear_force, limit
            );
            if state == ContactState::Locked {
                // A locked contact is its shear spring, within the limit.
                prop_assert!(
                    (r.shear_force - r.shear_stiffness * shear).abs() <= 1e-9 * (1.0 + r.shear_force),
                    "{}: locked force {} is not k_s·shear {}", name, r.shear_force, r.shear_stiffness * shear
                );
            }
        }
    }

    /// Apart, a contact opens unless bonded, and a bond's tension stays
    /// within the tensile strength.
    #[test]
    fn open_contacts_carry_nothing_and_tension_is_bounded(gap in 1e-6..1e-2f64, at_start in any::<bool>()) {
        let kin = kinematics(gap, 0.0, 0.0, 0.0, 0.0);
        for (name, law) in laws() {
            let h = law.initial_history(at_start);
            let state = law.next_state(ContactState::Locked, &kin, &h);
            let r = law.response(state, &kin, &h);
            if state.is_closed() {
                prop_assert!(at_start, "{}: closed across a gap without a bond", name);
                if name == "threshold_bond" {
                    // Its bond holds to an opening (max_opening, within
                    // the open-close tolerance), not a stress.
                    prop_assert!(gap <= 1e-4 + kin.tolerance, "{}: held open by {}", name, gap);
                } else {
                    prop_assert!(-r.normal_force <= TENSILE * kin.length * (1.0 + 1e-9),
                        "{}: tension {} beyond the strength", name, -r.normal_force);
                }
            } else {
                prop_assert_eq!(r.normal_force, 0.0);
                prop_assert_eq!(r.shear_force, 0.0);
            }
        }
    }
}
