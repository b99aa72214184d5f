//! Housner's free rocking (reference B3): a 1 m × 4 m block released at
//! half its slenderness angle on a rigid base with high friction. The time
//! to the first impact against the rigid-body answer (3 %), and the first
//! three amplitude ratios against Housner's recursion with
//! r = 1 − 1.5 sin² α (10 %), at the penalty (1e10 N/m) and time step
//! (0.5 ms) of examples/rocking_column_2d.ron.

mod common;

const B: f64 = 0.5;
const H: f64 = 2.0;

fn alpha() -> f64 {
    (B / H).atan()
}

/// Time for the rigid block to rock from θ0 at rest down to θ = 0:
/// θ̈ = −p² sin(α − θ), p² = 3g / (4R), by fine RK4 steps.
fn first_impact(theta0: f64) -> f64 {
    let p2 = 3.0 * 9.81 / (4.0 * (B * B + H * H).sqrt());
    let acc = |th: f64| -p2 * (alpha() - th).sin();
    let h = 1e-6;
    let (mut th, mut om, mut t) = (theta0, 0.0f64, 0.0);
    while th > 0.0 {
        let k1 = (om, acc(th));
        let k2 = (om + 0.5 * h * k1.1, acc(th + 0.5 * h * k1.0));
        let k3 = (om + 0.5 * h * k2.1, acc(th + 0.5 * h * k2.0));
        let k4 = (om + h * k3.1, acc(th + h * k3.0));
        th += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        om += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        t += h;
    }
    t
}

/// Housner's amplitudes: cos(α − θ_{n+1}) = cos α + r² [cos(α − θ_n) − cos α].
fn housner_amplitudes(theta0: f64, n: usize) -> Vec<f64> {
    let a = alpha();
    let r = 1.0 - 1.5 * a.sin().powi(2);
    let mut out = vec![theta0];
    for _ in 0..n {
        let last = *out.last().unwrap();
        let c = a.cos() + r * r * ((a - last).cos() - a.cos());
        out.push(a - c.acos());
    }
    out
}

#[test]
fn rocking_block_impacts_on_time_and_loses_housners_share_each_impact() {
    let rows = common::run_example("rocking_column_2d.ron");
    let theta0 = alpha() / 2.0;
    let column: Vec<&dda::HistoryRow> = rows.iter().filter(|r| r.block == 1).collect();
    // Tilt: released clockwise by θ0; counter-clockwise rotation rights it.
    let tilt = |r: &dda::HistoryRow| theta0 - r.rotation;

    // The impact is where |ω| peaks: the block falls until its other corner lands.
    let first_landing = column
        .iter()
        .position(|r| tilt(r) <= 0.0)
        .expect("the block rocks back");
    let peak = column[..=first_landing + 5]
        .iter()
        .max_by(|a, b| a.omega.abs().total_cmp(&b.omega.abs()))
        .unwrap();
    let expected = first_impact(theta0);
    assert!(
        ((peak.time - expected) / expected).abs() < 0.03,
        "first impact at {:.4} s, rigid {expected:.4} s",
        peak.time
    );

    // Amplitudes: the largest |tilt| between successive zero crossings.
    let mut amplitudes = vec![theta0];
    let mut current = 0.0f64;
    for w in column.windows(2).skip(first_landing) {
        let (a, b) = (tilt(w[0]), tilt(w[1]));
        current = current.max(b.abs());
        if a * b < 0.0 && current > 0.0 {
            amplitudes.push(current);
            current = 0.0;
        }
    }
    let housner = housner_amplitudes(theta0, 3);
    assert!(
        amplitudes.len() >= 4,
        "three rebounds within the run: {amplitudes:?}"
    );
    for n in 0..3 {
        let ratio = amplitudes[n + 1] / amplitudes[n];
        let expected = housner[n + 1] / housner[n];
        assert!(
            ((ratio - expected) / expected).abs() < 0.1,
            "ratio {}: {ratio:.4}, Housner {expected:.4}",
            n + 1
        );
    }
}
