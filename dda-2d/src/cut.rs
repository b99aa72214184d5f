//! Block cutting (Shi's DC step): a region cut into blocks by joint traces.
//!
//! The traces, clipped to the region, and the region's boundary form a line
//! arrangement. Every crossing is a node of a planar graph; edges that end in
//! a node of degree one (traces ending inside a block) are dropped, as are
//! edges with the same face on both sides and pieces of the graph no longer
//! joined to the boundary, since none of them separates two blocks. The
//! bounded faces of what is left are the blocks.
//!
//! Crossings are found with a tolerance of 1e-9 of the region's size: a
//! trace ending that close to another (or to the boundary) meets it there,
//! and nodes that close are one. Orientation tests use the exact predicate
//! of `dda_core::planar`, so a trace through a corner or along an edge is
//! classified alike from both sides.

use std::collections::HashMap;

use dda_core::planar::orient;
use nalgebra::{Point2, Vector2};

use crate::polygon::{self, PolygonError};

/// Tolerance as a fraction of the region's size (its bounding-box diagonal).
pub const SNAP: f64 = 1e-9;

/// At most this many blocks from one cut.
pub const MAX_BLOCKS: usize = 100_000;

/// A joint trace: a segment with the index of the set that made it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trace {
    pub a: Point2<f64>,
    pub b: Point2<f64>,
    pub set: usize,
}

/// Two blocks that share a joint: which set made the longest part of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SharedJoint {
    /// Block indices, lower first.
    pub blocks: (usize, usize),
    pub set: usize,
    /// Length shared, m.
    pub length: f64,
}

/// The blocks of a cut region and the joints between them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Cut {
    /// Counter-clockwise outlines, without corners on straight sides.
    pub blocks: Vec<Vec<Point2<f64>>>,
    pub joints: Vec<SharedJoint>,
    /// Blocks left out as slivers (below the smallest area).
    pub dropped: usize,
}

/// Why a region could not be cut.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CutError {
    #[error("the region is not a valid polygon: {0}")]
    Region(PolygonError),
    #[error("joint trace {0} has a coordinate that is not a finite number")]
    NotFinite(usize),
    #[error("the joints cut the region into more than {MAX_BLOCKS} blocks; use wider spacings or a smaller region")]
    TooMany,
    #[error("the joints make a block whose outline touches itself near ({x:.6}, {y:.6}); move the joints a little")]
    Pinched { x: f64, y: f64 },
}

fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Where two segments meet, as (parameter on the first, parameter on the
/// second, point): a crossing, or ends within `tol` of the other segment
/// (which also covers segments along each other).
fn meetings(
    (a1, b1): (Point2<f64>, Point2<f64>),
    (a2, b2): (Point2<f64>, Point2<f64>),
    tol: f64,
) -> Vec<(f64, f64, Point2<f64>)> {
    let (d1, d2) = (b1 - a1, b2 - a2);
    let mut out = Vec::new();
    let near = |p: &Point2<f64>, a: &Point2<f64>, d: Vector2<f64>| -> Option<f64> {
        let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        ((a + d * t - p).norm() <= tol).then_some(t)
    };
    for (t, p) in [(0.0, a1), (1.0, b1)] {
        if let Some(u) = near(&p, &a2, d2) {
            out.push((t, u, p));
        }
    }
    for (u, p) in [(0.0, a2), (1.0, b2)] {
        if let Some(t) = near(&p, &a1, d1) {
            out.push((t, u, p));
        }
    }
    // A proper crossing: the ends of each lie strictly on both sides of the other.
    let s1 = orient(&a1, &b1, &a2) * orient(&a1, &b1, &b2);
    let s2 = orient(&a2, &b2, &a1) * orient(&a2, &b2, &b1);
    if s1 < 0.0 && s2 < 0.0 {
        let w = a2 - a1;
        let den = cross(d1, d2);
        let t = (cross(w, d2) / den).clamp(0.0, 1.0);
        let u = (cross(w, d1) / den).clamp(0.0, 1.0);
        out.push((t, u, a1 + d1 * t));
    }
    out
}

/// The pairs of segments (i < j, in order) that may meet within `tol`:
/// those marking a common cell of a grid each segment is traced through,
/// so a long slanted trace marks the cells it passes rather than its box.
/// Within a cell, segments of one set (parallel joints) are paired only
/// when their spans across the set's direction come within `tol`, so
/// closely spaced joints are not all paired with each other.
fn candidates(segments: &[([Point2<f64>; 2], Option<usize>)], tol: f64) -> Vec<(usize, usize)> {
    if segments.is_empty() {
        return Vec::new();
    }
    let first = segments[0].0[0];
    let (lo, hi) = segments
        .iter()
        .flat_map(|(s, _)| s)
        .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    let mut lengths: Vec<f64> = segments.iter().map(|([a, b], _)| (b - a).norm()).collect();
    let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
    lengths.sort_by(f64::total_cmp);
    // About the typical segment; coarse enough that the segments mark
    // about 16 cells each on average and 8192 at most.
    let cell = lengths[lengths.len() / 2]
        .max(mean / 8.0)
        .max((hi - lo).max() / 4096.0)
        .max(4.0 * tol)
        .max(f64::MIN_POSITIVE);
    let index = |x: f64, o: f64| ((x - o) / cell).floor() as i64;
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let mut marked = Vec::new();
    for (i, ([a, b], _)) in segments.iter().enumerate() {
        let d = b - a;
        let steps = (d.abs().max() / (cell / 2.0)).ceil().clamp(1.0, 8192.0) as usize;
        marked.clear();
        for k in 0..steps {
            let p = a + d * (k as f64 / steps as f64);
            let q = a + d * ((k + 1) as f64 / steps as f64);
            let (x0, x1) = (
                index(p.x.min(q.x) - tol, lo.x),
                index(p.x.max(q.x) + tol, lo.x),
            );
            let (y0, y1) = (
                index(p.y.min(q.y) - tol, lo.y),
                index(p.y.max(q.y) + tol, lo.y),
            );
            for x in x0..=x1 {
                for y in y0..=y1 {
                    marked.push((x, y));
                }
            }
        }
        marked.sort_unstable();
        marked.dedup();
        for c in &marked {
            grid.entry(*c).or_default().push(i);
        }
    }
    let mut pairs = Vec::new();
    for list in grid.values_mut() {
        list.sort_by_key(|&i| (segments[i].1, i));
        let runs: Vec<&[usize]> = list
            .chunk_by(|&i, &j| segments[i].1 == segments[j].1)
            .collect();
        for (r, run) in runs.iter().enumerate() {
            for other in &runs[r + 1..] {
                for &i in *run {
                    pairs.extend(other.iter().map(|&j| (i.min(j), i.max(j))));
                }
            }
            // One set: sweep the spans across the first one's direction.
            let [a, b] = segments[run[0]].0;
            let normal = Vector2::new(a.y - b.y, b.x - a.x).normalize();
            let mut spans: Vec<(f64, f64, usize)> = run
                .iter()
                .map(|&i| {
                    let [p, q] = segments[i].0;
                    let (u, v) = (normal.dot(&p.coords), normal.dot(&q.coords));
                    (u.min(v), u.max(v), i)
                })
                .collect();
            spans.sort_by(|x, y| x.0.total_cmp(&y.0));
            for (k, &(_, end, i)) in spans.iter().enumerate() {
                for &(start, _, j) in &spans[k + 1..] {
                    // A NaN span (a direction that would not normalise) pairs
                    // with every later one: safe.
                    if start > end + tol {
                        break;
                    }
                    pairs.push((i.min(j), i.max(j)));
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// Nodes merged within a tolerance, found through a hash grid.
struct Nodes {
    points: Vec<Point2<f64>>,
    grid: HashMap<(i64, i64), Vec<usize>>,
    tol: f64,
}

impl Nodes {
    fn new(tol: f64) -> Self {
        Self {
            points: Vec::new(),
            grid: HashMap::new(),
            tol,
        }
    }

    fn cell(&self, p: &Point2<f64>) -> (i64, i64) {
        let h = 4.0 * self.tol;
        ((p.x / h).floor() as i64, (p.y / h).floor() as i64)
    }

    fn id(&mut self, p: Point2<f64>) -> usize {
        let (cx, cy) = self.cell(&p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &k in self.grid.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                    if (self.points[k] - p).norm() <= 2.0 * self.tol {
                        return k;
                    }
                }
            }
        }
        let k = self.points.len();
        self.points.push(p);
        self.grid.entry((cx, cy)).or_default().push(k);
        k
    }
}

/// The parts of a segment inside the region (counter-clockwise outline).
fn clip(a: Point2<f64>, b: Point2<f64>, region: &[Point2<f64>], tol: f64) -> Vec<[Point2<f64>; 2]> {
    let n = region.len();
    let mut ts = vec![0.0, 1.0];
    for i in 0..n {
        let edge = (region[i], region[(i + 1) % n]);
        ts.extend(meetings((a, b), edge, tol).iter().map(|m| m.0));
    }
    ts.sort_by(f64::total_cmp);
    let d = b - a;
    let min_t = tol / d.norm();
    let mut out: Vec<[Point2<f64>; 2]> = Vec::new();
    for w in ts.windows(2) {
        if w[1] - w[0] <= min_t {
            continue;
        }
        let mid = a + d * (0.5 * (w[0] + w[1]));
        if polygon::contains(region, &mid) {
            let (p, q) = (a + d * w[0], a + d * w[1]);
            match out.last_mut() {
                Some(last) if (last[1] - p).norm() <= tol => last[1] = q,
                _ => out.push([p, q]),
            }
        }
    }
    out
}

/// Cuts `region` (a simple polygon, either order) by the joint traces and
/// keeps the blocks of at least `min_area` (m²).
pub fn cut(region: &[Point2<f64>], traces: &[Trace], min_area: f64) -> Result<Cut, CutError> {
    let region = polygon::validate(region).map_err(CutError::Region)?;
    if let Some(k) = traces
        .iter()
        .position(|t| !(t.a.iter().chain(t.b.iter()).all(|v| v.is_finite())))
    {
        return Err(CutError::NotFinite(k));
    }
    let (lo, hi) = region
        .iter()
        .fold((region[0], region[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    let tol = SNAP * (hi - lo).norm();

    // Segments: the boundary (no set), then the traces' parts inside.
    let n = region.len();
    let mut segments: Vec<([Point2<f64>; 2], Option<usize>)> = (0..n)
        .map(|i| ([region[i], region[(i + 1) % n]], None))
        .collect();
    for t in traces {
        if (t.b - t.a).norm() > tol {
            for s in clip(t.a, t.b, &region, tol) {
                segments.push((s, Some(t.set)));
            }
        }
    }
    arrange(&segments, Some(0), tol, min_area)
}

/// Cuts the plane by the traces alone (Shi's DC step on a list of joint
/// lines, the rock mass being what they enclose): the blocks are the
/// closed faces of the traces once dangling ones are dropped.
pub fn cut_lines(traces: &[Trace], min_area: f64) -> Result<Cut, CutError> {
    if let Some(k) = traces
        .iter()
        .position(|t| !(t.a.iter().chain(t.b.iter()).all(|v| v.is_finite())))
    {
        return Err(CutError::NotFinite(k));
    }
    let Some(first) = traces.first() else {
        return Ok(Cut::default());
    };
    let (lo, hi) = traces.iter().fold((first.a, first.a), |(lo, hi), t| {
        (lo.inf(&t.a).inf(&t.b), hi.sup(&t.a).sup(&t.b))
    });
    let tol = SNAP * (hi - lo).norm();
    let segments: Vec<([Point2<f64>; 2], Option<usize>)> = traces
        .iter()
        .filter(|t| (t.b - t.a).norm() > tol)
        .map(|t| ([t.a, t.b], Some(t.set)))
        .collect();
    arrange(&segments, None, tol, min_area)
}

/// The blocks of an arrangement of segments (`None` for the region's
/// boundary); with a `root` node, only the part of the graph joined to it.
fn arrange(
    segments: &[([Point2<f64>; 2], Option<usize>)],
    root: Option<usize>,
    tol: f64,
    min_area: f64,
) -> Result<Cut, CutError> {
    // Split every segment where it meets another.
    let mut splits: Vec<Vec<(f64, Point2<f64>)>> = segments
        .iter()
        .map(|([a, b], _)| vec![(0.0, *a), (1.0, *b)])
        .collect();
    for (i, j) in candidates(segments, tol) {
        let ([a1, b1], [a2, b2]) = (segments[i].0, segments[j].0);
        for (t, u, p) in meetings((a1, b1), (a2, b2), tol) {
            splits[i].push((t, p));
            splits[j].push((u, p));
        }
    }
    let mut nodes = Nodes::new(tol);
    // Undirected edges (lower node first) and the set that made each; the
    // boundary wins over a trace along it, the lower set over a higher one.
    let mut edges: HashMap<(usize, usize), Option<usize>> = HashMap::new();
    for (split, (_, set)) in splits.iter_mut().zip(segments) {
        split.sort_by(|x, y| x.0.total_cmp(&y.0));
        let ids: Vec<usize> = split.iter().map(|(_, p)| nodes.id(*p)).collect();
        for w in ids.windows(2) {
            if w[0] != w[1] {
                let key = (w[0].min(w[1]), w[0].max(w[1]));
                let entry = edges.entry(key).or_insert(*set);
                *entry = match (*entry, *set) {
                    (None, _) | (_, None) => None,
                    (Some(x), Some(y)) => Some(x.min(y)),
                };
            }
        }
    }
    let points = nodes.points;
    let mut faces;
    loop {
        prune(&mut edges, root);
        faces = trace_faces(&points, &edges);
        let bridges: Vec<(usize, usize)> = faces
            .left
            .iter()
            .filter(|(&(u, v), f)| faces.left.get(&(v, u)) == Some(f))
            .map(|(&(u, v), _)| (u.min(v), u.max(v)))
            .collect();
        if bridges.is_empty() {
            break;
        }
        for e in bridges {
            edges.remove(&e);
        }
    }

    // Bounded faces are counter-clockwise; the outside is the one clockwise face.
    let mut index = vec![None; faces.cycles.len()];
    let mut out = Cut::default();
    for (f, cycle) in faces.cycles.iter().enumerate() {
        let outline: Vec<Point2<f64>> = cycle.iter().map(|&k| points[k]).collect();
        let area = polygon::signed_area(&outline);
        if area <= 0.0 {
            continue;
        }
        if area < min_area {
            out.dropped += 1;
            continue;
        }
        let mut seen = std::collections::HashSet::new();
        if let Some(&k) = cycle.iter().find(|k| !seen.insert(**k)) {
            let p = points[k];
            return Err(CutError::Pinched { x: p.x, y: p.y });
        }
        if out.blocks.len() == MAX_BLOCKS {
            return Err(CutError::TooMany);
        }
        index[f] = Some(out.blocks.len());
        out.blocks.push(straighten(outline, tol));
    }

    // Joints: edges between two kept blocks, by length per set.
    let mut shared: HashMap<(usize, usize), HashMap<usize, f64>> = HashMap::new();
    for (&(u, v), set) in &edges {
        let (Some(set), Some(&f), Some(&g)) =
            (set, faces.left.get(&(u, v)), faces.left.get(&(v, u)))
        else {
            continue;
        };
        if let (Some(a), Some(b)) = (index[f], index[g]) {
            let len = (points[v] - points[u]).norm();
            *shared
                .entry((a.min(b), a.max(b)))
                .or_default()
                .entry(*set)
                .or_default() += len;
        }
    }
    let mut joints: Vec<SharedJoint> = shared
        .into_iter()
        .map(|(blocks, sets)| {
            let length = sets.values().sum();
            let set = sets
                .into_iter()
                .max_by(|x, y| x.1.total_cmp(&y.1).then(y.0.cmp(&x.0)))
                .map_or(0, |(s, _)| s);
            SharedJoint {
                blocks,
                set,
                length,
            }
        })
        .collect();
    joints.sort_by_key(|j| j.blocks);
    out.joints = joints;
    Ok(out)
}

/// Drops nodes of degree one (again and again) and, with a `root`, every
/// piece of the graph not joined to it.
fn prune(edges: &mut HashMap<(usize, usize), Option<usize>>, root: Option<usize>) {
    loop {
        let mut adjacent: HashMap<usize, Vec<usize>> = HashMap::new();
        for &(u, v) in edges.keys() {
            adjacent.entry(u).or_default().push(v);
            adjacent.entry(v).or_default().push(u);
        }
        let mut joined: std::collections::HashSet<usize> = root.into_iter().collect();
        let mut stack: Vec<usize> = root.into_iter().collect();
        while let Some(u) = stack.pop() {
            for &v in adjacent.get(&u).into_iter().flatten() {
                if joined.insert(v) {
                    stack.push(v);
                }
            }
        }
        let before = edges.len();
        edges.retain(|&(u, v), _| {
            (root.is_none() || joined.contains(&u))
                && adjacent[&u].len() > 1
                && adjacent[&v].len() > 1
        });
        if edges.len() == before {
            return;
        }
    }
}

struct Faces {
    /// Each face's nodes, in order.
    cycles: Vec<Vec<usize>>,
    /// The face on the left of each directed edge.
    left: HashMap<(usize, usize), usize>,
}

/// Walks every face keeping it on the left: at each node, the next edge is
/// the first one clockwise from the way back.
fn trace_faces(points: &[Point2<f64>], edges: &HashMap<(usize, usize), Option<usize>>) -> Faces {
    let mut around: HashMap<usize, Vec<usize>> = HashMap::new();
    for &(u, v) in edges.keys() {
        around.entry(u).or_default().push(v);
        around.entry(v).or_default().push(u);
    }
    let angle = |u: usize, v: usize| {
        let d = points[v] - points[u];
        d.y.atan2(d.x)
    };
    for (&u, list) in around.iter_mut() {
        list.sort_by(|&a, &b| angle(u, a).total_cmp(&angle(u, b)).then(a.cmp(&b)));
    }
    let next = |u: usize, v: usize| -> usize {
        let list = &around[&v];
        let back = list.iter().position(|&w| w == u).unwrap_or(0);
        list[(back + list.len() - 1) % list.len()]
    };
    let mut directed: Vec<(usize, usize)> =
        edges.keys().flat_map(|&(u, v)| [(u, v), (v, u)]).collect();
    directed.sort_unstable();
    let mut faces = Faces {
        cycles: Vec::new(),
        left: HashMap::new(),
    };
    for start in directed {
        if faces.left.contains_key(&start) {
            continue;
        }
        let f = faces.cycles.len();
        let mut cycle = Vec::new();
        let mut e = start;
        while faces.left.insert(e, f).is_none() {
            cycle.push(e.0);
            e = (e.1, next(e.0, e.1));
        }
        faces.cycles.push(cycle);
    }
    faces
}

/// Drops corners on straight sides (within `tol` of the line through their
/// neighbours).
fn straighten(mut outline: Vec<Point2<f64>>, tol: f64) -> Vec<Point2<f64>> {
    let mut k = 0;
    while k < outline.len() && outline.len() > 3 {
        let n = outline.len();
        let (a, p, b) = (outline[(k + n - 1) % n], outline[k], outline[(k + 1) % n]);
        let d = b - a;
        if cross(d, p - a).abs() <= tol * d.norm() && (p - a).dot(&d) > 0.0 && (b - p).dot(&d) > 0.0
        {
            outline.remove(k);
            k = k.saturating_sub(1);
        } else {
            k += 1;
        }
    }
    outline
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2<f64> {
        Point2::new(x, y)
    }

    fn rect(w: f64, h: f64) -> Vec<Point2<f64>> {
        vec![p(0.0, 0.0), p(w, 0.0), p(w, h), p(0.0, h)]
    }

    fn trace(a: (f64, f64), b: (f64, f64), set: usize) -> Trace {
        Trace {
            a: p(a.0, a.1),
            b: p(b.0, b.1),
            set,
        }
    }

    fn total_area(cut: &Cut) -> f64 {
        cut.blocks.iter().map(|b| polygon::signed_area(b)).sum()
    }

    /// A 10 × 5 rectangle cut by persistent vertical and horizontal traces
    /// at spacing 1, the traces reaching past the region.
    #[test]
    fn two_orthogonal_sets_make_a_grid() {
        let mut traces = Vec::new();
        for k in 1..10 {
            traces.push(trace((k as f64, -1.0), (k as f64, 6.0), 0));
        }
        for k in 1..5 {
            traces.push(trace((-1.0, k as f64), (11.0, k as f64), 1));
        }
        let cut = cut(&rect(10.0, 5.0), &traces, 0.0).unwrap();
        assert_eq!(cut.blocks.len(), 50);
        assert!((total_area(&cut) - 50.0).abs() <= 1e-9 * 50.0);
        assert!(cut.blocks.iter().all(|b| b.len() == 4));
        // 9 × 5 vertical joints of set 0, 10 × 4 horizontal of set 1.
        assert_eq!(cut.joints.iter().filter(|j| j.set == 0).count(), 45);
        assert_eq!(cut.joints.iter().filter(|j| j.set == 1).count(), 40);
    }

    /// Traces ending inside a block leave it whole; two that cross and each
    /// reach the boundary cut off the corner between them.
    #[test]
    fn dangling_traces_do_not_cut() {
        let region = rect(4.0, 4.0);
        let dangling = [trace((-1.0, 2.0), (2.0, 2.0), 0)];
        assert_eq!(cut(&region, &dangling, 0.0).unwrap().blocks.len(), 1);
        let corner = [
            trace((-1.0, 2.0), (3.0, 2.0), 0),
            trace((2.0, 5.0), (2.0, 1.0), 1),
        ];
        let c = cut(&region, &corner, 0.0).unwrap();
        assert_eq!(c.blocks.len(), 2);
        let mut areas: Vec<f64> = c.blocks.iter().map(|b| polygon::signed_area(b)).collect();
        areas.sort_by(f64::total_cmp);
        assert!((areas[0] - 4.0).abs() < 1e-12 && (areas[1] - 12.0).abs() < 1e-12);
        // A joint between them is set 0 or 1, whichever is longer: 2 m of each.
        assert_eq!(c.joints.len(), 1);
        assert!((c.joints[0].length - 4.0).abs() < 1e-12);
    }

    /// Traces through corners, along edges, twice over the same line and
    /// parallel ones are handled.
    #[test]
    fn degenerate_traces() {
        let region = rect(2.0, 2.0);
        let traces = [
            trace((0.0, 0.0), (2.0, 2.0), 0),  // corner to corner
            trace((0.0, 0.0), (2.0, 2.0), 1),  // the same again
            trace((-1.0, 0.0), (3.0, 0.0), 0), // along the base
            trace((1.0, -1.0), (1.0, 3.0), 0), // through the diagonal's midpoint
            trace((1.5, 0.0), (1.5, 0.5), 0),  // dangling from the base
        ];
        let c = cut(&region, &traces, 0.0).unwrap();
        assert_eq!(c.blocks.len(), 4);
        assert!((total_area(&c) - 4.0).abs() <= 1e-9 * 4.0);
        assert!(c.blocks.iter().all(|b| polygon::validate(b).is_ok()));
    }

    #[test]
    fn a_concave_region_is_cut_in_its_parts() {
        // An L: a horizontal trace at y = 1.5 crosses only the upright.
        let region = vec![
            p(0.0, 0.0),
            p(3.0, 0.0),
            p(3.0, 1.0),
            p(1.0, 1.0),
            p(1.0, 3.0),
            p(0.0, 3.0),
        ];
        let c = cut(
            &region,
            &[
                trace((-1.0, 1.5), (4.0, 1.5), 0),
                trace((2.0, -1.0), (2.0, 4.0), 0),
            ],
            0.0,
        )
        .unwrap();
        assert_eq!(c.blocks.len(), 3);
        assert!((total_area(&c) - 5.0).abs() <= 1e-9 * 5.0);
    }

    #[test]
    fn slivers_are_dropped_and_bad_input_is_an_error() {
        let c = cut(
            &rect(1.0, 1.0),
            &[trace((-1.0, 1e-3), (2.0, 1e-3), 0)],
            1e-2,
        )
        .unwrap();
        assert_eq!((c.blocks.len(), c.dropped), (1, 1));
        assert!(matches!(
            cut(&rect(1.0, 0.0), &[], 0.0),
            Err(CutError::Region(_))
        ));
        let nan = [trace((f64::NAN, 0.0), (1.0, 1.0), 0)];
        assert_eq!(cut(&rect(1.0, 1.0), &nan, 0.0), Err(CutError::NotFinite(0)));
    }

    /// Joint lines alone: two squares sharing a side, drawn as overlapping
    /// lines with a dangling end, and a lone line elsewhere.
    #[test]
    fn lines_alone_enclose_blocks() {
        let traces = [
            trace((-0.01, 0.0), (2.01, 0.0), 0),
            trace((2.0, -0.01), (2.0, 1.0), 0),
            trace((2.0, 1.0), (0.0, 1.0), 0),
            trace((1.0, 1.0), (0.0, 1.0), 0), // along another
            trace((0.0, 1.01), (0.0, 0.0), 0),
            trace((1.0, 0.0), (1.0, 1.3), 1), // the shared side, overrunning
            trace((5.0, 5.0), (6.0, 6.0), 0),
        ];
        let c = cut_lines(&traces, 0.0).unwrap();
        assert_eq!(c.blocks.len(), 2);
        assert!((total_area(&c) - 2.0).abs() <= 1e-9 * 2.0);
        assert_eq!(c.joints.len(), 1);
        assert_eq!(c.joints[0].set, 1);
    }

    /// Traces between points of a coarse grid: many pass through each
    /// other's ends, the region's corners and crossings, or lie along each
    /// other and the boundary. The blocks always fill the region and are
    /// valid polygons; a block whose outline would touch itself is an error,
    /// never a wrong block.
    #[test]
    fn traces_on_a_grid_keep_the_area() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let region = vec![
            p(0.0, 0.0),
            p(4.0, 0.0),
            p(4.0, 3.0),
            p(2.0, 4.0),
            p(0.0, 3.0),
        ];
        let area = polygon::signed_area(&region);
        let (mut cuts, mut pinched) = (0, 0);
        for _ in 0..300 {
            let mut grid = || (next() * 12.0).floor() / 2.0 - 0.5;
            let traces: Vec<Trace> = (0..10)
                .map(|k| trace((grid(), grid()), (grid(), grid()), k % 3))
                .collect();
            match cut(&region, &traces, 0.0) {
                Ok(c) => {
                    cuts += 1;
                    let sum = total_area(&c);
                    assert!(
                        (sum - area).abs() <= 1e-9 * area,
                        "area {sum} of {area}: {traces:?}"
                    );
                    for b in &c.blocks {
                        assert!(polygon::validate(b).is_ok(), "{b:?} from {traces:?}");
                    }
                }
                Err(CutError::Pinched { .. }) => pinched += 1,
                Err(e) => panic!("{e} from {traces:?}"),
            }
        }
        println!("{cuts} cut, {pinched} with a block touching itself");
        assert!(cuts > 250, "{cuts} cut, {pinched} pinched");
    }

    /// Every pair of segments that meets is a candidate: random segments in
    /// sets of random directions, parallel families, pieces end to end.
    #[test]
    fn candidates_hold_every_meeting_pair() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..200 {
            let tol = 1e-9 * 10.0;
            let mut segments: Vec<([Point2<f64>; 2], Option<usize>)> = Vec::new();
            for set in 0..3 {
                let angle = next() * std::f64::consts::PI;
                let t = Vector2::new(angle.cos(), angle.sin());
                let n = Vector2::new(-t.y, t.x);
                let spacing = if case % 2 == 0 { 0.001 } else { next() };
                for k in 0..40 {
                    let c = (k as f64 - 20.0) * spacing;
                    let mut s = -5.0 + next();
                    while s < 5.0 {
                        let length = 2.0 * next();
                        let at = |s: f64| Point2::from(n * c + t * s);
                        segments.push(([at(s), at(s + length)], Some(set)));
                        // End to end, or a bridge.
                        s += length + if next() < 0.5 { 0.0 } else { next() };
                    }
                }
            }
            for _ in 0..10 {
                let mut p = || Point2::new(10.0 * next() - 5.0, 10.0 * next() - 5.0);
                segments.push(([p(), p()], None));
            }
            let found = candidates(&segments, tol);
            for i in 0..segments.len() {
                for j in i + 1..segments.len() {
                    let ([a1, b1], [a2, b2]) = (segments[i].0, segments[j].0);
                    if !meetings((a1, b1), (a2, b2), tol).is_empty() {
                        assert!(
                            found.binary_search(&(i, j)).is_ok(),
                            "{i}, {j} in case {case}"
                        );
                    }
                }
            }
        }
    }

    /// 10,000 traces 1 mm apart crossed by four joints: candidates are the
    /// crossings and the traces' neighbours along their line, not pairs of
    /// parallel traces.
    #[test]
    fn parallel_traces_are_not_paired() {
        let mut traces: Vec<Trace> = (0..10_000)
            .flat_map(|k| {
                let x = k as f64 * 0.001;
                [trace((x, 0.0), (x, 2.0), 0), trace((x, 2.5), (x, 4.5), 0)]
            })
            .collect();
        traces.extend((0..4).map(|k| trace((-1.0, k as f64), (11.0, k as f64), 1)));
        let segments: Vec<([Point2<f64>; 2], Option<usize>)> =
            traces.iter().map(|t| ([t.a, t.b], Some(t.set))).collect();
        let found = candidates(&segments, 1e-9 * 12.0);
        assert!(
            found.len() < 10 * segments.len(),
            "{} candidates",
            found.len()
        );
    }

    /// A loop of traces joined to the boundary by a single trace is not a
    /// block boundary there: only the loop's inside splits off if it closes.
    #[test]
    fn a_chain_to_a_closed_loop_is_dropped() {
        let region = rect(6.0, 6.0);
        let traces = [
            // A triangle in the middle, its sides overrunning the corners.
            trace((1.5, 2.0), (4.5, 2.0), 0),
            trace((2.0, 1.5), (3.25, 4.0 + 0.5 * 1.25 / 2.0), 0),
            trace((4.0, 1.5), (2.75, 4.0 + 0.5 * 1.25 / 2.0), 0),
            // A chain from the base to it.
            trace((3.0, -1.0), (3.0, 2.0), 1),
        ];
        let c = cut(&region, &traces, 0.0).unwrap();
        assert_eq!(c.blocks.len(), 1);
        assert!((total_area(&c) - 36.0).abs() < 1e-9 * 36.0);
    }
}
