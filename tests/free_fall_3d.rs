//! Free flight in 3D through the scene format (reference A10, B7.3):
//! Newmark β = 1/2, γ = 1 integrates constant acceleration exactly, so the
//! centroid follows x0 + v0 t + g t²/2 and the velocity v0 + g t to
//! round-off, and the block neither turns nor strains.

use dda::read_history_3d;

mod common;

#[test]
fn a_thrown_box_follows_the_parabola_to_round_off() {
    let out = common::out_dir("free-fall-3d");
    let summary = dda::run::run(&common::example("free_fall_3d.ron"), &out).unwrap();
    assert_eq!((summary.dimension, summary.steps), (3, 100));
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    assert_eq!(rows.len(), 5, "t = 0, 0.25, 0.5, 0.75, 1");
    common::assert_thrown_box_follows_the_parabola(&rows);
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for row in &rows {
        assert!(norm(row.spin) < 1e-12 && norm(row.rotation) < 1e-12);
        assert!(row.stress.iter().all(|s| s.abs() < 1e-6));
    }
}
