//! Point loads, fixed (or driven) points and measured points, in a space of
//! `D` dimensions.

use std::sync::Arc;

use nalgebra::{Point, SMatrix, SVector};

use crate::error::DdaError;
use crate::motion::GroundMotion;
use crate::settings::finite;

/// The names of the axes of a space of `D` dimensions.
fn axes<const D: usize>() -> &'static [&'static str] {
    &["x", "y", "z"][..D.min(3)]
}

/// Each of `values` is finite; the error names `field`.
fn finite_all<'a>(
    field: &'static str,
    what: &str,
    values: impl IntoIterator<Item = &'a f64>,
) -> Result<(), DdaError> {
    values.into_iter().try_for_each(|v| finite(field, what, *v))
}

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

impl<const D: usize> PointLoad<D> {
    /// Checks that the point and the force are finite and that a history
    /// has samples in time order; the error names the field (`point`,
    /// `force`, `history`) and, for a sample, its index.
    pub fn check(&self) -> Result<(), DdaError> {
        finite_all("point", "the load point", &self.point.coords)?;
        let samples = match &self.force {
            Force::Constant(f) => return finite_all("force", "the force", f),
            Force::History(samples) => samples,
        };
        if samples.is_empty() {
            let forces: Vec<String> = axes::<D>().iter().map(|a| format!("f{a}")).collect();
            return Err(DdaError::Setting {
                field: "history",
                message: format!(
                    "the history is empty; give at least one (t, {}) sample",
                    forces.join(", ")
                ),
            });
        }
        let at = |index, message| DdaError::Entry {
            field: "history",
            index,
            message,
        };
        for (i, (t, f)) in samples.iter().enumerate() {
            finite_all("", "the sample", std::iter::once(t).chain(f)).map_err(|e| match e {
                DdaError::Setting { message, .. } => at(i, message),
                e => e,
            })?;
            if let Some((before, _)) = i.checked_sub(1).map(|p| samples[p]) {
                if *t < before {
                    return Err(at(
                        i,
                        format!("the sample's time {t} comes before the previous one's ({before}); list samples in time order"),
                    ));
                }
            }
        }
        Ok(())
    }
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

    /// Checks that the point and its velocity are finite and that an axis
    /// has a direction; the error names the field (`point`, `velocity`,
    /// `axis`).
    pub fn check(&self) -> Result<(), DdaError> {
        finite_all("point", "the fixed point", &self.point.coords)?;
        finite_all("point", "the fixed point", &self.target.coords)?;
        finite_all("velocity", "the velocity", &self.velocity)?;
        self.axis
            .as_ref()
            .map_or(Ok(()), |a| direction(a).map(drop))
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

/// The unit vector along `axis` (of any length, however small or large),
/// or why it has none; the error names the field `axis`.
pub fn direction<const D: usize>(axis: &SVector<f64, D>) -> Result<SVector<f64, D>, DdaError> {
    finite_all("axis", "the axis", axis)?;
    let scale = axis.amax();
    if scale == 0.0 {
        let (example, all) = if D == 3 {
            ("(0.0, 1.0, 0.0)", "all three")
        } else {
            ("(1.0, 0.0)", "both")
        };
        let shown: Vec<String> = axis.iter().map(f64::to_string).collect();
        return Err(DdaError::Setting {
            field: "axis",
            message: format!(
                "the axis ({}) has no direction; give the direction to hold, like {example}, or leave axis out to hold {all}",
                shown.join(", ")
            ),
        });
    }
    // Scaled first so tiny or huge components neither underflow nor overflow.
    let v = axis / scale;
    Ok(v / v.norm())
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

    /// Checks that the point is finite; the error names the field `point`.
    pub fn check(&self) -> Result<(), DdaError> {
        let what = "the measured point";
        finite_all("point", what, self.start.iter().chain(&self.point.coords))
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

    fn field_of(e: DdaError) -> (&'static str, Option<usize>) {
        match e {
            DdaError::Setting { field, .. } => (field, None),
            DdaError::Entry { field, index, .. } => (field, Some(index)),
            e => panic!("{e}"),
        }
    }

    #[test]
    fn a_load_is_finite_and_its_history_in_time_order() {
        let load = |force| PointLoad {
            block: 0,
            point: Point2::new(0.5, 1.0),
            force,
        };
        let f = Vector2::new(0.0, -1e4);
        assert!(load(Force::Constant(f)).check().is_ok());
        let e = load(Force::Constant(Vector2::new(f64::INFINITY, 0.0))).check();
        let e = e.unwrap_err();
        assert!(e
            .to_string()
            .contains("the force is inf, not a finite number"));
        assert_eq!(field_of(e), ("force", None));
        let mut nan = load(Force::Constant(f));
        nan.point.y = f64::NAN;
        assert_eq!(field_of(nan.check().unwrap_err()), ("point", None));
        let e = load(Force::History(vec![])).check().unwrap_err();
        assert!(e
            .to_string()
            .contains("give at least one (t, fx, fy) sample"));
        assert_eq!(field_of(e), ("history", None));
        let late = load(Force::History(vec![(1.0, f), (0.5, f)])).check();
        let e = late.unwrap_err();
        assert!(e
            .to_string()
            .contains("comes before the previous one's (1)"));
        assert_eq!(field_of(e), ("history", Some(1)));
        let e = load(Force::History(vec![(0.0, f), (f64::NAN, f)])).check();
        assert_eq!(field_of(e.unwrap_err()), ("history", Some(1)));
    }

    #[test]
    fn a_fixed_point_is_finite_and_its_axis_a_direction() {
        let mut p = FixedPoint::at(0, Point2::new(1.0, 2.0));
        assert!(p.check().is_ok());
        p.axis = Some(Vector2::new(0.0, 0.0));
        let e = p.check().unwrap_err();
        assert!(e.to_string().contains("the axis (0, 0) has no direction"));
        assert_eq!(field_of(e), ("axis", None));
        p.axis = Some(Vector2::new(f64::NAN, 1.0));
        assert_eq!(field_of(p.check().unwrap_err()), ("axis", None));
        p.axis = None;
        p.velocity.x = f64::INFINITY;
        assert_eq!(field_of(p.check().unwrap_err()), ("velocity", None));
        // A tiny axis is still a direction.
        let n = direction(&Vector2::new(1e-300, 1e-300)).unwrap();
        assert!((n.norm() - 1.0).abs() < 1e-15 && n.x > 0.0);
        let e = direction(&nalgebra::Vector3::zeros()).unwrap_err();
        assert!(e
            .to_string()
            .contains("like (0.0, 1.0, 0.0), or leave axis out to hold all three"));
    }

    #[test]
    fn a_measured_point_is_finite() {
        assert!(MeasuredPoint::at(0, Point2::new(1.0, 2.0)).check().is_ok());
        let e = MeasuredPoint::at(0, Point2::new(1.0, f64::NAN)).check();
        assert_eq!(field_of(e.unwrap_err()), ("point", None));
    }
}
