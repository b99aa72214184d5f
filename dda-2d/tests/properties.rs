//! Properties of the polygon integrals, the T-matrix and the contact
//! geometry, over random polygons and placements.

use dda_2d::kinematics::{move_point, t_matrix, RotationUpdate};
use dda_2d::polygon::{central_moments, moments_about, signed_area};
use dda_2d::Block;
use nalgebra::{Point2, Rotation2, Vector2, Vector6};
use proptest::prelude::*;

/// A convex polygon: corners on an ellipse at sorted random angles.
fn convex() -> impl Strategy<Value = Vec<Point2<f64>>> {
    (
        prop::collection::vec(0.0..1.0f64, 3..12),
        0.2..5.0f64,
        0.2..5.0f64,
        -10.0..10.0f64,
        -10.0..10.0f64,
    )
        .prop_filter_map("corners too close", |(mut t, a, b, x, y)| {
            t.sort_by(f64::total_cmp);
            t.dedup_by(|p, q| (*p - *q).abs() < 0.02);
            if t.len() < 3 || 1.0 - t[t.len() - 1] + t[0] < 0.02 {
                return None;
            }
            let corners: Vec<Point2<f64>> = t
                .iter()
                .map(|s| {
                    let angle = s * std::f64::consts::TAU;
                    Point2::new(x + a * angle.cos(), y + b * angle.sin())
                })
                .collect();
            (signed_area(&corners) > 1e-3).then_some(corners)
        })
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-9 * scale.max(1.0)
}

proptest! {
    /// Area and the second moments about the centroid do not change when
    /// the polygon moves rigidly; the centroid moves with it.
    #[test]
    fn integrals_follow_a_rigid_motion(p in convex(), angle in -3.2..3.2f64,
                                       dx in -50.0..50.0f64, dy in -50.0..50.0f64) {
        let r = Rotation2::new(angle);
        let shift = Vector2::new(dx, dy);
        let moved: Vec<Point2<f64>> = p.iter().map(|v| r * v + shift).collect();
        let (m0, m1) = (central_moments(&p), central_moments(&moved));
        prop_assert!(close(m0.area, m1.area, m0.area));
        let c = r * m0.centroid + shift;
        prop_assert!((c - m1.centroid).norm() <= 1e-9 * (1.0 + c.coords.norm()));
        // The polar moment is invariant; the tensor turns with the body.
        let polar = |m: &dda_2d::polygon::CentralMoments| m.xx + m.yy;
        prop_assert!(close(polar(&m0), polar(&m1), polar(&m0)));
        let tensor = |m: &dda_2d::polygon::CentralMoments| {
            nalgebra::Matrix2::new(m.xx, m.xy, m.xy, m.yy)
        };
        let turned = r.matrix() * tensor(&m0) * r.matrix().transpose();
        prop_assert!((turned - tensor(&m1)).norm() <= 1e-9 * (1.0 + tensor(&m0).norm()));
    }

    /// Cut along a chord, the two parts' area and moments about any point
    /// add up to the whole's.
    #[test]
    fn integrals_add_under_subdivision(p in convex(), k in 2usize..11, ox in -5.0..5.0f64, oy in -5.0..5.0f64) {
        let k = 2 + k % (p.len() - 2).max(1);
        prop_assume!(k < p.len());
        let first: Vec<Point2<f64>> = p[..=k].to_vec();
        let second: Vec<Point2<f64>> = p[k..].iter().chain(&p[..1]).copied().collect();
        let o = Point2::new(ox, oy);
        let (w, a, b) = (moments_about(&p, &o), moments_about(&first, &o), moments_about(&second, &o));
        let scale = w.sxx.abs() + w.syy.abs() + w.area;
        for (whole, x, y) in [
            (w.area, a.area, b.area),
            (w.sx, a.sx, b.sx),
            (w.sy, a.sy, b.sy),
            (w.sxx, a.sxx, b.sxx),
            (w.syy, a.syy, b.syy),
            (w.sxy, a.sxy, b.sxy),
        ] {
            prop_assert!(close(whole, x + y, scale), "{whole} vs {x} + {y}");
        }
    }

    /// The T-matrix is the derivative of the exact motion at d = 0, and the
    /// linear update is x + T·d exactly.
    #[test]
    fn the_t_matrix_is_the_motions_derivative(
        px in -3.0..3.0f64, py in -3.0..3.0f64,
        d in prop::array::uniform6(-1.0..1.0f64),
    ) {
        let (p, c) = (Point2::new(px, py), Point2::new(0.3, -0.2));
        let d = Vector6::from_column_slice(&d);
        let t = t_matrix(&p, &c);
        let linear = move_point(&p, &c, &d, RotationUpdate::Linear);
        prop_assert!((linear - (p + t * d)).norm() <= 1e-12 * (1.0 + p.coords.norm()));
        let eps = 1e-6;
        let exact = move_point(&p, &c, &(d * eps), RotationUpdate::Exact);
        let slope = (exact - p) / eps;
        // The second-order term is eps·|d|²·|p − c|: a few 1e-6 here.
        prop_assert!((slope - t * d).norm() <= 1e-5 * (1.0 + (p - c).norm()), "{slope} vs {}", t * d);
    }

    /// A corner above (or in) an edge has the signed distance to the edge's
    /// line as its gap: positive apart, negative overlapping.
    #[test]
    fn a_corners_gap_is_its_signed_distance(x in -1.5..1.5f64, h in -0.02..0.05f64, tilt in -0.5..0.5f64) {
        let base = [
            Point2::new(-2.0, -1.0), Point2::new(2.0, -1.0),
            Point2::new(2.0, 0.0), Point2::new(-2.0, 0.0),
        ];
        // A triangle standing on its tip at (x, h).
        let tip = Point2::new(x, h);
        let r = Rotation2::new(tilt);
        let triangle = [tip, tip + r * Vector2::new(0.4, 0.8), tip + r * Vector2::new(-0.4, 0.8)];
        let blocks = vec![
            Block::new(&base, 0, 2000.0).unwrap(),
            Block::new(&triangle, 0, 2000.0).unwrap(),
        ];
        let contacts = dda_2d::contact::pair_contacts(&blocks, 0, 1, 0.1, 0);
        let at_tip: Vec<_> = contacts
            .iter()
            .filter(|c| c.key.block_a == 1 && blocks[1].vertices()[c.key.feature_a as usize] == tip)
            .collect();
        prop_assert_eq!(at_tip.len(), 1, "one contact at the tip: {:?}", contacts.iter().map(|c| c.key).collect::<Vec<_>>());
        let gap = at_tip[0].entrances.iter().map(|e| e.gap).fold(f64::NEG_INFINITY, f64::max);
        prop_assert!((gap - h).abs() <= 1e-12, "gap {} at height {}", gap, h);
    }
}
