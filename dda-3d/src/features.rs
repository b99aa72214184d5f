//! Which features of two polyhedra the narrow phase tests: every vertex,
//! edge and face pair that may make a contact within a range, found by
//! distances alone. Found at a wider range, the same list serves later
//! searches while no point of either block has moved by more than half the
//! difference (each distance tested changes by at most twice that), so a
//! standing wall's narrow phase tests its few near features instead of
//! every pair of them.

use dda_core::block_set::Reach;
use nalgebra::Point3;

use crate::block::Block;
use crate::contact::{apart, grown_bounds, segment_distance, within, Bounds, Feature};
use crate::polyhedron::Polyhedron;

/// A vertex makes a vertex-face contact only within the range of the face
/// (ahead of its plane by less than the range over its inside, or beside a
/// reflex edge by less than the range): within √2 times the range, so
/// within that of the face's plane. Kept within 1.5 times, the slack covers
/// round-off.
const FACE_REACH: f64 = 1.5;

/// The features of blocks `i` and `j` that may make contacts in a search
/// within `range` or wider, while no point of either block has moved by
/// more than half of `wide` less the range searched: in the order the
/// narrow phase takes them (vertex-vertex, then each side's vertices with
/// the other block's edges and faces, then edge-edge), every pair whose
/// distance test passes within `wide`, each block's within the other's
/// reach at `wide`, less those a convex corner within `2·range − wide`
/// rules out (an end of the edge near the vertex, a corner of the face,
/// an end of either edge near the other). A distance between points of the
/// two blocks changes by at most twice what a point moves, so such a
/// corner stays within the range searched, and rules the feature out,
/// while it stays convex.
pub fn pair_features(blocks: &[Block], i: usize, j: usize, range: f64, wide: f64) -> Vec<Feature> {
    let (sa, sb) = (blocks[i].shape(), blocks[j].shape());
    let near_a = Reach::new(sa.bounds(), wide);
    let near_b = Reach::new(sb.bounds(), wide);
    let sure = 2.0 * range - wide;
    let mut out = Vec::new();
    for (p, pv) in sa.vertices().iter().enumerate() {
        if !near_b.holds(pv) {
            continue;
        }
        for (q, qv) in sb.vertices().iter().enumerate() {
            if (pv - qv).norm() < wide {
                out.push(Feature::VertexVertex(p as u32, q as u32));
            }
        }
    }
    for (side, (sx, sy, near_x, near_y)) in [(sa, sb, &near_a, &near_b), (sb, sa, &near_b, &near_a)]
        .into_iter()
        .enumerate()
    {
        let side = side as u8;
        let edges = edges_meeting(sy, near_x, wide);
        for (p, pv) in sx.vertices().iter().enumerate() {
            if !near_y.holds(pv) {
                continue;
            }
            let corner =
                |k: &usize| sy.is_convex_vertex(*k) && (sy.vertices()[*k] - pv).norm() < sure;
            for (e, bounds) in &edges {
                let ends = sy.edges()[*e].ends;
                let [q0, q1] = ends.map(|k| sy.vertices()[k]);
                if within(bounds, pv)
                    && segment_distance(pv, &q0, &q1).0 < wide
                    && !ends.iter().any(corner)
                {
                    out.push(Feature::VertexEdge(side, p as u32, *e as u32));
                }
            }
            for f in 0..sy.faces().len() {
                if face_within(sy, f, pv, FACE_REACH * wide) && !sy.faces()[f].iter().any(corner) {
                    out.push(Feature::VertexFace(side, p as u32, f as u32));
                }
            }
        }
    }
    let (edges_a, edges_b) = (
        edges_meeting(sa, &near_b, wide),
        edges_meeting(sb, &near_a, wide),
    );
    // A convex end of one edge within `sure` of the other edge.
    let end_near = |s: &Polyhedron, ends: [usize; 2], o: &Polyhedron, other: [usize; 2]| {
        let [u, v] = other.map(|k| o.vertices()[k]);
        (ends.iter())
            .any(|&k| s.is_convex_vertex(k) && segment_distance(&s.vertices()[k], &u, &v).0 < sure)
    };
    for (ea, bounds_a) in &edges_a {
        for (eb, bounds_b) in &edges_b {
            let (ends_a, ends_b) = (sa.edges()[*ea].ends, sb.edges()[*eb].ends);
            if !apart(bounds_a, bounds_b)
                && !end_near(sa, ends_a, sb, ends_b)
                && !end_near(sb, ends_b, sa, ends_a)
            {
                out.push(Feature::EdgeEdge(*ea as u32, *eb as u32));
            }
        }
    }
    out
}

/// The edges of `s` whose bounds meet `reach`, each with its bounds grown
/// by `range`.
fn edges_meeting(s: &Polyhedron, reach: &Reach<3>, range: f64) -> Vec<(usize, Bounds)> {
    (s.edges().iter().enumerate())
        .filter_map(|(e, edge)| {
            let [u, v] = edge.ends.map(|k| s.vertices()[k]);
            reach
                .meets(&u, &v)
                .then(|| (e, grown_bounds(&u, &v, range)))
        })
        .collect()
}

/// Whether `p` may lie within `reach` of face `f` of `s`: within it of the
/// face's plane (no farther than the face).
fn face_within(s: &Polyhedron, f: usize, p: &Point3<f64>, reach: f64) -> bool {
    s.face_frame(f).height(p).abs() < reach
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::tests::l_block;
    use crate::contact::{contact_label, contacts_among, pair_contacts};
    use crate::polyhedron::cuboid;
    use dda_core::contacts::same_contacts;
    use nalgebra::{Rotation3, Vector3};
    use proptest::prelude::*;

    /// Motion of a block: a turn about its first vertex, then a shift.
    type Motion = (Rotation3<f64>, Vector3<f64>);

    /// An L-shaped prism (reflex edges and a concave face; its first vertex
    /// at the origin) and a box at `box_at` turned by `turn`, each moved.
    fn placed(box_at: Point3<f64>, turn: Rotation3<f64>, [l, b]: [Motion; 2]) -> Vec<Block> {
        let moved = |(turn, shift): Motion, at: Point3<f64>| {
            move |p: &Point3<f64>| at + turn * (p - at) + shift
        };
        let (v, f) = cuboid(box_at, Vector3::new(1.0, 0.8, 0.6), turn);
        let v: Vec<_> = v.iter().map(moved(b, v[0])).collect();
        vec![
            l_block(moved(l, Point3::origin())),
            Block::new(&v, &f, 0, 1000.0).unwrap(),
        ]
    }

    /// Features found at a range a quarter wider, for blocks that have
    /// since moved by up to an eighth of the range (each point), make the
    /// contacts a search of the moved blocks finds, the same to the bit, at
    /// that range or wider as far as the motion allows.
    #[test]
    fn features_found_wider_make_the_contacts_of_blocks_moved_since() {
        let mut runner = crate::seeded_runner(1024);
        let cases = (
            prop::array::uniform3(-1.6..1.6f64),
            prop::array::uniform3(-0.6..0.6f64),
            0.005..0.4f64,
            prop::array::uniform6(-1.0..1.0f64),
            prop::array::uniform6(-1.0..1.0f64),
            0.0..1.0f64,
        );
        let (touching, changed) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
        let crossings = std::cell::Cell::new(0);
        runner
            .run(&cases, |(at, turn, range, m0, m1, longer)| {
                let box_at = Point3::from(Vector3::from(at) + Vector3::new(1.0, 1.0, 0.5));
                let turn = Rotation3::from_euler_angles(turn[0], turn[1], turn[2]);
                let still = (Rotation3::identity(), Vector3::zeros());
                let blocks = placed(box_at, turn, [still, still]);
                let wide = 1.25 * range;
                let features = pair_features(&blocks, 0, 1, range, wide);
                // Each point moves by at most an eighth of the range: a
                // shift of up to 0.1 of it and a turn of up to 0.02/3.2 of
                // it in radians about a point at most 3.2 away.
                let motion = |m: [f64; 6]| {
                    let turn = Rotation3::from_scaled_axis(
                        Vector3::new(m[0], m[1], m[2]) * range * 0.02 / 3.2 / 3.0_f64.sqrt(),
                    );
                    (
                        turn,
                        Vector3::new(m[3], m[4], m[5]) * range * 0.1 / 3.0_f64.sqrt(),
                    )
                };
                let moved = placed(box_at, turn, [motion(m0), motion(m1)]);
                let farthest = (blocks.iter().zip(&moved))
                    .flat_map(|(b, m)| {
                        b.vertices()
                            .iter()
                            .zip(m.vertices())
                            .map(|(p, q)| (p - q).norm())
                    })
                    .fold(0.0, f64::max);
                prop_assert!(range + 2.0 * farthest <= wide, "moved {farthest}");
                // Searched again at the range asked or wider, as far as the
                // motion allows.
                let later = range + longer * (wide - 2.0 * farthest - range);
                let near = |b: &Block| Reach::new(b.shape().bounds(), later);
                let among = contacts_among(
                    &moved,
                    0,
                    1,
                    later,
                    0,
                    (&near(&moved[0]), &near(&moved[1])),
                    &features,
                );
                let searched = pair_contacts(&moved, 0, 1, later, 0);
                touching.set(touching.get() + usize::from(!searched.is_empty()));
                let crossing = |c: &crate::contact::Contact3| {
                    contact_label(&c.key)
                        .split('/')
                        .next()
                        .is_some_and(|a| a.contains(":e"))
                };
                crossings.set(crossings.get() + searched.iter().filter(|c| crossing(c)).count());
                let keys =
                    |c: &[crate::contact::Contact3]| c.iter().map(|c| c.key).collect::<Vec<_>>();
                let before = pair_contacts(&blocks, 0, 1, later, 0);
                changed.set(changed.get() + usize::from(keys(&before) != keys(&searched)));
                prop_assert!(
                    same_contacts(&among, &searched),
                    "{} against {}",
                    among.len(),
                    searched.len()
                );
                Ok(())
            })
            .unwrap();
        // Many placements touch, some with edges crossing, and the motion
        // changes which features touch in many.
        let (touching, changed) = (touching.get(), changed.get());
        assert!(crossings.get() > 20, "{} crossings", crossings.get());
        assert!(touching > 100, "{touching} of 1024 placements had contacts");
        assert!(
            changed > 20,
            "the motion changed which features touch in {changed} placements"
        );
    }
}
