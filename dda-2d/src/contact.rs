//! Narrow phase: vertex-edge and vertex-vertex contacts between two polygons,
//! linearised about the start of the step (Shi 1988).
//!
//! * Vertex-edge: a convex vertex near the interior of an edge of the other
//!   block, whose wedge lies outside that edge (it can only enter through it).
//! * Vertex-vertex: two convex vertices within range. Every edge at either
//!   vertex that the other vertex could enter through is an entrance; the
//!   driver uses the one with the largest gap at each pass (Shi's
//!   entrance-line choice). A convex vertex near a reflex one makes an
//!   ordinary vertex-edge contact with each edge at the reflex vertex.
//!   Edge-to-edge contacts are the two vertex contacts at their ends.

use dda_core::block_set::{Reach, ANGLE_TOLERANCE, PENETRATION_SHARE};
#[cfg(test)]
use dda_core::contacts::same_contacts;
use dda_core::{Contact, ContactKey, Entrance};
use nalgebra::{Matrix2x6, Point2, Vector2, Vector6};

use crate::block::{Block, Edge};
use crate::kinematics::t_matrix;

/// Marks `feature_b` of a vertex-vertex contact (a vertex, not an edge).
const VERTEX: u32 = 1 << 31;

/// A 2D contact: 6 DOF per block, one tangential direction.
pub type Contact2 = Contact<6, 1>;

/// Contacts between blocks `i` and `j` within `range`, with law index `law`.
pub fn pair_contacts(
    blocks: &[Block],
    i: usize,
    j: usize,
    range: f64,
    law: usize,
) -> Vec<Contact2> {
    let (a, b) = (&blocks[i], &blocks[j]);
    pair_contacts_near(
        blocks,
        i,
        j,
        range,
        law,
        Reach::new(a.bounds(), range),
        Reach::new(b.bounds(), range),
    )
}

/// [`pair_contacts`], examining only the vertices of block `i` within
/// `near_b`, the reach of block `j`, and those of `j` within `near_a`.
fn pair_contacts_near(
    blocks: &[Block],
    i: usize,
    j: usize,
    range: f64,
    law: usize,
    near_a: Reach<2>,
    near_b: Reach<2>,
) -> Vec<Contact2> {
    let (a, b) = (&blocks[i], &blocks[j]);
    let mut out = Vec::new();
    let near = |p: &Point2<f64>, q: &Point2<f64>| (p - q).norm() < range;
    // Vertex-vertex groups.
    for (p, pv) in a.vertices().iter().enumerate() {
        if !near_b.holds(pv) {
            continue;
        }
        for (q, qv) in b.vertices().iter().enumerate() {
            if !near(pv, qv) {
                continue;
            }
            // Near a reflex vertex the other block's material is the union of
            // the two edges' half-planes, not their intersection: the convex
            // vertex gets an ordinary contact with each edge (Shi's rule).
            match (is_reflex(a, p), is_reflex(b, q)) {
                (true, true) => continue,
                (false, true) => {
                    for e in [prev(q, b), q] {
                        if let Some(en) = entrance(a, p, b, e, range, false) {
                            let lengths = lengths(a, p, b, e);
                            out.push(contact(i, p, j, e as u32, law, lengths, vec![en]));
                        }
                    }
                    continue;
                }
                (true, false) => {
                    for e in [prev(p, a), p] {
                        if let Some(en) = entrance(b, q, a, e, range, false) {
                            let lengths = lengths(b, q, a, e);
                            out.push(contact(j, q, i, e as u32, law, lengths, vec![en]));
                        }
                    }
                    continue;
                }
                (false, false) => {}
            }
            let mut entrances = Vec::new();
            let mut group = (0.0, 0.0);
            let mut widen =
                |(l, s): (f64, f64)| group = (f64::max(group.0, l), f64::max(group.1, s));
            for e in [prev(q, b), q] {
                if let Some(en) = entrance(a, p, b, e, range, false) {
                    widen(lengths(a, p, b, e));
                    entrances.push(en);
                }
            }
            for e in [prev(p, a), p] {
                if let Some(en) = entrance(b, q, a, e, range, true) {
                    widen(lengths(b, q, a, e));
                    entrances.push(en);
                }
            }
            if !entrances.is_empty() {
                out.push(contact(i, p, j, VERTEX | q as u32, law, group, entrances));
            }
        }
    }
    // Vertex-edge, both ways, skipping vertices already in a vertex group
    // with an end of the edge. The contact's first block owns the vertex.
    for (x, y, bx, by, near_y) in [(i, j, a, b, &near_b), (j, i, b, a, &near_a)] {
        for (p, pv) in bx.vertices().iter().enumerate() {
            if !near_y.holds(pv) {
                continue;
            }
            for (e, edge) in by.edges().iter().enumerate() {
                let q1 = by.vertices()[e];
                // The entrance's own first test, made before the two
                // distances below: most vertices near a block lie far
                // ahead of or behind most of its edges.
                if !within_band(edge.normal.dot(&(pv - q1)), range) {
                    continue;
                }
                let q2 = by.vertices()[next(e, by)];
                if near(pv, &q1) || near(pv, &q2) {
                    continue;
                }
                if let Some(en) = entrance(bx, p, by, e, range, false) {
                    let lengths = lengths(bx, p, by, e);
                    out.push(contact(x, p, y, e as u32, law, lengths, vec![en]));
                }
            }
        }
    }
    out
}

/// A readable, stable name for a contact: `block:vertex/block:feature`,
/// the feature being an edge (`e3`) or, for vertex-vertex contacts, a vertex
/// (`v3`). For example `1:v0/0:e2` is vertex 0 of block 1 against edge 2 of
/// block 0.
pub fn contact_label(key: &ContactKey) -> String {
    let feature = if key.feature_b & VERTEX != 0 {
        format!("v{}", key.feature_b & !VERTEX)
    } else {
        format!("e{}", key.feature_b)
    };
    format!(
        "{}:v{}/{}:{feature}",
        key.block_a, key.feature_a, key.block_b
    )
}

fn contact(
    i: usize,
    feature_a: usize,
    j: usize,
    feature_b: u32,
    law: usize,
    (length, spring_length): (f64, f64),
    entrances: Vec<Entrance<6, 1>>,
) -> Contact2 {
    let key = ContactKey {
        block_a: i as u32,
        feature_a: feature_a as u32,
        block_b: j as u32,
        feature_b,
    };
    Contact::new(key, law, (length, spring_length), entrances)
}

fn is_reflex(b: &Block, k: usize) -> bool {
    b.angles()[k] > std::f64::consts::PI + ANGLE_TOLERANCE
}

fn next(k: usize, b: &Block) -> usize {
    (k + 1) % b.vertices().len()
}

fn prev(k: usize, b: &Block) -> usize {
    (k + b.vertices().len() - 1) % b.vertices().len()
}

/// The entrance of vertex `p` of block `v` through edge `e` of block `w`, if
/// the vertex can enter there. Rows are for the contact's blocks in the order
/// (vertex block, edge block), or the reverse with `swap`.
fn entrance(
    v: &Block,
    p: usize,
    w: &Block,
    e: usize,
    range: f64,
    swap: bool,
) -> Option<Entrance<6, 1>> {
    // Only convex (or flat) vertices enter; a reflex vertex is entered instead.
    if is_reflex(v, p) {
        return None;
    }
    let p1 = v.vertices()[p];
    let (q1, q2) = (w.vertices()[e], w.vertices()[next(e, w)]);
    let edge = q2 - q1;
    let Edge {
        length: l,
        tangent,
        normal,
    } = w.edges()[e];
    let gap = normal.dot(&(p1 - q1));
    if !within_band(gap, range) {
        return None;
    }
    let along = tangent.dot(&(p1 - q1)) / l;
    // Past the ends when approaching (near a corner); when behind, only by
    // its depth within the angle tolerance, as where the corners of two
    // parallel edges meet: there round-off puts each vertex a hair past
    // the other's edge, and the corner would find no entrance at all.
    let slack = if gap > 0.0 {
        range / l
    } else {
        -gap * ANGLE_TOLERANCE.tan() / l
    };
    if !(-slack..=1.0 + slack).contains(&along) {
        return None;
    }
    // The vertex's wedge must lie outside the edge's line.
    let before = v.vertices()[prev(p, v)] - p1;
    let after = v.vertices()[next(p, v)] - p1;
    let sin_tol = ANGLE_TOLERANCE.sin();
    if normal.dot(&before.normalize()) < -sin_tol || normal.dot(&after.normalize()) < -sin_tol {
        return None;
    }
    // Shi's linearised distance: gap = −Δ/l with Δ = (q2 − q1) × (p1 − q1).
    let tv = t_matrix(&p1, &v.centroid());
    let t1 = t_matrix(&q1, &w.centroid());
    let t2 = t_matrix(&q2, &w.centroid());
    let n_vertex = -cross_row(&edge, &tv) / l;
    let n_edge = -(cross_row(&(p1 - q2), &t1) - cross_row(&(p1 - q1), &t2)) / l;
    // Tangential motion of the vertex relative to its projection on the edge.
    let foot = q1 + edge * along.clamp(0.0, 1.0);
    let s_vertex = tv.transpose() * tangent;
    let s_edge = -(t_matrix(&foot, &w.centroid()).transpose() * tangent);
    let (normal_rows, tangent_rows) = if swap {
        ([n_edge, n_vertex], [s_edge, s_vertex])
    } else {
        ([n_vertex, n_edge], [s_vertex, s_edge])
    };
    Some(Entrance {
        gap,
        normal: normal_rows,
        tangents: [tangent_rows],
    })
}

/// Whether a vertex at `gap` from an edge's line can enter through it:
/// ahead of the edge by less than the range, or behind it by less than
/// Shi's penetration distance (0.3 of the range). A vertex deeper behind an
/// edge's line is inside the block only if it is deep behind another edge
/// too, and for thin blocks it is usually outside it altogether.
fn within_band(gap: f64, range: f64) -> bool {
    gap < range && gap > -PENETRATION_SHARE * range
}

/// Row r with r·D = a × (T·D) for a 2D cross product.
fn cross_row(a: &Vector2<f64>, t: &Matrix2x6<f64>) -> Vector6<f64> {
    (t.row(1) * a.x - t.row(0) * a.y).transpose()
}

/// The boundary length a vertex stands for against an edge, and the length
/// its springs stand for: the same where it has one; for a corner touching
/// the edge (no side of it along the edge), half of its side most nearly
/// along the edge, the length that side would bring into contact.
fn lengths(v: &Block, p: usize, w: &Block, e: usize) -> (f64, f64) {
    let length = contact_length(v, p, w, e);
    if length > 0.0 {
        return (length, length);
    }
    let p1 = v.vertices()[p];
    let tangent = (w.vertices()[next(e, w)] - w.vertices()[e]).normalize();
    let side = [v.vertices()[prev(p, v)], v.vertices()[next(p, v)]]
        .iter()
        .map(|q| q - p1)
        .max_by(|s, t| {
            let along = |x: &Vector2<f64>| (x.dot(&tangent) / x.norm()).abs();
            along(s).total_cmp(&along(t))
        })
        .expect("a polygon vertex has two sides");
    (0.0, side.norm() / 2.0)
}

/// Boundary length a vertex stands for against an edge: for each of its
/// edges that runs along the entered edge, half of the stretch where the
/// two overlap. Each end of that stretch is a contact (this vertex, and a
/// vertex of one block or the other at the far end), so the two stand for
/// it once: a joint is `penalty` stiff per metre however its blocks
/// overlap. Half of the vertex's own edge, clipped, counted a half-offset
/// overlap twice (the running bond's bed joints).
fn contact_length(v: &Block, p: usize, w: &Block, e: usize) -> f64 {
    let p1 = v.vertices()[p];
    let (q1, q2) = (w.vertices()[e], w.vertices()[next(e, w)]);
    let l = (q2 - q1).norm();
    let tangent = (q2 - q1) / l;
    let mut total = 0.0;
    for other in [v.vertices()[prev(p, v)], v.vertices()[next(p, v)]] {
        let side = other - p1;
        if side.norm() == 0.0 || (side.normalize().dot(&tangent)).abs() < ANGLE_TOLERANCE.cos() {
            continue;
        }
        let s0 = tangent.dot(&(p1 - q1));
        let s1 = s0 + tangent.dot(&side);
        let (lo, hi) = (s0.min(s1).max(0.0), s0.max(s1).min(l));
        total += (hi - lo).max(0.0) / 2.0;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::{move_point, RotationUpdate};

    fn block(points: &[(f64, f64)]) -> Block {
        let v: Vec<Point2<f64>> = points.iter().map(|&(x, y)| Point2::new(x, y)).collect();
        Block::new(&v, 0, 1000.0).unwrap()
    }

    /// A unit square whose bottom-left corner sits on the top edge of a
    /// wider, tilted base, between its ends.
    fn pair() -> Vec<Block> {
        vec![
            block(&[(-2.0, -1.1), (2.0, -0.9), (2.0, 0.1), (-2.0, -0.1)]),
            block(&[(0.0, 0.0), (1.0, 0.05), (0.95, 1.05), (-0.05, 1.0)]),
        ]
    }

    fn signed_distance(p: &Point2<f64>, q1: &Point2<f64>, q2: &Point2<f64>) -> f64 {
        let t = (q2 - q1).normalize();
        Vector2::new(t.y, -t.x).dot(&(p - q1))
    }

    /// Two bricks of a wall squeezed together at their head joint, as a
    /// step left them: each pair of corners meets, a hair inside the other
    /// brick, and round-off puts each corner just past the other's edge.
    /// Both corners are found, each closed by its depth.
    #[test]
    fn meeting_corners_of_a_squeezed_head_joint_are_both_found() {
        let blocks = vec![
            block(&[
                (9.499999641393076, -2.275629695877579e-5),
                (10.00000031290121, -2.2753075836587366e-5),
                (10.000000295098468, 0.24997155830749368),
                (9.499999623590334, 0.24997155508637148),
            ]),
            block(&[
                (9.99999968709879, -2.2753075836587366e-5),
                (10.500000358606924, -2.275629695877579e-5),
                (10.500000376409666, 0.24997155508637148),
                (9.999999704901532, 0.24997155830749368),
            ]),
        ];
        let contacts = pair_contacts(&blocks, 0, 1, 0.22, 0);
        let corners: Vec<(u32, u32)> = contacts
            .iter()
            .map(|c| (c.key.feature_a, c.key.feature_b & !VERTEX))
            .collect();
        assert_eq!(corners, [(1, 0), (2, 3)], "{contacts:?}");
        for c in &contacts {
            let deepest = c.entrances.iter().map(|e| e.gap).fold(0.0, f64::min);
            assert!((-6.3e-7..-5.8e-7).contains(&deepest), "{deepest}");
        }
    }

    #[test]
    fn vertex_edge_rows_are_the_derivatives_of_the_exact_gap_and_slip() {
        let blocks = pair();
        let contacts = pair_contacts(&blocks, 1, 0, 0.05, 0);
        assert!(contacts
            .iter()
            .any(|c| contact_label(&c.key) == "1:v0/0:e2"));
        let c = contacts
            .iter()
            .find(|c| c.key.feature_a == 0 && c.key.feature_b == 2)
            .expect("corner 0 of the square against the base's top edge");
        assert_eq!(c.blocks, [1, 0]);
        let e = &c.entrances[0];
        let (sq, base) = (&blocks[1], &blocks[0]);
        let p = sq.vertices()[0];
        let (q1, q2) = (base.vertices()[2], base.vertices()[3]);
        assert!((e.gap - signed_distance(&p, &q1, &q2)).abs() < 1e-15);
        let foot = q1 + (q2 - q1) * ((p - q1).dot(&(q2 - q1)) / (q2 - q1).norm_squared());
        let h = 1e-7;
        for k in 0..12 {
            let mut da = Vector6::zeros();
            let mut db = Vector6::zeros();
            if k < 6 {
                da[k] = h
            } else {
                db[k - 6] = h
            }
            let gap = |s: f64| {
                let m = |x: &Point2<f64>, b: &Block, d: &Vector6<f64>| {
                    move_point(x, &b.centroid(), &(d * s), RotationUpdate::Exact)
                };
                signed_distance(&m(&p, sq, &da), &m(&q1, base, &db), &m(&q2, base, &db))
            };
            let slip = |s: f64| {
                let m = |x: &Point2<f64>, b: &Block, d: &Vector6<f64>| {
                    move_point(x, &b.centroid(), &(d * s), RotationUpdate::Exact)
                };
                let t = (m(&q2, base, &db) - m(&q1, base, &db)).normalize();
                t.dot(&(m(&p, sq, &da) - m(&foot, base, &db)))
            };
            let fd_gap = (gap(1.0) - gap(-1.0)) / (2.0 * h);
            let fd_slip = (slip(1.0) - slip(-1.0)) / (2.0 * h);
            let row_gap = e.normal[0].dot(&da) / h + e.normal[1].dot(&db) / h;
            let row_slip = e.tangents[0][0].dot(&da) / h + e.tangents[0][1].dot(&db) / h;
            assert!(
                (fd_gap - row_gap).abs() < 1e-6,
                "gap DOF {k}: {fd_gap} vs {row_gap}"
            );
            assert!(
                (fd_slip - row_slip).abs() < 1e-6,
                "slip DOF {k}: {fd_slip} vs {row_slip}"
            );
        }
    }

    #[test]
    fn coincident_corners_make_one_contact_with_the_right_entrance() {
        // Two equal squares stacked: each bottom corner of the top one sits on
        // a top corner of the lower one.
        let blocks = vec![
            block(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]),
            block(&[(0.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)]),
        ];
        let contacts = pair_contacts(&blocks, 0, 1, 0.01, 0);
        assert_eq!(contacts.len(), 2, "one contact per corner: {contacts:?}");
        for c in &contacts {
            // Pushing the top block down must close every entrance, and
            // sliding it sideways must not open or close any.
            let down = Vector6::new(0.0, -1e-4, 0.0, 0.0, 0.0, 0.0);
            let side = Vector6::new(1e-4, 0.0, 0.0, 0.0, 0.0, 0.0);
            for e in &c.entrances {
                assert!(e.gap_at(&Vector6::zeros(), &down) < -0.99e-4);
                assert!(e.gap_at(&Vector6::zeros(), &side).abs() < 1e-12);
            }
        }
        // A vertex against the far side of a block is no contact.
        let apart = vec![
            blocks[0].clone(),
            block(&[(1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0)]),
        ];
        let side_by_side = pair_contacts(&apart, 0, 1, 0.01, 0);
        assert_eq!(side_by_side.len(), 2);
        let right = Vector6::new(-1e-4, 0.0, 0.0, 0.0, 0.0, 0.0);
        for c in &side_by_side {
            let widest = c
                .entrances
                .iter()
                .map(|e| e.gap_at(&Vector6::zeros(), &right))
                .fold(f64::MIN, f64::max);
            assert!(
                widest < -0.99e-4,
                "moving the right block left must penetrate"
            );
        }
    }

    #[test]
    fn contact_length_is_half_of_each_edge_along_the_contact() {
        let blocks = vec![
            block(&[(-5.0, -1.0), (5.0, -1.0), (5.0, 0.0), (-5.0, 0.0)]),
            block(&[(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)]),
        ];
        let contacts = pair_contacts(&blocks, 1, 0, 0.01, 0);
        assert_eq!(contacts.len(), 2);
        let total: f64 = contacts.iter().map(|c| c.length).sum();
        assert!(
            (total - 2.0).abs() < 1e-12,
            "the two corners stand for the 2 m base: {total}"
        );
    }

    /// Two blocks overlapping along part of their edges (a running bond's
    /// bed joint at offset 1): one corner of each stands at an end of the
    /// overlap, and together they stand for it once.
    #[test]
    fn a_partial_overlap_is_stood_for_once() {
        for offset in [0.1, 0.5, 1.0, 1.5, 1.9] {
            let blocks = vec![
                block(&[(0.0, -1.0), (2.0, -1.0), (2.0, 0.0), (0.0, 0.0)]),
                block(&[
                    (offset, 0.0),
                    (offset + 2.0, 0.0),
                    (offset + 2.0, 1.0),
                    (offset, 1.0),
                ]),
            ];
            let contacts = pair_contacts(&blocks, 1, 0, 0.01, 0);
            assert_eq!(contacts.len(), 2, "offset {offset}");
            let overlap = 2.0 - offset;
            for c in &contacts {
                assert!(
                    (c.length - overlap / 2.0).abs() < 1e-12,
                    "offset {offset}: a corner stands for {}, half the {overlap} m overlap",
                    c.length
                );
            }
        }
    }

    /// The vertices found by examining only those near the other block are
    /// the ones found by examining all: for an L-shaped block (a reflex
    /// corner) and a turned rectangle or L placed and ranged at random near
    /// each other, the contacts are the same, in the same order.
    #[test]
    fn examining_only_near_vertices_finds_every_contact() {
        use proptest::prelude::*;
        let outline = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ];
        let l = block(&outline);
        let mut runner = proptest::test_runner::TestRunner::new_with_rng(
            proptest::test_runner::Config::with_cases(1024),
            proptest::test_runner::TestRng::deterministic_rng(
                proptest::test_runner::RngAlgorithm::ChaCha,
            ),
        );
        let cases = (
            prop::array::uniform2(-1.6..1.6f64),
            -3.2..3.2f64,
            0.005..0.4f64,
            any::<bool>(),
        );
        let touching = std::cell::Cell::new(0);
        runner
            .run(&cases, |(at, turn, range, concave)| {
                let shape: Vec<(f64, f64)> = if concave {
                    outline.to_vec()
                } else {
                    vec![(0.0, 0.0), (1.2, 0.0), (1.2, 0.7), (0.0, 0.7)]
                };
                let (c, s) = (turn.cos(), turn.sin());
                let placed: Vec<(f64, f64)> = shape
                    .iter()
                    .map(|&(x, y)| (c * x - s * y + at[0] + 1.0, s * x + c * y + at[1] + 1.0))
                    .collect();
                let blocks = vec![l.clone(), block(&placed)];
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
}
