//! Where a contact is, from its label (`1:v0/0:e2`, `1:e4/0:e7`, `1:v3/0:f1`)
//! and the blocks' shapes: the VTK frames place contacts with it, and
//! `dda render` places the contacts of `contacts.csv`.

use dda_3d::Polyhedron;
use nalgebra::{Point2, Point3, Vector3};

/// A feature of a block named in a contact label.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    Vertex(usize),
    Edge(usize),
    Face(usize),
}

/// A contact label's two sides: (block, feature) of the entering block a
/// and of the entered block b.
pub fn parse_label(label: &str) -> Option<[(usize, Feature); 2]> {
    let (a, b) = label.split_once('/')?;
    let side = |s: &str| -> Option<(usize, Feature)> {
        let (block, feature) = s.split_once(':')?;
        let block = block.parse().ok()?;
        let index = feature.get(1..)?.parse().ok()?;
        let feature = match feature.as_bytes().first()? {
            b'v' => Feature::Vertex(index),
            b'e' => Feature::Edge(index),
            b'f' => Feature::Face(index),
            _ => return None,
        };
        Some((block, feature))
    };
    Some([side(a)?, side(b)?])
}

/// A 2D contact's point (the entering vertex) and unit normal from block b
/// towards block a (the outward normal of the entered edge; for two
/// vertices, from b's vertex towards a's, or between the centroids when they
/// coincide). `blocks` are the polygons' counter-clockwise corners.
pub fn contact_2d(label: &str, blocks: &[Vec<Point2<f64>>]) -> Option<(Point2<f64>, [f64; 2])> {
    let [(a, fa), (b, fb)] = parse_label(label)?;
    let (pa, pb) = (blocks.get(a)?, blocks.get(b)?);
    let Feature::Vertex(va) = fa else { return None };
    let p = *pa.get(va)?;
    let unit = |x: f64, y: f64| {
        let l = x.hypot(y);
        (l > 0.0).then(|| [x / l, y / l])
    };
    let centroid = |v: &[Point2<f64>]| {
        v.iter()
            .fold(Point2::origin(), |s, q| s + q.coords / v.len() as f64)
    };
    let n = match fb {
        Feature::Edge(e) => {
            let (s, t) = (pb.get(e)?, pb[(e + 1) % pb.len()]);
            unit(t.y - s.y, s.x - t.x)
        }
        Feature::Vertex(v) => {
            let q = pb.get(v)?;
            unit(p.x - q.x, p.y - q.y)
        }
        Feature::Face(_) => None,
    };
    let n = n.or_else(|| {
        let d = centroid(pa) - centroid(pb);
        unit(d.x, d.y)
    })?;
    Some((p, n))
}

/// A 3D contact's point: the entering vertex, or for crossing edges the
/// midpoint of their nearest points.
pub fn contact_point_3d(label: &str, shapes: &[&Polyhedron]) -> Option<Point3<f64>> {
    let [(a, fa), (b, fb)] = parse_label(label)?;
    let (sa, sb) = (shapes.get(a)?, shapes.get(b)?);
    match (fa, fb) {
        (Feature::Vertex(v), _) => sa.vertices().get(v).copied(),
        (Feature::Edge(ea), Feature::Edge(eb)) => {
            let ends = |s: &Polyhedron, e: usize| {
                let edge = s.edges().get(e)?;
                Some((s.vertices()[edge.ends[0]], s.vertices()[edge.ends[1]]))
            };
            let (p, q) = nearest_points(ends(sa, ea)?, ends(sb, eb)?);
            Some(Point3::from((p.coords + q.coords) / 2.0))
        }
        _ => None,
    }
}

/// A 3D contact's unit normal from block b towards block a: the entered
/// face's outward normal, for crossing edges their cross product, otherwise
/// between the centroids.
pub fn contact_normal_3d(label: &str, shapes: &[&Polyhedron]) -> Option<Vector3<f64>> {
    let [(a, fa), (b, fb)] = parse_label(label)?;
    let (sa, sb) = (shapes.get(a)?, shapes.get(b)?);
    let between = sa.centroid() - sb.centroid();
    let n = match (fa, fb) {
        (_, Feature::Face(f)) if f < sb.faces().len() => sb.normal(f),
        (Feature::Edge(ea), Feature::Edge(eb)) => {
            let dir = |s: &Polyhedron, e: usize| {
                let edge = s.edges().get(e)?;
                Some(s.vertices()[edge.ends[1]] - s.vertices()[edge.ends[0]])
            };
            let n = dir(sa, ea)?.cross(&dir(sb, eb)?);
            if n.dot(&between) < 0.0 {
                -n
            } else {
                n
            }
        }
        _ => between,
    };
    n.try_normalize(1e-300)
}

/// The nearest points of two segments.
fn nearest_points(
    (p0, p1): (Point3<f64>, Point3<f64>),
    (q0, q1): (Point3<f64>, Point3<f64>),
) -> (Point3<f64>, Point3<f64>) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.dot(&d1), d2.dot(&d2), d2.dot(&r));
    let (c, b) = (d1.dot(&r), d1.dot(&d2));
    let denom = a * e - b * b;
    let mut s = if denom > 1e-14 * a * e {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = if e > 0.0 { (b * s + f) / e } else { 0.0 };
    if t < 0.0 {
        t = 0.0;
        s = if a > 0.0 {
            (-c / a).clamp(0.0, 1.0)
        } else {
            0.0
        };
    } else if t > 1.0 {
        t = 1.0;
        s = if a > 0.0 {
            ((b - c) / a).clamp(0.0, 1.0)
        } else {
            0.0
        };
    }
    (p0 + d1 * s, q0 + d2 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_parse() {
        assert_eq!(
            parse_label("1:v0/0:e2"),
            Some([(1, Feature::Vertex(0)), (0, Feature::Edge(2))])
        );
        assert_eq!(
            parse_label("12:e4/3:f7"),
            Some([(12, Feature::Edge(4)), (3, Feature::Face(7))])
        );
        assert_eq!(parse_label("1:x0/0:e2"), None);
        assert_eq!(parse_label("garbage"), None);
    }

    #[test]
    fn crossing_edges_meet_midway() {
        let p = (Point3::new(-1.0, 0.0, 1.0), Point3::new(1.0, 0.0, 1.0));
        let q = (Point3::new(0.5, -1.0, 0.0), Point3::new(0.5, 1.0, 0.0));
        let (a, b) = nearest_points(p, q);
        assert!((a - Point3::new(0.5, 0.0, 1.0)).norm() < 1e-12);
        assert!((b - Point3::new(0.5, 0.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn a_vertex_on_an_edge_is_pushed_out_of_it() {
        let square = |x: f64, y: f64| {
            vec![
                Point2::new(x, y),
                Point2::new(x + 1.0, y),
                Point2::new(x + 1.0, y + 1.0),
                Point2::new(x, y + 1.0),
            ]
        };
        // Block 1's corner 0 on block 0's top edge (edge 2).
        let blocks = vec![square(0.0, 0.0), square(0.5, 1.0)];
        let (p, n) = contact_2d("1:v0/0:e2", &blocks).unwrap();
        assert_eq!(p, Point2::new(0.5, 1.0));
        assert!((n[0]).abs() < 1e-12 && (n[1] - 1.0).abs() < 1e-12);
    }
}
