//! Whether any two of a set of blocks overlap, in about N log N for any
//! shapes and either dimension; the dimension crates give the shapes'
//! corners, sides and exact overlap test (`dda_2d::polygon::first_overlap`,
//! `dda_3d::polyhedron::first_overlap`).
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

/// A plane: its unit normal and a point on it.
pub type Plane<const D: usize> = ([f64; D], [f64; D]);

/// An axis-aligned box: its lowest and highest corners.
pub type Bounds<const D: usize> = ([f64; D], [f64; D]);

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

/// The first overlapping pair (i, j), j < i, in the order of i then j,
/// and how many pairs were tested exactly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Found {
    pub first: Option<(usize, usize)>,
    pub tested: usize,
}

/// The first pair (i, j), j < i, in the order of i then j, that `overlap`
/// finds overlapping at a tolerance of 1e-6 of the model size, and how
/// many pairs it tested. `corners` gives each block's corners (the block
/// lies in their hull), `sides` the planes of its sides and `overlap`
/// whether two blocks overlap by more than a tolerance.
pub fn first_overlap<S, const D: usize>(
    shapes: &[S],
    corners: impl Fn(&S) -> Vec<[f64; D]>,
    sides: impl Fn(&S) -> Vec<Plane<D>>,
    overlap: impl Fn(&S, &S, f64) -> bool,
) -> Found {
    if shapes.len() < 2 {
        return Found {
            first: None,
            tested: 0,
        };
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
    Found {
        first: run.best,
        tested: run.tested,
    }
}

/// The smallest axis-aligned box holding the points.
pub fn bounds<const D: usize>(points: &[[f64; D]]) -> Bounds<D> {
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
