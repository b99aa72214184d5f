//! Every contact law in 3D: the 2D verification scenes extruded into prisms
//! (`dda::extrude`, 2D (x, y) → 3D (x, z), depth along y) must give the
//! same answers. Strengths are per area in 3D as per length in 2D, and
//! forces per unit thickness in 2D are totals over the depth in 3D.

use dda::run::{run_scene, RunOptions};
use dda::scene::Scene;
use dda_contact::LawRegistry;

mod common;

const DEPTH: f64 = 1.0;

/// Runs 2D scene text as its extruded 3D model; returns the 3D history and
/// contact rows.
fn run_3d(name: &str, text: &str) -> (Vec<dda::output::HistoryRow3>, Vec<dda::output::ContactRow>) {
    let scene = Scene::from_str(text, &format!("{name}.ron")).unwrap();
    let prism = dda::extrude::extrude(&scene, DEPTH).unwrap();
    let out = common::out_dir(&format!("{name}_3d"));
    run_scene(
        &prism,
        &out,
        RunOptions::default(),
        &LawRegistry::with_builtin(),
    )
    .unwrap();
    let history = dda::output::read_history_3d(out.join("history.csv")).unwrap();
    let contacts = if out.join("contacts.csv").exists() {
        dda::read_contacts(out.join("contacts.csv")).unwrap()
    } else {
        Vec::new()
    };
    let _ = std::fs::remove_dir_all(&out);
    (history, contacts)
}

fn at(rows: &[dda::output::HistoryRow3], block: usize, t: f64) -> &dda::output::HistoryRow3 {
    rows.iter()
        .filter(|r| r.block == block)
        .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))
        .unwrap()
}

/// Distance slid down a 30° incline (the 2D incline's xz image).
fn slid(rows: &[dda::output::HistoryRow3], t: f64) -> f64 {
    let theta = 30f64.to_radians();
    let (a, b) = (at(rows, 1, 0.0), at(rows, 1, t));
    let (dx, dz) = (b.position[0] - a.position[0], b.position[2] - a.position[2]);
    -(dx * theta.cos() + dz * theta.sin())
}

#[test]
fn two_stage_friction_in_3d() {
    let text = std::fs::read_to_string(common::example("two_stage_friction_2d.ron")).unwrap();
    let (rows, _) = run_3d("two_stage", &text);
    for t in [0.3, 1.0] {
        let (got, exact) = (slid(&rows, t), common::two_stage_slide(t));
        assert!(
            ((got - exact) / exact).abs() < 0.01,
            "t = {t}: {got:.5} m, exact {exact:.5} m"
        );
    }
}

#[test]
fn velocity_dependent_friction_in_3d() {
    let text = common::example_with(
        "sliding_block_2d.ron",
        "Coulomb(friction_angle: 20.0)",
        common::RATE_LAW,
    );
    let (rows, _) = run_3d("rate", &text);
    let (got, exact) = (slid(&rows, 1.0), common::rate_friction_slide(1.0));
    assert!(
        ((got - exact) / exact).abs() < 0.01,
        "{got:.5} m, ODE {exact:.5} m"
    );
}

/// Peak and final shear force of the extruded direct shear test.
fn shear_3d(law: &str) -> (f64, f64) {
    let text = common::example_with(
        "direct_shear_2d.ron",
        "Coulomb(friction_angle: 30.0, cohesion: 50000.0, shear_stiffness: 4e7)",
        law,
    );
    let name = format!("shear_{}", law.split('(').next().unwrap());
    let (_, contacts) = run_3d(&name, &text);
    let last = contacts.iter().map(|r| r.step).max().unwrap();
    let mut per_step = vec![0.0; last + 1];
    for r in contacts.iter().filter(|r| r.state.is_closed()) {
        per_step[r.step] += r.shear_force;
    }
    (per_step.iter().cloned().fold(0.0, f64::max), per_step[last])
}

/// The strength laws' peak and residual; velocity-dependent friction is
/// checked in 3D on the incline (against its ODE) instead, because on the
/// soft shear springs of this test its four corners stick and slip in turn.
#[test]
fn direct_shear_peaks_and_residuals_in_3d() {
    let tan = |d: f64| d.to_radians().tan();
    // 100 kN per metre of depth, over a 1 m × DEPTH joint.
    let n = 100_000.0 * DEPTH;
    let area = 1.0 * DEPTH;
    let cases = [
        ("Coulomb(friction_angle: 30.0, cohesion: 50000.0, shear_stiffness: 4e7)", tan(30.0) * n + 50_000.0 * area, tan(30.0) * n),
        (
            "DisplacementStrength(friction_angle: 35.0, residual_friction_angle: 25.0, cohesion: 50000.0, weakening: Linear(start: 0.001, end: 0.004), shear_stiffness: 4e7)",
            tan(35.0) * n + 50_000.0 * area,
            tan(25.0) * n,
        ),
        (
            "SlipFriction(peak_friction_angle: 35.0, residual_friction_angle: 25.0, weakening: Step(at: 0.005), shear_stiffness: 4e7)",
            tan(35.0) * n,
            tan(25.0) * n,
        ),
    ];
    for (law, peak, residual) in cases {
        let (got_peak, got_residual) = shear_3d(law);
        assert!(
            ((got_peak - peak) / peak).abs() < 0.01,
            "{law}: peak {got_peak:.0} N, expected {peak:.0} N"
        );
        assert!(
            ((got_residual - residual) / residual).abs() < 0.01,
            "{law}: residual {got_residual:.0} N, expected {residual:.0} N"
        );
    }
}

fn hang(t0: f64, mode: &str) -> Vec<dda::output::HistoryRow3> {
    let text = format!(
        r#"Scene(
    analysis: (duration: 0.5, dt: 0.001, mode: {mode}, penalty: 2e10, gravity: (0.0, -9.81)),
    output: (interval: 0.05),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    default_joint: Coulomb(friction_angle: 30.0, cohesion: {t0}, tensile_strength: {t0}),
    blocks: [
        Rectangle(center: (0.0, 1.5), width: 3.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, 0.5), width: 1.0, height: 1.0),
    ],
)"#
    );
    run_3d(&format!("hang_{mode}"), &text).0
}

#[test]
fn tensile_strength_in_3d() {
    // Weight over the 1 m × DEPTH joint, per unit area.
    let w = 2700.0 * 9.81 * DEPTH;
    let held = hang(1.25 * w / DEPTH, "Static");
    let drop = at(&held, 1, 0.0).position[2] - at(&held, 1, 0.5).position[2];
    assert!(drop > 0.0 && drop < 1e-5, "dropped {drop:e} m");

    let fell = hang(0.8 * w / DEPTH, "Dynamic");
    let (g, h) = (9.81, 0.05);
    let z: Vec<(f64, f64)> = fell
        .iter()
        .filter(|r| r.block == 1)
        .map(|r| (r.time, r.position[2]))
        .collect();
    for w in z.windows(3).filter(|w| w[0].0 >= 0.1) {
        let second = w[2].1 - 2.0 * w[1].1 + w[0].1;
        assert!(
            ((second + g * h * h) / (g * h * h)).abs() < 1e-9,
            "t = {}: {second:e}",
            w[1].0
        );
    }
}

#[test]
fn threshold_bond_in_3d() {
    // The bonded corners' springs (1e8 N/m³ over the 1 m × DEPTH joint)
    // hold k_s · max_shear until they break, then friction.
    let law = "ThresholdBond(friction_angle: 30.0, max_opening: 1e-4, max_shear: 1e-3, shear_stiffness: 1e8)";
    let text = common::example_with(
        "direct_shear_2d.ron",
        "Coulomb(friction_angle: 30.0, cohesion: 50000.0, shear_stiffness: 4e7)",
        law,
    );
    let (_, contacts) = run_3d("shear_threshold", &text);
    let last = contacts.iter().map(|r| r.step).max().unwrap();
    let mut per_step = vec![(0.0, 0usize); last + 1];
    for r in contacts.iter().filter(|r| r.state.is_closed()) {
        per_step[r.step].0 += r.shear_force;
        per_step[r.step].1 += 1;
    }
    let (peak, corners) = per_step
        .iter()
        .cloned()
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
    let expected = 1e8 * DEPTH * 1e-3;
    assert!(corners >= 4, "the bonded corners: {corners}");
    assert!(
        ((peak - expected) / expected).abs() < 0.01,
        "peak {peak:.0} N, expected {expected:.0} N"
    );
    let residual = 30f64.to_radians().tan() * 100_000.0 * DEPTH;
    assert!(
        ((per_step[last].0 - residual) / residual).abs() < 0.01,
        "residual {:.0} N",
        per_step[last].0
    );
}
