//! Narrow phase: contacts between two polyhedra, linearised about the start
//! of the step with the normal held fixed (A9.5, A9.6).
//!
//! Two mechanical entrance types are assembled:
//!
//! * vertex-face (VF): a convex vertex enters a face's plane. Its edges must
//!   all point to the outer side of the plane (within 3°).
//! * edge-edge (EE): two convex edges cross. The normal ±(e_a × e_b) is
//!   oriented so each block's wedge lies on its own side of the contact plane
//!   (within 3°), pointing from block b to block a.
//!
//! A contact is one of:
//!
//! * **VF**: a convex vertex over the inside of a face, farther than the
//!   range from the face's convex corners and edges. Next to a reflex edge
//!   of the face the projection may fall outside the face by up to the range
//!   (the material continues there), so a vertex in a reflex crease makes a
//!   VF contact with each face of the crease.
//! * **Vertex-edge group**: a convex vertex near the inside of a convex (or
//!   flat) edge. Entrances: the planes of the edge's two faces and the EE
//!   crossings of the vertex's edges with that edge.
//! * **Vertex-vertex group**: two convex vertices within range. Entrances:
//!   the planes of every face at either vertex and the EE crossings of every
//!   pair of their edges.
//! * **EE**: two convex edges whose closest points lie inside both, with no
//!   convex end of either within range of the other.
//!
//! In a group the driver uses the entrance with the largest gap at each pass
//! (Shi's entrance choice). For two convex corners this is the
//! separating-axis distance: the gap along each face normal and edge-pair
//! cross product whose plane separates the two corners, largest first.
//! An entrance that is one already found, to within round-off (the same
//! plane through the same points, from either block), is kept once: where
//! blocks meet square, as bricks in a bond do, a crossing lies in a face's
//! plane, and a wall's groups would otherwise read each entrance twice at
//! every decision.
//! Face-face contacts thus become VF contacts at the corners of each face
//! lying over the other plus EE contacts where their boundary edges cross;
//! edge-face contacts become VF (or groups) at the ends plus EE where the edge
//! crosses the face's boundary.
//!
//! Area (the contact's `length`, used by cohesion and tensile strength):
//! each corner of two faces' overlap, a vertex over a face or edges
//! crossing, stands for its own part of it (`area.rs`), so a joint is
//! covered once however its blocks overlap.
//!
//! Keys, stable from step to step: VF (vertex block, vertex, face block,
//! face); vertex-edge group (…, vertex, …, edge | EDGE); vertex-vertex group
//! (…, vertex, …, vertex | VERTEX); EE (block, edge | EDGE, block, edge).
//! Edge ids index [`Polyhedron::edges`] (sorted by end vertices).
//!
//! Non-convex blocks: reflex edges never enter or get entered by EE, and
//! non-convex vertices never enter; a convex vertex near a non-convex one
//! makes ordinary VF and vertex-edge contacts with the faces and edges there.
//! Concave faces are handled by point-in-polygon tests and ear-clipped
//! triangles.

use dda_core::block_set::{Reach, ANGLE_TOLERANCE, PENETRATION_SHARE};
#[cfg(test)]
use dda_core::contacts::same_contacts;
use dda_core::planar;
use dda_core::{Contact, ContactKey};
use nalgebra::{Point3, Vector3};

use crate::area::{crossing_area, vertex_areas};
use crate::block::Block;
use crate::entrance::PointEntrance;
use crate::polyhedron::{EdgeKind, Polyhedron};

/// A 3D contact: 12 DOF per block, two tangential directions.
pub type Contact3 = Contact<12, 2, PointEntrance>;

/// A pair of features of blocks (a, b) that may touch; a side of 0 puts
/// the vertex on a, 1 on b.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// Vertex of a, vertex of b.
    VertexVertex(u32, u32),
    /// Side, vertex, the other block's edge.
    VertexEdge(u8, u32, u32),
    /// Side, vertex, the other block's face.
    VertexFace(u8, u32, u32),
    /// Edge of a, edge of b.
    EdgeEdge(u32, u32),
}

/// Marks a feature as a vertex (`feature_b` of a vertex-vertex group).
const VERTEX: u32 = 1 << 31;
/// Marks a feature as an edge (`feature_b` of a vertex-edge group, both
/// features of an edge-edge contact's `feature_a`).
const EDGE: u32 = 1 << 30;

fn sin_tol() -> f64 {
    ANGLE_TOLERANCE.sin()
}

/// Contacts between blocks `i` and `j` within `range`, with law index `law`.
pub fn pair_contacts(
    blocks: &[Block],
    i: usize,
    j: usize,
    range: f64,
    law: usize,
) -> Vec<Contact3> {
    let (a, b) = (&blocks[i], &blocks[j]);
    pair_contacts_near(
        blocks,
        i,
        j,
        range,
        law,
        Reach::new(a.shape().bounds(), range),
        Reach::new(b.shape().bounds(), range),
    )
}

/// [`pair_contacts`] among `features` (see [`contacts_among`]).
pub fn pair_contacts_among(
    blocks: &[Block],
    i: usize,
    j: usize,
    range: f64,
    law: usize,
    features: &[Feature],
) -> Vec<Contact3> {
    let near = |b: &Block| Reach::new(b.shape().bounds(), range);
    let (near_a, near_b) = (near(&blocks[i]), near(&blocks[j]));
    contacts_among(blocks, i, j, range, law, (&near_a, &near_b), features)
}

/// [`pair_contacts`], examining only the features of block `i` within
/// `near_b`, the reach of block `j`, and those of `j` within `near_a`.
fn pair_contacts_near(
    blocks: &[Block],
    i: usize,
    j: usize,
    range: f64,
    law: usize,
    near_a: Reach<3>,
    near_b: Reach<3>,
) -> Vec<Contact3> {
    let (a, b) = (&blocks[i], &blocks[j]);
    let (sa, sb) = (a.shape(), b.shape());
    let mut pair = Pair::new(blocks, i, j, range, law, (&near_a, &near_b));
    // Every feature in the narrow phase's order, each ruled out by the
    // first of its tests it fails, cheapest first; `Pair::test` makes them
    // all again, as the features of a kept list need (`features.rs`).
    for (p, pv) in sa.vertices().iter().enumerate() {
        if !sa.is_convex_vertex(p) || !near_b.holds(pv) {
            continue;
        }
        for (q, qv) in sb.vertices().iter().enumerate() {
            if (pv - qv).norm() < range && sb.is_convex_vertex(q) {
                pair.test(Feature::VertexVertex(p as u32, q as u32));
            }
        }
    }
    // Each block's edges that can take part (not reflex) within the other's
    // reach, with their bounds grown by the range: a vertex or an edge
    // outside those bounds is farther from the edge than the range.
    let near_a_edges = edges_within(sa, &near_b, range);
    let near_b_edges = edges_within(sb, &near_a, range);
    for (side, (sx, sy, near_y, edges_y)) in [
        (sa, sb, &near_b, &near_b_edges),
        (sb, sa, &near_a, &near_a_edges),
    ]
    .into_iter()
    .enumerate()
    {
        for (p, pv) in sx.vertices().iter().enumerate() {
            if !sx.is_convex_vertex(p) || !near_y.holds(pv) {
                continue;
            }
            for &(e, bounds) in edges_y {
                let edge = &sy.edges()[e];
                if within(&bounds, pv) && !near_convex_end(sy, edge.ends, pv, range) {
                    pair.test(Feature::VertexEdge(side as u8, p as u32, e as u32));
                }
            }
            for f in 0..sy.faces().len() {
                pair.test(Feature::VertexFace(side as u8, p as u32, f as u32));
            }
        }
    }
    let convex = |s: &Polyhedron, (e, _): &&(usize, Bounds)| s.edge_kind(*e) == EdgeKind::Convex;
    for &(ea, bounds_a) in near_a_edges.iter().filter(|n| convex(sa, n)) {
        for &(eb, bounds_b) in near_b_edges.iter().filter(|n| convex(sb, n)) {
            if !apart(&bounds_a, &bounds_b) {
                pair.test(Feature::EdgeEdge(ea as u32, eb as u32));
            }
        }
    }
    pair.found
}

/// The edges of `s` that are not reflex and whose bounds meet `reach`,
/// each with its bounds grown by `range` (min, max).
fn edges_within(s: &Polyhedron, reach: &Reach<3>, range: f64) -> Vec<(usize, Bounds)> {
    (s.edges().iter().enumerate())
        .filter_map(|(e, edge)| {
            let [u, v] = edge.ends.map(|k| s.vertices()[k]);
            (s.edge_kind(e) != EdgeKind::Reflex && reach.meets(&u, &v))
                .then(|| (e, grown_bounds(&u, &v, range)))
        })
        .collect()
}

/// The contacts between blocks `i` and `j` within `range` that `features`
/// make, in their order: each feature is tested as the search would test
/// it at this range, so the features `features::pair_features` found at a
/// wider range make, while they serve, the contacts a search would find,
/// the same to the last bit and in the same order.
pub(crate) fn contacts_among(
    blocks: &[Block],
    i: usize,
    j: usize,
    range: f64,
    law: usize,
    near: (&Reach<3>, &Reach<3>),
    features: &[Feature],
) -> Vec<Contact3> {
    let mut pair = Pair::new(blocks, i, j, range, law, near);
    for &feature in features {
        pair.test(feature);
    }
    pair.found
}

/// Contacts of blocks `i` and `j` within `range`, found feature by feature.
struct Pair<'a> {
    blocks: &'a [Block],
    i: usize,
    j: usize,
    range: f64,
    law: usize,
    near_a: &'a Reach<3>,
    near_b: &'a Reach<3>,
    /// A group's entrances, found here and then moved to a vector of their
    /// own, exactly as long: one allocation a group, none for the misses.
    group: Vec<PointEntrance>,
    found: Vec<Contact3>,
}

impl<'a> Pair<'a> {
    fn new(
        blocks: &'a [Block],
        i: usize,
        j: usize,
        range: f64,
        law: usize,
        (near_a, near_b): (&'a Reach<3>, &'a Reach<3>),
    ) -> Self {
        Self {
            blocks,
            i,
            j,
            range,
            law,
            near_a,
            near_b,
            group: Vec::new(),
            found: Vec::new(),
        }
    }

    /// Adds the contact `feature` makes at the range, if it makes one.
    fn test(&mut self, feature: Feature) {
        let (i, j, range, law) = (self.i, self.j, self.range, self.law);
        let (near_a, near_b) = (self.near_a, self.near_b);
        let (a, b) = (&self.blocks[i], &self.blocks[j]);
        let (sa, sb) = (a.shape(), b.shape());
        let (out, group) = (&mut self.found, &mut self.group);
        match feature {
            // Vertex-vertex groups between convex corners.
            Feature::VertexVertex(p, q) => {
                let (p, q) = (p as usize, q as usize);
                let (pv, qv) = (&sa.vertices()[p], &sb.vertices()[q]);
                if !sa.is_convex_vertex(p)
                    || !near_b.holds(pv)
                    || (pv - qv).norm() >= range
                    || !sb.is_convex_vertex(q)
                {
                    return;
                }
                vertex_vertex(a, p, b, q, group);
                if group.is_empty() {
                    return;
                }
                let areas = sb
                    .vertex_faces(q)
                    .iter()
                    .map(|&f| vertex_areas(a, p, b, f, range))
                    .chain(
                        sa.vertex_faces(p)
                            .iter()
                            .map(|&g| vertex_areas(b, q, a, g, range)),
                    )
                    .fold((0.0, 0.0), widest);
                out.push(contact(
                    (i, p as u32),
                    (j, VERTEX | q as u32),
                    law,
                    areas,
                    exactly(group),
                ));
            }
            // Vertex-edge groups: a convex vertex near the inside of an edge
            // (not reflex) within its block's reach, away from the edge's
            // convex ends.
            Feature::VertexEdge(side, p, e) => {
                let ((x, bx, near_x), (y, by, near_y)) =
                    sides(side, (i, a, near_a), (j, b, near_b));
                let (sx, sy) = (bx.shape(), by.shape());
                let (p, e) = (p as usize, e as usize);
                let pv = &sx.vertices()[p];
                let edge = &sy.edges()[e];
                let [q0, q1] = edge.ends.map(|k| sy.vertices()[k]);
                if !sx.is_convex_vertex(p)
                    || !near_y.holds(pv)
                    || sy.edge_kind(e) == EdgeKind::Reflex
                    || !near_x.meets(&q0, &q1)
                    || !within(&grown_bounds(&q0, &q1, range), pv)
                    || near_convex_end(sy, edge.ends, pv, range)
                {
                    return;
                }
                let (distance, s) = segment_distance(pv, &q0, &q1);
                if distance >= range || s <= 0.0 || s >= 1.0 {
                    return;
                }
                vertex_edge(bx, p, by, e, group);
                if group.is_empty() {
                    return;
                }
                let areas = edge
                    .faces
                    .iter()
                    .map(|&f| vertex_areas(bx, p, by, f, range))
                    .fold((0.0, 0.0), widest);
                out.push(contact(
                    (x, p as u32),
                    (y, EDGE | e as u32),
                    law,
                    areas,
                    exactly(group),
                ));
            }
            // Vertex-face contacts.
            Feature::VertexFace(side, p, f) => {
                let ((x, bx, _), (y, by, near_y)) = sides(side, (i, a, near_a), (j, b, near_b));
                let (sx, sy) = (bx.shape(), by.shape());
                let (p, f) = (p as usize, f as usize);
                if !sx.is_convex_vertex(p)
                    || !near_y.holds(&sx.vertices()[p])
                    || !vertex_over_face(sx, p, sy, f, range)
                {
                    return;
                }
                let en = face_entrance(bx, p, by, f, false);
                let areas = vertex_areas(bx, p, by, f, range);
                out.push(contact((x, p as u32), (y, f as u32), law, areas, vec![en]));
            }
            // Edge-edge crossings away from corners, between convex edges
            // of each block within the other's reach. Two edges whose
            // bounds, each grown by the range, do not overlap are farther
            // apart than the range.
            Feature::EdgeEdge(ea, eb) => {
                let (ea, eb) = (ea as usize, eb as usize);
                let (edge_a, edge_b) = (&sa.edges()[ea], &sb.edges()[eb]);
                if sa.edge_kind(ea) != EdgeKind::Convex || sb.edge_kind(eb) != EdgeKind::Convex {
                    return;
                }
                let [ua, va] = edge_a.ends.map(|k| sa.vertices()[k]);
                let [ub, vb] = edge_b.ends.map(|k| sb.vertices()[k]);
                if !near_b.meets(&ua, &va)
                    || !near_a.meets(&ub, &vb)
                    || apart(
                        &grown_bounds(&ua, &va, range),
                        &grown_bounds(&ub, &vb, range),
                    )
                {
                    return;
                }
                if let Some(en) = edge_edge(a, ea, edge_a.ends, b, eb, edge_b.ends, range) {
                    // A crossing between two faces facing each other stands
                    // for its part of their overlap; elsewhere (edges
                    // crossing at an angle) for no area, its springs for a
                    // square of half the shorter edge.
                    let shorter = [(edge_a.ends, sa), (edge_b.ends, sb)]
                        .iter()
                        .map(|([u, v], s)| (s.vertices()[*u] - s.vertices()[*v]).norm())
                        .fold(f64::INFINITY, f64::min);
                    let areas = match crossing_area(a, ea, b, eb, range) {
                        Some(area) if area > 0.0 => (area, area),
                        _ => (0.0, (shorter / 2.0).powi(2)),
                    };
                    out.push(contact(
                        (i, EDGE | ea as u32),
                        (j, eb as u32),
                        law,
                        areas,
                        vec![en],
                    ));
                }
            }
        }
    }
}

/// A feature's two blocks, each with its index and reach, the vertex's
/// first: side 0 is the pair's first block's vertex.
type Side<'a> = (usize, &'a Block, &'a Reach<3>);

fn sides<'a>(side: u8, a: Side<'a>, b: Side<'a>) -> (Side<'a>, Side<'a>) {
    if side == 0 {
        (a, b)
    } else {
        (b, a)
    }
}

/// The entrances found, moved to a vector exactly as long (a contact keeps
/// them for the step); `found` keeps its
/// room for the next group. Taking `found` whole would hand over its spare
/// room and leave the next group to grow a new one.
#[allow(clippy::drain_collect)]
fn exactly(found: &mut Vec<PointEntrance>) -> Vec<PointEntrance> {
    found.drain(..).collect()
}

/// A readable, stable name for a contact: `block:feature/block:feature`, a
/// feature being a vertex (`v3`), an edge (`e3`) or a face (`f3`). For
/// example `1:v0/0:f2` is vertex 0 of block 1 against face 2 of block 0,
/// `1:e4/0:e7` a crossing of edges, `1:v0/0:v5` and `1:v0/0:e7` vertex groups.
pub fn contact_label(key: &ContactKey) -> String {
    let a = if key.feature_a & EDGE != 0 {
        format!("e{}", key.feature_a & !EDGE)
    } else {
        format!("v{}", key.feature_a)
    };
    let b = if key.feature_b & VERTEX != 0 {
        format!("v{}", key.feature_b & !VERTEX)
    } else if key.feature_b & EDGE != 0 || key.feature_a & EDGE != 0 {
        format!("e{}", key.feature_b & !EDGE)
    } else {
        format!("f{}", key.feature_b)
    };
    format!("{}:{a}/{}:{b}", key.block_a, key.block_b)
}

fn contact(
    (i, feature_a): (usize, u32),
    (j, feature_b): (usize, u32),
    law: usize,
    (length, spring_length): (f64, f64),
    entrances: Vec<PointEntrance>,
) -> Contact3 {
    let key = ContactKey {
        block_a: i as u32,
        feature_a,
        block_b: j as u32,
        feature_b,
    };
    Contact::new(key, law, (length, spring_length), entrances)
}

/// Whether a convex end of an edge lies within `range` of `p` (a corner
/// group handles that vertex instead).
fn near_convex_end(s: &Polyhedron, ends: [usize; 2], p: &Point3<f64>, range: f64) -> bool {
    ends.iter()
        .any(|&k| s.is_convex_vertex(k) && (s.vertices()[k] - p).norm() < range)
}

/// Axis-aligned bounds (min, max).
pub(crate) type Bounds = (Point3<f64>, Point3<f64>);

/// The bounds of the segment from `u` to `v`, grown by `range`.
pub(crate) fn grown_bounds(u: &Point3<f64>, v: &Point3<f64>, range: f64) -> Bounds {
    let grow = Vector3::repeat(range);
    (u.inf(v) - grow, u.sup(v) + grow)
}

/// Whether `p` lies within the bounds.
pub(crate) fn within((lo, hi): &Bounds, p: &Point3<f64>) -> bool {
    (0..3).all(|k| lo[k] <= p[k] && p[k] <= hi[k])
}

/// Whether two bounds do not overlap.
pub(crate) fn apart((lo_a, hi_a): &Bounds, (lo_b, hi_b): &Bounds) -> bool {
    (0..3).any(|k| lo_a[k] > hi_b[k] || lo_b[k] > hi_a[k])
}

/// Convex vertex `p` of `x` can enter a plane with normal `n` (pointing
/// towards `x`): every edge at `p` points to the plane's outer side.
fn vertex_enters(x: &Polyhedron, p: usize, n: &Vector3<f64>) -> bool {
    x.is_convex_vertex(p)
        && x.vertex_edges(p)
            .iter()
            .all(|&e| n.dot(&x.edge_direction(e, p)) >= -sin_tol())
}

/// The corner of `y` at `q` lies below a plane with normal `n`.
fn vertex_below(y: &Polyhedron, q: usize, n: &Vector3<f64>) -> bool {
    y.vertex_edges(q)
        .iter()
        .all(|&e| n.dot(&y.edge_direction(e, q)) <= sin_tol())
}

/// The wedge of edge `e` of `x` lies above a plane with normal `n`.
fn edge_enters(x: &Polyhedron, e: usize, n: &Vector3<f64>) -> bool {
    x.edge_wedge(e).iter().all(|w| n.dot(w) >= -sin_tol())
}

/// The wedge of edge `e` of `y` lies below a plane with normal `n`.
fn edge_below(y: &Polyhedron, e: usize, n: &Vector3<f64>) -> bool {
    y.edge_wedge(e).iter().all(|w| n.dot(w) <= sin_tol())
}

/// The linearised contact of a point `pa` of block `enter` with a point `pb`
/// of block `entered` along unit normal `n` (from `entered` to `enter`),
/// tangents `t1` and n × t1. With `swap` the rows are given in the order
/// (entered, enter).
fn entrance(
    enter: &Block,
    pa: &Point3<f64>,
    entered: &Block,
    pb: &Point3<f64>,
    n: &Vector3<f64>,
    t1: &Vector3<f64>,
    swap: bool,
) -> PointEntrance {
    let (ca, cb) = (enter.centroid(), entered.centroid());
    let t2 = n.cross(t1);
    PointEntrance::new(n.dot(&(pa - pb)), pa - ca, pb - cb, [*n, *t1, t2], swap)
}

/// Vertex `p` of `x` against the plane of face `f` of `y`, measured at the
/// vertex's projection on the plane; tangents along the face's first edge.
fn face_entrance(x: &Block, p: usize, y: &Block, f: usize, swap: bool) -> PointEntrance {
    let frame = y.shape().face_frame(f);
    let pv = x.vertices()[p];
    let foot = pv - frame.normal * frame.height(&pv);
    entrance(x, &pv, y, &foot, &frame.normal, &frame.u, swap)
}

/// Edge `ea` of `x` against edge `eb` of `y` along `n`, measured between the
/// closest points of the two lines; tangents along `eb`. `None` if parallel.
fn edge_entrance(
    x: &Block,
    ea: usize,
    y: &Block,
    eb: usize,
    n: &Vector3<f64>,
    swap: bool,
) -> Option<PointEntrance> {
    let [p1, q1] = x.shape().edges()[ea].ends.map(|k| x.vertices()[k]);
    let [p2, q2] = y.shape().edges()[eb].ends.map(|k| y.vertices()[k]);
    let (s, t) = line_closest(&p1, &q1, &p2, &q2)?;
    let pa = p1 + (q1 - p1) * s;
    let pb = p2 + (q2 - p2) * t;
    let along = (q2 - p2).normalize();
    let t1 = (along - n * n.dot(&along)).normalize();
    Some(entrance(x, &pa, y, &pb, n, &t1, swap))
}

/// The unit normal of the plane spanned by two edge directions, oriented by
/// `valid` (which must accept exactly one sign); `None` for parallel edges or
/// when neither or both signs fit.
fn crossing_normal(
    da: &Vector3<f64>,
    db: &Vector3<f64>,
    valid: impl Fn(&Vector3<f64>) -> bool,
) -> Option<Vector3<f64>> {
    let c = da.normalize().cross(&db.normalize());
    if c.norm() < sin_tol() {
        return None;
    }
    let n = c.normalize();
    match (valid(&n), valid(&-n)) {
        (true, false) => Some(n),
        (false, true) => Some(-n),
        _ => None,
    }
}

/// Entrances of two convex corners, into `out`: every face plane and
/// edge-pair plane that separates them.
fn vertex_vertex(a: &Block, p: usize, b: &Block, q: usize, out: &mut Vec<PointEntrance>) {
    let (sa, sb) = (a.shape(), b.shape());
    let (edges_a, edges_b) = (sa.vertex_edges(p), sb.vertex_edges(q));
    let length = round_off_length(a, p);
    out.clear();
    for &f in sb.vertex_faces(q) {
        let n = sb.normal(f);
        if vertex_enters(sa, p, &n) && vertex_below(sb, q, &n) {
            add_distinct(out, Some(face_entrance(a, p, b, f, false)), length);
        }
    }
    for &g in sa.vertex_faces(p) {
        let n = sa.normal(g);
        if vertex_enters(sb, q, &n) && vertex_below(sa, p, &n) {
            add_distinct(out, Some(face_entrance(b, q, a, g, true)), length);
        }
    }
    for &ea in edges_a {
        for &eb in edges_b {
            let valid = |n: &Vector3<f64>| vertex_enters(sa, p, n) && vertex_below(sb, q, n);
            let da = sa.edge_direction(ea, p);
            let db = sb.edge_direction(eb, q);
            if let Some(n) = crossing_normal(&da, &db, valid) {
                add_distinct(out, edge_entrance(a, ea, b, eb, &n, false), length);
            }
        }
    }
}

/// Adds an entrance to a group's `out` unless it is one already found:
/// where blocks meet square (a corner on an edge or on a corner), a
/// crossing of two edges lies in a face's plane through the same points,
/// and two corners' face planes are one plane seen from either block; a
/// copy would only be read again at every decision. `length`: the group's
/// scale of round-off ([`round_off_length`]).
fn add_distinct(out: &mut Vec<PointEntrance>, entrance: Option<PointEntrance>, length: f64) {
    if let Some(entrance) = entrance {
        if !out.iter().any(|o| o.same_as(&entrance, length)) {
            out.push(entrance);
        }
    }
}

/// The length on which a group's entrances are made: the vertex's farthest
/// coordinate (points far from the origin round off more) and the block's
/// extent.
fn round_off_length(x: &Block, p: usize) -> f64 {
    let (lo, hi) = x.bounds();
    x.vertices()[p].coords.amax() + (hi - lo).amax()
}

/// Entrances of convex vertex `p` of `x` near the inside of edge `e` of `y`,
/// into `out`: the planes of the edge's faces and the crossings of the
/// vertex's edges with it.
fn vertex_edge(x: &Block, p: usize, y: &Block, e: usize, out: &mut Vec<PointEntrance>) {
    let (sx, sy) = (x.shape(), y.shape());
    let length = round_off_length(x, p);
    out.clear();
    for &f in &sy.edges()[e].faces {
        let n = sy.normal(f);
        if vertex_enters(sx, p, &n) && edge_below(sy, e, &n) {
            out.push(face_entrance(x, p, y, f, false));
        }
    }
    let [e0, e1] = sy.edges()[e].ends;
    let de = sy.vertices()[e1] - sy.vertices()[e0];
    for &ex in sx.vertex_edges(p) {
        let valid = |n: &Vector3<f64>| vertex_enters(sx, p, n) && edge_below(sy, e, n);
        if let Some(n) = crossing_normal(&sx.edge_direction(ex, p), &de, valid) {
            add_distinct(out, edge_entrance(x, ex, y, e, &n, false), length);
        }
    }
}

/// Whether convex vertex `p` of `x` makes a plain VF contact with face `f`
/// of `y` (see the module notes).
fn vertex_over_face(x: &Polyhedron, p: usize, y: &Polyhedron, f: usize, range: f64) -> bool {
    let n = y.normal(f);
    let pv = x.vertices()[p];
    // Ahead of the face by less than the range, or behind it by less than
    // Shi's penetration distance (0.3 of the range): deeper behind a face's
    // plane the vertex is usually not inside the block at all (thin blocks).
    // First, as it rules out most faces: the face frame's height.
    let height = n.dot(&(pv - y.vertices()[y.faces()[f][0]]));
    if height >= range || height <= -PENETRATION_SHARE * range {
        return false;
    }
    if !vertex_enters(x, p, &n) {
        return false;
    }
    let frame = y.face_frame(f);
    let face = &y.faces()[f];
    // Corners and edges nearby belong to the groups.
    if face
        .iter()
        .any(|&q| y.is_convex_vertex(q) && (y.vertices()[q] - pv).norm() < range)
    {
        return false;
    }
    let mut near_reflex = false;
    let polygon = y.face_polygon(f);
    let at = frame.to_plane(&pv);
    for (k, &e) in y.face_edges(f).iter().enumerate() {
        let [q0, q1] = y.edges()[e].ends.map(|i| y.vertices()[i]);
        if y.edge_kind(e) == EdgeKind::Reflex {
            let next = (k + 1) % polygon.len();
            near_reflex |= planar::point_segment(&at, &polygon[k], &polygon[next]).0 < range;
            continue;
        }
        let (distance, s) = segment_distance(&pv, &q0, &q1);
        if distance < range && s > 0.0 && s < 1.0 {
            return false;
        }
    }
    near_reflex || planar::contains(&polygon, &at)
}

/// Edge-edge crossing of convex edges away from their ends.
fn edge_edge(
    a: &Block,
    ea: usize,
    ends_a: [usize; 2],
    b: &Block,
    eb: usize,
    ends_b: [usize; 2],
    range: f64,
) -> Option<PointEntrance> {
    let (sa, sb) = (a.shape(), b.shape());
    let [p1, q1] = ends_a.map(|k| sa.vertices()[k]);
    let [p2, q2] = ends_b.map(|k| sb.vertices()[k]);
    let (s, t) = line_closest(&p1, &q1, &p2, &q2)?;
    if !(s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0) {
        return None;
    }
    let (pa, pb) = (p1 + (q1 - p1) * s, p2 + (q2 - p2) * t);
    if (pa - pb).norm() >= range {
        return None;
    }
    let end_near = |ends: [usize; 2], s: &Polyhedron, from: &Point3<f64>, to: &Point3<f64>| {
        ends.iter().any(|&k| {
            s.is_convex_vertex(k) && segment_distance(&s.vertices()[k], from, to).0 < range
        })
    };
    if end_near(ends_a, sa, &p2, &q2) || end_near(ends_b, sb, &p1, &q1) {
        return None;
    }
    let valid = |n: &Vector3<f64>| edge_enters(sa, ea, n) && edge_below(sb, eb, n);
    let n = crossing_normal(&(q1 - p1), &(q2 - p2), valid)?;
    edge_entrance(a, ea, b, eb, &n, false).filter(|e| e.gap > -PENETRATION_SHARE * range)
}

/// Parameters (s, t) of the closest points of the lines p1 + s(q1 − p1) and
/// p2 + t(q2 − p2); `None` if they are parallel.
fn line_closest(
    p1: &Point3<f64>,
    q1: &Point3<f64>,
    p2: &Point3<f64>,
    q2: &Point3<f64>,
) -> Option<(f64, f64)> {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, b) = (d1.dot(&d1), d2.dot(&d2), d1.dot(&d2));
    let (c, f) = (d1.dot(&r), d2.dot(&r));
    let denom = a * e - b * b;
    if denom <= 1e-12 * a * e {
        return None;
    }
    Some(((b * f - c * e) / denom, (a * f - b * c) / denom))
}

/// Distance from `p` to the segment (a, b) and the parameter of the nearest
/// point, clamped to [0, 1].
pub(crate) fn segment_distance(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> (f64, f64) {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p - (a + ab * s)).norm(), s)
}

/// The wider of two (area, spring area) pairs: a true area brings its own
/// spring area, and a corner's fallback spring area (no true area) counts
/// only where no pair has a true area. Taking the two maxima apart let a
/// fallback from a face that round-off picks outweigh the true area, so a
/// head joint's corners changed their springs from step to step.
fn widest(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    match (a.0 > 0.0, b.0 > 0.0) {
        (true, true) if b.0 > a.0 => b,
        (true, _) => a,
        (false, true) => b,
        (false, false) => (0.0, a.1.max(b.1)),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::kinematics::Vector12;
    use crate::kinematics::{move_point, RotationUpdate};
    use crate::polyhedron::cuboid;
    use dda_core::EntranceRows;
    use nalgebra::Point2;
    use nalgebra::Rotation3;

    fn block(center: Point3<f64>, size: Vector3<f64>, rotation: Rotation3<f64>) -> Block {
        let (v, f) = cuboid(center, size, rotation);
        Block::new(&v, &f, 0, 1000.0).unwrap()
    }

    fn moved(b: &Block, p: &Point3<f64>, d: &Vector12) -> Point3<f64> {
        move_point(p, &b.centroid(), d, RotationUpdate::Exact)
    }

    /// A small increment on one of the 24 DOF of a pair.
    fn increment(k: usize, h: f64) -> (Vector12, Vector12) {
        let (mut da, mut db) = (Vector12::zeros(), Vector12::zeros());
        if k < 12 {
            da[k] = h
        } else {
            db[k - 12] = h
        }
        (da, db)
    }

    /// Two boxes, one on the other, overlapping along part of their faces (a
    /// running bond's bed joint, offset along the wall and, for a second
    /// case, across it as well), the pair turned as a whole: the corners at
    /// the overlap's ends stand for its area once.
    #[test]
    fn a_partial_overlap_is_stood_for_once() {
        let turn = Rotation3::from_euler_angles(0.3, -0.2, 0.5);
        let place = |x: f64, y: f64, z: f64| turn * Point3::new(x, y, z);
        for (along, across) in [
            (0.1, 0.0),
            (0.25, 0.0),
            (0.4, 0.0),
            (0.25, 1e-6),
            (0.25, 0.0625),
        ] {
            let blocks = vec![
                block(
                    place(0.25, 0.0, -0.125),
                    Vector3::new(0.5, 0.25, 0.25),
                    turn,
                ),
                block(
                    place(0.25 + along, across, 0.125),
                    Vector3::new(0.5, 0.25, 0.25),
                    turn,
                ),
            ];
            let overlap = (0.5 - along) * (0.25 - across);
            let contacts = pair_contacts(&blocks, 1, 0, 0.01, 0);
            let areas: Vec<f64> = contacts.iter().map(|c| c.length).collect();
            let total: f64 = areas.iter().sum();
            assert!(
                (total - overlap).abs() < 1e-12,
                "offset ({along}, {across}): the corners stand for {total} m², {areas:?}, of the {overlap} m² overlap"
            );
            // Offset across by more than the range, two of the overlap's
            // corners are where the faces' edges cross, edge-edge contacts
            // standing for their quarters too. Within the range (a strained
            // brick a micrometre wider), a corner just off the other face
            // stands for its quarter, moved by half the offset.
            let slack = if across < 0.01 { across * 0.25 } else { 0.0 };
            for a in areas.iter().filter(|a| **a > 0.0) {
                assert!((a - overlap / 4.0).abs() < 1e-12 + slack, "{areas:?}");
            }
        }
    }

    /// A tilted base and a tilted cube whose lowest corner (vertex 0) sits on
    /// the base's top face, clear of its edges.
    fn corner_on_face() -> Vec<Block> {
        let tilt = Rotation3::from_euler_angles(0.2, -0.1, 0.3);
        let base = block(
            Point3::new(0.3, -0.2, -0.5),
            Vector3::new(6.0, 5.0, 1.0),
            tilt,
        );
        let top = base.shape().face_frame(1);
        let spot = top.origin + top.u * 2.5 + top.v * 2.0;
        // Cube corner 0 is (−½, −½, −½) in its frame: rotate it so the corner
        // points down along the base's normal, then place it at `spot`.
        let r =
            Rotation3::rotation_between(&Vector3::new(-1.0, -1.0, -1.0), &(-top.normal)).unwrap();
        let c = spot - r * Vector3::new(-0.5, -0.5, -0.5);
        vec![base, block(c, Vector3::new(1.0, 1.0, 1.0), r)]
    }

    #[test]
    fn vertex_face_rows_are_the_derivatives_of_the_exact_gap_and_slip() {
        let blocks = corner_on_face();
        let contacts = pair_contacts(&blocks, 1, 0, 0.05, 0);
        let c = contacts
            .iter()
            .find(|c| contact_label(&c.key) == "1:v0/0:f1")
            .unwrap_or_else(|| panic!("corner on the top face: {contacts:?}"));
        assert_eq!(contacts.len(), 1, "only the corner is near");
        assert_eq!(c.blocks, [1, 0]);
        let (cube, base) = (&blocks[1], &blocks[0]);
        let e = &c.entrances[0];
        let pv = cube.vertices()[0];
        let face = &base.faces()[1];
        let frame = base.shape().face_frame(1);
        assert!(e.gap.abs() < 1e-12);
        let foot = pv - frame.normal * frame.height(&pv);
        // The exact gap: distance from the moved face's plane; the exact slip:
        // the moved vertex relative to the moved foot, along the moved face's
        // first edge and its in-plane perpendicular.
        let exact = |da: &Vector12, db: &Vector12| {
            let q: Vec<Point3<f64>> = face
                .iter()
                .map(|&k| moved(base, &base.vertices()[k], db))
                .collect();
            let n = (q[1] - q[0]).cross(&(q[2] - q[0])).normalize();
            let p = moved(cube, &pv, da);
            let t1 = (q[1] - q[0]).normalize();
            let t2 = n.cross(&t1);
            let rel = p - moved(base, &foot, db);
            (n.dot(&(p - q[0])), t1.dot(&rel), t2.dot(&rel))
        };
        let h = 1e-6;
        for k in 0..24 {
            let (da, db) = increment(k, h);
            let (g1, s1, r1) = exact(&da, &db);
            let (g0, s0, r0) = exact(&-da, &-db);
            let fd = [(g1 - g0), (s1 - s0), (r1 - r0)].map(|x| x / (2.0 * h));
            let rows = [
                e.gap_at(&da, &db) - e.gap,
                e.shear_at(&da, &db)[0],
                e.shear_at(&da, &db)[1],
            ]
            .map(|x| x / h);
            for (what, (f, r)) in ["gap", "slip 1", "slip 2"].iter().zip(fd.iter().zip(rows)) {
                assert!((f - r).abs() < 1e-8, "{what}, DOF {k}: {f} vs {r}");
            }
        }
        // Off the face the gap is still exact to first order.
        let mut lifted = blocks.clone();
        let mut up = Vector12::zeros();
        up.fixed_rows_mut::<3>(0).copy_from(&(frame.normal * 0.01));
        lifted[1].commit(&up, nalgebra::Vector6::zeros(), RotationUpdate::Exact);
        let c = pair_contacts(&lifted, 1, 0, 0.05, 0);
        let e = &c[0].entrances[0];
        assert!((e.gap - 0.01).abs() < 1e-12);
    }

    /// Two boxes whose long edges cross at right angles-ish, touching.
    fn crossing_edges() -> (Vec<Block>, Point3<f64>) {
        let lower = block(
            Point3::new(0.0, 0.0, -0.5),
            Vector3::new(4.0, 1.0, 1.0),
            Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_4),
        );
        // The lower box's top ridge runs along x at height z = −0.5 + √2/2.
        let ridge = -0.5 + std::f64::consts::SQRT_2 / 2.0;
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), 1.2)
            * Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_4);
        // Its bottom ridge runs along the rotated x axis, √2/2 below its centre.
        let c = Point3::new(0.3, 0.0, ridge + std::f64::consts::SQRT_2 / 2.0);
        let upper = block(c, Vector3::new(4.0, 1.0, 1.0), r);
        (vec![lower, upper], Point3::new(0.3, 0.0, ridge))
    }

    #[test]
    fn edge_edge_rows_are_the_derivatives_of_the_exact_gap_and_slip() {
        let (blocks, touch) = crossing_edges();
        let contacts = pair_contacts(&blocks, 0, 1, 0.05, 0);
        assert_eq!(contacts.len(), 1, "{contacts:?}");
        let c = &contacts[0];
        let label = contact_label(&c.key);
        assert!(
            label.starts_with("0:e") && label.contains("/1:e"),
            "{label}"
        );
        let e = &c.entrances[0];
        assert!(e.gap.abs() < 1e-12, "touching: {}", e.gap);
        // The normal is vertical and points from the upper block (b) to the lower (a).
        let push = Vector12::from_fn(|i, _| if i == 2 { 1e-3 } else { 0.0 });
        assert!((e.gap_at(&Vector12::zeros(), &push) - 1e-3).abs() < 1e-12);
        let (lo, up) = (&blocks[0], &blocks[1]);
        let ea = c.key.feature_a & !EDGE;
        let eb = c.key.feature_b;
        let ends = |b: &Block, e: u32| b.shape().edges()[e as usize].ends.map(|k| b.vertices()[k]);
        let ([p1, q1], [p2, q2]) = (ends(lo, ea), ends(up, eb));
        assert!(segment_distance(&touch, &p1, &q1).0 < 1e-12);
        let n0 = (q1 - p1).cross(&(q2 - p2)).normalize();
        let sign = if n0.z < 0.0 { 1.0 } else { -1.0 }; // from the upper to the lower block
        let exact = |da: &Vector12, db: &Vector12| {
            let [m1, n1] = [p1, q1].map(|p| moved(lo, &p, da));
            let [m2, n2] = [p2, q2].map(|p| moved(up, &p, db));
            let n = (n1 - m1).cross(&(n2 - m2)).normalize() * sign;
            let (s, t) = line_closest(&m1, &n1, &m2, &n2).unwrap();
            let gap = n.dot(&((m1 + (n1 - m1) * s) - (m2 + (n2 - m2) * t)));
            let t1 = (n2 - m2).normalize();
            let t2 = n.cross(&t1);
            let rel = moved(lo, &touch, da) - moved(up, &touch, db);
            (gap, t1.dot(&rel), t2.dot(&rel))
        };
        let h = 1e-6;
        for k in 0..24 {
            let (da, db) = increment(k, h);
            let (g1, s1, r1) = exact(&da, &db);
            let (g0, s0, r0) = exact(&-da, &-db);
            let fd = [(g1 - g0), (s1 - s0), (r1 - r0)].map(|x| x / (2.0 * h));
            let rows = [
                e.gap_at(&da, &db) - e.gap,
                e.shear_at(&da, &db)[0],
                e.shear_at(&da, &db)[1],
            ]
            .map(|x| x / h);
            for (what, (f, r)) in ["gap", "slip 1", "slip 2"].iter().zip(fd.iter().zip(rows)) {
                assert!((f - r).abs() < 1e-8, "{what}, DOF {k}: {f} vs {r}");
            }
        }
    }

    /// A 10 × 10 × 1 slab whose top face is z = 0.
    fn slab() -> Block {
        block(
            Point3::new(0.0, 0.0, -0.5),
            Vector3::new(10.0, 10.0, 1.0),
            Rotation3::identity(),
        )
    }

    #[test]
    fn a_cube_on_a_larger_face_makes_four_vertex_face_contacts_standing_for_its_base() {
        let base = slab();
        let cube = block(
            Point3::new(0.4, -0.3, 1.0),
            Vector3::new(2.0, 2.0, 2.0),
            Rotation3::from_axis_angle(&Vector3::z_axis(), 0.3),
        );
        let blocks = vec![base, cube];
        let contacts = pair_contacts(&blocks, 0, 1, 0.05, 0);
        assert_eq!(contacts.len(), 4, "{contacts:?}");
        for c in &contacts {
            assert!(contact_label(&c.key).starts_with("1:v"));
            assert!(contact_label(&c.key).ends_with("/0:f1"));
            assert!(c.entrances[0].gap.abs() < 1e-12);
        }
        let total: f64 = contacts.iter().map(|c| c.length).sum();
        assert!(
            (total - 4.0).abs() < 1e-12,
            "stands for the 2 × 2 base: {total}"
        );
        // Overhanging by half: each contact stands for the part over the base.
        let edge = block(
            Point3::new(5.0, 0.0, 1.0),
            Vector3::new(2.0, 2.0, 2.0),
            Rotation3::identity(),
        );
        let blocks = vec![blocks[0].clone(), edge];
        let contacts = pair_contacts(&blocks, 0, 1, 0.05, 0);
        let total: f64 = contacts.iter().map(|c| c.length).sum();
        assert!(
            (total - 2.0).abs() < 1e-12,
            "half the base is supported: {total}"
        );
    }

    /// A corner's share of a concave face is clipped triangle by triangle,
    /// of a convex one against the whole face: a cube standing on a
    /// dart-shaped face, wholly on it but away from the part a clip by its
    /// sides alone would keep (its kernel), stands for its whole base, and
    /// so does one on a box.
    #[test]
    fn a_cube_on_a_concave_face_stands_for_its_base() {
        let outline =
            [(0.0, 0.0), (2.0, 1.0), (0.0, 2.0), (0.8, 1.0)].map(|(x, y)| Point2::new(x, y));
        let (v, f) = crate::polyhedron::prism(&outline, 0.0, 1.0);
        let dart = Block::new(&v, &f, 0, 1000.0).unwrap();
        let top = (0..dart.shape().faces().len())
            .find(|&f| dart.shape().normal(f).z > 0.5)
            .unwrap();
        assert!(!dart.shape().is_convex_face(top));
        let cube = block(
            Point3::new(0.6, 0.5, 1.1),
            Vector3::repeat(0.2),
            Rotation3::identity(),
        );
        assert!((0..6).all(|f| cube.shape().is_convex_face(f)));
        assert!(!l_block(|p| *p).shape().is_convex_face(0));
        let contacts = pair_contacts(&[dart, cube], 0, 1, 0.01, 0);
        assert_eq!(contacts.len(), 4, "{contacts:?}");
        let total: f64 = contacts.iter().map(|c| c.length).sum();
        assert!((total - 0.04).abs() < 1e-12, "{total}");
        let on_box = block(
            Point3::new(0.6, 0.5, 0.1),
            Vector3::repeat(0.2),
            Rotation3::identity(),
        );
        let contacts = pair_contacts(&[slab(), on_box], 0, 1, 0.01, 0);
        let total: f64 = contacts.iter().map(|c| c.length).sum();
        assert!((total - 0.04).abs() < 1e-12, "{total}");
    }

    /// A face within 3° of the entered one stands for its own area, not its
    /// shadow on the entered plane: a corner, whose springs stand for its
    /// face's true share, and a vertex of a face on the plane then agree, so
    /// a vertex passing between the two keeps its springs' area.
    #[test]
    fn a_cube_tilted_on_a_face_stands_for_its_base_not_its_shadow() {
        let base = slab();
        let tilt = 1f64.to_radians();
        let cube = block(
            Point3::new(0.4, -0.3, tilt.sin() + tilt.cos()),
            Vector3::new(2.0, 2.0, 2.0),
            Rotation3::from_axis_angle(&Vector3::x_axis(), tilt),
        );
        let blocks = vec![base, cube];
        let contacts = pair_contacts(&blocks, 0, 1, 0.05, 0);
        assert_eq!(contacts.len(), 4, "{contacts:?}");
        for c in &contacts {
            assert!((c.length - 1.0).abs() < 1e-12, "{}", c.length);
            assert_eq!(c.spring_length, c.length);
        }
    }

    #[test]
    fn equal_cubes_stacked_make_one_group_per_corner_and_resist_only_pushing() {
        let lower = block(
            Point3::new(0.0, 0.0, 0.5),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        let upper = block(
            Point3::new(0.0, 0.0, 1.5),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        let blocks = vec![lower, upper];
        let contacts = pair_contacts(&blocks, 0, 1, 0.02, 0);
        assert_eq!(contacts.len(), 4, "{contacts:?}");
        let down = Vector12::from_fn(|i, _| if i == 2 { -1e-4 } else { 0.0 });
        let side = Vector12::from_fn(|i, _| if i == 1 { 1e-4 } else { 0.0 });
        for c in &contacts {
            assert!(
                contact_label(&c.key).contains("/1:v"),
                "{}",
                contact_label(&c.key)
            );
            // The faces' planes and the edges' crossings of two corners
            // meeting square are one plane through the same points.
            assert_eq!(c.entrances.len(), 1, "{:?}", c.entrances);
            for e in &c.entrances {
                assert!((e.gap_at(&Vector12::zeros(), &down) + 1e-4).abs() < 1e-12);
                assert!(e.gap_at(&Vector12::zeros(), &side).abs() < 1e-12);
            }
            assert!((c.length - 0.25).abs() < 1e-12);
        }
        // Side by side: moving the right cube left penetrates every contact.
        let right = block(
            Point3::new(1.0, 0.0, 0.5),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        let blocks = vec![blocks[0].clone(), right];
        let left = Vector12::from_fn(|i, _| if i == 0 { -1e-4 } else { 0.0 });
        let contacts = pair_contacts(&blocks, 0, 1, 0.02, 0);
        assert_eq!(contacts.len(), 4);
        for c in &contacts {
            let widest = c
                .entrances
                .iter()
                .map(|e| e.gap_at(&Vector12::zeros(), &left))
                .fold(f64::MIN, f64::max);
            assert!((widest + 1e-4).abs() < 1e-12, "{widest}");
        }
    }

    /// Bricks in running bond: the upper brick's corners stand on the lower
    /// bricks' edges and theirs on its edges, each group's planes and
    /// crossings one entrance, kept once. Turned by a ten-thousandth of a
    /// radian, the crossings leave the faces' planes and are kept beside
    /// them.
    #[test]
    fn coinciding_entrances_are_kept_once() {
        let brick = |x: f64, z: f64, turn: f64| {
            block(
                Point3::new(x, 0.0, z),
                Vector3::new(1.0, 0.5, 0.25),
                Rotation3::from_axis_angle(&Vector3::z_axis(), turn),
            )
        };
        let counts = |turn: f64| {
            let blocks = vec![
                brick(0.0, 0.125, 0.0),
                brick(1.0, 0.125, 0.0),
                brick(0.5, 0.375, turn),
            ];
            let contacts: Vec<_> = [(0, 2), (1, 2)]
                .iter()
                .flat_map(|&(i, j)| pair_contacts(&blocks, i, j, 0.01, 0))
                .collect();
            let groups = contacts
                .iter()
                .filter(|c| c.key.feature_b & (VERTEX | EDGE) != 0);
            groups.map(|c| c.entrances.len()).collect::<Vec<_>>()
        };
        let square = counts(0.0);
        assert!(square.len() >= 8, "{square:?}");
        assert!(square.iter().all(|&n| n == 1), "{square:?}");
        let turned = counts(1e-4);
        assert!(turned.iter().any(|&n| n > 1), "{turned:?}");
    }

    #[test]
    fn a_vertex_beside_a_block_is_not_in_contact() {
        // The upper cube's bottom is below the lower one's top, but the two
        // stand apart by 0.03 sideways: the widest entrance is open.
        let lower = block(
            Point3::new(0.0, 0.0, 0.5),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        let beside = block(
            Point3::new(1.03, 0.2, 1.45),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        let blocks = vec![lower, beside];
        for c in pair_contacts(&blocks, 0, 1, 0.1, 0) {
            let widest = c.entrances.iter().map(|e| e.gap).fold(f64::MIN, f64::max);
            assert!(widest > 0.029, "{}: {widest}", contact_label(&c.key));
        }
    }

    /// An L-shaped prism 1 high, its outline's corner at (1, 1) reflex,
    /// with its corners moved by `place`.
    pub(crate) fn l_block(place: impl Fn(&Point3<f64>) -> Point3<f64>) -> Block {
        let outline = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ];
        let (v, f) = crate::polyhedron::prism(&outline.map(|(x, y)| Point2::new(x, y)), 0.0, 1.0);
        let v: Vec<Point3<f64>> = v.iter().map(place).collect();
        Block::new(&v, &f, 0, 1000.0).unwrap()
    }

    #[test]
    fn a_concave_block_enters_only_at_convex_corners_and_holds_in_its_notch() {
        let l = l_block(|p| *p);
        let base = block(
            Point3::new(1.0, 1.0, -0.5),
            Vector3::new(6.0, 6.0, 1.0),
            Rotation3::identity(),
        );
        let blocks = vec![base, l.clone()];
        let contacts = pair_contacts(&blocks, 0, 1, 0.02, 0);
        let mut labels: Vec<String> = contacts.iter().map(|c| contact_label(&c.key)).collect();
        labels.sort();
        // The bottom corners of the L except the inner one (vertex 3).
        assert_eq!(
            labels,
            [
                "1:v0/0:f1",
                "1:v1/0:f1",
                "1:v2/0:f1",
                "1:v4/0:f1",
                "1:v5/0:f1"
            ]
        );
        // A half-metre cube in the notch, against both walls: its four
        // corners in the crease touch both walls, the others one wall each.
        let cube = block(
            Point3::new(1.25, 1.25, 0.5),
            Vector3::repeat(0.5),
            Rotation3::identity(),
        );
        let blocks = vec![l, cube];
        let contacts = pair_contacts(&blocks, 0, 1, 0.02, 0);
        assert_eq!(contacts.len(), 8, "{contacts:?}");
        let walls = |c: &Contact3| {
            contact_label(&c.key)
                .rsplit('f')
                .next()
                .unwrap()
                .to_string()
        };
        let on = |face: &str| contacts.iter().filter(|c| walls(c) == face).count();
        // Side faces 2 + k stand over outline edge k: the walls are 4 and 5.
        let all: Vec<String> = contacts.iter().map(|c| contact_label(&c.key)).collect();
        assert_eq!((on("4"), on("5")), (4, 4), "{all:?}");
        let zero = Vector12::zeros();
        let step =
            |x: f64, y: f64| Vector12::from_fn(|i, _| [x, y][..].get(i).copied().unwrap_or(0.0));
        for c in &contacts {
            let e = &c.entrances[0];
            assert!(e.gap.abs() < 1e-12);
            // The contacts are (cube, L): moving the L towards the cube closes
            // every contact, moving the cube away from both walls opens them.
            assert!(
                e.gap_at(&zero, &step(1e-4, 1e-4)) < -0.99e-4,
                "the L moves into the cube"
            );
            assert!(e.gap_at(&step(1e-4, 1e-4), &zero) > 0.99e-4);
        }
        let into_x = contacts
            .iter()
            .filter(|c| c.entrances[0].gap_at(&step(-1e-4, 0.0), &zero) < -0.99e-4)
            .count();
        assert_eq!(
            into_x, 4,
            "pushing the cube into the wall x = 1 closes its four contacts"
        );
    }

    /// The facing features found by examining only those near the other
    /// block are the features found by examining all: for a box and an
    /// L-shaped prism (reflex edges) placed, turned and ranged at random
    /// near each other, the contacts are the same, in the same order.
    #[test]
    fn examining_only_near_features_finds_every_contact() {
        use proptest::prelude::*;
        let l = l_block(|p| *p);
        let mut runner = crate::seeded_runner(1024);
        let cases = (
            prop::array::uniform3(-1.6..1.6f64),
            prop::array::uniform3(-0.6..0.6f64),
            0.005..0.4f64,
            any::<bool>(),
        );
        let touching = std::cell::Cell::new(0);
        runner
            .run(&cases, |(at, turn, range, concave)| {
                let other = if concave {
                    let r = Rotation3::from_euler_angles(turn[0], turn[1], turn[2]);
                    let shift = Vector3::from(at) + Vector3::new(0.5, 0.5, 0.5);
                    l_block(|p| r * p + shift)
                } else {
                    block(
                        Point3::from(Vector3::from(at) + Vector3::new(1.0, 1.0, 0.5)),
                        Vector3::new(1.0, 0.8, 0.6),
                        Rotation3::from_euler_angles(turn[0], turn[1], turn[2]),
                    )
                };
                let blocks = vec![l.clone(), other];
                let all = pair_contacts_near(
                    &blocks,
                    0,
                    1,
                    range,
                    0,
                    Reach::everywhere(),
                    Reach::everywhere(),
                );
                let near = pair_contacts(&blocks, 0, 1, range, 0);
                touching.set(touching.get() + usize::from(!all.is_empty()));
                prop_assert!(
                    same_contacts(&all, &near),
                    "{} against {}",
                    all.len(),
                    near.len()
                );
                Ok(())
            })
            .unwrap();
        // Many placements touch (the others overlap deeply or stand
        // apart), so contacts are compared.
        let touching = touching.get();
        assert!(touching > 100, "{touching} of 1024 placements had contacts");
    }

    /// Two edges' bounds grown by the range, when apart, rule out a
    /// crossing: whenever the closest points of two segments lie inside
    /// both and within the range, the grown bounds overlap.
    #[test]
    fn edges_whose_grown_bounds_are_apart_make_no_crossing() {
        use proptest::prelude::*;
        let mut runner = crate::seeded_runner(4096);
        let point = || prop::array::uniform3(-1.0..1.0f64).prop_map(Point3::from);
        let cases = (point(), point(), point(), point(), 0.001..0.5f64);
        let crossings = std::cell::Cell::new(0);
        runner
            .run(&cases, |(p1, q1, p2, q2, range)| {
                let Some((s, t)) = line_closest(&p1, &q1, &p2, &q2) else {
                    return Ok(());
                };
                let (pa, pb) = (p1 + (q1 - p1) * s, p2 + (q2 - p2) * t);
                let inside = s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0;
                if inside && (pa - pb).norm() < range {
                    crossings.set(crossings.get() + 1);
                    let (a, b) = (grown_bounds(&p1, &q1, range), grown_bounds(&p2, &q2, range));
                    prop_assert!(!apart(&a, &b));
                }
                Ok(())
            })
            .unwrap();
        assert!(crossings.get() > 100, "{} crossings", crossings.get());
    }

    #[test]
    fn a_point_outside_an_edges_grown_bounds_is_farther_than_the_range() {
        use proptest::prelude::*;
        let mut runner = crate::seeded_runner(4096);
        let point = || prop::array::uniform3(-1.0..1.0f64).prop_map(Point3::from);
        let near = std::cell::Cell::new(0);
        runner
            .run(
                &(point(), point(), point(), 0.001..0.5f64),
                |(p, u, v, range)| {
                    if segment_distance(&p, &u, &v).0 < range {
                        near.set(near.get() + 1);
                        prop_assert!(within(&grown_bounds(&u, &v, range), &p));
                    }
                    Ok(())
                },
            )
            .unwrap();
        assert!(near.get() > 100, "{} near", near.get());
    }
}
