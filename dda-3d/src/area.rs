//! The area a contact's springs stand for (its `length`): every corner of
//! where two faces overlap is a contact, a vertex of either block over the
//! other's face (vertex-face) or a point where their edges cross
//! (edge-edge), and each stands for the part of the overlap nearer it than
//! any other corner (a quarter of a rectangle). So a joint is `penalty`
//! stiff per square metre however its blocks overlap: each end's share of
//! its own face, clipped, counted a half-offset overlap twice (a running
//! bond's bed joints). A group takes the largest area of its vertex-face
//! entrances.
//! Against a concave face, or from a face of more than [`WHOLE_FACE`]
//! corners, a vertex stands for its share of its own face (the
//! quadrilateral of the vertex, the midpoints of its two sides and the
//! face's centroid) clipped to the entered one.

use dda_core::block_set::ANGLE_TOLERANCE;
use dda_core::planar;
use nalgebra::{Point2, Point3};

use crate::block::Block;
use crate::face::FaceFrame;
use crate::polyhedron::Polyhedron;

/// The most corners of an entered face clipped against whole (a face of
/// more is clipped triangle by triangle): a corner's share of four corners
/// clipped by five sides stays within `planar::clipped_area`'s room on the
/// stack.
const WHOLE_FACE: usize = 5;

/// Points of an overlap closer than this share of its face's size are one
/// (a clip repeats a point lying on a cut).
const MERGED_CORNERS: f64 = 1e-9;

/// The area a contact at `at` stands for where the convex faces `own` and
/// `entered` (at most [`WHOLE_FACE`] corners each, in the entered face's
/// plane) overlap: the part nearer it than any other corner of the overlap
/// (a quarter of a rectangular one). Each corner of the overlap is a
/// contact: a corner of either face over the other (a vertex contact) or
/// where their edges cross (an edge-edge one), so together they stand for
/// the overlap once, and a joint is `penalty` stiff per square metre
/// however its blocks overlap. Corners within `range` of each other are
/// one contact (a corner just off the other face, as a loaded brick's
/// spreads past the one on it, and the crossing beside it); corners
/// turning by less than the contact's angle tolerance are none (edges that
/// near parallel make no crossing).
fn overlap_cell(own: &[Point2<f64>], entered: &[Point2<f64>], at: &Point2<f64>, range: f64) -> f64 {
    let (lo, hi) = planar::bounds(own);
    let merge = MERGED_CORNERS * (hi - lo).norm();
    let near = range.max(merge);
    planar::clip_on_stack(own, entered, true, |overlap| {
        planar::corners_on_stack(overlap, merge, ANGLE_TOLERANCE.sin(), |corners| {
            if corners.len() < 3 {
                return 0.0;
            }
            // The contact's own corner, so that the cells tile the overlap.
            let own = (corners.iter())
                .min_by(|c, d| (*c - at).norm().total_cmp(&(*d - at).norm()))
                .filter(|c| (*c - at).norm() <= near)
                .unwrap_or(at);
            planar::site_cell_area(overlap, own, corners, near)
        })
        .unwrap_or(0.0)
    })
    .expect("two faces of at most five corners clip on the stack")
}

/// The corners of `shape`'s face `face` (at most [`WHOLE_FACE`]) in
/// `frame`'s plane, the rest left at the origin.
fn in_plane(frame: &FaceFrame, shape: &Polyhedron, face: &[usize]) -> [Point2<f64>; WHOLE_FACE] {
    let mut corners = [Point2::origin(); WHOLE_FACE];
    for (c, k) in corners.iter_mut().zip(face) {
        *c = frame.to_plane(&shape.vertices()[*k]);
    }
    corners
}

/// The area an edge-edge crossing of `a`'s edge `ea` and `b`'s edge `eb`
/// stands for: its part of the overlap of a face of each at the two edges
/// facing each other ([`overlap_cell`]); `None` where no two such faces
/// face each other, convex and of at most [`WHOLE_FACE`] corners.
pub(crate) fn crossing_area(a: &Block, ea: usize, b: &Block, eb: usize, range: f64) -> Option<f64> {
    let (sa, sb) = (a.shape(), b.shape());
    let mut best: Option<f64> = None;
    for &g in &sa.edges()[ea].faces {
        for &f in &sb.edges()[eb].faces {
            let facing = -sa.normal(g).dot(&sb.normal(f));
            let (own, entered) = (&sa.faces()[g], &sb.faces()[f]);
            if facing < ANGLE_TOLERANCE.cos()
                || !sa.is_convex_face(g)
                || !sb.is_convex_face(f)
                || own.len() > WHOLE_FACE
                || entered.len() > WHOLE_FACE
            {
                continue;
            }
            let frame = sb.face_frame(f);
            let polygon = in_plane(&frame, sa, own);
            let outline = in_plane(&frame, sb, entered);
            // Where the two edges cross, in the entered face's plane.
            let [u, v] = sa.edges()[ea]
                .ends
                .map(|k| frame.to_plane(&sa.vertices()[k]));
            let [w, z] = sb.edges()[eb]
                .ends
                .map(|k| frame.to_plane(&sb.vertices()[k]));
            let (d, e) = (v - u, z - w);
            let across = d.perp(&e);
            if across == 0.0 {
                continue;
            }
            let at = u + d * ((w - u).perp(&e) / across);
            let area = overlap_cell(&polygon[..own.len()], &outline[..entered.len()], &at, range);
            best = Some(best.map_or(area / facing, |b: f64| b.max(area / facing)));
        }
    }
    best
}

/// Area a vertex stands for against a face: for each face at the vertex
/// lying on the contact plane (facing the entered face within 3°), its part
/// of where the two faces overlap ([`overlap_cell`]), on its own face, not
/// on the entered one's plane. A corner's share of its own face clipped to
/// the entered one counted a half-offset overlap twice, as in a running
/// bond's bed joints. Against a concave face, or from one of more than
/// [`WHOLE_FACE`] corners, the vertex's share of its own face (the
/// quadrilateral of the vertex, the midpoints of its two sides and the
/// face's centroid) clipped to the entered one. Second, the area its springs
/// stand for: the same where it has one; for a corner touching the face (no
/// face of it on the plane), its whole share of the face most nearly facing
/// the entered one, the area that face would bring into contact.
pub(crate) fn vertex_areas(x: &Block, p: usize, y: &Block, f: usize, range: f64) -> (f64, f64) {
    let (sx, sy) = (x.shape(), y.shape());
    let n = sy.normal(f);
    let frame = sy.face_frame(f);
    let on_plane = |k: &usize| frame.to_plane(&sy.vertices()[*k]);
    // The entered face in its plane, made only for a face at the vertex
    // found facing it (for most groups none is): whole where it is convex
    // (one clip instead of one a triangle), else its triangles.
    let whole = sy.is_convex_face(f) && sy.faces()[f].len() <= WHOLE_FACE;
    let mut outline = None;
    let share = |g: usize| -> [Point2<f64>; 4] {
        let face = &sx.faces()[g];
        let k = face.iter().position(|&v| v == p).unwrap_or(0);
        let m = face.len();
        let at = |i: usize| sx.vertices()[face[i]];
        let corner = at(k);
        let next = Point3::from((corner.coords + at((k + 1) % m).coords) / 2.0);
        let prev = Point3::from((corner.coords + at((k + m - 1) % m).coords) / 2.0);
        // Counter-clockwise about g's normal is clockwise in f's frame.
        [prev, sx.face_centroid(g), next, corner].map(|q| frame.to_plane(&q))
    };
    let mut total = 0.0;
    for &g in sx.vertex_faces(p) {
        let facing = -sx.normal(g).dot(&n);
        if facing < ANGLE_TOLERANCE.cos() {
            continue;
        }
        let face = &sy.faces()[f];
        if whole && outline.is_none() {
            outline = Some(in_plane(&frame, sy, face));
        }
        let outline = outline.as_ref().map(|o| &o[..face.len()]);
        let own = &sx.faces()[g];
        if let Some(outline) = outline.filter(|_| sx.is_convex_face(g) && own.len() <= WHOLE_FACE) {
            let polygon = in_plane(&frame, sx, own);
            let polygon = &polygon[..own.len()];
            let (lo, hi) = planar::bounds(polygon);
            let corner = frame.to_plane(&sx.vertices()[p]);
            let area = if planar::bounds_meet(&(lo, hi), &planar::bounds(outline)) {
                overlap_cell(polygon, outline, &corner, range)
            } else {
                0.0
            };
            total += area / facing;
            continue;
        }
        let share = share(g);
        let reach = planar::bounds(&share);
        // Clipped in f's plane, then taken back to g's own: the corner's
        // area below is g's true area, and a vertex passing between the
        // two (an edge of f at its share) keeps its springs' area. Left
        // projected, the two differed by 3.7e-7 on a prism settling on an
        // incline of its own depth, and its energy jumped by that. Pieces
        // whose bounds only touch the share's, or are apart, hold none of
        // it.
        let clipped = |piece: &[Point2<f64>]| {
            if planar::bounds_meet(&planar::bounds(piece), &reach) {
                planar::clipped_area(&share, piece).abs()
            } else {
                0.0
            }
        };
        let area = match outline {
            Some(outline) => clipped(outline),
            None => (sy.face_triangles(f).iter())
                .map(|t| clipped(&t.each_ref().map(on_plane)))
                .sum::<f64>(),
        };
        total += area / facing;
    }
    if total > 0.0 {
        return (total, total);
    }
    let facing = sx
        .vertex_faces(p)
        .iter()
        .copied()
        .min_by(|&g, &h| sx.normal(g).dot(&n).total_cmp(&sx.normal(h).dot(&n)));
    // The share's true area: half the cross product of its diagonals.
    let springs = facing.map_or(0.0, |g| {
        let face = &sx.faces()[g];
        let k = face.iter().position(|&v| v == p).unwrap_or(0);
        let m = face.len();
        let at = |i: usize| sx.vertices()[face[i]];
        let diagonal = sx.face_centroid(g) - at(k);
        let across = (at((k + 1) % m) - at((k + m - 1) % m)) / 2.0;
        diagonal.cross(&across).norm() / 2.0
    });
    (0.0, springs)
}
