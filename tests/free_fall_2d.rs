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
