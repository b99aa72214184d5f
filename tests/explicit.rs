//! The explicit integrator (`analysis: (integrator: Explicit)`: central
//! differences on the same blocks, contacts and laws) against the answers
//! the implicit one is held to, with its own tolerances:
//!
//! * free flight, 2D and 3D: central differences integrate a constant
//!   force exactly, so the parabola to round-off (1e-9 relative);
//! * the sliding block, 2D and 3D, with critical contact damping (without
//!   it the block chatters on its undamped corner springs, which the
//!   implicit step's numerical damping removes and central differences
//!   keep: it slides 5 % too far): 0.9064 m in 1 s within 0.5 %, the
//!   velocity within 0.5 %;
//! * Housner's rocking block: the first impact within 3 %, the amplitude
//!   ratios within 10 % (the implicit test's tolerances);
//! * the resting block at a factor of safety of 1.01 holds (creep below
//!   1e-7 m between 1 s and 2 s) and at 0.99 slides with the Coulomb
//!   acceleration within 0.5 % once landed;
//! * the critical step: printed, every step below 0.9 of it, a longer dt
//!   shortened, and a block resting at that step gains no energy;
//! * local damping relaxes the self-weight block to its static stress.

use dda::scene::Integrator;
use dda::{read_history, read_history_3d, HistoryRow, HistoryRow3, Scene, Summary};

mod common;

/// Runs a shipped example with the explicit integrator, after `edit`.
fn run(name: &str, edit: impl FnOnce(&mut Scene)) -> (Summary, std::path::PathBuf) {
    common::run_edited(name, "explicit", |scene| {
        scene.analysis.integrator = Integrator::Explicit;
        edit(scene);
    })
}

fn rows_2d(name: &str, edit: impl FnOnce(&mut Scene)) -> (Summary, Vec<HistoryRow>) {
    let (summary, out) = run(name, edit);
    let rows = read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    (summary, rows)
}

fn rows_3d(name: &str, edit: impl FnOnce(&mut Scene)) -> (Summary, Vec<HistoryRow3>) {
    let (summary, out) = run(name, edit);
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    (summary, rows)
}

#[test]
fn free_flight_follows_the_parabola_to_round_off_in_2d_and_3d() {
    let (summary, rows) = rows_2d("free_fall_2d.ron", |_| {});
    assert_eq!(summary.status, dda::summary::Status::Finished);
    let first = *common::at(&rows, 0, 0.0);
    for row in &rows {
        let t = row.time;
        let y = first.y - 9.81 * t * t / 2.0;
        assert!(
            (row.y - y).abs() < 1e-9 * y.abs(),
            "t = {t}: y {} vs {y}",
            row.y
        );
        assert!((row.x - first.x).abs() < 1e-12);
        assert!(
            (row.vy + 9.81 * t).abs() < 1e-9 * 9.81,
            "t = {t}: vy {}",
            row.vy
        );
        assert!(row.rotation.abs() < 1e-12);
    }
    assert_eq!(rows.last().unwrap().time, 1.0);

    let (_, rows) = rows_3d("free_fall_3d.ron", |_| {});
    common::assert_thrown_box_follows_the_parabola(&rows);
}

/// d = ½ g (sin θ − cos θ tan φ) t² for θ = 30°, φ = 20°.
fn slide(t: f64) -> (f64, f64) {
    let (theta, phi) = (30f64.to_radians(), 20f64.to_radians());
    let a = 9.81 * (theta.sin() - theta.cos() * phi.tan());
    (0.5 * a * t * t, a * t)
}

#[test]
fn sliding_block_slides_the_coulomb_distance_in_2d_and_3d() {
    let damped = |s: &mut Scene| s.analysis.contact_damping = 1.0;
    let (summary, rows) = rows_2d("sliding_block_2d.ron", damped);
    let start = common::at(&rows, 1, 0.0);
    for t in [0.5, 1.0] {
        let now = common::at(&rows, 1, t);
        let moved = common::distance(start, now);
        let speed = now.vx.hypot(now.vy);
        let (d, v) = slide(t);
        assert!(
            ((moved - d) / d).abs() < 0.005,
            "2D t = {t}: {moved} m, exact {d}"
        );
        assert!(
            ((speed - v) / v).abs() < 0.005,
            "2D t = {t}: {speed} m/s, exact {v}"
        );
    }
    assert_eq!(summary.energy_growth_steps, 0);

    let (_, rows) = rows_3d("sliding_block_3d.ron", damped);
    let at = |t: f64| {
        rows.iter()
            .filter(|r| r.block == 1)
            .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))
            .unwrap()
    };
    let start = at(0.0);
    for t in [0.5, 1.0] {
        let now = at(t);
        let moved = (0..3)
            .map(|k| (now.position[k] - start.position[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let speed = now.velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
        let (d, v) = slide(t);
        assert!(
            ((moved - d) / d).abs() < 0.005,
            "3D t = {t}: {moved} m, exact {d}"
        );
        assert!(
            ((speed - v) / v).abs() < 0.005,
            "3D t = {t}: {speed} m/s, exact {v}"
        );
    }
}

#[test]
fn rocking_block_impacts_on_time_and_loses_housners_share_each_impact() {
    // Every step's row would be 300,000 rows: every half millisecond, as
    // the implicit run's steps.
    let (summary, rows) = rows_2d("rocking_column_2d.ron", |s| {
        s.output.interval = Some(5e-4);
        // Impacts as impulses belong to the implicit step; the explicit
        // run ends them with the contact dashpots alone.
        s.analysis.restitution = None;
    });
    assert!(summary.critical_dt.unwrap() < 5e-4, "the step was limited");
    common::assert_rocks_like_housner(&rows);
}

#[test]
fn steps_stay_below_the_critical_step_which_the_run_prints() {
    // The resting block near its friction limit, asked for 5 ms steps.
    let (summary, rows) = rows_2d("resting_block_2d.ron", |s| {
        s.analysis.dt = Some(5e-3);
        s.analysis.duration = 1.0;
        s.analysis.contact_damping = 1.0;
    });
    let critical = summary.critical_dt.expect("the critical step is reported");
    let note = summary
        .notes
        .iter()
        .find(|n| n.starts_with("explicit integration"))
        .expect("the critical step is printed");
    assert!(
        note.contains("critical time step") && note.contains("shortened"),
        "{note}"
    );
    assert!(summary.critical_limited_steps > 0);
    // The steps taken: at least 1 s / (0.9 × the smallest critical step).
    assert!(
        summary.steps as f64 >= 1.0 / (0.9 * critical) * 0.999,
        "{} steps for a critical step of {critical} s",
        summary.steps
    );
    // At that step the method is stable: no energy appears, the block holds.
    assert_eq!(summary.energy_growth_steps, 0, "{:?}", summary.warnings);
    let (a, b) = (common::at(&rows, 1, 0.5), common::at(&rows, 1, 1.0));
    assert!(
        common::distance(a, b) < 1e-6,
        "crept {} m",
        common::distance(a, b)
    );
}

#[test]
fn an_automatic_step_is_nine_tenths_of_the_critical_one() {
    let (summary, _) = rows_2d("resting_block_2d.ron", |s| {
        s.analysis.dt = None;
        s.analysis.duration = 0.05;
    });
    // 0.9 of the critical step at the start; the smallest one seen is a
    // little shorter, as the springs load.
    let critical = summary.critical_dt.unwrap();
    let ratio = summary.dt / (0.9 * critical);
    assert!(
        (1.0..1.01).contains(&ratio),
        "dt {} vs critical {critical}",
        summary.dt
    );
}

#[test]
fn local_damping_relaxes_the_standing_block_to_its_static_stress() {
    // Dynamic: the example's static mode (each step from rest) relaxes by
    // itself; here only the local damping stops the block ringing.
    let (_, rows) = rows_2d("self_weight_2d.ron", |s| {
        s.analysis.mode = dda::scene::Mode::Dynamic;
        s.analysis.local_damping = 0.8;
    });
    let (rho, g, h) = (2700.0, 9.81, 2.0);
    let expected = -rho * g * h / 2.0;
    let last = common::at(&rows, 1, 1.0);
    assert!(
        ((last.syy - expected) / expected).abs() < 1e-5,
        "σy = {}, expected {expected}",
        last.syy
    );
    assert!(last.vy.abs() < 1e-6, "still moving at {} m/s", last.vy);
}

#[test]
fn local_damping_is_refused_with_the_implicit_integrator() {
    let mut scene = Scene::load(common::example("self_weight_2d.ron")).unwrap();
    scene.analysis.local_damping = 0.8;
    let message = format!("{:#}", scene.build_any().err().expect("refused"));
    assert!(
        message.contains("local_damping") && message.contains("Explicit"),
        "{message}"
    );
}

/// The resting block at a factor of safety of 1.01 and 0.99 (30° incline,
/// contact damping 1, steps at the critical one): at 1.01 it creeps less
/// than 1e-7 m between 1 s and 2 s (the implicit step's floor); at 0.99 it
/// slides with g·sin θ·(1 − FS) within 0.5 %.
#[test]
fn near_its_friction_limit_the_block_holds_or_slides_as_coulomb_says() {
    let theta = 30f64.to_radians();
    for fs in [1.01, 0.99] {
        let phi = (fs * theta.tan()).atan().to_degrees();
        let (_, rows) = rows_2d("resting_block_2d.ron", |s| {
            s.analysis.contact_damping = 1.0;
            let dda::scene::JointLaw::Coulomb(law) = &mut s.default_joint else {
                panic!("the example's joints are Coulomb's");
            };
            law.friction_angle = phi;
        });
        let (one, half, two) = (
            common::at(&rows, 1, 1.0),
            common::at(&rows, 1, 1.5),
            common::at(&rows, 1, 2.0),
        );
        if fs > 1.0 {
            let creep = common::distance(one, two);
            assert!(
                creep < 1e-7,
                "FS {fs}: crept {creep:e} m between 1 s and 2 s"
            );
        } else {
            // After the landing (which the limits tests leave out too): the
            // second difference of the position over 1, 1.5 and 2 s.
            let a = (two.x - 2.0 * half.x + one.x).hypot(two.y - 2.0 * half.y + one.y) / 0.25;
            let exact = 9.81 * theta.sin() * (1.0 - fs);
            assert!(
                ((a - exact) / exact).abs() < 0.005,
                "FS {fs}: {a} m/s², Coulomb {exact}"
            );
        }
    }
}
