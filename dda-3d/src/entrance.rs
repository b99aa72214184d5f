//! A 3D entrance kept as its two points and its frame: 16 numbers (136
//! bytes) from which its 72 row entries are made when read (a point's row
//! is the T-matrix transposed times a direction), the same to the last bit
//! as rows made once. A 10,000-block wall's contacts keep some 320,000
//! entrances, made every step; as rows they took 584 bytes each.

use dda_core::EntranceRows;
use nalgebra::{Vector2, Vector3};

use crate::kinematics::{t_matrix_times_arm, t_matrix_transpose_times_arm, Vector12};

/// How far apart, as a share, two entrances may lie and count as one
/// ([`PointEntrance::same_as`]): round-off, not geometry.
const SAME_SHARE: f64 = 1e-12;

/// A point of one block against a point of another along a unit normal,
/// linearised about the start of the step.
#[derive(Debug, Clone, PartialEq)]
pub struct PointEntrance {
    /// Gap at the start of the step (negative: penetration).
    pub gap: f64,
    /// Each block's point less its centroid, in the contact's block order.
    arms: [Vector3<f64>; 2],
    /// Whether the contact's first block is the entering one (its rows
    /// positive, the entered block's negative).
    entering_first: bool,
    /// The unit normal (from the entered block towards the entering one)
    /// and the two tangents.
    frame: [Vector3<f64>; 3],
}

impl PointEntrance {
    /// The entering block's point at `enter` from its centroid, the entered
    /// block's at `entered`, normal `n`, tangents `t1` and `t2`; with
    /// `swap` the contact's blocks are (entered, entering).
    pub fn new(
        gap: f64,
        enter: Vector3<f64>,
        entered: Vector3<f64>,
        frame: [Vector3<f64>; 3],
        swap: bool,
    ) -> Self {
        Self {
            gap,
            arms: if swap {
                [entered, enter]
            } else {
                [enter, entered]
            },
            entering_first: !swap,
            frame,
        }
    }

    /// Whether `other` is this entrance to within round-off (1e-12 of the
    /// unit normal, 1e-12 of `length` for the gap and each point): the same
    /// plane through the same points, whatever its tangents. Either block
    /// may be the entering one: a point of a entering b's plane along n is
    /// b's point entering a's along −n, the same rows and gap.
    pub fn same_as(&self, other: &Self, length: f64) -> bool {
        let near = |a: &Vector3<f64>, b: &Vector3<f64>, tol: f64| (a - b).norm() <= tol;
        let tol = SAME_SHARE * length;
        let normal = if self.entering_first == other.entering_first {
            other.frame[0]
        } else {
            -other.frame[0]
        };
        near(&self.frame[0], &normal, SAME_SHARE)
            && (self.gap - other.gap).abs() <= tol
            && near(&self.arms[0], &other.arms[0], tol)
            && near(&self.arms[1], &other.arms[1], tol)
    }

    /// The entering point's displacement less the entered point's, the
    /// blocks moving by `da` and `db`.
    #[inline]
    fn approach(&self, da: &Vector12, db: &Vector12) -> Vector3<f64> {
        let a = t_matrix_times_arm(&self.arms[0], da);
        let b = t_matrix_times_arm(&self.arms[1], db);
        if self.entering_first {
            a - b
        } else {
            b - a
        }
    }

    /// The two blocks' rows along direction `v`.
    #[inline]
    fn rows(&self, v: &Vector3<f64>) -> [Vector12; 2] {
        // Not `[0, 1].map(..)`: that built the pair aside and copied it,
        // a call to memcpy a contact a move (1.7 % of a 3D wall's samples).
        [self.row(0, v), self.row(1, v)]
    }

    /// Block `side`'s row along direction `v`: the entering block's
    /// positive, the entered one's negative.
    #[inline]
    fn row(&self, side: usize, v: &Vector3<f64>) -> Vector12 {
        let row = t_matrix_transpose_times_arm(&self.arms[side], v);
        if self.entering_first == (side == 0) {
            row
        } else {
            -row
        }
    }
}

impl EntranceRows<12, 2> for PointEntrance {
    #[inline]
    fn gap(&self) -> f64 {
        self.gap
    }

    #[inline]
    fn normal(&self) -> [Vector12; 2] {
        self.rows(&self.frame[0])
    }

    #[inline]
    fn tangent(&self, k: usize) -> [Vector12; 2] {
        self.rows(&self.frame[1 + k])
    }

    /// One block's row alone: a diagonal block of the tangent reads no
    /// other (half the products).
    #[inline]
    fn normal_of(&self, side: usize) -> Vector12 {
        self.row(side, &self.frame[0])
    }

    #[inline]
    fn tangent_of(&self, k: usize, side: usize) -> Vector12 {
        self.row(side, &self.frame[1 + k])
    }

    /// By the points' motion: the rows dotted with the motions, summed
    /// in another order (the same to round-off).
    #[inline]
    fn gap_at(&self, da: &Vector12, db: &Vector12) -> f64 {
        self.gap + self.frame[0].dot(&self.approach(da, db))
    }

    #[inline]
    fn shear_at(&self, da: &Vector12, db: &Vector12) -> Vector2<f64> {
        self.gap_and_shear_at(da, db).1
    }

    #[inline]
    fn gap_and_shear_at(&self, da: &Vector12, db: &Vector12) -> (f64, Vector2<f64>) {
        let s = self.approach(da, db);
        let shear = Vector2::new(self.frame[1].dot(&s), self.frame[2].dot(&s));
        (self.gap + self.frame[0].dot(&s), shear)
    }

    /// The contact force at the points, given to each block by one
    /// transposed product where the rows take three.
    #[inline]
    fn spread(&self, normal: f64, shear: &Vector2<f64>) -> [Vector12; 2] {
        let [n, t1, t2] = &self.frame;
        self.rows(&(n * normal + t1 * shear[0] + t2 * shear[1]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::t_matrix_transpose_times;
    use nalgebra::Point3;

    /// The gap, the shear and the forces read through the points' motion
    /// are those of the rows, to round-off, in either block order and for
    /// motions with strain.
    #[test]
    fn the_points_motion_and_forces_are_the_rows() {
        use dda_core::Entrance;
        use proptest::prelude::*;
        let mut runner = crate::seeded_runner(1024);
        let vector = || prop::array::uniform3(-5.0..5.0f64).prop_map(Vector3::from);
        let dofs = || prop::array::uniform12(-1e-2..1e-2f64).prop_map(Vector12::from);
        let forces = (-1e6..1e6f64, -1e6..1e6f64, -1e6..1e6f64);
        let cases = (
            vector(),
            vector(),
            vector(),
            any::<bool>(),
            dofs(),
            dofs(),
            forces,
        );
        runner
            .run(
                &cases,
                |(enter, entered, n, swap, da, db, (fn_, f1, f2))| {
                    let Some(n) = n.try_normalize(1e-3) else {
                        return Ok(());
                    };
                    let t1 = n.cross(&Vector3::new(0.3, -0.7, 0.2)).normalize();
                    let t2 = n.cross(&t1);
                    let e = PointEntrance::new(0.01, enter, entered, [n, t1, t2], swap);
                    let rows = Entrance {
                        gap: e.gap(),
                        normal: e.normal(),
                        tangents: [e.tangent(0), e.tangent(1)],
                    };
                    // The size of the products summed, for round-off.
                    let arm = 1.0 + enter.norm().max(entered.norm());
                    let motion = arm * (da.norm() + db.norm());
                    let (gap, shear) = e.gap_and_shear_at(&da, &db);
                    prop_assert!((gap - rows.gap_at(&da, &db)).abs() <= 1e-14 * (0.01 + motion));
                    prop_assert_eq!(gap.to_bits(), e.gap_at(&da, &db).to_bits());
                    prop_assert!((shear - rows.shear_at(&da, &db)).norm() <= 1e-14 * motion);
                    prop_assert_eq!(shear, e.shear_at(&da, &db));
                    let shear_force = Vector2::new(f1, f2);
                    let force = arm * (fn_.abs() + shear_force.norm());
                    let spread = e.spread(fn_, &shear_force);
                    let made = rows.spread(fn_, &shear_force);
                    for (s, m) in spread.iter().zip(&made) {
                        prop_assert!((s - m).abs().max() <= 1e-14 * force, "{s} {m}");
                    }
                    Ok(())
                },
            )
            .unwrap();
    }

    /// A point of a entering b's plane along n and b's point entering a's
    /// along −n are one entrance: the same normal rows, to the bit, and the
    /// same gap at any motion, whatever their tangents; `same_as` says so.
    /// A point moved, the normal turned or the gap changed by more than
    /// round-off is another entrance.
    #[test]
    fn an_entrance_seen_from_either_block_is_one() {
        let (pa, ca) = (Point3::new(0.3, -1.7, 2.9), Point3::new(0.11, -1.2, 2.5));
        let (pb, cb) = (Point3::new(0.31, -1.69, 2.93), Point3::new(0.7, -2.1, 3.3));
        let n = Vector3::new(0.2, -0.5, 0.9).normalize();
        let frame = |n: Vector3<f64>, towards: Vector3<f64>| {
            let t1 = n.cross(&towards).normalize();
            [n, t1, n.cross(&t1)]
        };
        let (gap, length) = (n.dot(&(pa - pb)), 4.0);
        let a_enters = PointEntrance::new(gap, pa - ca, pb - cb, frame(n, Vector3::x()), false);
        let b_enters = PointEntrance::new(gap, pb - cb, pa - ca, frame(-n, Vector3::y()), true);
        assert!(a_enters.same_as(&b_enters, length) && b_enters.same_as(&a_enters, length));
        assert_eq!(a_enters.normal(), b_enters.normal());
        use proptest::prelude::*;
        let dofs = || prop::array::uniform12(-1e-2..1e-2f64).prop_map(Vector12::from);
        let mut runner = crate::seeded_runner(256);
        runner
            .run(&(dofs(), dofs()), |(da, db)| {
                let (ga, gb) = (a_enters.gap_at(&da, &db), b_enters.gap_at(&da, &db));
                prop_assert!((ga - gb).abs() <= 1e-15 * length, "{ga} {gb}");
                Ok(())
            })
            .unwrap();
        let apart = 1e-9 * length;
        let turned = (n + 1e-9 * frame(n, Vector3::x())[1]).normalize();
        let others = [
            PointEntrance::new(
                gap,
                pa - ca + Vector3::x() * apart,
                pb - cb,
                frame(n, Vector3::x()),
                false,
            ),
            PointEntrance::new(
                gap,
                pa - ca,
                pb - cb + Vector3::z() * apart,
                frame(n, Vector3::x()),
                false,
            ),
            PointEntrance::new(gap + apart, pa - ca, pb - cb, frame(n, Vector3::x()), false),
            PointEntrance::new(gap, pa - ca, pb - cb, frame(turned, Vector3::x()), false),
            PointEntrance::new(gap, pb - cb, pa - ca, frame(n, Vector3::y()), true),
        ];
        for other in &others {
            assert!(!a_enters.same_as(other, length), "{other:?}");
        }
    }

    /// Rows made when read are the rows made once from the points, to the
    /// last bit, in either block order; and so is each block's row read
    /// alone.
    #[test]
    fn rows_read_are_the_rows_made_from_the_points() {
        let (pa, ca) = (Point3::new(0.3, -1.7, 2.9), Point3::new(0.11, -1.2, 2.5));
        let (pb, cb) = (Point3::new(0.31, -1.69, 2.93), Point3::new(0.7, -2.1, 3.3));
        let n = Vector3::new(0.2, -0.5, 0.9).normalize();
        let t1 = n.cross(&Vector3::new(1.0, 0.3, -0.2)).normalize();
        let t2 = n.cross(&t1);
        for swap in [false, true] {
            let e = PointEntrance::new(n.dot(&(pa - pb)), pa - ca, pb - cb, [n, t1, t2], swap);
            for (v, rows) in [(n, e.normal()), (t1, e.tangent(0)), (t2, e.tangent(1))] {
                let enter = t_matrix_transpose_times(&pa, &ca, &v);
                let entered = -t_matrix_transpose_times(&pb, &cb, &v);
                let made = if swap {
                    [entered, enter]
                } else {
                    [enter, entered]
                };
                assert_eq!(rows, made);
            }
            for side in [0, 1] {
                assert_eq!(e.normal_of(side), e.normal()[side]);
                for k in [0, 1] {
                    assert_eq!(e.tangent_of(k, side), e.tangent(k)[side]);
                }
            }
        }
    }
}
