//! Properties of the polyhedron integrals and the T-matrix over random
//! boxes, cuts and motions.

use dda_3d::cut::{cut, Convex, JointPlane};
use dda_3d::kinematics::{move_point, t_matrix};
use dda_3d::polyhedron::validate;
use dda_3d::RotationUpdate;
use nalgebra::{Point3, Rotation3, SVector, Vector3};
use proptest::prelude::*;

fn vector() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-1.0..1.0f64).prop_map(Vector3::from)
}

/// A box and one plane through it, cut into two convex blocks.
fn split_box() -> impl Strategy<Value = ([f64; 3], Vector3<f64>, f64)> {
    (prop::array::uniform3(0.5..4.0f64), vector(), -0.4..0.4f64)
        .prop_filter("a plane needs a direction", |(_, n, _)| n.norm() > 0.2)
}

proptest! {
    /// Cut by a plane, the two blocks' volumes, first and second moments
    /// about the origin add up to the box's.
    #[test]
    fn integrals_add_under_subdivision((size, n, s) in split_box()) {
        let max = Point3::new(size[0], size[1], size[2]);
        let region = Convex::cuboid(Point3::origin(), max).unwrap();
        let centre = max.coords / 2.0;
        let plane = JointPlane { normal: n, offset: n.dot(&centre) + s * n.norm(), set: 0, joint: 0 };
        let parts = cut(&region, &[plane], 0.0).unwrap();
        prop_assume!(parts.blocks.len() == 2);
        let whole = size[0] * size[1] * size[2];
        let mut volume = 0.0;
        let mut first = Vector3::zeros();
        let mut second = nalgebra::Matrix3::zeros();
        for (corners, faces) in &parts.blocks {
            let p = validate(corners, faces).unwrap();
            let m = p.moments();
            volume += m.volume;
            first += m.volume * m.centroid.coords;
            // Parallel axis: about the origin.
            let c = m.centroid.coords;
            second += m.second + m.volume * c * c.transpose();
        }
        prop_assert!((volume - whole).abs() <= 1e-9 * whole);
        prop_assert!((first - whole * centre).norm() <= 1e-9 * whole * (1.0 + centre.norm()));
        let expected = nalgebra::Matrix3::from_diagonal(&Vector3::new(
            whole * size[0] * size[0] / 3.0,
            whole * size[1] * size[1] / 3.0,
            whole * size[2] * size[2] / 3.0,
        )) + whole * (centre * centre.transpose() - nalgebra::Matrix3::from_diagonal(&centre.component_mul(&centre)));
        prop_assert!((second - expected).norm() <= 1e-9 * expected.norm(), "{second} vs {expected}");
    }

    /// Volume and centroid follow a rigid motion.
    #[test]
    fn integrals_follow_a_rigid_motion(size in prop::array::uniform3(0.5..4.0f64), axis in vector(),
                                       angle in -3.0..3.0f64, shift in vector()) {
        let max = Point3::new(size[0], size[1], size[2]);
        let region = Convex::cuboid(Point3::origin(), max).unwrap();
        let (corners, faces) = cut(&region, &[], 0.0).unwrap().blocks.remove(0);
        let p = validate(&corners, &faces).unwrap();
        let r = Rotation3::new(axis * angle);
        let q = p.moved(|v| r * v + shift * 10.0);
        prop_assert!((p.volume() - q.volume()).abs() <= 1e-9 * p.volume());
        let c = r * p.centroid() + shift * 10.0;
        prop_assert!((c - q.centroid()).norm() <= 1e-9 * (1.0 + c.coords.norm()));
        let turned = r.matrix() * p.moments().second * r.matrix().transpose();
        prop_assert!((turned - q.moments().second).norm() <= 1e-9 * p.moments().second.norm());
    }

    /// The T-matrix is the derivative of the exact motion at d = 0, and the
    /// linear update is x + T·d exactly.
    #[test]
    fn the_t_matrix_is_the_motions_derivative(p in vector(), d in prop::array::uniform12(-1.0..1.0f64)) {
        let (p, c) = (Point3::from(p * 3.0), Point3::new(0.3, -0.2, 0.1));
        let d = SVector::<f64, 12>::from_column_slice(&d);
        let t = t_matrix(&p, &c);
        let linear = move_point(&p, &c, &d, RotationUpdate::Linear);
        prop_assert!((linear - (p + t * d)).norm() <= 1e-12 * (1.0 + p.coords.norm()));
        let eps = 1e-6;
        let exact = move_point(&p, &c, &(d * eps), RotationUpdate::Exact);
        let slope = (exact - p) / eps;
        prop_assert!((slope - t * d).norm() <= 1e-5 * (1.0 + (p - c).norm()), "{slope} vs {}", t * d);
    }

    /// A corner above (or in) a face has the signed distance to the face's
    /// plane as its gap: positive apart, negative overlapping.
    #[test]
    fn a_corners_gap_is_its_signed_distance(x in -1.2..1.2f64, y in -1.2..1.2f64,
                                            h in -0.02..0.05f64, axis in vector(), tilt in 0.0..0.4f64) {
        let (base, faces) = cut(&Convex::cuboid(Point3::new(-2.0, -2.0, -1.0), Point3::new(2.0, 2.0, 0.0)).unwrap(), &[], 0.0)
            .unwrap().blocks.remove(0);
        // A tetrahedron standing on its tip at (x, y, h), tilted a little.
        let tip = Point3::new(x, y, h);
        let r = Rotation3::new(axis.try_normalize(1e-9).unwrap_or(Vector3::x()) * tilt);
        let up = [Vector3::new(0.5, 0.0, 0.8), Vector3::new(-0.25, 0.43, 0.8), Vector3::new(-0.25, -0.43, 0.8)];
        let mut corners = vec![tip];
        corners.extend(up.iter().map(|u| tip + r * u));
        let tetra_faces = vec![vec![0, 2, 1], vec![0, 3, 2], vec![0, 1, 3], vec![1, 2, 3]];
        let blocks = vec![
            dda_3d::Block::new(&base, &faces, 0, 2000.0).unwrap(),
            dda_3d::Block::new(&corners, &tetra_faces, 0, 2000.0).unwrap(),
        ];
        let contacts = dda_3d::contact::pair_contacts(&blocks, 0, 1, 0.1, 0);
        let at_tip: Vec<_> = contacts.iter()
            .filter(|c| c.key.block_a == 1 && c.key.feature_a == 0)
            .collect();
        prop_assert_eq!(at_tip.len(), 1, "one contact at the tip: {:?}", contacts.iter().map(|c| c.key).collect::<Vec<_>>());
        let gap = at_tip[0].entrances.iter().map(|e| e.gap).fold(f64::NEG_INFINITY, f64::max);
        prop_assert!((gap - h).abs() <= 1e-12, "gap {} at height {}", gap, h);
    }
}
