//! Simple polygons: validation, area moments and the few geometric predicates
//! the 2D blocks need.
//!
//! A polygon is a slice of vertices, implicitly closed: edge `k` goes from
//! `v[k]` to `v[(k + 1) % n]`. After [`validate`] the vertices are
//! counter-clockwise, so the interior lies on the left of every edge.
//!
//! The routines a face of a 3D block needs too (area, containment, segments
//! meeting, ear clipping, clipping, the exact orientation predicate) are
//! `dda_core::planar`'s; the ones a 2D block or scene uses are re-exported
//! here.

use dda_core::overlap::Found;
use dda_core::planar::{clip_convex, edge, edges, segments_meet, triangulate};
pub use dda_core::planar::{contains, point_segment, signed_area};
use nalgebra::{Point2, Vector2};
use std::f64::consts::TAU;

/// Two vertices closer than this fraction of the polygon size coincide.
const DUPLICATE_EPS: f64 = 1.0e-12;
/// An area below this fraction of size² is zero.
const AREA_EPS: f64 = 1.0e-14;

/// Why a polygon was rejected, with what to do about it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolygonError {
    #[error("a polygon needs at least 3 vertices, this one has {0}; add vertices")]
    TooFewVertices(usize),
    /// `value` is the first coordinate that is not a finite number.
    #[error("vertex {index} is {value}, not a finite number; write finite coordinates")]
    NotFinite { index: usize, value: f64 },
    #[error("vertices {a} and {b} coincide; remove one of them")]
    DuplicateVertex { a: usize, b: usize },
    #[error("the polygon is self-intersecting (edges {a} and {b} cross each other); reorder its vertices so the boundary does not cross itself")]
    SelfIntersecting { a: usize, b: usize },
    #[error("the polygon has zero area (its vertices lie on one line); give vertices that enclose an area")]
    ZeroArea,
}

/// Area moments of a polygon about a chosen origin: S = ∫dA, Sx = ∫x dA, Sy = ∫y dA,
/// Sxx = ∫x² dA, Syy = ∫y² dA, Sxy = ∫xy dA (coordinates relative to the origin).
///
/// All are signed: a clockwise polygon gives the negated values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    pub area: f64,
    pub sx: f64,
    pub sy: f64,
    pub sxx: f64,
    pub syy: f64,
    pub sxy: f64,
}

/// Central second moments: ∫X² dA, ∫Y² dA, ∫XY dA with X = x − x0, Y = y − y0 about the centroid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentralMoments {
    pub area: f64,
    pub centroid: Point2<f64>,
    pub xx: f64,
    pub yy: f64,
    pub xy: f64,
}

/// Checks a simple polygon and returns its vertices in counter-clockwise order
/// (clockwise input is returned reversed).
///
/// Rejects, in this order: fewer than 3 vertices, NaN/inf, coincident vertices
/// (consecutive or not, within 1e-12 of the polygon size), vertices all on one
/// line (zero area), self-intersection (non-adjacent edges that cross or touch,
/// or adjacent edges that fold back onto each other), and a negligible area
/// (|area| ≤ 1e-14 size²). Edge indices in errors refer to the input order.
/// Concave polygons are fine. The check is O(n²).
pub fn validate(vertices: &[Point2<f64>]) -> Result<Vec<Point2<f64>>, PolygonError> {
    let n = vertices.len();
    if n < 3 {
        return Err(PolygonError::TooFewVertices(n));
    }
    if let Some(index) = vertices.iter().position(|v| !is_finite(v)) {
        let value = vertices[index].iter().copied().find(|x| !x.is_finite());
        return Err(PolygonError::NotFinite {
            index,
            value: value.unwrap_or_default(),
        });
    }

    let size = bbox_size(vertices);
    let eps_len = DUPLICATE_EPS * size;

    for a in 0..n {
        for b in (a + 1)..n {
            if (vertices[b] - vertices[a]).norm() <= eps_len {
                return Err(PolygonError::DuplicateVertex { a, b });
            }
        }
    }

    // A flat polygon always folds back somewhere; "zero area" is the useful message.
    if is_flat(vertices, size) {
        return Err(PolygonError::ZeroArea);
    }

    for i in 0..n {
        let (a0, a1) = edge(vertices, i);
        for j in (i + 1)..n {
            let (b0, b1) = edge(vertices, j);
            let hit = if j == i + 1 {
                // Shared vertex a1 == b0.
                folds_back(a0, a1, b1, eps_len)
            } else if i == 0 && j == n - 1 {
                // Shared vertex b1 == a0.
                folds_back(b0, b1, a1, eps_len)
            } else {
                // Near-touching counts too, with the same tolerance as coincident vertices.
                segments_meet(a0, a1, b0, b1) || segment_distance(a0, a1, b0, b1) <= eps_len
            };
            if hit {
                return Err(PolygonError::SelfIntersecting { a: i, b: j });
            }
        }
    }

    let area = signed_area(vertices);
    if area.abs() <= AREA_EPS * size * size {
        return Err(PolygonError::ZeroArea);
    }
    let mut out = vertices.to_vec();
    if area < 0.0 {
        out.reverse();
    }
    Ok(out)
}

/// Moments about `origin`, by summing signed triangles (origin, v_k, v_{k+1}).
///
/// With c_k = x_k y_{k+1} − x_{k+1} y_k in coordinates relative to origin:
/// S = ½Σc_k; Sx = ⅙Σc_k(x_k+x_{k+1}); Sy likewise; Sxx = (1/12)Σc_k(x_k² + x_k x_{k+1} + x_{k+1}²);
/// Syy likewise; Sxy = (1/24)Σc_k(2x_k y_k + x_k y_{k+1} + x_{k+1} y_k + 2x_{k+1} y_{k+1}).
pub fn moments_about(vertices: &[Point2<f64>], origin: &Point2<f64>) -> Moments {
    let mut m = Moments {
        area: 0.0,
        sx: 0.0,
        sy: 0.0,
        sxx: 0.0,
        syy: 0.0,
        sxy: 0.0,
    };
    for (p, q) in edges(vertices) {
        let (x0, y0) = (p.x - origin.x, p.y - origin.y);
        let (x1, y1) = (q.x - origin.x, q.y - origin.y);
        let c = x0 * y1 - x1 * y0;
        m.area += c;
        m.sx += c * (x0 + x1);
        m.sy += c * (y0 + y1);
        m.sxx += c * (x0 * x0 + x0 * x1 + x1 * x1);
        m.syy += c * (y0 * y0 + y0 * y1 + y1 * y1);
        m.sxy += c * (2.0 * x0 * y0 + x0 * y1 + x1 * y0 + 2.0 * x1 * y1);
    }
    m.area /= 2.0;
    m.sx /= 6.0;
    m.sy /= 6.0;
    m.sxx /= 12.0;
    m.syy /= 12.0;
    m.sxy /= 24.0;
    m
}

/// Central moments (signed like [`Moments`]: validate first for positive values).
///
/// The sums are taken about the bounding-box centre and shifted to the centroid
/// afterwards: about the global origin, polygons at 1e5–1e6 m would lose most
/// digits to cancellation. A zero-area polygon gets its bounding-box centre as
/// centroid.
pub fn central_moments(vertices: &[Point2<f64>]) -> CentralMoments {
    let origin = bbox_centre(vertices);
    let m = moments_about(vertices, &origin);
    if m.area == 0.0 {
        return CentralMoments {
            area: 0.0,
            centroid: origin,
            xx: m.sxx,
            yy: m.syy,
            xy: m.sxy,
        };
    }
    // Parallel-axis shift; the offset c is at most the polygon size, so little cancels.
    let c = Vector2::new(m.sx / m.area, m.sy / m.area);
    CentralMoments {
        area: m.area,
        centroid: origin + c,
        xx: m.sxx - m.area * c.x * c.x,
        yy: m.syy - m.area * c.y * c.y,
        xy: m.sxy - m.area * c.x * c.y,
    }
}

/// Interior angle at each vertex, in radians, in (0, 2π) for a counter-clockwise
/// polygon (> π at reflex vertices of concave polygons). Empty for fewer than 3 vertices.
pub fn interior_angles(vertices: &[Point2<f64>]) -> Vec<f64> {
    let n = vertices.len();
    if n < 3 {
        return Vec::new();
    }
    (0..n)
        .map(|k| {
            let cur = vertices[k];
            let to_next = vertices[(k + 1) % n] - cur;
            let to_prev = vertices[(k + n - 1) % n] - cur;
            // Sweeping counter-clockwise from the outgoing edge to the incoming one
            // crosses the interior of a CCW polygon.
            let angle = to_next.perp(&to_prev).atan2(to_next.dot(&to_prev));
            if angle < 0.0 {
                angle + TAU
            } else {
                angle
            }
        })
        .collect()
}

/// Whether two simple polygons overlap with positive area, beyond a tolerance
/// `tol` (a length: contact along a shared edge or at a vertex, or penetration
/// shallower than tol, is NOT overlap). Either orientation is accepted.
///
/// They overlap if any of:
/// 1. a vertex of one lies inside the other, deeper than `tol` from its boundary;
/// 2. two edges properly cross, each with its endpoints on opposite sides of the
///    other's line by more than `tol`;
/// 3. some point is inside both deeper than `tol` (this catches coincident or
///    nested polygons sharing boundaries, where 1 and 2 see only contacts). The
///    candidates are the centroids of the pairwise intersections of the two
///    ear-clipping triangulations, so an overlap is found when it is thicker
///    than about 3 tol.
///
/// `tol` is raised to at least 1e-12 of the pair's size to absorb rounding.
/// Polygons with fewer than 3 vertices or non-finite coordinates never overlap.
pub fn overlap(a: &[Point2<f64>], b: &[Point2<f64>], tol: f64) -> bool {
    if a.len() < 3 || b.len() < 3 || !a.iter().chain(b).all(is_finite) {
        return false;
    }
    let (a_min, a_max) = bbox(a);
    let (b_min, b_max) = bbox(b);
    if a_max.x < b_min.x || b_max.x < a_min.x || a_max.y < b_min.y || b_max.y < a_min.y {
        return false;
    }

    // Work about a common local origin, so far-away scenes keep their digits.
    let lo = a_min.inf(&b_min);
    let hi = a_max.sup(&b_max);
    let origin = nalgebra::center(&lo, &hi);
    let a: Vec<_> = a.iter().map(|p| Point2::from(p - origin)).collect();
    let b: Vec<_> = b.iter().map(|p| Point2::from(p - origin)).collect();
    // `max` also maps a NaN tol to the floor.
    let tol = tol.max(DUPLICATE_EPS * (hi - lo).norm());
    // A side of a convex polygon with the other wholly beyond it: apart. Cheap,
    // and it settles most pairs whose boxes meet (thin voussoirs side by side).
    if separated_by_a_side(&a, &b, tol) || separated_by_a_side(&b, &a, tol) {
        return false;
    }

    vertex_inside(&a, &b, tol)
        || vertex_inside(&b, &a, tol)
        || edges_cross(&a, &b, tol)
        || common_interior(&a, &b, tol)
}

/// The first pair of outlines (i, j), j < i, in the order of i then j, that
/// overlap by more than 1e-6 of the set's size, found in about N log N
/// ([`dda_core::overlap`]; a side of each outline is a plane that may split
/// the set); and how many pairs were tested.
pub fn first_overlap(outlines: &[Vec<Point2<f64>>]) -> Found {
    let corners = |o: &Vec<Point2<f64>>| o.iter().map(|p| [p.x, p.y]).collect();
    let sides = |o: &Vec<Point2<f64>>| {
        let n = o.len();
        (0..n)
            .filter_map(|k| {
                let (p, q) = (o[k], o[(k + 1) % n]);
                let along = (q - p).normalize();
                along
                    .iter()
                    .all(|c| c.is_finite())
                    .then_some(([-along.y, along.x], [p.x, p.y]))
            })
            .collect()
    };
    dda_core::overlap::first_overlap(outlines, corners, sides, |a, b, tol| overlap(a, b, tol))
}

/// Whether `a` is convex and `b` lies within `tol` of the far side of one of
/// its sides' lines (so the two overlap by no more than `tol`).
fn separated_by_a_side(a: &[Point2<f64>], b: &[Point2<f64>], tol: f64) -> bool {
    let n = a.len();
    let sign = signed_area(a).signum();
    let convex = (0..n).all(|i| {
        let (p, q, r) = (a[i], a[(i + 1) % n], a[(i + 2) % n]);
        sign * (q - p).perp(&(r - q)) >= 0.0
    });
    convex
        && (0..n).any(|i| {
            let (p, q) = (a[i], a[(i + 1) % n]);
            let edge = q - p;
            let length = edge.norm();
            // Outward distance of each of b's corners from the side's line.
            length > 0.0
                && b.iter()
                    .all(|v| -sign * edge.perp(&(v - p)) / length >= -tol)
        })
}

// ---------------------------------------------------------------------------
// Helpers.

fn is_finite(p: &Point2<f64>) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

/// Bounding box (min, max); the origin for an empty slice.
fn bbox(vertices: &[Point2<f64>]) -> (Point2<f64>, Point2<f64>) {
    let Some(first) = vertices.first() else {
        return (Point2::origin(), Point2::origin());
    };
    vertices
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
}

fn bbox_size(vertices: &[Point2<f64>]) -> f64 {
    let (lo, hi) = bbox(vertices);
    (hi - lo).norm()
}

fn bbox_centre(vertices: &[Point2<f64>]) -> Point2<f64> {
    let (lo, hi) = bbox(vertices);
    nalgebra::center(&lo, &hi)
}

/// Whether all vertices lie within a strip of negligible area along one line.
fn is_flat(vertices: &[Point2<f64>], size: f64) -> bool {
    let o = vertices[0];
    // The farthest vertex from the first one gives the best-conditioned direction.
    let far = vertices
        .iter()
        .map(|v| v - o)
        .fold(Vector2::zeros(), |best, d| {
            if d.norm_squared() > best.norm_squared() {
                d
            } else {
                best
            }
        });
    let len = far.norm();
    if len == 0.0 {
        return true;
    }
    let u = far / len;
    let width = vertices
        .iter()
        .map(|v| u.perp(&(v - o)).abs())
        .fold(0.0, f64::max);
    width <= AREA_EPS * size
}

/// Whether edges p→s and s→q fold back onto each other (overlap collinearly).
fn folds_back(p: &Point2<f64>, s: &Point2<f64>, q: &Point2<f64>, eps_len: f64) -> bool {
    let u = p - s;
    let w = q - s;
    if u.dot(&w) <= 0.0 {
        return false;
    }
    // They overlap when the shorter edge lies along the longer one.
    let (short_end, long_end) = if u.norm_squared() <= w.norm_squared() {
        (p, q)
    } else {
        (q, p)
    };
    point_segment(short_end, s, long_end).0 <= eps_len
}

/// Distance between two segments that do not intersect.
fn segment_distance(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>, d: &Point2<f64>) -> f64 {
    point_segment(a, c, d)
        .0
        .min(point_segment(b, c, d).0)
        .min(point_segment(c, a, b).0)
        .min(point_segment(d, a, b).0)
}

/// Distance from p to the polygon's boundary.
fn boundary_distance(vertices: &[Point2<f64>], p: &Point2<f64>) -> f64 {
    edges(vertices)
        .map(|(a, b)| point_segment(p, a, b).0)
        .fold(f64::INFINITY, f64::min)
}

/// How far `p` lies outside the polygon: 0 inside, or within a millionth
/// of the polygon's size of its boundary (a point written on a corner
/// keeps its round-off).
pub fn distance_outside(vertices: &[Point2<f64>], p: &Point2<f64>) -> f64 {
    let size = vertices
        .iter()
        .flat_map(|a| vertices.iter().map(move |b| (a - b).norm()))
        .fold(0.0, f64::max);
    let distance = boundary_distance(vertices, p);
    if contains(vertices, p) || distance <= 1e-6 * size {
        0.0
    } else {
        distance
    }
}

/// Whether p is inside `poly` deeper than `tol`.
fn deep_inside(poly: &[Point2<f64>], p: &Point2<f64>, tol: f64) -> bool {
    contains(poly, p) && boundary_distance(poly, p) > tol
}

fn vertex_inside(a: &[Point2<f64>], b: &[Point2<f64>], tol: f64) -> bool {
    a.iter().any(|v| deep_inside(b, v, tol))
}

/// Whether an edge of `a` and an edge of `b` cross with margin `tol` on all four endpoints.
fn edges_cross(a: &[Point2<f64>], b: &[Point2<f64>], tol: f64) -> bool {
    let opposite =
        |u: f64, v: f64, margin: f64| (u > margin && v < -margin) || (u < -margin && v > margin);
    edges(a).any(|(p, q)| {
        let pq = q - p;
        let margin_pq = tol * pq.norm();
        edges(b).any(|(r, s)| {
            let rs = s - r;
            // perp / |edge| is the signed distance to the edge's line.
            opposite(pq.perp(&(r - p)), pq.perp(&(s - p)), margin_pq)
                && opposite(rs.perp(&(p - r)), rs.perp(&(q - r)), tol * rs.norm())
        })
    })
}

/// Whether the centroid of some piece (triangle of a) ∩ (triangle of b) is deep inside both.
fn common_interior(a: &[Point2<f64>], b: &[Point2<f64>], tol: f64) -> bool {
    let corners = |p: &[Point2<f64>]| -> Vec<[Point2<f64>; 3]> {
        triangulate(p).iter().map(|t| t.map(|k| p[k])).collect()
    };
    let tris_b = corners(b);
    corners(a).iter().any(|ta| {
        tris_b.iter().any(|tb| {
            let piece = clip_convex(ta, tb);
            if piece.len() < 3 {
                return false;
            }
            let m = moments_about(&piece, &piece[0]);
            if m.area <= 0.0 {
                return false;
            }
            let c = piece[0] + Vector2::new(m.sx / m.area, m.sy / m.area);
            deep_inside(a, &c, tol) && deep_inside(b, &c, tol)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_outside_is_zero_inside_and_on_the_boundary() {
        let square =
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| Point2::new(x, y));
        assert_eq!(distance_outside(&square, &Point2::new(0.5, 0.5)), 0.0);
        assert_eq!(
            distance_outside(&square, &Point2::new(1.0, 1.0 + 1e-9)),
            0.0
        );
        assert!((distance_outside(&square, &Point2::new(2.0, 0.5)) - 1.0).abs() < 1e-15);
    }
    use approx::assert_relative_eq;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn pts(coords: &[(f64, f64)]) -> Vec<Point2<f64>> {
        coords.iter().map(|&(x, y)| Point2::new(x, y)).collect()
    }

    fn shifted(v: &[Point2<f64>], dx: f64, dy: f64) -> Vec<Point2<f64>> {
        v.iter().map(|p| p + Vector2::new(dx, dy)).collect()
    }

    /// Axis-aligned w×h rectangle with lower-left corner (x, y), CCW.
    fn rect(x: f64, y: f64, w: f64, h: f64) -> Vec<Point2<f64>> {
        pts(&[(x, y), (x + w, y), (x + w, y + h), (x, y + h)])
    }

    fn square(x: f64, y: f64) -> Vec<Point2<f64>> {
        rect(x, y, 1.0, 1.0)
    }

    /// The L of a 3×1 bar along x with a 1×1 block on its left end.
    fn l_shape() -> Vec<Point2<f64>> {
        pts(&[
            (0.0, 0.0),
            (3.0, 0.0),
            (3.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ])
    }

    fn assert_central(m: &CentralMoments, expected: &CentralMoments, rel: f64) {
        let scale = expected.area.abs().max(1e-300);
        assert_relative_eq!(m.area, expected.area, max_relative = rel);
        assert_relative_eq!(
            m.centroid,
            expected.centroid,
            epsilon = rel * scale.sqrt(),
            max_relative = rel
        );
        // Moments are compared relative to area · size², so that zero products of inertia work.
        let second = rel * (expected.xx.abs() + expected.yy.abs());
        assert_relative_eq!(m.xx, expected.xx, epsilon = second, max_relative = rel);
        assert_relative_eq!(m.yy, expected.yy, epsilon = second, max_relative = rel);
        assert_relative_eq!(m.xy, expected.xy, epsilon = second, max_relative = rel);
    }

    /// Closed form of a w×h rectangle centred at (cx, cy).
    fn rect_closed_form(w: f64, h: f64, cx: f64, cy: f64) -> CentralMoments {
        CentralMoments {
            area: w * h,
            centroid: Point2::new(cx, cy),
            xx: h * w.powi(3) / 12.0,
            yy: w * h.powi(3) / 12.0,
            xy: 0.0,
        }
    }

    #[test]
    fn square_and_rectangle_moments() {
        let sq = square(0.0, 0.0);
        assert_relative_eq!(signed_area(&sq), 1.0);
        assert_central(
            &central_moments(&sq),
            &rect_closed_form(1.0, 1.0, 0.5, 0.5),
            1e-12,
        );
        // About the corner: ∫x² = 1/3, ∫xy = 1/4.
        let m = moments_about(&sq, &Point2::origin());
        assert_relative_eq!(m.sx, 0.5, max_relative = 1e-12);
        assert_relative_eq!(m.sxx, 1.0 / 3.0, max_relative = 1e-12);
        assert_relative_eq!(m.syy, 1.0 / 3.0, max_relative = 1e-12);
        assert_relative_eq!(m.sxy, 0.25, max_relative = 1e-12);

        // 2 wide, 1 high: ∫X² = h b³/12 = 2/3, ∫Y² = b h³/12 = 1/6.
        let r = rect(3.0, -1.0, 2.0, 1.0);
        let cm = central_moments(&r);
        assert_central(&cm, &rect_closed_form(2.0, 1.0, 4.0, -0.5), 1e-12);
        assert_relative_eq!(cm.xx, 2.0 / 3.0, max_relative = 1e-12);
        assert_relative_eq!(cm.yy, 1.0 / 6.0, max_relative = 1e-12);
    }

    #[test]
    fn right_triangle_moments() {
        let (a, b) = (3.0, 2.0);
        let tri = pts(&[(0.0, 0.0), (a, 0.0), (0.0, b)]);
        // About the right-angle corner: ∫x² = b a³/12, ∫y² = a b³/12, ∫xy = a² b²/24.
        let m = moments_about(&tri, &Point2::origin());
        assert_relative_eq!(m.area, a * b / 2.0, max_relative = 1e-12);
        assert_relative_eq!(m.sx, a * a * b / 6.0, max_relative = 1e-12);
        assert_relative_eq!(m.sy, a * b * b / 6.0, max_relative = 1e-12);
        assert_relative_eq!(m.sxx, b * a.powi(3) / 12.0, max_relative = 1e-12);
        assert_relative_eq!(m.syy, a * b.powi(3) / 12.0, max_relative = 1e-12);
        assert_relative_eq!(m.sxy, a * a * b * b / 24.0, max_relative = 1e-12);
        // Centroidal: b a³/36, a b³/36 and −a² b²/72.
        let expected = CentralMoments {
            area: a * b / 2.0,
            centroid: Point2::new(a / 3.0, b / 3.0),
            xx: b * a.powi(3) / 36.0,
            yy: a * b.powi(3) / 36.0,
            xy: -a * a * b * b / 72.0,
        };
        assert_central(&central_moments(&tri), &expected, 1e-12);
    }

    #[test]
    fn l_shape_moments_by_parallel_axis() {
        // Two rectangles: 3×1 centred (1.5, 0.5) and 1×1 centred (0.5, 1.5).
        let parts = [
            rect_closed_form(3.0, 1.0, 1.5, 0.5),
            rect_closed_form(1.0, 1.0, 0.5, 1.5),
        ];
        let area: f64 = parts.iter().map(|p| p.area).sum();
        let cx = parts.iter().map(|p| p.area * p.centroid.x).sum::<f64>() / area;
        let cy = parts.iter().map(|p| p.area * p.centroid.y).sum::<f64>() / area;
        let (mut xx, mut yy, mut xy) = (0.0, 0.0, 0.0);
        for p in &parts {
            let (dx, dy) = (p.centroid.x - cx, p.centroid.y - cy);
            xx += p.xx + p.area * dx * dx;
            yy += p.yy + p.area * dy * dy;
            xy += p.xy + p.area * dx * dy;
        }
        let expected = CentralMoments {
            area,
            centroid: Point2::new(cx, cy),
            xx,
            yy,
            xy,
        };
        assert_relative_eq!(area, 4.0);
        assert_relative_eq!(expected.centroid, Point2::new(1.25, 0.75));
        assert_central(&central_moments(&l_shape()), &expected, 1e-12);
    }

    #[test]
    fn central_moments_are_translation_invariant() {
        let (dx, dy) = (1.0e6, -2.0e6);
        let irregular = pts(&[(0.1, 0.2), (2.3, -0.4), (3.1, 1.7), (1.2, 0.9), (0.4, 2.6)]);
        for poly in [l_shape(), irregular] {
            let near = central_moments(&poly);
            let far = central_moments(&shifted(&poly, dx, dy));
            let expected = CentralMoments {
                centroid: near.centroid + Vector2::new(dx, dy),
                ..near
            };
            assert_central(&far, &expected, 1e-9);
        }
    }

    #[test]
    fn clockwise_input_is_reversed() {
        let ccw = l_shape();
        let cw: Vec<_> = ccw.iter().rev().copied().collect();
        assert!(signed_area(&cw) < 0.0);
        let fixed = validate(&cw).unwrap();
        assert_eq!(fixed, ccw);
        assert_relative_eq!(signed_area(&fixed), signed_area(&ccw));
        assert_relative_eq!(signed_area(&fixed), 4.0);
        // CCW input comes back unchanged.
        assert_eq!(validate(&ccw).unwrap(), ccw);
    }

    #[test]
    fn validation_rejections() {
        use PolygonError::*;
        assert_eq!(
            validate(&pts(&[(0.0, 0.0), (1.0, 0.0)])),
            Err(TooFewVertices(2))
        );
        // NaN is not equal to itself, so the value is matched apart.
        assert!(matches!(
            validate(&pts(&[(0.0, 0.0), (1.0, f64::NAN), (0.0, 1.0)])),
            Err(NotFinite { index: 1, value }) if value.is_nan()
        ));
        assert_eq!(
            validate(&pts(&[(0.0, 0.0), (1.0, 0.0), (f64::INFINITY, 1.0)])),
            Err(NotFinite {
                index: 2,
                value: f64::INFINITY
            })
        );
        // Non-consecutive duplicate.
        assert_eq!(
            validate(&pts(&[
                (0.0, 0.0),
                (2.0, 0.0),
                (1.0, 1.0),
                (2.0, 2.0),
                (0.0, 2.0),
                (1.0, 1.0)
            ])),
            Err(DuplicateVertex { a: 2, b: 5 })
        );
        // Consecutive, within the relative tolerance.
        assert_eq!(
            validate(&pts(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1e-14), (0.0, 1.0)])),
            Err(DuplicateVertex { a: 1, b: 2 })
        );
        // Bow-tie: edges 0 and 2 cross.
        assert_eq!(
            validate(&pts(&[(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)])),
            Err(SelfIntersecting { a: 0, b: 2 })
        );
        assert_eq!(
            validate(&pts(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)])),
            Err(ZeroArea)
        );
        assert_eq!(
            validate(&pts(&[(0.0, 0.0), (2.0, 0.0), (1.0, 0.0), (3.0, 0.0)])),
            Err(ZeroArea)
        );
        // A spike that runs out along the bottom edge and back.
        let folded = pts(&[
            (0.0, 0.0),
            (2.0, 0.0),
            (3.0, 0.0),
            (2.5, 0.0),
            (2.0, 2.0),
            (0.0, 2.0),
        ]);
        assert!(matches!(validate(&folded), Err(SelfIntersecting { .. })));
        // A vertex touching a non-adjacent edge.
        let touching = pts(&[(0.0, 0.0), (2.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]);
        assert!(matches!(validate(&touching), Err(SelfIntersecting { .. })));
    }

    #[test]
    fn validation_accepts_concave_and_far_polygons() {
        assert!(validate(&l_shape()).is_ok());
        assert!(validate(&shifted(&l_shape(), 1.0e6, -2.0e6)).is_ok());
        // Collinear vertex on a straight edge is fine.
        assert!(validate(&pts(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (1.0, 1.0)])).is_ok());
    }

    #[test]
    fn interior_angles_of_square_and_l() {
        for angle in interior_angles(&square(0.0, 0.0)) {
            assert_relative_eq!(angle, FRAC_PI_2, max_relative = 1e-12);
        }
        let l = l_shape();
        let angles = interior_angles(&l);
        assert_eq!(angles.len(), 6);
        assert_relative_eq!(angles.iter().sum::<f64>(), 4.0 * PI, max_relative = 1e-12);
        let reflex: Vec<_> = angles.iter().filter(|&&a| a > PI).collect();
        assert_eq!(reflex.len(), 1);
        assert_relative_eq!(angles[3], 1.5 * PI, max_relative = 1e-12);

        let irregular = pts(&[(0.1, 0.2), (2.3, -0.4), (3.1, 1.7), (1.2, 0.9), (0.4, 2.6)]);
        let sum: f64 = interior_angles(&irregular).iter().sum();
        assert_relative_eq!(sum, 3.0 * PI, max_relative = 1e-12);
    }

    #[test]
    fn overlap_cases() {
        let a = square(0.0, 0.0);
        for tol in [0.0, 1e-4] {
            // Shared edge, shared corner: contact only.
            assert!(!overlap(&a, &square(1.0, 0.0), tol));
            assert!(!overlap(&a, &square(1.0, 1.0), tol));
            assert!(!overlap(&a, &square(0.3, 1.0), tol));
            // Shifted by half: overlap.
            assert!(overlap(&a, &square(0.5, 0.0), tol));
            assert!(overlap(&a, &square(0.5, 0.5), tol));
            // Identical, also far from the origin and concave.
            assert!(overlap(&a, &a, tol));
            let far = shifted(&l_shape(), 1.0e6, -2.0e6);
            assert!(overlap(&far, &far, tol));
            assert!(overlap(&l_shape(), &l_shape(), tol));
            // Nested, sharing three edges.
            assert!(overlap(&a, &rect(0.0, 0.0, 1.0, 2.0), tol));
            assert!(overlap(&rect(0.0, 0.0, 1.0, 2.0), &a, tol));
            // Wholly inside.
            assert!(overlap(&rect(-1.0, -1.0, 3.0, 3.0), &a, tol));
        }

        // In the notch of an L, touching nothing or touching both notch edges.
        let l = pts(&[
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]);
        assert!(!overlap(&l, &rect(1.25, 1.25, 0.5, 0.5), 0.0));
        assert!(!overlap(&l, &square(1.0, 1.0), 0.0));
        assert!(!overlap(&square(1.0, 1.0), &l, 1e-4));
        // A square pushed into the L's corner does overlap.
        assert!(overlap(&l, &square(0.5, 0.5), 1e-4));

        // Penetration of 1e-6 is within tol = 1e-4, but 1e-3 is not.
        assert!(!overlap(&a, &square(1.0 - 1e-6, 0.0), 1e-4));
        assert!(!overlap(&a, &square(1.0 - 1e-6, 0.3), 1e-4));
        assert!(!overlap(&a, &square(0.3, 1.0 - 1e-6), 1e-4));
        assert!(overlap(&a, &square(1.0 - 1e-3, 0.3), 1e-4));
        assert!(overlap(&a, &square(1.0 - 1e-6, 0.3), 0.0));

        // Clockwise input is accepted.
        let cw: Vec<_> = a.iter().rev().copied().collect();
        assert!(overlap(&cw, &cw, 0.0));
        assert!(!overlap(&cw, &square(1.0, 0.0), 0.0));
    }

    /// The side test only ever says "apart" where the full test does.
    #[test]
    fn a_separating_side_agrees_with_the_full_test() {
        let mut seed = 12345u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut apart = 0;
        for _ in 0..2000 {
            let polygon = |cx: f64, w: f64, h: f64, turn: f64| -> Vec<Point2<f64>> {
                let (s, c) = turn.sin_cos();
                [(-w, -h), (w, -h), (w, h), (-w, h)]
                    .iter()
                    .map(|&(x, y)| Point2::new(cx + c * x - s * y, s * x + c * y))
                    .collect()
            };
            let a = polygon(0.0, 0.05 + next(), 0.05 + next(), next() * 3.0);
            let b = polygon(next() * 2.0, 0.05 + next(), 0.05 + next(), next() * 3.0);
            let tol = 1e-9;
            if separated_by_a_side(&a, &b, tol) || separated_by_a_side(&b, &a, tol) {
                apart += 1;
                let full = vertex_inside(&a, &b, tol)
                    || vertex_inside(&b, &a, tol)
                    || edges_cross(&a, &b, tol)
                    || common_interior(&a, &b, tol);
                assert!(!full, "{a:?} and {b:?} overlap, yet a side separates them");
            }
        }
        assert!(apart > 200, "the case must be tried: {apart}");
    }
}
