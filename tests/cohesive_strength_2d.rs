//! Cohesion in its strength form (Coulomb with c, Shi's breaking rule): a
//! 1 m block on a 30° incline, φ = 20°, c = 20 kPa. Cohesion holds it; a
//! load ramped down the slope breaks the bond at the predicted load, then
//! the block slides with the frictional acceleration.
//!
//! Prediction. The block stands on two corner contacts (L = 0.5 m each) and
//! shares the shear T = W sin θ + P equally between them (they move
//! together). The load acts at the centroid, h/2 above the joint, so the
//! contacts' normal forces differ by T·h/w: the up-slope one carries
//! N = (W cos θ − T h/w)/2. It breaks first, when T/2 = tan φ·N + c·L, i.e.
//! T = (tan φ W cos θ + c·2L)/(1 + tan φ h/w); with its bond gone, the other
//! contact cannot carry the rest and the joint fails.

mod common;

const THETA: f64 = 30.0;
const PHI: f64 = 20.0;
const COHESION: f64 = 20_000.0;

fn scene(ramp_end: f64) -> String {
    let (s, c) = THETA.to_radians().sin_cos();
    let with_cohesion = common::example_with(
        "sliding_block_2d.ron",
        "Coulomb(friction_angle: 20.0)",
        &format!("Coulomb(friction_angle: {PHI}, cohesion: {COHESION})"),
    );
    // At rest for 0.2 s, then the load grows down the slope to `ramp_end` at 1.2 s.
    let load = format!(
        "loads: [PointLoad(block: 1, point: (-0.5, 0.8660254037844386), history: [(0.0, 0.0, 0.0), (0.2, 0.0, 0.0), (1.2, {}, {})])],\n    blocks: [",
        -ramp_end * c,
        -ramp_end * s
    );
    with_cohesion
        .replace("duration: 1.0", "duration: 1.2")
        // Rigid-like blocks: the prediction is for a rigid block, and an
        // elastic one's Poisson strain loads its two corners unequally.
        .replace("young: 1e10", "young: 1e12")
        .replace(
            "output: (interval: 0.01),",
            "output: (interval: 0.0, contacts: true),",
        )
        .replace("blocks: [", &load)
}

#[test]
fn bond_breaks_at_the_predicted_load_then_the_block_slides() {
    let (theta, mu, g) = (THETA.to_radians(), PHI.to_radians().tan(), 9.81);
    let mass = 2700.0;
    let weight = mass * g;
    let t_break = (mu * weight * theta.cos() + COHESION * 1.0) / (1.0 + mu);
    let p_break = t_break - weight * theta.sin();
    assert!(p_break > 0.0, "cohesion alone holds the block");
    let ramp_end = 1.5 * p_break;
    let out = common::run_text("cohesive_strength", &scene(ramp_end));
    let history = dda::read_history(out.join("history.csv")).unwrap();
    let contacts = common::read_contacts(&out.join("contacts.csv"));
    let _ = std::fs::remove_dir_all(&out);

    // Held while the load is zero.
    let start = common::at(&history, 1, 0.0);
    let rest = common::at(&history, 1, 0.2);
    assert!(
        common::distance(start, rest) < 1e-5,
        "moved {:e} m before loading",
        common::distance(start, rest)
    );

    // The first slide is the break.
    let broke = contacts
        .iter()
        .find(|r| r.state == "sliding")
        .expect("the bond breaks")
        .time;
    let load = ramp_end * (broke - 0.2) / 1.0;
    assert!(
        ((load - p_break) / p_break).abs() < 0.01,
        "broke at {load:.0} N, predicted {p_break:.0} N"
    );

    // Then friction alone: a = g (sin θ − cos θ tan φ) + P(t)/m along the slope.
    let along = |r: &dda::HistoryRow| -(r.vx * theta.cos() + r.vy * theta.sin());
    let (t1, t2) = (1.0, 1.2);
    let dv = along(common::at(&history, 1, t2)) - along(common::at(&history, 1, t1));
    let rate = ramp_end / 1.0;
    let expected = g * (theta.sin() - theta.cos() * mu) * (t2 - t1)
        + rate / mass * ((t2 - 0.2f64).powi(2) - (t1 - 0.2f64).powi(2)) / 2.0;
    assert!(
        ((dv - expected) / expected).abs() < 0.01,
        "gained {dv:.4} m/s, expected {expected:.4} m/s"
    );
}
