//! A tetrahedral wedge on two planes, dip/dip direction 50/130 and 50/230
//! (reference B5), through the scene format with explicit polyhedra. With
//! φ = 20° it slides along the line of intersection with a/g = 0.2513;
//! with φ = 40° it stays put.

use dda::read_history_3d;
use nalgebra::Vector3;

mod common;

/// The sliding direction and a/g of the vector solution (equal friction).
fn analytical(phi: f64) -> (Vector3<f64>, f64) {
    let (s, along, reactions) = common::reference_wedge();
    (s, along - reactions * phi.to_radians().tan())
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
