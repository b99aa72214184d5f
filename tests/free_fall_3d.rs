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
    let (x0, v0, g) = ([3.0, -2.0, 10.0], [1.0, 2.0, 3.0], [0.0, 0.0, -9.81]);
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for row in &rows {
        let t = row.time;
        let x: [f64; 3] = [0, 1, 2].map(|k| x0[k] + v0[k] * t + g[k] * t * t / 2.0);
        let v: [f64; 3] = [0, 1, 2].map(|k| v0[k] + g[k] * t);
        let dx = norm([0, 1, 2].map(|k| row.position[k] - x[k]));
        let dv = norm([0, 1, 2].map(|k| row.velocity[k] - v[k]));
        assert!(dx < 1e-9 * norm(x), "t = {t}: {:?} vs {x:?}", row.position);
        assert!(dv < 1e-9 * norm(v), "t = {t}: {:?} vs {v:?}", row.velocity);
        assert!(norm(row.spin) < 1e-12 && norm(row.rotation) < 1e-12);
        assert!(row.stress.iter().all(|s| s.abs() < 1e-6));
    }
    assert_eq!(rows.last().unwrap().time, 1.0);
}
