//! A 3D entrance kept as its two points and its frame: 16 numbers (136
//! bytes) from which its 72 row entries are made when read (a point's row
//! is the T-matrix transposed times a direction), the same to the last bit
//! as rows made once. A 10,000-block wall's contacts keep some 320,000
//! entrances, made every step; as rows they took 584 bytes each.

use dda_core::EntranceRows;
use nalgebra::Vector3;

use crate::kinematics::{t_matrix_transpose_times_arm, Vector12};

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

    /// The two blocks' rows along direction `v`.
    #[inline]
    fn rows(&self, v: &Vector3<f64>) -> [Vector12; 2] {
        let [a, b] = self.arms.map(|arm| t_matrix_transpose_times_arm(&arm, v));
        if self.entering_first {
            [a, -b]
        } else {
            [-a, b]
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::t_matrix_transpose_times;
    use nalgebra::Point3;

    /// Rows made when read are the rows made once from the points, to the
    /// last bit, in either block order.
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
        }
    }
}
