//! Direct shear test of every law: a block pressed on a fixed base by
//! N = 100 kN and driven sideways at 5 mm/s. The joint's shear force (the
//! sum over its contacts in contacts.csv) must peak at the law's peak
//! strength and end at its residual strength, each within 1 %.

mod common;

const N: f64 = 100_000.0;
const L: f64 = 1.0;

fn tan(deg: f64) -> f64 {
    deg.to_radians().tan()
}

/// Peak and final shear force of the joint for a law.
fn shear(law: &str) -> (f64, f64) {
    let name = format!("direct_shear_{}", law.split('(').next().unwrap());
    let text = common::example_with(
        "direct_shear_2d.ron",
        "Coulomb(friction_angle: 30.0, cohesion: 50000.0, shear_stiffness: 4e7)",
        law,
    );
    let out = common::run_text(&name, &text);
    let rows = common::read_contacts(&out.join("contacts.csv"));
    let _ = std::fs::remove_dir_all(&out);
    let last = rows.iter().map(|r| r.step).max().unwrap();
    let mut per_step = vec![0.0; last + 1];
    for r in rows.iter().filter(|r| r.state != "open") {
        assert_eq!(
            (r.blocks.0.min(r.blocks.1), r.blocks.0.max(r.blocks.1)),
            (0, 1)
        );
        per_step[r.step] += r.shear;
    }
    let peak = per_step.iter().cloned().fold(0.0, f64::max);
    (peak, per_step[last])
}

fn close(value: f64, expected: f64, what: &str) {
    assert!(
        ((value - expected) / expected).abs() < 0.01,
        "{what}: {value:.1} N, expected {expected:.1} N"
    );
}

#[test]
fn coulomb_peaks_at_friction_plus_cohesion_and_keeps_friction() {
    let (peak, residual) =
        shear("Coulomb(friction_angle: 30.0, cohesion: 50000.0, shear_stiffness: 4e7)");
    close(peak, tan(30.0) * N + 50_000.0 * L, "peak");
    close(residual, tan(30.0) * N, "residual");
}

#[test]
fn displacement_strength_falls_from_peak_to_residual() {
    let (peak, residual) = shear(
        "DisplacementStrength(friction_angle: 35.0, residual_friction_angle: 25.0, cohesion: 50000.0, weakening: Linear(start: 0.001, end: 0.004), shear_stiffness: 4e7)",
    );
    close(peak, tan(35.0) * N + 50_000.0 * L, "peak");
    close(residual, tan(25.0) * N, "residual");
}

#[test]
fn slip_friction_falls_from_peak_to_residual_angle() {
    let (peak, residual) =
        shear("SlipFriction(peak_friction_angle: 35.0, residual_friction_angle: 25.0, weakening: Step(at: 0.005), shear_stiffness: 4e7)");
    close(peak, tan(35.0) * N, "peak");
    close(residual, tan(25.0) * N, "residual");
}

#[test]
fn rate_friction_starts_static_and_slides_at_the_drive_rate_coefficient() {
    let (peak, residual) =
        shear("RateFriction(static_friction_angle: 35.0, dynamic_friction_angle: 25.0, characteristic_rate: 0.001, shear_stiffness: 4e7)");
    close(peak, tan(35.0) * N, "peak");
    let mu = tan(25.0) + (tan(35.0) - tan(25.0)) * (-0.005f64 / 0.001).exp();
    close(residual, mu * N, "residual at 5 mm/s");
}

#[test]
fn threshold_bond_holds_up_to_its_shear_threshold_then_slides() {
    let (peak, residual) = shear(
        "ThresholdBond(friction_angle: 30.0, max_opening: 1e-4, max_shear: 1e-3, shear_stiffness: 1e8)",
    );
    // The corners' springs, 1e8 N/m³ per unit length over the L = 1 m
    // joint, each at max_shear when it breaks.
    close(peak, 1e8 * L * 1e-3, "peak");
    close(residual, tan(30.0) * N, "residual");
}
