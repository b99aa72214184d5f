//! Generators: scene entries that stand for several blocks (arches, columns,
//! walls, jointed domains), and the shapes of rectangles, boxes and prisms.
//! Each checks its own parameters and says which field is at fault and
//! what to change ([`Failure`]); the scene adds the place in the file.
//! Nonsense (too few voussoirs, non-positive sizes, too many blocks) is
//! refused before anything is made, never a panic or an endless loop.

use dda_core::settings::{finite, positive};
use dda_core::DdaError;
use nalgebra::{Point2, Point3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};

pub(crate) mod jointed;

/// How a wall's courses are cut (the wall generator's own choice; the
/// scene re-exports it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Bond {
    /// Every course cut at multiples of the brick length.
    Stack,
    /// Every second course starts with half a brick, so joints alternate.
    #[default]
    Running,
}

/// More blocks than this from one generator is taken as a mistake.
pub(crate) const MAX_PARTS: usize = 100_000;

/// One block made by an entry, in 2D (`[f64; 2]` corners) or 3D.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Piece<P = [f64; 2]> {
    /// Like "voussoir 3" or "course 1, brick 2"; none for an entry that
    /// makes one block.
    pub name: Option<String>,
    /// Counter-clockwise in 2D.
    pub vertices: Vec<P>,
    /// Each face's corners, counter-clockwise seen from outside; none in 2D.
    pub faces: Vec<Vec<usize>>,
    /// Held whatever the entry says (an arch's abutments, blocks below a
    /// jointed domain's `fixed_below`).
    pub always_fixed: bool,
}

/// Why an entry makes no blocks: the field at fault (of its joint set
/// `set`, when given; the entry as a whole when `field` is `None`) and what
/// to change.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Failure {
    pub set: Option<usize>,
    pub field: Option<&'static str>,
    pub message: String,
}

impl Failure {
    /// The entry as a whole.
    pub fn entry(message: String) -> Self {
        Self {
            set: None,
            field: None,
            message,
        }
    }

    pub fn field(field: &'static str, message: String) -> Self {
        Self {
            set: None,
            field: Some(field),
            message,
        }
    }
}

/// A check's error at the field it names.
impl From<DdaError> for Failure {
    fn from(e: DdaError) -> Self {
        match e {
            DdaError::Setting { field, message } => Failure::field(field, message),
            e => Failure::entry(e.to_string()),
        }
    }
}

/// What an entry makes: its blocks, and for a jointed domain which set
/// separates each pair of them, as (block, block, set).
pub(crate) struct Generated<P> {
    pub pieces: Vec<Piece<P>>,
    pub joints: Vec<(usize, usize, usize)>,
}

impl<P> From<Vec<Piece<P>>> for Generated<P> {
    fn from(pieces: Vec<Piece<P>>) -> Self {
        Self {
            pieces,
            joints: Vec::new(),
        }
    }
}

/// Each number of a point finite.
fn finite_all(field: &'static str, what: &str, values: &[f64]) -> Result<(), DdaError> {
    values.iter().try_for_each(|v| finite(field, what, *v))
}

impl<P> Piece<P> {
    pub fn new(name: Option<String>, vertices: Vec<P>, faces: Vec<Vec<usize>>) -> Self {
        Self {
            name,
            vertices,
            faces,
            always_fixed: false,
        }
    }
}

/// The arch's shape, as a scene gives it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct ArchShape {
    pub center: [f64; 2],
    pub radius: f64,
    pub thickness: f64,
    pub voussoirs: usize,
    /// Degrees.
    pub span_angle: f64,
    /// Offset of the two centres as a fraction of the radius.
    pub pointed: f64,
    pub abutments: bool,
}

impl ArchShape {
    /// Intrados and extrados radii.
    pub fn radii(&self) -> (f64, f64) {
        (
            self.radius - self.thickness / 2.0,
            self.radius + self.thickness / 2.0,
        )
    }

    /// Angle (degrees from +x, about the left half's centre) of the left
    /// springing joint.
    pub fn springing_angle(&self) -> f64 {
        90.0 + self.span_angle / 2.0
    }

    /// Angle (degrees, about the left half's centre) where the centreline
    /// meets the vertical through the centre: 90 for a round arch.
    pub fn crown_angle(&self) -> f64 {
        if self.pointed == 0.0 {
            90.0
        } else {
            (-self.pointed).acos().to_degrees()
        }
    }

    /// Whether the shape makes an arch: the first field at fault and what
    /// to change, as the core's checks say it.
    pub fn check(&self) -> Result<(), DdaError> {
        let fail = |field, message| Err(DdaError::Setting { field, message });
        let (r, t, e, span) = (self.radius, self.thickness, self.pointed, self.span_angle);
        let hint = "give the arch's size in m";
        finite_all("center", "the center", &self.center)?;
        positive("radius", "the radius", r, hint)?;
        positive("thickness", "the thickness", t, hint)?;
        if r <= t / 2.0 {
            return fail("radius", format!("the radius ({r}) must exceed half the thickness ({t}): it is the centreline's, with the intrados at radius − thickness/2; use a larger radius or a thinner arch"));
        }
        count("voussoirs", "voussoirs", self.voussoirs, 2)?;
        finite("span_angle", "the span angle", span)?;
        if !(span > 0.0 && span <= 180.0) {
            return fail("span_angle", format!("the span angle must lie in (0, 180] degrees, got {span}; 180 is a semicircular arch, less a segmental one"));
        }
        finite("pointed", "pointed", e)?;
        if !(0.0..1.0).contains(&e) {
            return fail("pointed", format!("pointed must lie in [0, 1), got {e}; it is the offset of the two centres as a fraction of the radius (0 for a round arch)"));
        }
        let (ri, _) = self.radii();
        if e > 0.0 && self.voussoirs % 2 == 1 {
            return fail("voussoirs", format!("a pointed arch needs an even number of voussoirs (half on each side of the crown joint), got {}", self.voussoirs));
        }
        if e > 0.0 && ri <= e * r {
            return fail("pointed", format!("the intrados (radius {ri}) does not reach the crown: the centres are {} from it; use a smaller pointed or a thinner arch", e * r));
        }
        if self.springing_angle() <= self.crown_angle() {
            let least = 2.0 * (self.crown_angle() - 90.0);
            return fail("span_angle", format!("a span angle of {span} degrees ends above the crown of this pointed arch; use more than {least} degrees"));
        }
        Ok(())
    }
}

/// A number of generated blocks: at least `min`, at most [`MAX_PARTS`].
pub(crate) fn count(field: &'static str, what: &str, n: usize, min: usize) -> Result<(), DdaError> {
    let message = if n < min {
        format!("{what} must be at least {min}, got {n}")
    } else if n > MAX_PARTS {
        format!("{n} {what} is more than the {MAX_PARTS} a generator makes; use fewer")
    } else {
        return Ok(());
    };
    Err(DdaError::Setting { field, message })
}

/// (cos, sin) of an angle in degrees, exact at multiples of 90°.
fn direction(degrees: f64) -> [f64; 2] {
    let r = degrees.rem_euclid(360.0);
    if r == 0.0 {
        [1.0, 0.0]
    } else if r == 90.0 {
        [0.0, 1.0]
    } else if r == 180.0 {
        [-1.0, 0.0]
    } else if r == 270.0 {
        [0.0, -1.0]
    } else {
        let (s, c) = degrees.to_radians().sin_cos();
        [c, s]
    }
}

/// Voussoirs from the left springing to the right, then the left and right
/// abutments. Joints are radial about the centre of their half (one centre
/// for a round arch); a pointed arch's crown joint is the vertical through
/// the centre. The right half mirrors the left exactly.
pub(crate) fn arch(shape: &ArchShape) -> Result<Vec<Piece>, DdaError> {
    shape.check()?;
    let n = shape.voussoirs;
    let (ri, re) = shape.radii();
    let offset = shape.pointed * shape.radius;
    let (spring, crown) = (shape.springing_angle(), shape.crown_angle());
    let half = n as f64 / 2.0;
    // Joints as (intrados, extrados), relative to the centre.
    let left = |j: usize| -> [[f64; 2]; 2] {
        if 2 * j == n {
            let up = |r: f64| {
                if offset == 0.0 {
                    r
                } else {
                    (r * r - offset * offset).sqrt()
                }
            };
            return [[0.0, up(ri)], [0.0, up(re)]];
        }
        let [c, s] = direction(spring - j as f64 * (spring - crown) / half);
        [[offset + ri * c, ri * s], [offset + re * c, re * s]]
    };
    let joints: Vec<[[f64; 2]; 2]> = (0..=n)
        .map(|j| {
            if 2 * j <= n {
                left(j)
            } else {
                let [i, e] = left(n - j);
                [[-i[0], i[1]], [-e[0], e[1]]]
            }
        })
        .collect();
    let [cx, cy] = shape.center;
    let at = |p: [f64; 2]| [cx + p[0], cy + p[1]];
    let mut pieces: Vec<Piece> = joints
        .windows(2)
        .enumerate()
        .map(|(k, w)| {
            let ([i0, e0], [i1, e1]) = (w[0], w[1]);
            Piece::new(
                Some(format!("voussoir {k}")),
                vec![at(i0), at(i1), at(e1), at(e0)],
                Vec::new(),
            )
        })
        .collect();
    if shape.abutments {
        let t = shape.thickness;
        // The springing joint's line, t/2 longer at each end, on a block
        // reaching t below the joint's lowest point.
        let [i, e] = joints[0];
        let (a, b) = if e[0] <= i[0] { (e, i) } else { (i, e) };
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        let (ux, uy) = (dx / len * t / 2.0, dy / len * t / 2.0);
        let p = [a[0] - ux, a[1] - uy];
        let q = [b[0] + ux, b[1] + uy];
        let bottom = i[1].min(e[1]) - t;
        let left = vec![[p[0], bottom], [q[0], bottom], q, p];
        let right = vec![
            [-q[0], bottom],
            [-p[0], bottom],
            [-p[0], p[1]],
            [-q[0], q[1]],
        ];
        for (name, outline) in [("left abutment", left), ("right abutment", right)] {
            pieces.push(Piece {
                always_fixed: true,
                ..Piece::new(
                    Some(name.to_string()),
                    outline.into_iter().map(at).collect(),
                    Vec::new(),
                )
            });
        }
    }
    Ok(pieces)
}

/// Drums from the bottom up, the first with its bottom centre at `base`.
pub(crate) fn column(
    base: [f64; 2],
    drums: usize,
    drum_height: f64,
    width: f64,
) -> Result<Vec<Piece>, DdaError> {
    let hint = "give the column's size in m";
    finite_all("base", "the base", &base)?;
    count("drums", "drums", drums, 1)?;
    positive("drum_height", "the drum height", drum_height, hint)?;
    positive("width", "the width", width, hint)?;
    let [bx, by] = base;
    let (x0, x1) = (bx - width / 2.0, bx + width / 2.0);
    let y = |k: usize| by + k as f64 * drum_height;
    Ok((0..drums)
        .map(|k| {
            let (y0, y1) = (y(k), y(k + 1));
            Piece::new(
                Some(format!("drum {k}")),
                vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]],
                Vec::new(),
            )
        })
        .collect())
}

/// The brick joints of one course, as distances from the wall's start:
/// 0, the cuts, then `length`.
pub(crate) fn course_cuts(length: f64, brick_length: f64, offset: f64) -> Vec<f64> {
    let mut cuts = vec![0.0];
    // A brick shorter than this at an end is rounding, not a brick.
    let tiny = 1e-9 * length;
    let mut k = 0;
    loop {
        let x = offset + k as f64 * brick_length;
        if x >= length - tiny {
            break;
        }
        if x > tiny {
            cuts.push(x);
        }
        k += 1;
    }
    cuts.push(length);
    cuts
}

/// Courses from the bottom up, bricks from left to right.
pub(crate) fn wall(
    origin: [f64; 2],
    length: f64,
    courses: usize,
    brick_length: f64,
    brick_height: f64,
    bond: Bond,
) -> Result<Vec<Piece>, Failure> {
    let hint = "give the wall's sizes in m";
    finite_all("origin", "the origin", &origin)?;
    positive("length", "the length", length, hint)?;
    count("courses", "courses", courses, 1)?;
    positive("brick_length", "the brick length", brick_length, hint)?;
    positive("brick_height", "the brick height", brick_height, hint)?;
    // Counted before they are made.
    let n = courses as f64 * ((length / brick_length).ceil() + 1.0);
    if n > MAX_PARTS as f64 {
        return Err(Failure::entry(format!(
            "the wall would have about {n:.0} bricks, more than {MAX_PARTS}; use longer bricks, fewer courses or a shorter wall"
        )));
    }
    let [x0, y0] = origin;
    let y = |c: usize| y0 + c as f64 * brick_height;
    let mut pieces = Vec::new();
    for c in 0..courses {
        let offset = match bond {
            Bond::Running if c % 2 == 1 => brick_length / 2.0,
            _ => 0.0,
        };
        let cuts = course_cuts(length, brick_length, offset);
        let (ya, yb) = (y(c), y(c + 1));
        for (k, w) in cuts.windows(2).enumerate() {
            let (xa, xb) = (x0 + w[0], x0 + w[1]);
            pieces.push(Piece::new(
                Some(format!("course {c}, brick {k}")),
                vec![[xa, ya], [xb, ya], [xb, yb], [xa, yb]],
                Vec::new(),
            ));
        }
    }
    Ok(pieces)
}

/// A rectangle: centre, width, height and a counter-clockwise angle in
/// degrees.
pub(crate) fn rectangle(
    center: [f64; 2],
    width: f64,
    height: f64,
    angle: f64,
) -> Result<Vec<Piece>, DdaError> {
    let hint = "give the rectangle's size";
    finite_all("center", "the center", &center)?;
    positive("width", "the width", width, hint)?;
    positive("height", "the height", height, hint)?;
    finite("angle", "the angle", angle)?;
    let (s, c) = angle.to_radians().sin_cos();
    let (hw, hh) = (width / 2.0, height / 2.0);
    let corners = [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)]
        .into_iter()
        .map(|(x, y)| [center[0] + c * x - s * y, center[1] + s * x + c * y]);
    Ok(vec![Piece::new(None, corners.collect(), vec![])])
}

/// Corners and faces of a 3D block.
pub(crate) type Shape3 = (Vec<[f64; 3]>, Vec<Vec<usize>>);

/// A box: centre, edge lengths and a rotation vector in degrees (see
/// `BlockSpec::Box`).
pub(crate) fn cuboid(
    center: [f64; 3],
    size: [f64; 3],
    rotation: [f64; 3],
) -> Result<Shape3, DdaError> {
    finite_all("center", "the center", &center)?;
    for (axis, s) in ["x", "y", "z"].iter().zip(size) {
        let what = format!("the size along its own {axis}");
        positive(
            "size",
            &what,
            s,
            "give the box's edge lengths (a, b, c) in m",
        )?;
    }
    finite_all("rotation", "the rotation", &rotation)?;
    let turn = Rotation3::from_scaled_axis(Vector3::from(rotation).map(f64::to_radians));
    let (v, f) = dda_3d::polyhedron::cuboid(Point3::from(center), Vector3::from(size), turn);
    Ok((v.iter().map(|p| [p.x, p.y, p.z]).collect(), f))
}

/// A vertical prism over an outline (either order; made counter-clockwise)
/// from `z0` up to `z1`.
pub(crate) fn prism(outline: &[[f64; 2]], z0: f64, z1: f64) -> Result<Shape3, Failure> {
    let points: Vec<Point2<f64>> = outline.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let ccw =
        dda_2d::polygon::validate(&points).map_err(|e| Failure::field("outline", e.to_string()))?;
    finite("z0", "z0", z0)?;
    finite("z1", "z1", z1)?;
    if z1 <= z0 {
        return Err(Failure::field(
            "z1",
            format!("the prism's top z1 = {z1} must lie above its bottom z0 = {z0}"),
        ));
    }
    let (v, f) = dda_3d::polyhedron::prism(&ccw, z0, z1);
    Ok((v.iter().map(|p| [p.x, p.y, p.z]).collect(), f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_courses_start_with_half_a_brick() {
        assert_eq!(course_cuts(2.0, 0.5, 0.0), [0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(
            course_cuts(2.0, 0.5, 0.25),
            [0.0, 0.25, 0.75, 1.25, 1.75, 2.0]
        );
        // Not a multiple: a shorter last brick.
        assert_eq!(course_cuts(1.2, 0.5, 0.0), [0.0, 0.5, 1.0, 1.2]);
        // No sliver from rounding.
        assert_eq!(course_cuts(0.3, 0.1, 0.0).len(), 4);
    }

    #[test]
    fn nonsense_makes_nothing() {
        let shape = ArchShape {
            center: [0.0, 0.0],
            radius: 1.0,
            thickness: 0.2,
            voussoirs: 1,
            span_angle: 180.0,
            pointed: 0.0,
            abutments: true,
        };
        assert!(arch(&shape).is_err());
        assert_eq!(
            arch(&ArchShape {
                voussoirs: 4,
                ..shape
            })
            .map(|p| p.len())
            .ok(),
            Some(6)
        );
        assert!(arch(&ArchShape {
            voussoirs: 5,
            pointed: 0.2,
            ..shape
        })
        .is_err());
        assert!(column([0.0, 0.0], MAX_PARTS + 1, 1.0, 1.0).is_err());
        assert!(wall([0.0, 0.0], 1e9, 10, 1e-3, 0.1, Bond::Stack).is_err());
    }
}
