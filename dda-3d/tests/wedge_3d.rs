//! A tetrahedral wedge on two planes, dip/dip direction 50/130 and 50/230
//! (x east, y north, z up; reference B5). With φ = 20° on both it slides
//! along their line of intersection (plunge 37.45° towards 180°) with
//! a/g = 0.2513; with φ = 40° (factor of safety 1.35) it stays put.
//!
//! The support is one fixed, non-convex block: a V-shaped trough made as a
//! prism along the line of intersection, whose two inner faces are the
//! planes. The wedge's edge along the crease rests in it, and its other two
//! corners on one plane each.

mod common;

use dda_3d::polyhedron::prism;
use dda_3d::{Block, Driver3d, Polyhedra};
use dda_core::Settings;
use nalgebra::{Matrix3, Point2, Point3, Vector2, Vector3};

/// Upward unit normal of a plane of given dip and dip direction (degrees).
fn plane_normal(dip: f64, direction: f64) -> Vector3<f64> {
    let (d, a) = (dip.to_radians(), direction.to_radians());
    Vector3::new(d.sin() * a.sin(), d.sin() * a.cos(), d.cos())
}

/// Sliding direction along the intersection and a/g from the vector
/// solution of B5 (equal friction on both planes).
fn analytical(n1: &Vector3<f64>, n2: &Vector3<f64>, phi: f64) -> (Vector3<f64>, f64) {
    let w = Vector3::new(0.0, 0.0, -1.0);
    let m = n1.cross(n2);
    let s = if m.dot(&w) > 0.0 { m } else { -m }.normalize();
    let m2 = m.norm_squared();
    let r1 = -w.cross(n2).dot(&m) / m2;
    let r2 = -w.cross(n1).dot(&n2.cross(n1)) / m2;
    assert!(r1 > 0.0 && r2 > 0.0, "both planes carry the wedge");
    (s, w.dot(&s) - (r1 + r2) * phi.to_radians().tan())
}

struct Setup {
    driver: Driver3d,
    slide: Vector3<f64>,
    ratio: f64,
}

fn wedge(phi: f64) -> Setup {
    let n1 = plane_normal(50.0, 130.0);
    let n2 = plane_normal(50.0, 230.0);
    let (slide, ratio) = analytical(&n1, &n2, phi);
    // A frame with its third axis down the line of intersection and its
    // second axis up between the planes.
    let up = (n1 + n2).normalize();
    let across = up.cross(&slide);
    let frame = Matrix3::from_columns(&[across, up, slide]);
    let to_world = |p: Point3<f64>| Point3::from(frame * p.coords) + Vector3::new(5.0, 5.0, 5.0);
    // In the cross-section, each plane leaves the crease along the
    // direction perpendicular to its normal that rises.
    let arm = |n: &Vector3<f64>| {
        let n2d = Vector2::new(n.dot(&across), n.dot(&up));
        let a = Vector2::new(n2d.y, -n2d.x);
        if a.y > 0.0 {
            a
        } else {
            -a
        }
    };
    let (arm1, arm2) = (arm(&n1), arm(&n2));
    let (right, left) = if arm1.x > 0.0 {
        (arm1, arm2)
    } else {
        (arm2, arm1)
    };
    // The trough: crease at the origin, arms 3 m long, 2 m deep below the
    // crease, 10 m along the line; counter-clockwise: crease, left arm's tip,
    // down, across, right arm's tip.
    let (lt, rt) = (left * 3.0, right * 3.0);
    let outline = [
        Point2::origin(),
        Point2::from(lt),
        Point2::new(lt.x, -2.0),
        Point2::new(rt.x, -2.0),
        Point2::from(rt),
    ];
    let (v, f) = prism(&outline, -4.0, 6.0);
    let v: Vec<Point3<f64>> = v.into_iter().map(to_world).collect();
    let base = Block::new(&v, &f, 0, common::ROCK).expect("the trough is valid");
    // The wedge: two corners on the crease 2 m apart, one on each plane
    // 1.5 m up its arm, halfway between them.
    let (l1, l2) = (right * 1.5, left * 1.5);
    let corners = [
        Point3::new(0.0, 0.0, -1.0),
        Point3::new(0.0, 0.0, 1.0),
        Point3::new(l1.x, l1.y, 0.0),
        Point3::new(l2.x, l2.y, 0.0),
    ]
    .map(to_world);
    let faces = vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]];
    let wedge = Block::new(&corners, &faces, 0, common::ROCK).expect("the wedge is valid");
    let mut system = Polyhedra::new(vec![base, wedge], common::rock());
    system.gravity = Vector3::new(0.0, 0.0, -common::G);
    system.fix_block(0);
    let settings = Settings {
        dt: Some(1e-3),
        penalty: Some(1e10),
        ..Settings::default()
    };
    Setup {
        driver: common::driver(system, phi, settings),
        slide,
        ratio,
    }
}

#[test]
fn the_reference_numbers_follow_from_the_geometry() {
    let (s, ratio) = analytical(&plane_normal(50.0, 130.0), &plane_normal(50.0, 230.0), 20.0);
    assert!((ratio - 0.2513).abs() < 1e-4, "a/g = {ratio}");
    let plunge = (-s.z).asin().to_degrees();
    assert!((plunge - 37.454).abs() < 1e-3, "plunge {plunge}");
    assert!(s.x.abs() < 1e-12 && s.y < 0.0, "trend 180°");
}

#[test]
fn the_wedge_rests_on_both_planes_at_six_corners() {
    let setup = wedge(20.0);
    let range = 0.025 * setup.driver.length_scale();
    let found = dda_core::BlockSystem::find_contacts(&setup.driver.system, range);
    let labels: Vec<String> = found
        .iter()
        .map(|c| dda_3d::contact_label(&c.key))
        .collect();
    assert_eq!(found.len(), 6, "{labels:?}");
    for c in &found {
        assert_eq!(c.entrances.len(), 1);
        assert!(c.entrances[0].gap.abs() < 1e-12, "touching");
    }
}

#[test]
fn the_wedge_slides_along_the_intersection_at_the_analytical_rate() {
    let Setup {
        mut driver,
        slide,
        ratio,
    } = wedge(20.0);
    let start = driver.system.blocks[1].centroid();
    driver.advance_to(1.0).unwrap();
    let moved = driver.system.blocks[1].centroid() - start;
    let along = moved.dot(&slide);
    let a = 2.0 * along; // d = a t² / 2 at t = 1 s
    println!(
        "a/g {} vs {ratio}; {:?}",
        a / common::G,
        driver.statistics()
    );
    assert!(
        ((a / common::G - ratio) / ratio).abs() < 0.02,
        "a/g = {}, exact {ratio}",
        a / common::G
    );
    let off = common::angle(&moved, &slide);
    assert!(off < 0.5, "{off}° off the line of intersection");
}

#[test]
fn the_wedge_stays_put_with_forty_degrees_of_friction() {
    let Setup { mut driver, .. } = wedge(40.0);
    let start = driver.system.blocks[1].centroid();
    driver.advance_to(1.0).unwrap();
    let moved = (driver.system.blocks[1].centroid() - start).norm();
    println!("moved {moved:e}; {:?}", driver.statistics());
    assert!(moved < 1e-4, "moved {moved:e} m in 1 s");
}
