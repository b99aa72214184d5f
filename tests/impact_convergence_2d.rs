//! Impacts converge: the shipped rocking column (1 m × 4 m, released at
//! half its slenderness angle) at three time steps. Its impacts are
//! impulses (`restitution: 0.0`): the peak tilt after the first impact and
//! the restitution it implies approach Housner's (r = 1 − 1.5 sin² α) as
//! dt shrinks, monotonically, within 1 % at dt ≤ 0.5 ms; the landing
//! corner closes once and stays closed (measured: no change of state after
//! it closes, at every step size). Without the impulse, the corner opened
//! and closed for 19, 47 and 148 steps at 1, 0.5 and 0.25 ms.

use dda::scene::Scene;
use dda::Simulation;

mod common;

const B: f64 = 0.5;
const H: f64 = 2.0;

fn alpha() -> f64 {
    (B / H).atan()
}

/// Housner's coefficient and the first rebound's amplitude from θ0.
fn housner(theta0: f64) -> (f64, f64) {
    let a = alpha();
    let r = 1.0 - 1.5 * a.sin().powi(2);
    let c = a.cos() + r * r * ((a - theta0).cos() - a.cos());
    (r, a - c.acos())
}

/// The restitution an amplitude θ1 after θ0 implies (Housner's recursion
/// solved for r).
fn restitution(theta0: f64, theta1: f64) -> f64 {
    let a = alpha();
    (((a - theta1).cos() - a.cos()) / ((a - theta0).cos() - a.cos())).sqrt()
}

struct Rebound {
    theta1: f64,
    /// Steps from the landing corner's first closing to its last change of
    /// state within 0.1 s.
    settling_steps: usize,
}

fn rebound(dt: f64) -> Rebound {
    let text = std::fs::read_to_string(common::example("rocking_column_2d.ron")).unwrap();
    assert!(
        text.contains("dt: 0.0005")
            && text.contains("duration: 4.0")
            && text.contains("restitution: 0.0")
    );
    let text = text
        .replace("dt: 0.0005", &format!("dt: {dt}"))
        .replace("duration: 4.0", "duration: 1.6");
    let mut model = Scene::from_str(&text, "rocking_column_2d.ron")
        .unwrap()
        .build()
        .unwrap();
    let driver = &mut model.driver;
    let theta0 = alpha() / 2.0;
    // Released clockwise by θ0: counter-clockwise rotation rights it.
    let tilt = |d: &dda_2d::Driver2d| theta0 - d.history_values(1)[2];
    // The landing corner is the column's vertex 0 (the left one).
    let landing = |d: &dda_2d::Driver2d| {
        d.contacts()
            .iter()
            .filter(|c| c.key.block_a == 1 && c.key.feature_a == 0)
            .any(|c| c.record.state.is_closed())
    };
    let (mut peak, mut crossed) = (0.0f64, false);
    let (mut first_close, mut last_change, mut was) = (None, 0usize, false);
    let mut step = 0usize;
    while driver.time() < 1.6 - 1e-9 {
        driver.step(1.6 - driver.time()).unwrap();
        step += 1;
        let t = tilt(driver);
        crossed |= t < 0.0;
        if crossed {
            peak = peak.max(-t);
        }
        let closed = landing(driver);
        if closed != was {
            first_close.get_or_insert(step);
            if (step - first_close.unwrap()) as f64 * dt < 0.1 {
                last_change = step;
            }
            was = closed;
        }
    }
    assert!(crossed, "the column rocked back over its base");
    assert_eq!(driver.statistics().unconverged_steps, 0);
    Rebound {
        theta1: peak,
        settling_steps: last_change - first_close.expect("the corner landed"),
    }
}

#[test]
fn the_first_rebound_converges_to_housner_as_dt_shrinks() {
    let theta0 = alpha() / 2.0;
    let (r, theta1) = housner(theta0);
    let mut errors = Vec::new();
    for dt in [1e-3, 5e-4, 2.5e-4] {
        let got = rebound(dt);
        let error = got.theta1 / theta1 - 1.0;
        let r_got = restitution(theta0, got.theta1);
        println!(
            "dt {:.2} ms: θ1 {:.6} rad (Housner {theta1:.6}, {:+.2} %), r {r_got:.5} (Housner {r:.5}), corner settled in {} steps",
            dt * 1e3,
            got.theta1,
            100.0 * error,
            got.settling_steps
        );
        if dt <= 5e-4 {
            assert!(
                error.abs() < 0.01,
                "dt {dt}: θ1 off by {:.2} %",
                100.0 * error
            );
            assert!(
                (r_got / r - 1.0).abs() < 0.01,
                "dt {dt}: restitution {r_got:.5}, Housner {r:.5}"
            );
        }
        assert!(
            got.settling_steps <= 2,
            "dt {dt}: the landing corner opened and closed for {} steps",
            got.settling_steps
        );
        errors.push(error);
    }
    // Monotone in dt: each halving moves the answer the same way.
    assert!(
        errors.windows(2).all(|w| w[1] > w[0]),
        "not monotone: {errors:?}"
    );
}
