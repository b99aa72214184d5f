//! The seed's sliding-block case for displacement-dependent strength (after
//! Wang et al. 2013): a block on a 30° incline, φ = 20°, whose Mohr-Coulomb
//! strength tan φ W cos θ + c L exceeds the driving force W sin θ by 5 %.
//! Shi's rule drops a contact's cohesion at its first slide, which the
//! settling of the lightly loaded up-slope corner triggers, and the block is
//! released; with cohesion lost only after 1 mm of slip it stays put. Once
//! the driving force exceeds the strength the block slides, and after the
//! cohesion is gone its acceleration is the residual friction's. The
//! hold-or-release cases run in static mode (each step starts at rest), where
//! a released block creeps steadily instead of accelerating.

mod common;

fn cohesion_for(safety: f64) -> f64 {
    let (theta, mu, w) = (30f64.to_radians(), 20f64.to_radians().tan(), 2700.0 * 9.81);
    // c·L = FS·W sin θ − tan φ W cos θ, with L = 1 m.
    safety * w * theta.sin() - mu * w * theta.cos()
}

fn run(name: &str, law: &str, mode: &str) -> Vec<dda::HistoryRow> {
    // Rigid-like blocks, as the limit-equilibrium reasoning assumes.
    let text = common::example_with("sliding_block_2d.ron", "Coulomb(friction_angle: 20.0)", law)
        .replace("young: 1e10", "young: 1e12")
        .replace("dt: 0.001,", &format!("dt: 0.001, mode: {mode},"));
    let out = common::run_text(name, &text);
    let rows = dda::read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    rows
}

#[test]
fn strength_above_the_load_holds_unless_cohesion_goes_at_the_first_slip() {
    let c = cohesion_for(1.05);
    // Whether a 5 % margin holds is a static question: gravity switched on
    // at once would overshoot the equilibrium by more than 5 %.
    let wang = run(
        "wang_holds",
        &format!(
            "DisplacementStrength(friction_angle: 20.0, cohesion: {c}, weakening: Step(at: 0.001))"
        ),
        "Static",
    );
    // Motion relative to the base (which sags onto its fixed points).
    let relative = |rows: &[dda::HistoryRow], t: f64| {
        let (b, base) = (common::at(rows, 1, t), common::at(rows, 0, t));
        (b.x - base.x, b.y - base.y)
    };
    let shift = |rows: &[dda::HistoryRow], t0: f64, t1: f64| {
        let (a, b) = (relative(rows, t0), relative(rows, t1));
        (b.0 - a.0).hypot(b.1 - a.1)
    };
    // The penalty settling: at most the whole weight on one shear spring
    // (k_s = p / 2.5 = 4e9 N/m), the softest spring of the joint.
    let settling = 2700.0 * 9.81 / 4e9;
    let moved = shift(&wang, 0.0, 1.0);
    assert!(
        moved < settling,
        "moved {moved:e} m, settling {settling:e} m"
    );
    let creep = shift(&wang, 0.5, 1.0);
    assert!(creep < 1e-9, "crept {creep:e} m");

    let shi = run(
        "shi_releases",
        &format!("Coulomb(friction_angle: 20.0, cohesion: {c})"),
        "Static",
    );
    let released = shift(&shi, 0.5, 1.0);
    assert!(
        released > 10.0 * settling,
        "Shi's rule should release the block: moved {released:e} m in 0.5 s"
    );
}

#[test]
fn strength_below_the_load_slides_on_the_residual_friction() {
    let c = cohesion_for(0.95);
    let rows = run(
        "wang_slides",
        &format!(
            "DisplacementStrength(friction_angle: 20.0, cohesion: {c}, weakening: Step(at: 0.001))"
        ),
        "Dynamic",
    );
    let theta = 30f64.to_radians();
    let along = |r: &dda::HistoryRow| -(r.vx * theta.cos() + r.vy * theta.sin());
    let (t1, t2) = (0.5, 1.0);
    let a = (along(common::at(&rows, 1, t2)) - along(common::at(&rows, 1, t1))) / (t2 - t1);
    let residual = 9.81 * (theta.sin() - theta.cos() * 20f64.to_radians().tan());
    assert!(
        ((a - residual) / residual).abs() < 0.01,
        "a = {a:.4} m/s², residual {residual:.4} m/s²"
    );
}
