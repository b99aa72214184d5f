//! Overturning threshold (reference B3 with a pulse): the 1 m × 4 m block of
//! the rocking example, standing upright, under a one-sine ground pulse.
//! The threshold amplitude comes from the rigid-block equation with
//! Housner's impacts, computed here; the block must overturn 10 % above it
//! and survive 10 % below it.

mod common;

const B: f64 = 0.5;
const H: f64 = 2.0;
const PERIOD: f64 = 0.5;

/// Whether the rigid block overturns under a pulse of amplitude `a` (m/s²):
/// θ̈ = −p² [sin(α sgn θ − θ) + (a_g/g) cos(α sgn θ − θ)], rocking starting
/// once |a_g| > g tan α, θ̇ ← r θ̇ at each impact (θ crossing 0).
fn rigid_overturns(a: f64) -> bool {
    let (g, alpha) = (9.81, (B / H).atan());
    let p2 = 3.0 * g / (4.0 * (B * B + H * H).sqrt());
    let r = 1.0 - 1.5 * alpha.sin().powi(2);
    let ground = |t: f64| {
        if t < PERIOD {
            a * (std::f64::consts::TAU * t / PERIOD).sin()
        } else {
            0.0
        }
    };
    let accel = |t: f64, th: f64| {
        let s = if th > 0.0 { 1.0 } else { -1.0 };
        -p2 * ((s * alpha - th).sin() + ground(t) / g * (s * alpha - th).cos())
    };
    let h = 1e-5;
    let (mut th, mut om, mut t) = (0.0f64, 0.0f64, 0.0f64);
    while t < 6.0 {
        if th == 0.0 && om == 0.0 {
            // At rest: it lifts off a corner only once the ground pushes hard enough.
            let ag = ground(t);
            if ag.abs() > g * alpha.tan() {
                th = -ag.signum() * 1e-12;
            } else {
                t += h;
                continue;
            }
        }
        let (th0, om0) = (th, om);
        let k1 = (om, accel(t, th));
        let k2 = (om + 0.5 * h * k1.1, accel(t + 0.5 * h, th + 0.5 * h * k1.0));
        let k3 = (om + 0.5 * h * k2.1, accel(t + 0.5 * h, th + 0.5 * h * k2.0));
        let k4 = (om + h * k3.1, accel(t + h, th + h * k3.0));
        th += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        om += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        t += h;
        if th0 * th < 0.0 {
            // Impact on the other corner.
            om *= r;
            let _ = om0;
        }
        if th.abs() > alpha {
            return true;
        }
    }
    false
}

/// The rigid threshold amplitude, by bisection.
fn threshold() -> f64 {
    let (mut lo, mut hi) = (9.81 * (B / H), 40.0);
    assert!(!rigid_overturns(lo) && rigid_overturns(hi));
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if rigid_overturns(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// Runs the standing block under the pulse and returns its final tilt.
fn dda_final_tilt(amplitude: f64, name: &str) -> f64 {
    let text = format!(
        r#"Scene(
    analysis: (duration: 4.0, dt: 0.0005, penalty: 1e10, gravity: (0.0, -9.81)),
    output: (interval: 0.05),
    materials: {{ "stone": (density: 2700.0, young: 1e11, poisson: 0.25) }},
    default_joint: Coulomb(friction_angle: 80.0),
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 6.0, height: 1.0, fixed: true),
        Rectangle(center: (0.0, 2.0), width: 1.0, height: 4.0),
    ],
    ground_motion: (blocks: [0], motion: Pulse(amplitude: ({amplitude:?}, 0.0), period: {PERIOD:?})),
)"#
    );
    let out = common::run_text(name, &text);
    let rows = dda::read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    common::at(&rows, 1, 4.0).rotation.abs()
}

#[test]
fn block_overturns_above_and_survives_below_the_rigid_threshold() {
    let a_c = threshold();
    let alpha = (B / H).atan();
    assert!(
        a_c > 9.81 * alpha.tan(),
        "the pulse must lift the block: {a_c}"
    );
    let below = dda_final_tilt(0.9 * a_c, "pulse_below");
    let above = dda_final_tilt(1.1 * a_c, "pulse_above");
    assert!(
        below < alpha,
        "survived 0.9 a_c = {:.3} m/s²? final tilt {below:.3} rad",
        0.9 * a_c
    );
    assert!(
        above > 1.0,
        "overturned at 1.1 a_c = {:.3} m/s²? final tilt {above:.3} rad",
        1.1 * a_c
    );
}
