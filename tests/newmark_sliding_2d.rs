//! Newmark's sliding block (reference B2): a block on a 20° incline with
//! φ = 30° whose ground is shaken horizontally. Its slip down the incline,
//! relative to the ground, against a rigid-plastic integration:
//! while sliding (or once a_h exceeds the yield acceleration g tan(φ − θ)),
//! ẍ = g (sin θ − cos θ tan φ) + a_h (cos θ + sin θ tan φ), until the
//! relative velocity returns to zero (the incline descends toward −x).

mod common;

const THETA: f64 = 20.0;
const PHI: f64 = 30.0;

fn yield_acceleration() -> f64 {
    9.81 * (PHI - THETA).to_radians().tan()
}

/// Rigid-plastic slip down the incline after `t_end` for a 2 Hz sine of
/// `amplitude` lasting 1 s.
fn rigid_plastic(amplitude: f64, t_end: f64) -> f64 {
    let a_h = |t: f64| {
        if t < 1.0 {
            amplitude * (std::f64::consts::TAU * 2.0 * t).sin()
        } else {
            0.0
        }
    };
    dda::validate::formulas::newmark_slip(9.81, THETA.to_radians(), PHI.to_radians(), a_h, t_end)
}

/// Slip of the block relative to the ground, down the incline, at `t`.
fn slip(rows: &[dda::HistoryRow], t: f64) -> f64 {
    let theta = THETA.to_radians();
    let rel = |t: f64| {
        let (b, g) = (common::at(rows, 1, t), common::at(rows, 0, t));
        (b.x - g.x, b.y - g.y)
    };
    let (r0, r1) = (rel(0.0), rel(t));
    -((r1.0 - r0.0) * theta.cos() + (r1.1 - r0.1) * theta.sin())
}

#[test]
fn shaking_above_the_yield_acceleration_slips_as_newmark_predicts() {
    let amplitude = 2.5 * yield_acceleration();
    let rows = common::run_example("shaken_block_2d.ron");
    let exact = rigid_plastic(amplitude, 1.5);
    assert!(exact > 0.05, "the case slips {exact} m");
    let got = slip(&rows, 1.5);
    assert!(
        ((got - exact) / exact).abs() < 0.05,
        "slipped {got:.5} m, rigid-plastic {exact:.5} m"
    );
}

#[test]
fn shaking_below_the_yield_acceleration_does_not_slip() {
    let amplitude = 0.8 * yield_acceleration();
    assert_eq!(rigid_plastic(amplitude, 1.5), 0.0);
    let full = 2.5 * yield_acceleration();
    let text = common::example_with(
        "shaken_block_2d.ron",
        &format!("amplitude: ({full:?}, 0.0)"),
        &format!("amplitude: ({amplitude:?}, 0.0)"),
    );
    let out = common::run_text("shaken_below_yield", &text);
    let rows = dda::read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    // Only the contact springs' give, far below a millimetre.
    let got = slip(&rows, 1.5).abs();
    assert!(got < 1e-5, "slipped {got:e} m");
}
