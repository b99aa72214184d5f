//! The overlap search of the scene's check (`dda_core::overlap`, through
//! `dda_2d::polygon::first_overlap` and `dda_3d::polyhedron::first_overlap`)
//! finds the same first overlapping pair as trying every pair, and tests
//! slanted slivers against a few neighbours only.

use std::f64::consts::PI;

use dda_2d::polygon;
use dda_3d::polyhedron::{self, Polyhedron};
use dda_core::overlap::{bounds, Found};
use nalgebra::{Point2, Point3, Rotation3, Vector3};
use proptest::prelude::*;

/// Every pair in order, the plain way: what the search must agree with.
fn every_pair<S, const D: usize>(
    shapes: &[S],
    corners: impl Fn(&S) -> Vec<[f64; D]>,
    overlap: impl Fn(&S, &S, f64) -> bool,
) -> Option<(usize, usize)> {
    let boxes: Vec<([f64; D], [f64; D])> = shapes.iter().map(|s| bounds(&corners(s))).collect();
    let all: Vec<[f64; D]> = boxes.iter().flat_map(|b| [b.0, b.1]).collect();
    let (lo, hi) = bounds(&all);
    let tol = 1e-6 * (0..D).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    (0..shapes.len()).find_map(|i| {
        (0..i)
            .find(|&j| {
                let (a, b) = (boxes[i], boxes[j]);
                let apart = (0..D).any(|k| b.0[k] > a.1[k] + tol || a.0[k] > b.1[k] + tol);
                !apart && overlap(&shapes[j], &shapes[i], tol)
            })
            .map(|j| (i, j))
    })
}

/// Voussoirs of a ring from angle `start` over `span`; voussoir `wide`
/// reaches over its neighbour at the outside.
fn ring(
    n: usize,
    centre: [f64; 2],
    (inner, outer): (f64, f64),
    (start, span): (f64, f64),
    wide: Option<usize>,
) -> Vec<Vec<Point2<f64>>> {
    let at = |r: f64, k: usize| {
        let a = start + span * k as f64 / n as f64;
        Point2::new(centre[0] + r * a.cos(), centre[1] + r * a.sin())
    };
    (0..n)
        .map(|k| {
            let reach = if Some(k) == wide { 2 } else { 1 };
            vec![
                at(inner, k),
                at(outer, k),
                at(outer, k + reach),
                at(inner, k + 1),
            ]
        })
        .collect()
}

/// A turned grid of rectangles sharing their sides; one may be moved.
fn grid(
    (rows, cols): (usize, usize),
    (w, h): (f64, f64),
    angle: f64,
    origin: [f64; 2],
    moved: Option<(usize, f64)>,
) -> Vec<Vec<Point2<f64>>> {
    let (c, s) = (angle.cos(), angle.sin());
    let at = |i: usize, j: usize, shift: f64| {
        let (x, y) = (j as f64 * w + shift, i as f64 * h);
        Point2::new(origin[0] + c * x - s * y, origin[1] + s * x + c * y)
    };
    let mut out = Vec::new();
    for i in 0..rows {
        for j in 0..cols {
            let shift = match moved {
                Some((k, f)) if k % (rows * cols) == out.len() => f * w,
                _ => 0.0,
            };
            out.push(vec![
                at(i, j, shift),
                at(i, j + 1, shift),
                at(i + 1, j + 1, shift),
                at(i + 1, j, shift),
            ]);
        }
    }
    out
}

fn rectangle(centre: [f64; 2], (w, h): (f64, f64), angle: f64) -> Vec<Point2<f64>> {
    let (c, s) = (angle.cos(), angle.sin());
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|(x, y)| {
            let (x, y) = (x * w / 2.0, y * h / 2.0);
            Point2::new(centre[0] + c * x - s * y, centre[1] + s * x + c * y)
        })
        .collect()
}

fn polygons() -> impl Strategy<Value = Vec<Vec<Point2<f64>>>> {
    let rings = (
        2usize..400,
        (-100.0..100.0, -100.0..100.0),
        (0.1..20.0, 0.001..1.0),
        (0.0..2.0 * PI, 0.1..1.9 * PI),
        prop::option::of(0usize..400),
    );
    let grids = (
        (1usize..20, 1usize..20),
        (0.001..2.0, 0.001..1000.0),
        0.0..PI,
        (-200.0..200.0, -200.0..200.0),
        prop::option::of((0usize..400, -0.9..0.9)),
    );
    let rectangles = prop::collection::vec(
        (
            (-100.0..100.0, -100.0..100.0),
            (0.01..5.0, 0.0001..5.0),
            0.0..PI,
        ),
        0..5,
    );
    (rings, grids, rectangles).prop_map(|(r, g, rectangles)| {
        let (n, centre, (inner, thickness), angles, wide) = r;
        let wide = wide.map(|k| k % n);
        let mut out = ring(
            n,
            [centre.0, centre.1],
            (inner, inner * (1.0 + thickness)),
            angles,
            wide,
        );
        let (count, (w, aspect), angle, origin, moved) = g;
        out.extend(grid(
            count,
            (w, w * aspect),
            angle,
            [origin.0, origin.1],
            moved,
        ));
        for (c, size, angle) in rectangles {
            out.push(rectangle([c.0, c.1], size, angle));
        }
        // Only valid blocks reach the search.
        out.retain(|o| polygon::validate(o).is_ok());
        out
    })
}

/// The prisms over the outlines that make valid blocks.
fn prisms(outlines: &[Vec<Point2<f64>>], z: (f64, f64)) -> Vec<Polyhedron> {
    outlines
        .iter()
        .filter_map(|o| {
            let (v, f) = polyhedron::prism(o, z.0, z.1);
            polyhedron::validate(&v, &f).ok()
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Slivers, turned grids and loose rectangles: the search finds the
    /// same first overlap as trying every pair.
    #[test]
    fn polygons_agree_with_every_pair(outlines in polygons()) {
        let corners = |o: &Vec<Point2<f64>>| o.iter().map(|p| [p.x, p.y]).collect();
        let plain = every_pair(&outlines, corners, |a, b, tol| polygon::overlap(a, b, tol));
        prop_assert_eq!(polygon::first_overlap(&outlines).first, plain);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The same in 3D: a ring of prism staves with turned boxes.
    #[test]
    fn polyhedra_agree_with_every_pair(
        n in 2usize..150,
        (inner, thickness) in (0.1..20.0, 0.001..1.0),
        span in 0.1..1.9 * PI,
        wide in prop::option::of(0usize..150),
        boxes in prop::collection::vec(
            ((-20.0..20.0, -20.0..20.0, -2.0..2.0), (0.01..5.0, 0.001..5.0), (0.0..PI, 0.0..PI)),
            0..5,
        ),
    ) {
        let outer = inner * (1.0 + thickness);
        let outlines = ring(n, [0.0, 0.0], (inner, outer), (0.0, span), wide.map(|k| k % n));
        let mut shapes = prisms(&outlines, (-1.0, 1.0));
        for ((x, y, z), (a, b), (yaw, tilt)) in boxes {
            let turn = Rotation3::from_euler_angles(tilt, 0.0, yaw);
            let (v, f) = polyhedron::cuboid(Point3::new(x, y, z), Vector3::new(a, b, a), turn);
            shapes.push(polyhedron::validate(&v, &f).unwrap());
        }
        let corners = |s: &Polyhedron| s.vertices().iter().map(|p| p.coords.into()).collect();
        let plain = every_pair(&shapes, corners, polyhedron::overlap);
        prop_assert_eq!(polyhedron::first_overlap(&shapes).first, plain);
    }
}

/// A voussoir 0.3 mm thick along the arc of a 10 m arch has a box
/// meeting those of thousands of others; the search tests each
/// voussoir against a few neighbours only.
#[test]
fn slivers_are_tested_against_a_few_neighbours() {
    let n = 100_000;
    let outlines = ring(n, [0.0, 0.0], (9.5, 10.5), (0.0, PI), None);
    let Found { first, tested } = polygon::first_overlap(&outlines);
    assert_eq!(first, None);
    println!("2D: {tested} pairs tested for {n} slivers");
    assert!(tested < 20 * n, "{tested} pairs tested for {n} slivers");
    let n = 20_000;
    let shapes = prisms(
        &ring(n, [0.0, 0.0], (9.5, 10.5), (0.0, PI), None),
        (0.0, 1.0),
    );
    let Found { first, tested } = polyhedron::first_overlap(&shapes);
    assert_eq!(first, None);
    println!("3D: {tested} pairs tested for {n} slivers");
    assert!(tested < 20 * n, "{tested} pairs tested for {n} slivers");
}
