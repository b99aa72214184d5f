//! Free fall: Newmark β = 1/2, γ = 1 integrates constant acceleration
//! exactly, so the centroid follows y0 − g t²/2 at every output time.

mod common;

#[test]
fn free_fall_matches_the_parabola_to_round_off() {
    let rows = common::run_example("free_fall_2d.ron");
    let first = common::at(&rows, 0, 0.0);
    let (y0, g) = (first.y, 9.81);
    assert_eq!(rows.len(), 11, "eleven output times, t = 0 to 1 s");
    for r in &rows {
        let y = y0 - 0.5 * g * r.time * r.time;
        let v = -g * r.time;
        assert!(
            ((r.y - y) / y).abs() < 1e-9,
            "t = {}: y = {}, exact {}",
            r.time,
            r.y,
            y
        );
        assert!(
            (r.vy - v).abs() <= 1e-9 * g * r.time.max(1.0),
            "t = {}: vy = {}",
            r.time,
            r.vy
        );
        assert!((r.x - first.x).abs() < 1e-12 && r.vx.abs() < 1e-12 && r.rotation.abs() < 1e-12);
    }
    assert!(
        (common::at(&rows, 0, 1.0).time - 1.0).abs() < 1e-12,
        "the run ends at 1 s"
    );
}

#[test]
fn a_linear_step_takes_one_newton_iteration() {
    let out = common::out_dir("free_fall_newton");
    let summary = dda::run::run(&common::example("free_fall_2d.ron"), &out).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    assert_eq!(summary.steps, 100);
    assert_eq!(
        summary.open_close_iterations, 100,
        "no contacts: one pass per step"
    );
    assert_eq!(summary.newton_iterations, 100, "linear: one solve per pass");
}
