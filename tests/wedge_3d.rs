//! A tetrahedral wedge on two planes, dip/dip direction 50/130 and 50/230
//! (reference B5), through the scene format with explicit polyhedra. With
//! φ = 20° it slides along the line of intersection with a/g = 0.2513;
//! with φ = 40° it stays put.

use dda::read_history_3d;
use nalgebra::Vector3;

mod common;

/// Upward unit normal of a plane of given dip and dip direction (degrees).
fn plane_normal(dip: f64, direction: f64) -> Vector3<f64> {
    let (d, a) = (dip.to_radians(), direction.to_radians());
    Vector3::new(d.sin() * a.sin(), d.sin() * a.cos(), d.cos())
}

/// The sliding direction and a/g of the vector solution (equal friction).
fn analytical(phi: f64) -> (Vector3<f64>, f64) {
    let (n1, n2) = (plane_normal(50.0, 130.0), plane_normal(50.0, 230.0));
    let w = Vector3::new(0.0, 0.0, -1.0);
    let m = n1.cross(&n2);
    let s = if m.dot(&w) > 0.0 { m } else { -m }.normalize();
    let m2 = m.norm_squared();
    let r1 = -w.cross(&n2).dot(&m) / m2;
    let r2 = -w.cross(&n1).dot(&n2.cross(&n1)) / m2;
    (s, w.dot(&s) - (r1 + r2) * phi.to_radians().tan())
}

/// The wedge's (block 1) centroid displacement after 1 s.
fn slide(name: &str) -> Vector3<f64> {
    let out = common::out_dir(name.trim_end_matches(".ron"));
    dda::run::run(&common::example(name), &out).unwrap();
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let wedge: Vec<_> = rows.iter().filter(|r| r.block == 1).collect();
    let (first, last) = (wedge[0], wedge[wedge.len() - 1]);
    assert_eq!((first.time, last.time), (0.0, 1.0));
    Vector3::from(last.position) - Vector3::from(first.position)
}

#[test]
fn the_reference_numbers_follow_from_the_planes() {
    let (s, ratio) = analytical(20.0);
    assert!((ratio - 0.2513).abs() < 1e-4, "a/g = {ratio}");
    assert!(((-s.z).asin().to_degrees() - 37.454).abs() < 1e-3, "plunge");
    assert!(s.x.abs() < 1e-12 && s.y < 0.0, "trend 180°");
}

#[test]
fn the_wedge_slides_along_the_intersection_at_the_analytical_rate() {
    let (s, ratio) = analytical(20.0);
    let moved = slide("wedge_3d.ron");
    let a = 2.0 * moved.dot(&s); // d = a t² / 2 at t = 1 s
    let measured = a / 9.81;
    assert!(
        ((measured - ratio) / ratio).abs() < 0.02,
        "a/g = {measured}, exact {ratio}"
    );
    let off = moved.angle(&s).to_degrees();
    assert!(off < 0.5, "{off}° off the line of intersection");
}

#[test]
fn the_wedge_stays_put_with_forty_degrees_of_friction() {
    let (_, ratio) = analytical(40.0);
    assert!(ratio < 0.0, "friction exceeds the driving force");
    let moved = slide("wedge_stable_3d.ron").norm();
    assert!(moved < 1e-4, "moved {moved:e} m in 1 s");
}
