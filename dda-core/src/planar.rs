//! Planar polygons: the geometry a 2D block's outline and a 3D block's face
//! (in its own plane) have in common.
//!
//! A polygon is a slice of vertices, implicitly closed: edge `k` runs from
//! `v[k]` to `v[(k + 1) % n]`. Orientation signs come from `robust`'s
//! adaptive exact predicate, so the topological answers (is a corner convex,
//! do two segments touch, is a point on an edge) do not depend on rounding.

use nalgebra::Point2;

/// Twice the signed area of the triangle (a, b, c), positive
/// counter-clockwise. The sign is exact: `robust` refines the determinant
/// whenever rounding could have changed it.
pub fn orient(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> f64 {
    let coord = |p: &Point2<f64>| robust::Coord { x: p.x, y: p.y };
    robust::orient2d(coord(a), coord(b), coord(c))
}

/// Whether a polygon is convex and counter-clockwise: a positive area and
/// no corner turning clockwise (straight corners allowed), so
/// [`clip_convex`] and [`clipped_area`] may clip against it whole.
pub fn is_convex(poly: &[Point2<f64>]) -> bool {
    let m = poly.len();
    signed_area(poly) > 0.0
        && (0..m).all(|k| orient(&poly[(k + m - 1) % m], &poly[k], &poly[(k + 1) % m]) >= 0.0)
}

/// Signed area (positive counter-clockwise); zero below 3 vertices.
pub fn signed_area(poly: &[Point2<f64>]) -> f64 {
    // About the first vertex, not the global origin: far from the origin
    // the products would lose the digits that make up the area.
    let Some(o) = poly.first() else {
        return 0.0;
    };
    0.5 * edges(poly)
        .map(|(p, q)| (p - o).perp(&(q - o)))
        .sum::<f64>()
}

/// Whether `p` lies strictly inside the polygon (either orientation), by
/// winding number. Points on the boundary are not inside.
pub fn contains(poly: &[Point2<f64>], p: &Point2<f64>) -> bool {
    let mut winding = 0i64;
    for (a, b) in edges(poly) {
        let side = orient(a, b, p);
        if side == 0.0 && in_box(a, b, p) {
            return false;
        }
        // Upward crossings with p on the left count +1, downward ones with
        // p on the right −1.
        if a.y <= p.y {
            if b.y > p.y && side > 0.0 {
                winding += 1;
            }
        } else if b.y <= p.y && side < 0.0 {
            winding -= 1;
        }
    }
    winding != 0
}

/// Distance from `p` to the segment [a, b] and the parameter of the nearest
/// point (0 at a, 1 at b). A segment of zero length is the point a.
pub fn point_segment(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> (f64, f64) {
    let ab = b - a;
    let ap = p - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        (ap.dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((ap - ab * t).norm(), t)
}

/// Whether the closed segments [a, b] and [c, d] meet: they cross, touch,
/// or overlap along one line (a segment of zero length is a point).
pub fn segments_meet(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>, d: &Point2<f64>) -> bool {
    let (o1, o2) = (sign(orient(a, b, c)), sign(orient(a, b, d)));
    let (o3, o4) = (sign(orient(c, d, a)), sign(orient(c, d, b)));
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    // Otherwise only an end lying on the other segment; collinearity is
    // exact, so the box test is exact too.
    (o1 == 0 && in_box(a, b, c))
        || (o2 == 0 && in_box(a, b, d))
        || (o3 == 0 && in_box(c, d, a))
        || (o4 == 0 && in_box(c, d, b))
}

/// Whether two edges that do not share a vertex meet: the polygon is not
/// simple.
pub fn self_intersects(poly: &[Point2<f64>]) -> bool {
    let n = poly.len();
    (0..n).any(|i| {
        (i + 2..n).any(|j| {
            let adjacent = i == 0 && j == n - 1;
            let (a, b) = edge(poly, i);
            let (c, d) = edge(poly, j);
            !adjacent && segments_meet(a, b, c, d)
        })
    })
}

/// Ear clipping: counter-clockwise triangles, as index triples, covering a
/// simple polygon of either orientation. Each ear is the first convex
/// corner, in vertex order, whose triangle holds no other remaining vertex.
/// O(n³) at worst, fine for block outlines and faces. A polygon that is not
/// simple may leave area uncovered, but never panics.
pub fn triangulate(poly: &[Point2<f64>]) -> Vec<[usize; 3]> {
    let mut left: Vec<usize> = (0..poly.len()).collect();
    if signed_area(poly) < 0.0 {
        left.reverse();
    }
    let mut out = Vec::with_capacity(left.len().saturating_sub(2));
    while left.len() > 3 {
        let m = left.len();
        let Some(k) = (0..m).find(|&k| is_ear(poly, &left, k)) else {
            break;
        };
        out.push([left[(k + m - 1) % m], left[k], left[(k + 1) % m]]);
        left.remove(k);
    }
    if let [a, b, c] = left[..] {
        if orient(&poly[a], &poly[b], &poly[c]) > 0.0 {
            out.push([a, b, c]);
        }
    }
    out
}

/// Whether corner k of the remaining polygon `left` is strictly convex and
/// its triangle holds no other remaining vertex (on its sides counts).
fn is_ear(poly: &[Point2<f64>], left: &[usize], k: usize) -> bool {
    let m = left.len();
    let (ia, ib, ic) = (left[(k + m - 1) % m], left[k], left[(k + 1) % m]);
    let (a, b, c) = (&poly[ia], &poly[ib], &poly[ic]);
    orient(a, b, c) > 0.0
        && left.iter().all(|&i| {
            let p = &poly[i];
            i == ia
                || i == ib
                || i == ic
                || orient(a, b, p) < 0.0
                || orient(b, c, p) < 0.0
                || orient(c, a, p) < 0.0
        })
}

/// The part of `subject` inside the convex counter-clockwise polygon `clip`
/// (Sutherland–Hodgman). A concave subject is fine: the result may then
/// have edges running back along each other, which add no area.
pub fn clip_convex(subject: &[Point2<f64>], clip: &[Point2<f64>]) -> Vec<Point2<f64>> {
    // Two buffers passed back and forth.
    let mut out = subject.to_vec();
    let mut input = Vec::with_capacity(subject.len() + clip.len());
    for (a, b) in edges(clip) {
        if out.is_empty() {
            break;
        }
        std::mem::swap(&mut input, &mut out);
        out.clear();
        cut(&input, a, b, |p| out.push(p));
    }
    out
}

/// The most corners [`clipped_area`] and [`clip_on_stack`] clip on the
/// stack.
const SMALL: usize = 32;

/// `read` of [`clip_convex`]'s polygon, made between two arrays on the
/// stack; `None` where it might not fit (then clip on the heap). With
/// `convex_subject`, each cut adds at most one corner; a concave subject's
/// may grow by half at each.
pub fn clip_on_stack<R>(
    subject: &[Point2<f64>],
    clip: &[Point2<f64>],
    convex_subject: bool,
    read: impl FnOnce(&[Point2<f64>]) -> R,
) -> Option<R> {
    // A cut keeps at most the i vertices inside and adds one per crossing
    // edge, at most 2 min(i, n − i) and at most n: n grows at most to 3n/2.
    let room = if convex_subject {
        Some(subject.len() + clip.len()).filter(|&m| m <= SMALL)
    } else {
        (0..clip.len()).try_fold(subject.len(), |n, _| {
            Some(n + n / 2).filter(|&m| m <= SMALL)
        })
    };
    room?;
    let (mut a_buffer, mut b_buffer) = ([Point2::origin(); SMALL], [Point2::origin(); SMALL]);
    let (mut out, mut input) = (&mut a_buffer, &mut b_buffer);
    let mut n = subject.len();
    out[..n].copy_from_slice(subject);
    for (a, b) in edges(clip) {
        if n == 0 {
            break;
        }
        std::mem::swap(&mut input, &mut out);
        let kept = n;
        n = 0;
        cut(&input[..kept], a, b, |p| {
            out[n] = p;
            n += 1;
        });
    }
    Some(read(&out[..n]))
}

/// The signed area of [`clip_convex`]'s polygon. A small clip is made on
/// the stack ([`clip_on_stack`]): the 3D narrow phase weighs tens of
/// thousands of corners' shares of faces a step, each against a face of up
/// to five corners or a triangle.
pub fn clipped_area(subject: &[Point2<f64>], clip: &[Point2<f64>]) -> f64 {
    clip_on_stack(subject, clip, false, signed_area)
        .unwrap_or_else(|| signed_area(&clip_convex(subject, clip)))
}

/// The area of the convex polygon `poly` nearer the point `own` than any
/// of `sites` (those within `merge` of `own` are its own): half of a
/// rectangle between two sites at the ends of a side's midline, a quarter
/// of it among four at its corners.
pub fn site_cell_area(
    poly: &[Point2<f64>],
    own: &Point2<f64>,
    sites: &[Point2<f64>],
    merge: f64,
) -> f64 {
    if poly.len() > SMALL {
        return 0.0;
    }
    let (mut cell, mut input) = ([Point2::origin(); SMALL], [Point2::origin(); SMALL]);
    let mut m = poly.len();
    cell[..m].copy_from_slice(poly);
    // Cut by each other site's bisector, keeping the own site's side.
    for other in sites.iter().filter(|s| (*s - own).norm() > merge) {
        if m == 0 {
            break;
        }
        let (mid, away) = (nalgebra::center(own, other), own - other);
        let along = nalgebra::Vector2::new(away.y, -away.x);
        std::mem::swap(&mut cell, &mut input);
        let kept = m;
        m = 0;
        cut(&input[..kept], &mid, &(mid + along), |p| {
            if m < SMALL {
                cell[m] = p;
                m += 1;
            }
        });
    }
    signed_area(&cell[..m]).abs()
}

/// `read` of the corners of a polygon: its points, less those within
/// `merge` of the last kept (a clip repeats a point lying on a cut) and
/// those turning by less than the angle whose sine is `straight` (where a
/// side runs along a cut to round-off, a clip may leave a point anywhere
/// along it); `None` for a polygon of more than the stack's room.
pub fn corners_on_stack<R>(
    poly: &[Point2<f64>],
    merge: f64,
    straight: f64,
    read: impl FnOnce(&[Point2<f64>]) -> R,
) -> Option<R> {
    if poly.len() > SMALL {
        return None;
    }
    let mut corners = [Point2::origin(); SMALL];
    let mut m = 0;
    for p in poly {
        if m == 0 || (p - corners[m - 1]).norm() > merge {
            corners[m] = *p;
            m += 1;
        }
    }
    while m > 1 && (corners[m - 1] - corners[0]).norm() <= merge {
        m -= 1;
    }
    // Straight corners dropped until none is left: each drop may make its
    // neighbours' turns straight.
    let mut k = 0;
    while m >= 3 && k < m {
        let (prev, next) = (corners[(k + m - 1) % m], corners[(k + 1) % m]);
        let (a, b) = (corners[k] - prev, next - corners[k]);
        if a.perp(&b).abs() <= straight * a.norm() * b.norm() {
            corners.copy_within(k + 1..m, k);
            m -= 1;
            k = k.saturating_sub(1);
        } else {
            k += 1;
        }
    }
    Some(read(&corners[..m]))
}

/// One cut of [`clip_convex`]: the vertices of `input` on the left of the
/// line (a, b) or on it, and where its edges cross the line, in order.
fn cut(input: &[Point2<f64>], a: &Point2<f64>, b: &Point2<f64>, mut keep: impl FnMut(Point2<f64>)) {
    // Each vertex's side, found once: it is both an edge's start and the
    // previous edge's end.
    let first = orient(a, b, &input[0]);
    let mut sp = first;
    for (k, &p) in input.iter().enumerate() {
        let (q, sq) = match input.get(k + 1) {
            Some(q) => (*q, orient(a, b, q)),
            None => (input[0], first),
        };
        if sp >= 0.0 {
            keep(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            // Opposite signs: the denominator is not zero.
            keep(p + (q - p) * (sp / (sp - sq)));
        }
        sp = sq;
    }
}

/// The edges (v\[k\], v\[k + 1\]), closing back to the first vertex.
pub fn edges(poly: &[Point2<f64>]) -> impl Iterator<Item = (&Point2<f64>, &Point2<f64>)> {
    poly.iter().zip(poly.iter().cycle().skip(1))
}

/// The bounds of a polygon's corners: (lowest, highest) of each coordinate.
pub fn bounds(poly: &[Point2<f64>]) -> (Point2<f64>, Point2<f64>) {
    poly.iter().fold(
        (
            Point2::from([f64::INFINITY; 2]),
            Point2::from([f64::NEG_INFINITY; 2]),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

/// Whether two bounds overlap with room between them: bounds that only
/// touch or lie apart enclose no common area.
pub fn bounds_meet(
    (lo_a, hi_a): &(Point2<f64>, Point2<f64>),
    (lo_b, hi_b): &(Point2<f64>, Point2<f64>),
) -> bool {
    lo_a.x < hi_b.x && lo_b.x < hi_a.x && lo_a.y < hi_b.y && lo_b.y < hi_a.y
}

/// Edge k: (v\[k\], v\[k + 1\]).
pub fn edge(poly: &[Point2<f64>], k: usize) -> (&Point2<f64>, &Point2<f64>) {
    (&poly[k], &poly[(k + 1) % poly.len()])
}

/// Whether p, known to be on the line through a and b, lies on [a, b].
fn in_box(a: &Point2<f64>, b: &Point2<f64>, p: &Point2<f64>) -> bool {
    a.x.min(b.x) <= p.x && p.x <= a.x.max(b.x) && a.y.min(b.y) <= p.y && p.y <= a.y.max(b.y)
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(coords: &[(f64, f64)]) -> Vec<Point2<f64>> {
        coords.iter().map(|&(x, y)| Point2::new(x, y)).collect()
    }

    /// A convex polygon counter-clockwise is convex, with a straight corner
    /// too; clockwise, or with a reflex corner, or degenerate, it is not.
    #[test]
    fn convex_polygons_are_told_from_the_rest() {
        let square = pts(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
        assert!(is_convex(&square));
        let straight = pts(&[(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
        assert!(is_convex(&straight));
        let clockwise: Vec<_> = square.iter().rev().copied().collect();
        assert!(!is_convex(&clockwise));
        let dart = pts(&[(0.0, 0.0), (2.0, 1.0), (0.0, 2.0), (0.8, 1.0)]);
        assert!(!is_convex(&dart));
        assert!(!is_convex(&pts(&[(0.0, 0.0), (1.0, 0.0)])));
    }

    /// Bounds that only touch, or lie apart, do not meet: the polygons
    /// inside them share no area, which the clip confirms.
    #[test]
    fn bounds_meet_only_with_room_between_them() {
        let square = pts(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
        let (lo, hi) = bounds(&square);
        assert_eq!((lo, hi), (Point2::new(0.0, 0.0), Point2::new(1.0, 1.0)));
        let moved = |dx: f64, dy: f64| -> Vec<Point2<f64>> {
            square
                .iter()
                .map(|p| p + nalgebra::Vector2::new(dx, dy))
                .collect()
        };
        for (dx, dy, meet) in [
            (0.5, 0.5, true),
            (1.0, 0.0, false),
            (0.0, -1.0, false),
            (1.0, 1.0, false),
            (2.0, 0.3, false),
            (-0.999, 0.999, true),
        ] {
            let other = moved(dx, dy);
            let (a, b) = (bounds(&square), bounds(&other));
            assert_eq!(bounds_meet(&a, &b), meet, "{dx} {dy}");
            assert_eq!(bounds_meet(&b, &a), meet, "{dx} {dy}");
            assert_eq!(clipped_area(&other, &square) != 0.0, meet, "{dx} {dy}");
        }
    }

    fn shifted(poly: &[Point2<f64>], dx: f64, dy: f64) -> Vec<Point2<f64>> {
        poly.iter()
            .map(|p| Point2::new(p.x + dx, p.y + dy))
            .collect()
    }

    fn square(x: f64, y: f64, side: f64) -> Vec<Point2<f64>> {
        pts(&[(x, y), (x + side, y), (x + side, y + side), (x, y + side)])
    }

    /// A 2 × 2 square without its upper-right unit square: area 3, one
    /// reflex corner at (1, 1).
    fn l_shape() -> Vec<Point2<f64>> {
        pts(&[
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ])
    }

    fn naive(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> f64 {
        (b - a).perp(&(c - a))
    }

    #[test]
    fn orientation_is_exact_where_the_naive_determinant_is_not() {
        // Consecutive Fibonacci numbers: F(n+1)F(n−1) − F(n)² = ±1, while
        // the products exceed 2⁵³ and round.
        let mut fib = vec![0i128, 1];
        while fib.len() < 80 {
            let k = fib.len();
            fib.push(fib[k - 1] + fib[k - 2]);
        }
        let mut naive_wrong = 0;
        for n in 30..78 {
            let a = Point2::new(fib[n + 1] as f64, fib[n] as f64);
            let b = Point2::new(fib[n] as f64, fib[n - 1] as f64);
            let c = Point2::origin();
            // The exact determinant of the (possibly rounded) inputs.
            let exact = (a.x as i128 * b.y as i128 - a.y as i128 * b.x as i128).signum();
            assert_eq!(sign(orient(&a, &b, &c)) as i128, exact, "n = {n}");
            naive_wrong += usize::from(sign(naive(&c, &a, &b)) as i128 != exact);
        }
        assert!(
            naive_wrong > 0,
            "the case must defeat the naive determinant"
        );
    }

    #[test]
    fn orientation_of_nearly_collinear_points_far_from_the_origin() {
        // c on the line through a and b, and two units in the last place
        // off it on either side.
        let (a, b) = (
            Point2::new(1.0e6, 1.0e6),
            Point2::new(1.0e6 + 3.0, 1.0e6 + 3.0),
        );
        let c = Point2::new(1.0e6 + 1.0, 1.0e6 + 1.0);
        let step = f64::EPSILON * 1.0e6;
        assert_eq!(orient(&a, &b, &c), 0.0);
        assert!(orient(&a, &b, &Point2::new(c.x, c.y + step)) > 0.0);
        assert!(orient(&a, &b, &Point2::new(c.x, c.y - step)) < 0.0);
        // Shewchuk's example: points a few ulps from the line y = x near
        // (0.5, 0.5), against (12, 12) and (24, 24); every sign must agree
        // with the exact one, which is that of y − x.
        let ulp = 0.5 * f64::EPSILON;
        let (q, r) = (Point2::new(12.0, 12.0), Point2::new(24.0, 24.0));
        let mut naive_wrong = 0;
        for i in 0..64 {
            for j in 0..64 {
                let p = Point2::new(0.5 + i as f64 * ulp, 0.5 + j as f64 * ulp);
                let exact = (j as i64 - i as i64).signum() as i8;
                // (p, q, r) turns left when p is above the line.
                assert_eq!(sign(orient(&p, &q, &r)), exact, "i = {i}, j = {j}");
                naive_wrong += usize::from(sign(naive(&p, &q, &r)) != exact);
            }
        }
        assert!(
            naive_wrong > 0,
            "the case must defeat the naive determinant"
        );
    }

    #[test]
    fn areas_of_a_triangle_a_square_and_an_l() {
        assert_eq!(
            signed_area(&pts(&[(0.0, 0.0), (4.0, 0.0), (1.0, 3.0)])),
            6.0
        );
        assert_eq!(signed_area(&square(-1.0, 2.0, 2.0)), 4.0);
        assert_eq!(signed_area(&l_shape()), 3.0);
        let clockwise: Vec<_> = l_shape().into_iter().rev().collect();
        assert_eq!(signed_area(&clockwise), -3.0);
        // Far from the origin the area keeps its digits.
        assert_eq!(signed_area(&shifted(&l_shape(), 1.0e6, -2.0e6)), 3.0);
        assert_eq!(signed_area(&pts(&[(0.0, 0.0), (1.0, 1.0)])), 0.0);
        assert_eq!(signed_area(&[]), 0.0);
    }

    #[test]
    fn containment_in_a_concave_polygon() {
        let l = l_shape();
        let cw: Vec<_> = l.iter().rev().copied().collect();
        for poly in [&l, &cw] {
            assert!(contains(poly, &Point2::new(0.5, 1.5)));
            assert!(contains(poly, &Point2::new(1.5, 0.5)));
            // In the notch, outside, on an edge, at the reflex corner.
            assert!(!contains(poly, &Point2::new(1.5, 1.5)));
            assert!(!contains(poly, &Point2::new(-1.0, 0.5)));
            assert!(!contains(poly, &Point2::new(2.0, 0.5)));
            assert!(!contains(poly, &Point2::new(1.0, 1.0)));
        }
        // On a slanted edge far from the origin, and just inside it.
        let (x, y) = (1.0e6, -2.0e6);
        let tri = pts(&[(x, y), (x + 2.0, y + 1.0), (x, y + 3.0)]);
        assert!(!contains(&tri, &Point2::new(x + 1.0, y + 0.5)));
        assert!(contains(&tri, &Point2::new(x + 1.0, y + 0.5 + 1e-9)));
    }

    #[test]
    fn point_segment_distances() {
        let (a, b) = (Point2::new(0.0, 0.0), Point2::new(2.0, 0.0));
        assert_eq!(point_segment(&Point2::new(0.5, 1.0), &a, &b), (1.0, 0.25));
        // Beyond the ends the nearest point is the end.
        assert_eq!(point_segment(&Point2::new(5.0, 4.0), &a, &b), (5.0, 1.0));
        assert_eq!(point_segment(&Point2::new(-1.0, 0.0), &a, &b), (1.0, 0.0));
        // A segment of zero length is a point.
        assert_eq!(point_segment(&Point2::new(3.0, 4.0), &a, &a), (5.0, 0.0));
    }

    #[test]
    fn segments_meeting() {
        let meet = |a: (f64, f64), b: (f64, f64), c: (f64, f64), d: (f64, f64)| {
            let [a, b, c, d] = [a, b, c, d].map(|(x, y)| Point2::new(x, y));
            segments_meet(&a, &b, &c, &d)
        };
        // Crossing; parallel and apart.
        assert!(meet((0., 0.), (1., 1.), (0., 1.), (1., 0.)));
        assert!(!meet((0., 0.), (1., 0.), (0., 1.), (1., 1.)));
        // Along one line, overlapping and apart.
        assert!(meet((0., 0.), (2., 0.), (1., 0.), (3., 0.)));
        assert!(!meet((0., 0.), (1., 0.), (2., 0.), (3., 0.)));
        // A shared end, a T, a crossing only if extended.
        assert!(meet((0., 0.), (1., 0.), (1., 0.), (1., 1.)));
        assert!(meet((0., 0.), (2., 0.), (1., 0.), (1., 1.)));
        assert!(!meet((0., 0.), (1., 0.), (2., -1.), (2., 1.)));
        // A point on the segment, and off it.
        assert!(meet((0., 0.), (2., 2.), (1., 1.), (1., 1.)));
        assert!(!meet((0., 0.), (2., 2.), (1., 1.5), (1., 1.5)));
        // A T far from the origin, along a slanted line exact in binary.
        let (x, y) = (1.0e6, -2.0e6);
        assert!(meet(
            (x, y),
            (x + 2., y + 1.),
            (x + 1., y + 0.5),
            (x, y + 3.)
        ));
        let off = y + 0.5 + 1e-9;
        assert!(!meet((x, y), (x + 2., y + 1.), (x + 1., off), (x, y + 3.)));
    }

    #[test]
    fn polygons_that_cross_themselves() {
        assert!(!self_intersects(&l_shape()));
        assert!(self_intersects(&pts(&[
            (0., 0.),
            (1., 1.),
            (1., 0.),
            (0., 1.)
        ])));
        // A corner touching a side that does not end at it.
        let touching = pts(&[(0., 0.), (2., 0.), (1., 1.), (1., 0.), (0., 1.)]);
        assert!(self_intersects(&touching));
    }

    /// The L by hand: the first ear in vertex order is corner 1 (corner 0's
    /// triangle has the reflex corner on its side), then corners 2 and 0 of
    /// what is left, and the last three.
    #[test]
    fn ear_clipping_of_a_concave_polygon() {
        let l = l_shape();
        let tris = triangulate(&l);
        assert_eq!(tris, vec![[0, 1, 2], [0, 2, 3], [5, 0, 3], [3, 4, 5]]);
        let areas: Vec<f64> = tris
            .iter()
            .map(|t| orient(&l[t[0]], &l[t[1]], &l[t[2]]) / 2.0)
            .collect();
        assert_eq!(areas, vec![1.0, 0.5, 1.0, 0.5]);
        // Clockwise input gives the same counter-clockwise cover.
        let cw: Vec<_> = l.iter().rev().copied().collect();
        let cover: f64 = triangulate(&cw)
            .iter()
            .map(|t| orient(&cw[t[0]], &cw[t[1]], &cw[t[2]]) / 2.0)
            .sum();
        assert_eq!(cover, 3.0);
        let irregular = pts(&[(0.1, 0.2), (2.3, -0.4), (3.1, 1.7), (1.2, 0.9), (0.4, 2.6)]);
        let tris = triangulate(&irregular);
        assert_eq!(tris.len(), 3);
        let cover: f64 = tris
            .iter()
            .map(|t| signed_area(&t.map(|k| irregular[k])))
            .inspect(|&a| assert!(a > 0.0))
            .sum();
        assert!((cover - signed_area(&irregular)).abs() < 1e-14);
    }

    #[test]
    fn clipping_keeps_the_common_part() {
        let unit = square(0.0, 0.0, 2.0);
        // A square over another's corner: the unit square they share.
        let common = clip_convex(&square(1.0, 1.0, 2.0), &unit);
        assert_eq!(signed_area(&common), 1.0);
        // A square cut by a triangle along its diagonal: half of it.
        let half = pts(&[(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)]);
        assert_eq!(signed_area(&clip_convex(&unit, &half)), 2.0);
        // The L cut by the lower 2 × 1.5 strip: its bottom 2 × 1 and the
        // 1 × 0.5 of its upright above it.
        let strip = pts(&[(-1.0, -1.0), (3.0, -1.0), (3.0, 1.5), (-1.0, 1.5)]);
        assert_eq!(signed_area(&clip_convex(&l_shape(), &strip)), 2.5);
        // The L by a triangle through its reflex corner: the triangle's part
        // in the notch (area 0.5) is cut away, the rest (area 1.5) kept.
        let diagonal = pts(&[(0.0, 0.0), (2.0, 0.0), (2.0, 2.0)]);
        assert_eq!(signed_area(&clip_convex(&l_shape(), &diagonal)), 1.5);
        // Apart: nothing left.
        let far = pts(&[(5.0, 5.0), (6.0, 5.0), (6.0, 6.0)]);
        assert!(clip_convex(&far, &unit).is_empty());
    }

    #[test]
    fn a_sawtooth_cut_across_every_tooth_gives_half_again_its_vertices_on_and_off_the_stack() {
        // A block m − 1 wide whose top zigzags between heights 3 and 1 at
        // each unit, clipped by a wide triangle whose top side lies at
        // height 2: that side crosses every edge of the top, so the cut
        // keeps half the vertices and adds one per edge, nearly the 3n/2 a
        // cut can give (a convex subject gains at most one). With m = 4 the
        // clip is made on the stack, with 8 and 12 on the heap.
        let below = pts(&[(100.0, 2.0), (-100.0, 2.0), (0.0, -300.0)]);
        for m in [4usize, 8, 12] {
            let w = (m - 1) as f64;
            let mut saw = pts(&[(0.0, 0.0), (w, 0.0)]);
            saw.extend(
                (0..m).map(|j| Point2::new(w - j as f64, if j % 2 == 0 { 3.0 } else { 1.0 })),
            );
            assert!((signed_area(&saw) - 2.0 * w).abs() < 1e-12);
            let kept = clip_convex(&saw, &below);
            // Both base corners, the m / 2 low teeth and a crossing on each
            // of the m edges up to and along the top: more than n + 1.
            assert_eq!(kept.len(), 2 + m / 2 + m, "m = {m}");
            assert!(kept.len() > saw.len() + 1);
            // Each unit of the top loses the triangle above 2 (0.5 by 1).
            assert!((signed_area(&kept) - 1.75 * w).abs() < 1e-12, "m = {m}");
            assert_eq!(clipped_area(&saw, &below), signed_area(&kept));
        }
        // A face of many sides by another: on the heap, with no room to
        // reserve beforehand. Two regular 40-gons of radius 1, one turned by
        // half a side: their common part lies between the inscribed and the
        // circumscribed circle's areas.
        let gon = |turn: f64| -> Vec<Point2<f64>> {
            (0..40)
                .map(|k| {
                    let t = (k as f64 + turn) * std::f64::consts::TAU / 40.0;
                    Point2::new(t.cos(), t.sin())
                })
                .collect()
        };
        let common = clipped_area(&gon(0.0), &gon(0.5));
        assert!(common < signed_area(&gon(0.0)) && common > 0.99 * std::f64::consts::PI);
        // A quadrilateral by a triangle, on the stack: the same as on the heap.
        let share = pts(&[(0.2, 0.1), (1.3, 0.4), (1.1, 1.2), (0.1, 0.9)]);
        let triangle = pts(&[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]);
        let heap = signed_area(&clip_convex(&share, &triangle));
        assert!(heap > 0.0 && heap < 0.5);
        assert_eq!(clipped_area(&share, &triangle), heap);
    }

    /// A rectangle's cells about four sites at its corners are its
    /// quarters, whichever way round and with a clip's repeated corner;
    /// about two at a side's ends, its halves; a site repeated is one.
    #[test]
    fn sites_share_a_convex_polygon() {
        let rectangle = pts(&[(0.0, 0.0), (4.0, 0.0), (4.0, 1.0), (0.0, 1.0)]);
        let repeated = pts(&[(0.0, 0.0), (1e-15, 0.0), (4.0, 0.0), (4.0, 1.0), (0.0, 1.0)]);
        let reversed: Vec<_> = rectangle.iter().rev().copied().collect();
        for poly in [&rectangle, &repeated, &reversed] {
            let total: f64 = (rectangle.iter())
                .map(|own| site_cell_area(poly, own, &rectangle, 1e-9))
                .sum();
            assert!((total - 4.0).abs() < 1e-12, "{total}");
            for own in &rectangle {
                let quarter = site_cell_area(poly, own, &rectangle, 1e-9);
                assert!((quarter - 1.0).abs() < 1e-12, "{quarter}");
            }
            let ends = [rectangle[0], rectangle[3], rectangle[3]];
            let half = site_cell_area(poly, &ends[0], &ends, 1e-9);
            assert!((half - 2.0).abs() < 1e-12, "{half}");
        }
        // A clip's repeated point and one left along a side are no corners.
        let messy = pts(&[
            (0.0, 0.0),
            (1e-15, 0.0),
            (3.1, 1e-12),
            (4.0, 0.0),
            (4.0, 1.0),
            (0.0, 1.0),
        ]);
        let found = corners_on_stack(&messy, 1e-9, 1e-6, |c| c.to_vec()).unwrap();
        assert_eq!(found, rectangle);
    }
}
