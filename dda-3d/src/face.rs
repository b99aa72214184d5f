//! Planar polygons in a face's own 2D frame: point-in-polygon, distances,
//! ear-clipping triangulation and convex clipping. The faces of a block may
//! be concave; everything here works for simple polygons.

use nalgebra::{Point2, Point3, Vector3};

/// An orthonormal frame in a face's plane: `u` along the face's first edge,
/// `v = n × u`, origin at the face's first vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceFrame {
    pub origin: Point3<f64>,
    pub u: Vector3<f64>,
    pub v: Vector3<f64>,
    pub normal: Vector3<f64>,
}

impl FaceFrame {
    /// The frame of a face with unit normal `normal` whose first two
    /// vertices are `p0`, `p1`. The first edge is projected on the plane so the
    /// frame stays orthonormal for slightly non-planar input.
    pub fn new(p0: Point3<f64>, p1: Point3<f64>, normal: Vector3<f64>) -> Self {
        let edge = p1 - p0;
        let along = edge - normal * normal.dot(&edge);
        let u = along
            .try_normalize(0.0)
            .unwrap_or_else(|| any_perpendicular(&normal));
        Self {
            origin: p0,
            u,
            v: normal.cross(&u),
            normal,
        }
    }

    /// In-plane coordinates of a point (its projection on the plane).
    pub fn to_plane(&self, p: &Point3<f64>) -> Point2<f64> {
        let d = p - self.origin;
        Point2::new(d.dot(&self.u), d.dot(&self.v))
    }

    /// Signed distance of a point from the plane (positive on the normal side).
    pub fn height(&self, p: &Point3<f64>) -> f64 {
        self.normal.dot(&(p - self.origin))
    }
}

/// A unit vector perpendicular to `n`.
pub fn any_perpendicular(n: &Vector3<f64>) -> Vector3<f64> {
    let pick = if n.x.abs() < 0.6 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    (pick - n * n.dot(&pick)).normalize()
}

/// Twice the signed area of the triangle (a, b, c): positive counter-clockwise.
pub fn orient(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> f64 {
    (b - a).perp(&(c - a))
}

/// Signed area of a polygon (positive counter-clockwise).
pub fn area(poly: &[Point2<f64>]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|k| poly[k].coords.perp(&poly[(k + 1) % n].coords))
        .sum::<f64>()
        / 2.0
}

/// Whether `p` lies strictly inside the polygon (crossing number; a point on
/// the boundary may go either way).
pub fn contains(poly: &[Point2<f64>], p: &Point2<f64>) -> bool {
    let n = poly.len();
    let mut inside = false;
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Distance from `p` to the segment (a, b) and the parameter of the nearest
/// point (0 at a, 1 at b).
pub fn segment_distance(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> (f64, f64) {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p - (a + ab * s)).norm(), s)
}

/// Whether the closed segments (a, b) and (c, d) meet.
pub fn segments_meet(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>, d: &Point2<f64>) -> bool {
    let (d1, d2) = (orient(a, b, c), orient(a, b, d));
    let (d3, d4) = (orient(c, d, a), orient(c, d, b));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: &Point2<f64>, q: &Point2<f64>, r: &Point2<f64>, o: f64| {
        o == 0.0
            && r.x >= p.x.min(q.x)
            && r.x <= p.x.max(q.x)
            && r.y >= p.y.min(q.y)
            && r.y <= p.y.max(q.y)
    };
    on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4)
}

/// Whether two non-adjacent edges of the polygon meet (it is not simple).
/// Edge k runs from vertex k to vertex k + 1.
pub fn self_intersects(poly: &[Point2<f64>]) -> bool {
    let n = poly.len();
    for i in 0..n {
        for j in i + 1..n {
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if adjacent {
                continue;
            }
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let (c, d) = (poly[j], poly[(j + 1) % n]);
            if segments_meet(&a, &b, &c, &d) {
                return true;
            }
        }
    }
    false
}

/// Triangles (as index triples) covering a simple counter-clockwise polygon,
/// by ear clipping. A degenerate polygon may leave some area uncovered but
/// never panics.
pub fn triangulate(poly: &[Point2<f64>]) -> Vec<[usize; 3]> {
    let mut left: Vec<usize> = (0..poly.len()).collect();
    let mut out = Vec::with_capacity(poly.len().saturating_sub(2));
    let mut guard = 0;
    while left.len() > 3 && guard < 4 * poly.len() * poly.len() {
        guard += 1;
        let m = left.len();
        let mut clipped = false;
        for k in 0..m {
            let (ia, ib, ic) = (left[(k + m - 1) % m], left[k], left[(k + 1) % m]);
            let (a, b, c) = (poly[ia], poly[ib], poly[ic]);
            if orient(&a, &b, &c) <= 0.0 {
                continue;
            }
            let blocked = left.iter().any(|&i| {
                i != ia
                    && i != ib
                    && i != ic
                    && orient(&a, &b, &poly[i]) >= 0.0
                    && orient(&b, &c, &poly[i]) >= 0.0
                    && orient(&c, &a, &poly[i]) >= 0.0
            });
            if !blocked {
                out.push([ia, ib, ic]);
                left.remove(k);
                clipped = true;
                break;
            }
        }
        if !clipped {
            break;
        }
    }
    if left.len() == 3 {
        out.push([left[0], left[1], left[2]]);
    }
    out
}

/// The part of `subject` inside the convex counter-clockwise polygon `clip`
/// (Sutherland-Hodgman).
pub fn clip_convex(subject: &[Point2<f64>], clip: &[Point2<f64>]) -> Vec<Point2<f64>> {
    let mut out = subject.to_vec();
    let n = clip.len();
    for k in 0..n {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clip[k], clip[(k + 1) % n]);
        let input = std::mem::take(&mut out);
        let m = input.len();
        for i in 0..m {
            let (p, q) = (input[i], input[(i + 1) % m]);
            let (sp, sq) = (orient(&a, &b, &p), orient(&a, &b, &q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let s = sp / (sp - sq);
                out.push(p + (q - p) * s);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[(f64, f64)]) -> Vec<Point2<f64>> {
        v.iter().map(|&(x, y)| Point2::new(x, y)).collect()
    }

    #[test]
    fn concave_polygons_are_tested_and_triangulated_exactly() {
        // An L: 2 x 2 square without its upper-right unit square.
        let l = pts(&[
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]);
        assert!((area(&l) - 3.0).abs() < 1e-15);
        assert!(contains(&l, &Point2::new(0.5, 1.5)));
        assert!(!contains(&l, &Point2::new(1.5, 1.5)));
        let tris = triangulate(&l);
        assert_eq!(tris.len(), 4);
        let total: f64 = tris
            .iter()
            .map(|t| orient(&l[t[0]], &l[t[1]], &l[t[2]]) / 2.0)
            .sum();
        assert!((total - 3.0).abs() < 1e-15);
        assert!(!self_intersects(&l));
        let bow = pts(&[(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]);
        assert!(self_intersects(&bow));
    }

    #[test]
    fn clipping_keeps_the_common_part() {
        let square = pts(&[(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]);
        let shifted = pts(&[(1.0, 1.0), (3.0, 1.0), (3.0, 3.0), (1.0, 3.0)]);
        let common = clip_convex(&shifted, &square);
        assert!((area(&common) - 1.0).abs() < 1e-15);
        let far = pts(&[(5.0, 5.0), (6.0, 5.0), (6.0, 6.0)]);
        assert!(area(&clip_convex(&far, &square)).abs() < 1e-15);
    }
}
