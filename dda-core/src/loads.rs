//! Point loads, fixed (or driven) points and measured points, in a space of
//! `D` dimensions.

use std::sync::Arc;

use nalgebra::{Point, SMatrix, SVector};

use crate::motion::GroundMotion;

/// A force at a material point, constant or a time history.
#[derive(Debug, Clone, PartialEq)]
pub enum Force<const D: usize> {
    Constant(SVector<f64, D>),
    /// (time, force) samples, linearly interpolated, held beyond the ends.
    History(Vec<(f64, SVector<f64, D>)>),
}

impl<const D: usize> Force<D> {
    pub fn at(&self, t: f64) -> SVector<f64, D> {
        match self {
            Force::Constant(f) => *f,
            Force::History(samples) => {
                let Some(first) = samples.first() else {
                    return SVector::zeros();
                };
                if t <= first.0 {
                    return first.1;
                }
                for w in samples.windows(2) {
                    let ((t0, f0), (t1, f1)) = (w[0], w[1]);
                    if t <= t1 {
                        let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
                        return f0 + (f1 - f0) * s;
                    }
                }
                samples.last().map(|s| s.1).unwrap_or_else(SVector::zeros)
            }
        }
    }
}

/// A point load on a block; the point moves with the block.
#[derive(Debug, Clone, PartialEq)]
pub struct PointLoad<const D: usize> {
    pub block: usize,
    pub point: Point<f64, D>,
    pub force: Force<D>,
}

/// A point of a block held by a penalty spring at
/// `target + velocity·t + ground(t)` (a fixed point when both are zero, a
/// driven one otherwise). With an `axis` only the motion along that unit
/// vector is held.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedPoint<const D: usize> {
    pub block: usize,
    pub point: Point<f64, D>,
    pub target: Point<f64, D>,
    pub velocity: SVector<f64, D>,
    pub axis: Option<SVector<f64, D>>,
    /// Ground motion carried by this point (base blocks in earthquakes).
    pub ground: Option<Arc<GroundMotion<D>>>,
}

impl<const D: usize> FixedPoint<D> {
    /// A point held where it is.
    pub fn at(block: usize, point: Point<f64, D>) -> Self {
        Self {
            block,
            point,
            target: point,
            velocity: SVector::zeros(),
            axis: None,
            ground: None,
        }
    }

    /// Where the point is held at time t.
    pub fn target_at(&self, t: f64) -> Point<f64, D> {
        let ground = self
            .ground
            .as_ref()
            .map_or(SVector::zeros(), |g| g.displacement(t));
        self.target + self.velocity * t + ground
    }

    /// The projector onto the held directions.
    pub fn held(&self) -> SMatrix<f64, D, D> {
        match self.axis {
            Some(n) => n * n.transpose(),
            None => SMatrix::identity(),
        }
    }

    /// Whether the point is driven (moves with time), so it does work.
    pub fn is_driven(&self) -> bool {
        self.velocity != SVector::<f64, D>::zeros() || self.ground.is_some()
    }
}

/// A point of a block whose motion is recorded; nothing acts there. It
/// moves with its block as load and fixed points do.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredPoint<const D: usize> {
    pub block: usize,
    /// Where it was when the system was built.
    pub start: Point<f64, D>,
    /// Where it is now.
    pub point: Point<f64, D>,
}

impl<const D: usize> MeasuredPoint<D> {
    /// A point of `block` at `point`, not yet moved.
    pub fn at(block: usize, point: Point<f64, D>) -> Self {
        Self {
            block,
            start: point,
            point,
        }
    }

    /// How far it has moved since the start.
    pub fn displacement(&self) -> SVector<f64, D> {
        self.point - self.start
    }
}

/// One held direction of a fixed or driven point: the spring along `row`
/// (the point's displacement along the direction is `row·d` for the block's
/// step displacement d), so the driver can put a dashpot beside it.
#[derive(Debug, Clone, PartialEq)]
pub struct Support<const N: usize> {
    pub block: usize,
    pub row: SVector<f64, N>,
    /// Spring stiffness (force per length).
    pub stiffness: f64,
    /// How far the point's target moves along the direction in the step.
    pub target_step: f64,
}

/// The held directions of `fixed` for a step from `start` to `end`; `t`
/// gives a point's T-matrix (D × N) on its block.
pub fn supports<const D: usize, const N: usize>(
    fixed: &[FixedPoint<D>],
    stiffness: f64,
    (start, end): (f64, f64),
    t: impl Fn(&FixedPoint<D>) -> SMatrix<f64, D, N>,
) -> Vec<Support<N>> {
    let mut rows = Vec::new();
    for f in fixed {
        let t = t(f);
        let moved = f.target_at(end) - f.target_at(start);
        let directions: Vec<SVector<f64, D>> = match f.axis {
            Some(n) => vec![n],
            None => (0..D)
                .map(|k| SVector::<f64, D>::from_fn(|r, _| if r == k { 1.0 } else { 0.0 }))
                .collect(),
        };
        for n in directions {
            rows.push(Support {
                block: f.block,
                row: t.transpose() * n,
                stiffness,
                target_step: n.dot(&moved),
            });
        }
    }
    rows
}

/// Energy stored in the springs (of stiffness `stiffness`) that hold fixed
/// points, or `None` when a point is driven and so does work on the blocks.
pub fn held_energy<const D: usize>(fixed: &[FixedPoint<D>], stiffness: f64) -> Option<f64> {
    if fixed.iter().any(|f| f.is_driven()) {
        return None;
    }
    Some(
        fixed
            .iter()
            .map(|f| 0.5 * stiffness * (f.held() * (f.target - f.point)).norm_squared())
            .sum(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point2, Vector2};

    #[test]
    fn load_histories_interpolate_and_hold() {
        let f = Force::History(vec![
            (0.0, Vector2::new(0.0, 0.0)),
            (2.0, Vector2::new(4.0, -2.0)),
        ]);
        assert_eq!(f.at(-1.0), Vector2::new(0.0, 0.0));
        assert_eq!(f.at(0.5), Vector2::new(1.0, -0.5));
        assert_eq!(f.at(3.0), Vector2::new(4.0, -2.0));
    }

    #[test]
    fn driven_points_move_and_hold_only_their_axis() {
        let mut p = FixedPoint::at(0, Point2::new(1.0, 2.0));
        assert!(!p.is_driven());
        p.velocity = Vector2::new(0.5, 0.0);
        p.axis = Some(Vector2::new(1.0, 0.0));
        assert!(p.is_driven());
        assert_eq!(p.target_at(2.0), Point2::new(2.0, 2.0));
        assert_eq!(p.held() * Vector2::new(3.0, 4.0), Vector2::new(3.0, 0.0));
    }
}
