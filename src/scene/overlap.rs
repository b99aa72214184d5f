//! Whether any two blocks overlap at the start, in about N log N for any
//! shapes.
//!
//! Bounding boxes alone do not do: the boxes of slanted slivers (the
//! voussoirs of a big arch) meet those of thousands of neighbours. The
//! blocks are instead split again and again by a plane, most often one of
//! their own sides, into those wholly on one side and those wholly on the
//! other (a block the plane cuts goes to both). A side of a sliver passes
//! between its neighbours, so a split costs one pass over its blocks and
//! halves them whatever their shapes; small sets are tested pair by pair.
//! Two blocks a plane separates overlap by no more than the tolerance.

use std::collections::HashMap;

use dda_2d::polygon;
use dda_3d::polyhedron::{self, Polyhedron};
use nalgebra::Point2;

/// A plane: its unit normal and a point on it.
type Plane<const D: usize> = ([f64; D], [f64; D]);

type Bounds<const D: usize> = ([f64; D], [f64; D]);

/// Sets this small are tested pair by pair.
const LEAF: usize = 16;
/// Blocks a split's plane is chosen on.
const SAMPLE: usize = 64;
/// Blocks whose sides are tried for a split.
const TRIED: usize = 5;
/// Sides of one block tried, at most.
const SIDES: usize = 8;
/// Planes tried on the whole set before a set is left to the grid.
const ATTEMPTS: usize = 3;

/// The first pair (i, j), j < i, in the order of i then j, of polygons
/// overlapping by more than 1e-6 of the model size.
pub(super) fn first_overlap_2d(outlines: &[Vec<Point2<f64>>]) -> Option<(usize, usize)> {
    search_2d(outlines).0
}

/// `first_overlap_2d` for polyhedra.
pub(super) fn first_overlap_3d(shapes: &[Polyhedron]) -> Option<(usize, usize)> {
    search_3d(shapes).0
}

/// The first overlap among polygons, and how many pairs were tested.
fn search_2d(outlines: &[Vec<Point2<f64>>]) -> (Option<(usize, usize)>, usize) {
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
    search(outlines, corners, sides, |a, b, tol| {
        polygon::overlap(a, b, tol)
    })
}

/// The first overlap among polyhedra, and how many pairs were tested.
fn search_3d(shapes: &[Polyhedron]) -> (Option<(usize, usize)>, usize) {
    let corners = |s: &Polyhedron| s.vertices().iter().map(|p| p.coords.into()).collect();
    let sides = |s: &Polyhedron| {
        (0..s.faces().len())
            .map(|f| {
                let point = s.vertices()[s.faces()[f][0]];
                (s.normal(f).into(), point.coords.into())
            })
            .collect()
    };
    search(shapes, corners, sides, polyhedron::overlap)
}

/// The first pair (i, j), j < i, in the order of i then j, that `overlap`
/// finds overlapping at a tolerance of 1e-6 of the model size, and how
/// many pairs it tested. `corners` gives each block's corners (the block
/// lies in their hull) and `sides` the planes of its sides.
fn search<S, const D: usize>(
    shapes: &[S],
    corners: impl Fn(&S) -> Vec<[f64; D]>,
    sides: impl Fn(&S) -> Vec<Plane<D>>,
    overlap: impl Fn(&S, &S, f64) -> bool,
) -> (Option<(usize, usize)>, usize) {
    if shapes.len() < 2 {
        return (None, 0);
    }
    let corners: Vec<Vec<[f64; D]>> = shapes.iter().map(corners).collect();
    let boxes: Vec<Bounds<D>> = corners.iter().map(|c| bounds(c)).collect();
    let (mut lo, mut hi) = boxes[0];
    for (l, h) in &boxes {
        for k in 0..D {
            lo[k] = lo[k].min(l[k]);
            hi[k] = hi[k].max(h[k]);
        }
    }
    let tol = 1e-6 * (0..D).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    let centres = corners
        .iter()
        .map(|c| {
            let mut m = [0.0; D];
            for p in c {
                for k in 0..D {
                    m[k] += p[k] / c.len() as f64;
                }
            }
            m
        })
        .collect();
    let mut run = Search {
        shapes,
        corners,
        boxes,
        centres,
        tol,
        sides,
        overlap,
        best: None,
        tested: 0,
        state: 0x9e37_79b9_7f4a_7c15,
    };
    let mut sets = vec![(0..shapes.len()).collect::<Vec<usize>>()];
    while let Some(set) = sets.pop() {
        if set.len() <= LEAF {
            run.pairs(&set);
        } else if let Some((a, b)) = run.split(&set) {
            sets.push(a);
            sets.push(b);
        } else {
            run.grid(&set);
        }
    }
    (run.best, run.tested)
}

fn bounds<const D: usize>(points: &[[f64; D]]) -> Bounds<D> {
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for p in points {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

struct Search<'a, S, F, G, const D: usize> {
    shapes: &'a [S],
    corners: Vec<Vec<[f64; D]>>,
    boxes: Vec<Bounds<D>>,
    centres: Vec<[f64; D]>,
    tol: f64,
    sides: F,
    overlap: G,
    /// The first overlapping pair found so far; later pairs are not tested.
    best: Option<(usize, usize)>,
    tested: usize,
    state: u64,
}

/// Where a block lies from a plane.
#[derive(Clone, Copy, PartialEq)]
enum Side {
    Front,
    Back,
    Both,
}

impl<S, F, G, const D: usize> Search<'_, S, F, G, D>
where
    F: Fn(&S) -> Vec<Plane<D>>,
    G: Fn(&S, &S, f64) -> bool,
{
    /// A pseudo-random index below n; fixed, so a scene is always checked
    /// the same way.
    fn random(&mut self, n: usize) -> usize {
        self.state ^= self.state << 13;
        self.state ^= self.state >> 7;
        self.state ^= self.state << 17;
        (self.state % n as u64) as usize
    }

    /// Whether (i, j) is to be tested: it comes before the best pair so far.
    fn wanted(&self, i: usize, j: usize) -> bool {
        self.best.is_none_or(|b| (i, j) < b)
    }

    /// Tests blocks i and j (j < i), keeping the pair if they overlap.
    fn test(&mut self, i: usize, j: usize) -> bool {
        let (a, b) = (&self.boxes[i], &self.boxes[j]);
        let tol = self.tol;
        let apart = (0..D).any(|k| b.0[k] > a.1[k] + tol || a.0[k] > b.1[k] + tol);
        self.tested += usize::from(!apart);
        let found = !apart && (self.overlap)(&self.shapes[j], &self.shapes[i], tol);
        if found {
            self.best = Some((i, j));
        }
        found
    }

    /// Every pair of an ascending set, in order, up to the first overlap.
    fn pairs(&mut self, set: &[usize]) {
        for (a, &i) in set.iter().enumerate() {
            for &j in &set[..a] {
                if !self.wanted(i, j) || self.test(i, j) {
                    return;
                }
            }
        }
    }

    fn side(&self, i: usize, (normal, point): &Plane<D>) -> Side {
        let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
        for c in &self.corners[i] {
            let d: f64 = (0..D).map(|k| normal[k] * (c[k] - point[k])).sum();
            min = min.min(d);
            max = max.max(d);
        }
        // Half the tolerance each way: blocks on two sides overlap by at
        // most the tolerance.
        let margin = self.tol / 2.0;
        match (min >= -margin, max <= margin) {
            (true, false) => Side::Front,
            (false, true) => Side::Back,
            _ => Side::Both,
        }
    }

    /// The planes a set may be split by: through the middle across each
    /// axis, and the sides of the middle block along the widest axis and
    /// of a few others.
    fn planes(&mut self, sample: &[usize]) -> Vec<Plane<D>> {
        let mut planes = Vec::new();
        let mut widest = (0, -1.0);
        for k in 0..D {
            let mut order = sample.to_vec();
            let mid = order.len() / 2;
            order.select_nth_unstable_by(mid, |&a, &b| {
                self.centres[a][k].total_cmp(&self.centres[b][k])
            });
            let (min, max) = order
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |m, &i| {
                    (m.0.min(self.centres[i][k]), m.1.max(self.centres[i][k]))
                });
            let middle = order[mid];
            if max - min > widest.1 {
                widest = (middle, max - min);
            }
            let mut normal = [0.0; D];
            normal[k] = 1.0;
            planes.push((normal, self.centres[middle]));
        }
        let mut blocks = vec![widest.0];
        blocks.extend((1..TRIED).map(|_| sample[self.random(sample.len())]));
        for b in blocks {
            let sides = (self.sides)(&self.shapes[b]);
            let stride = sides.len().div_ceil(SIDES).max(1);
            planes.extend(sides.into_iter().step_by(stride));
        }
        planes
    }

    /// Two smaller sets that hold every overlapping pair of `set`, if a
    /// plane divides it well.
    fn split(&mut self, set: &[usize]) -> Option<(Vec<usize>, Vec<usize>)> {
        let sample: Vec<usize> = if set.len() <= SAMPLE {
            set.to_vec()
        } else {
            (0..SAMPLE).map(|_| set[self.random(set.len())]).collect()
        };
        let planes = self.planes(&sample);
        // The larger part, plus the blocks that would go to both.
        let cost = |front: usize, back: usize, n: usize| front.max(back) + (front + back - n);
        let mut scored: Vec<(usize, usize)> = planes
            .iter()
            .enumerate()
            .map(|(p, plane)| {
                let (mut front, mut back) = (0, 0);
                for &i in &sample {
                    let side = self.side(i, plane);
                    front += usize::from(side != Side::Back);
                    back += usize::from(side != Side::Front);
                }
                (cost(front, back, sample.len()), p)
            })
            .collect();
        scored.sort_unstable();
        for &(_, p) in scored.iter().take(ATTEMPTS) {
            let (mut front, mut back) = (Vec::new(), Vec::new());
            for &i in set {
                let side = self.side(i, &planes[p]);
                if side != Side::Back {
                    front.push(i);
                }
                if side != Side::Front {
                    back.push(i);
                }
            }
            // Each part at most 7/8 of the set, and at most a quarter more
            // blocks in all: the sets shrink geometrically.
            let n = set.len();
            if 8 * front.len().max(back.len()) <= 7 * n && 4 * (front.len() + back.len()) <= 5 * n {
                return Some((front, back));
            }
        }
        None
    }

    /// A set no plane divides: candidates share a cell of a grid of about
    /// the median block's size.
    fn grid(&mut self, set: &[usize]) {
        let tol = self.tol;
        let lo: [f64; D] = std::array::from_fn(|k| {
            set.iter()
                .map(|&i| self.boxes[i].0[k])
                .fold(f64::INFINITY, f64::min)
        });
        let mut sizes: Vec<f64> = set
            .iter()
            .map(|&i| self.boxes[i].1[0] - self.boxes[i].0[0])
            .collect();
        sizes.sort_by(f64::total_cmp);
        let cell = sizes[sizes.len() / 2].max(tol).max(f64::MIN_POSITIVE);
        let index = |x: f64, k: usize| ((x - lo[k]) / cell).floor().clamp(0.0, 1e9) as i64;
        let mut grid: HashMap<[i64; D], Vec<usize>> = HashMap::new();
        // Blocks spanning many cells (a long base) are checked against all.
        let mut large: Vec<usize> = Vec::new();
        for (a, &i) in set.iter().enumerate() {
            let (l, h) = self.boxes[i];
            let first: [i64; D] = std::array::from_fn(|k| index(l[k] - tol, k));
            let last: [i64; D] = std::array::from_fn(|k| index(h[k] + tol, k));
            let spanned: i64 = (0..D).map(|k| last[k] - first[k] + 1).product();
            let mut candidates: Vec<usize> = large.clone();
            if spanned > 64 {
                candidates.extend(&set[..a]);
                large.push(i);
            } else {
                let mut at = first;
                'cells: loop {
                    let list = grid.entry(at).or_default();
                    candidates.extend(list.iter().copied());
                    list.push(i);
                    for k in 0..D {
                        if at[k] < last[k] {
                            at[k] += 1;
                            continue 'cells;
                        }
                        at[k] = first[k];
                    }
                    break;
                }
            }
            // A pair sharing several cells is tested once.
            candidates.sort_unstable();
            candidates.dedup();
            for j in candidates {
                if !self.wanted(i, j) || self.test(i, j) {
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use nalgebra::{Point3, Rotation3, Vector3};
    use proptest::prelude::*;

    use super::*;

    /// Every pair in order, the plain way: what the search must agree with.
    fn every_pair<S, const D: usize>(
        shapes: &[S],
        corners: impl Fn(&S) -> Vec<[f64; D]>,
        overlap: impl Fn(&S, &S, f64) -> bool,
    ) -> Option<(usize, usize)> {
        let boxes: Vec<Bounds<D>> = shapes.iter().map(|s| bounds(&corners(s))).collect();
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
            prop_assert_eq!(first_overlap_2d(&outlines), plain);
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
            prop_assert_eq!(first_overlap_3d(&shapes), plain);
        }
    }

    /// A voussoir 0.3 mm thick along the arc of a 10 m arch has a box
    /// meeting those of thousands of others; the search tests each
    /// voussoir against a few neighbours only.
    #[test]
    fn slivers_are_tested_against_a_few_neighbours() {
        let n = 100_000;
        let outlines = ring(n, [0.0, 0.0], (9.5, 10.5), (0.0, PI), None);
        let (first, tested) = search_2d(&outlines);
        assert_eq!(first, None);
        println!("2D: {tested} pairs tested for {n} slivers");
        assert!(tested < 20 * n, "{tested} pairs tested for {n} slivers");
        let n = 20_000;
        let shapes = prisms(
            &ring(n, [0.0, 0.0], (9.5, 10.5), (0.0, PI), None),
            (0.0, 1.0),
        );
        let (first, tested) = search_3d(&shapes);
        assert_eq!(first, None);
        println!("3D: {tested} pairs tested for {n} slivers");
        assert!(tested < 20 * n, "{tested} pairs tested for {n} slivers");
    }
}
