//! Block cutting in 3D: a convex region cut by persistent joint planes, one
//! plane after another, each splitting every convex block it crosses into
//! two convex blocks.
//!
//! A block is split when some of its corners lie more than the tolerance
//! (1e-9 of the region's size) on each side of the plane; corners within it
//! count as on the plane, so a plane through a corner or along a face does
//! not leave slivers or duplicate corners behind.

use std::collections::BTreeMap;

use dda_core::planar;
use nalgebra::{Point2, Point3, Vector3};

use crate::face::FaceFrame;

/// Tolerance as a fraction of the region's size (its bounding-box diagonal).
pub const SNAP: f64 = 1e-9;

/// At most this many blocks from one cut.
pub const MAX_BLOCKS: usize = 100_000;

/// At most this many corners for a region given by its corners.
pub const MAX_REGION_CORNERS: usize = 64;

/// A joint plane `normal · x = offset` (the normal need not be a unit
/// vector), the `joint`th of set `set`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointPlane {
    pub normal: Vector3<f64>,
    pub offset: f64,
    pub set: usize,
    pub joint: usize,
}

/// A face of a block: its corners counter-clockwise seen from outside, and
/// the joint it lies on (`None` on the region's boundary).
#[derive(Debug, Clone, PartialEq)]
struct Face {
    points: Vec<Point3<f64>>,
    joint: Option<(usize, usize)>,
}

/// A convex block as faces.
#[derive(Debug, Clone, PartialEq)]
pub struct Convex {
    faces: Vec<Face>,
}

/// Two blocks that share a joint face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SharedJoint {
    /// Block indices, lower first.
    pub blocks: (usize, usize),
    pub set: usize,
    /// Area shared, m².
    pub area: f64,
}

/// A block's corners and faces (corner indices counter-clockwise seen
/// from outside).
pub type Shape = (Vec<Point3<f64>>, Vec<Vec<usize>>);

/// The blocks of a cut region and the joints between them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Cut {
    pub blocks: Vec<Shape>,
    pub joints: Vec<SharedJoint>,
    /// Blocks left out as slivers (below the smallest volume).
    pub dropped: usize,
}

/// Why a region could not be made or cut.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CutError {
    #[error("the region's corners {0}")]
    Region(String),
    #[error(
        "joint plane {0} has a normal or offset that is not a finite number, or a zero normal"
    )]
    BadPlane(usize),
    #[error("the joints cut the region into more than {MAX_BLOCKS} blocks; use wider spacings or a smaller region")]
    TooMany,
}

impl Convex {
    /// The box between two opposite corners.
    pub fn cuboid(min: Point3<f64>, max: Point3<f64>) -> Result<Convex, CutError> {
        if !(min.iter().chain(max.iter()).all(|v| v.is_finite()))
            || (0..3).any(|k| max[k] <= min[k])
        {
            return Err(CutError::Region(
                "must be finite, with max above min along every axis".into(),
            ));
        }
        let c = |i: usize| {
            Point3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        };
        let faces = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        Ok(Convex {
            faces: faces
                .iter()
                .map(|f| Face {
                    points: f.iter().map(|&i| c(i)).collect(),
                    joint: None,
                })
                .collect(),
        })
    }

    /// The convex hull of `corners` (at most [`MAX_REGION_CORNERS`], not all
    /// in one plane).
    pub fn hull(corners: &[Point3<f64>]) -> Result<Convex, CutError> {
        let n = corners.len();
        if !(4..=MAX_REGION_CORNERS).contains(&n) {
            return Err(CutError::Region(format!(
                "must number from 4 to {MAX_REGION_CORNERS}, got {n}"
            )));
        }
        if !corners.iter().all(|p| p.iter().all(|v| v.is_finite())) {
            return Err(CutError::Region("must be finite numbers".into()));
        }
        let (lo, hi) = bounds(corners.iter());
        let tol = SNAP * (hi - lo).norm();
        let mut region = Convex::cuboid(lo, hi)?;
        // Every plane through three corners with all corners on one side
        // bounds the hull; cut the bounding box by each.
        let mut planes: Vec<(Vector3<f64>, f64)> = Vec::new();
        for i in 0..n {
            for j in (i + 1)..n {
                for k in (j + 1)..n {
                    let (a, b, c) = (corners[i], corners[j], corners[k]);
                    let normal = (b - a).cross(&(c - a));
                    if normal.norm() <= tol * (hi - lo).norm() {
                        continue;
                    }
                    let normal = normal.normalize();
                    let offset = normal.dot(&a.coords);
                    let side = |p: &Point3<f64>| normal.dot(&p.coords) - offset;
                    let (above, below) = corners.iter().fold((false, false), |(u, d), p| {
                        (u || side(p) > tol, d || side(p) < -tol)
                    });
                    let outward = match (above, below) {
                        (false, true) => (normal, offset),
                        (true, false) => (-normal, -offset),
                        _ => continue,
                    };
                    if !planes
                        .iter()
                        .any(|(m, o)| (m - outward.0).norm() < 1e-9 && (o - outward.1).abs() <= tol)
                    {
                        planes.push(outward);
                    }
                }
            }
        }
        if planes.len() < 4 {
            return Err(CutError::Region(
                "all lie in one plane; give a solid".into(),
            ));
        }
        for (normal, offset) in planes {
            if let (Some(inside), _) = region.split(&normal, offset, None, tol) {
                region = inside;
            }
        }
        Ok(region)
    }

    /// The volume, m³.
    pub fn volume(&self) -> f64 {
        let c = self.faces[0].points[0];
        self.faces
            .iter()
            .map(|f| {
                let p = &f.points;
                (1..p.len() - 1)
                    .map(|k| (p[0] - c).dot(&(p[k] - c).cross(&(p[k + 1] - c))))
                    .sum::<f64>()
            })
            .sum::<f64>()
            / 6.0
    }

    fn corners(&self) -> impl Iterator<Item = &Point3<f64>> {
        self.faces.iter().flat_map(|f| f.points.iter())
    }

    /// The parts below (`normal · x < offset`) and above the plane; one is
    /// `None` when the plane misses the block, or touches it within `tol`.
    fn split(
        &self,
        normal: &Vector3<f64>,
        offset: f64,
        joint: Option<(usize, usize)>,
        tol: f64,
    ) -> (Option<Convex>, Option<Convex>) {
        let side = |p: &Point3<f64>| normal.dot(&p.coords) - offset;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in self.corners() {
            lo = lo.min(side(p));
            hi = hi.max(side(p));
        }
        if hi <= tol {
            return (Some(self.clone()), None);
        }
        if lo >= -tol {
            return (None, Some(self.clone()));
        }
        let (mut below, mut above, mut cap) = (Vec::new(), Vec::new(), Vec::new());
        for face in &self.faces {
            let p = &face.points;
            let s: Vec<f64> = p.iter().map(side).collect();
            let (mut b, mut a) = (Vec::new(), Vec::new());
            for i in 0..p.len() {
                let j = (i + 1) % p.len();
                if s[i] <= tol {
                    b.push(p[i]);
                }
                if s[i] >= -tol {
                    a.push(p[i]);
                }
                if s[i].abs() <= tol {
                    cap.push(p[i]);
                }
                if (s[i] < -tol && s[j] > tol) || (s[i] > tol && s[j] < -tol) {
                    // From the lower end, so both faces of the edge agree.
                    let (u, v, su, sv) = if s[i] < s[j] {
                        (p[i], p[j], s[i], s[j])
                    } else {
                        (p[j], p[i], s[j], s[i])
                    };
                    let x = u + (v - u) * (su / (su - sv));
                    b.push(x);
                    a.push(x);
                    cap.push(x);
                }
            }
            for (part, out) in [(b, &mut below), (a, &mut above)] {
                if part.len() >= 3 && face_area(&part) > tol * tol {
                    out.push(Face {
                        points: part,
                        joint: face.joint,
                    });
                }
            }
        }
        let cap = ordered_cap(cap, normal, tol);
        if cap.len() < 3 {
            return (Some(self.clone()), None);
        }
        let mut reversed = cap.clone();
        reversed.reverse();
        below.push(Face { points: cap, joint });
        above.push(Face {
            points: reversed,
            joint,
        });
        (Some(Convex { faces: below }), Some(Convex { faces: above }))
    }

    /// Corners welded within `tol` and faces as corner indices.
    fn indexed(&self, tol: f64) -> Shape {
        let mut corners: Vec<Point3<f64>> = Vec::new();
        let faces = self
            .faces
            .iter()
            .map(|f| {
                let mut ids: Vec<usize> = Vec::new();
                for p in &f.points {
                    let id = match corners.iter().position(|q| (q - p).norm() <= 2.0 * tol) {
                        Some(k) => k,
                        None => {
                            corners.push(*p);
                            corners.len() - 1
                        }
                    };
                    if ids.last() != Some(&id) && ids.first() != Some(&id) {
                        ids.push(id);
                    }
                }
                ids
            })
            .filter(|ids| ids.len() >= 3)
            .collect();
        (corners, faces)
    }
}

fn bounds<'a>(points: impl Iterator<Item = &'a Point3<f64>>) -> (Point3<f64>, Point3<f64>) {
    points.fold(
        (
            Point3::from([f64::INFINITY; 3]),
            Point3::from([f64::NEG_INFINITY; 3]),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

fn face_area(points: &[Point3<f64>]) -> f64 {
    let p0 = points[0];
    (1..points.len() - 1)
        .map(|k| (points[k] - p0).cross(&(points[k + 1] - p0)))
        .sum::<Vector3<f64>>()
        .norm()
        / 2.0
}

/// The cut face's corners, duplicates merged, counter-clockwise about `normal`.
fn ordered_cap(points: Vec<Point3<f64>>, normal: &Vector3<f64>, tol: f64) -> Vec<Point3<f64>> {
    let mut unique: Vec<Point3<f64>> = Vec::new();
    for p in points {
        if !unique.iter().any(|q| (q - p).norm() <= 2.0 * tol) {
            unique.push(p);
        }
    }
    if unique.len() < 3 {
        return unique;
    }
    let n = normal.normalize();
    let u = n
        .cross(
            &(if n.x.abs() < 0.9 {
                Vector3::x()
            } else {
                Vector3::y()
            }),
        )
        .normalize();
    let v = n.cross(&u);
    let c = unique.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / unique.len() as f64;
    let angle = |p: &Point3<f64>| (p.coords - c).dot(&v).atan2((p.coords - c).dot(&u));
    unique.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
    unique
}

/// Cuts `region` by the joint planes in turn and keeps the blocks of at
/// least `min_volume` (m³).
pub fn cut(region: &Convex, planes: &[JointPlane], min_volume: f64) -> Result<Cut, CutError> {
    let (lo, hi) = bounds(region.corners());
    let tol = SNAP * (hi - lo).norm();
    let mut blocks = vec![region.clone()];
    for (k, plane) in planes.iter().enumerate() {
        let norm = plane.normal.norm();
        if !(norm > 0.0 && norm.is_finite() && plane.offset.is_finite()) {
            return Err(CutError::BadPlane(k));
        }
        let (normal, offset) = (plane.normal / norm, plane.offset / norm);
        let mut next = Vec::with_capacity(blocks.len());
        for block in &blocks {
            let (b, a) = block.split(&normal, offset, Some((plane.set, plane.joint)), tol);
            next.extend(b);
            next.extend(a);
        }
        if next.len() > MAX_BLOCKS {
            return Err(CutError::TooMany);
        }
        blocks = next;
    }
    let mut out = Cut::default();
    let mut kept = Vec::new();
    for block in blocks {
        if block.volume() < min_volume {
            out.dropped += 1;
        } else {
            out.blocks.push(block.indexed(tol));
            kept.push(block);
        }
    }
    out.joints = shared_joints(&kept, tol);
    Ok(out)
}

/// Block pairs with faces on the same joint that overlap by more than
/// tol², with the area they share.
fn shared_joints(blocks: &[Convex], tol: f64) -> Vec<SharedJoint> {
    // Ordered maps: a pair of blocks on two joints takes the first joint's
    // set, and the areas add up in one order, the same every run.
    let mut on_joint: BTreeMap<(usize, usize), Vec<(usize, &Face)>> = BTreeMap::new();
    for (b, block) in blocks.iter().enumerate() {
        for face in &block.faces {
            if let Some(j) = face.joint {
                on_joint.entry(j).or_default().push((b, face));
            }
        }
    }
    let mut shared: BTreeMap<(usize, usize), (usize, f64)> = BTreeMap::new();
    for (&(set, _), faces) in &on_joint {
        for (i, (a, fa)) in faces.iter().enumerate() {
            for (b, fb) in &faces[i + 1..] {
                if a == b {
                    continue;
                }
                let area = overlap_area(&fa.points, &fb.points);
                if area > tol * tol {
                    let e = shared
                        .entry(((*a).min(*b), (*a).max(*b)))
                        .or_insert((set, 0.0));
                    e.1 += area;
                }
            }
        }
    }
    shared
        .into_iter()
        .map(|(blocks, (set, area))| SharedJoint { blocks, set, area })
        .collect()
}

/// The area two convex faces in one plane share.
fn overlap_area(a: &[Point3<f64>], b: &[Point3<f64>]) -> f64 {
    let normal = (1..a.len() - 1)
        .map(|k| (a[k] - a[0]).cross(&(a[k + 1] - a[0])))
        .sum::<Vector3<f64>>()
        .normalize();
    let frame = FaceFrame::new(a[0], a[1], normal);
    // The faces of the two blocks face opposite ways: both counter-clockwise.
    let flat = |points: &[Point3<f64>]| -> Vec<Point2<f64>> {
        let mut out: Vec<_> = points.iter().map(|p| frame.to_plane(p)).collect();
        if planar::signed_area(&out) < 0.0 {
            out.reverse();
        }
        out
    };
    planar::clipped_area(&flat(a), &flat(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polyhedron;

    fn plane(n: [f64; 3], offset: f64, set: usize, joint: usize) -> JointPlane {
        JointPlane {
            normal: Vector3::from(n),
            offset,
            set,
            joint,
        }
    }

    fn volume_of(cut: &Cut) -> f64 {
        cut.blocks
            .iter()
            .map(|(v, f)| polyhedron::validate(v, f).unwrap().volume())
            .sum()
    }

    #[test]
    fn three_orthogonal_sets_make_a_grid() {
        let region =
            Convex::cuboid(Point3::new(0.0, 0.0, 0.0), Point3::new(4.0, 3.0, 2.0)).unwrap();
        let mut planes = Vec::new();
        for (axis, n) in [(0, 4), (1, 3), (2, 2)] {
            for k in 1..n {
                let mut normal = [0.0; 3];
                normal[axis] = 1.0;
                planes.push(plane(normal, k as f64, axis, k));
            }
        }
        let c = cut(&region, &planes, 0.0).unwrap();
        assert_eq!(c.blocks.len(), 24);
        assert!((volume_of(&c) - 24.0).abs() <= 1e-9 * 24.0);
        // Interior faces of a 4 × 3 × 2 grid: 3·3·2 + 4·2·2 + 4·3·1.
        assert_eq!(c.joints.len(), 18 + 16 + 12);
        assert!(c.joints.iter().all(|j| (j.area - 1.0).abs() < 1e-12));
    }

    #[test]
    fn inclined_planes_keep_the_volume() {
        let corners = [
            [0.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [6.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 4.0],
            [2.0, 0.0, 4.0],
            [2.0, 2.0, 4.0],
            [0.0, 2.0, 4.0],
        ]
        .map(Point3::from);
        let region = Convex::hull(&corners).unwrap();
        // A trapezoidal prism: (6 + 2)/2 · 4 · 2.
        assert!((region.volume() - 32.0).abs() < 1e-12);
        let dip = 35f64.to_radians();
        let n = [dip.sin() * 0.3, dip.sin() * 0.95, dip.cos()];
        let planes: Vec<JointPlane> = (0..12)
            .map(|k| plane(n, -2.0 + 0.61 * k as f64, 0, k))
            .chain((0..8).map(|k| plane([0.8, -0.1, 0.3], 0.37 + 0.7 * k as f64, 1, k)))
            .chain([plane([1.0, 0.0, 0.0], 2.0, 2, 0)]) // through the crest's corners
            .collect();
        let c = cut(&region, &planes, 0.0).unwrap();
        assert!(c.blocks.len() > 30, "{} blocks", c.blocks.len());
        assert!((volume_of(&c) - 32.0).abs() <= 1e-9 * 32.0);
    }

    /// Planes through points of a coarse grid with grid-like normals: many
    /// pass through corners and edges, lie along faces or repeat. The
    /// blocks fill the box and are valid polyhedra facing outward.
    #[test]
    fn planes_on_a_grid_keep_the_volume() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let region = Convex::cuboid(Point3::origin(), Point3::new(3.0, 2.0, 2.0)).unwrap();
        for _ in 0..100 {
            let mut pick = |n: f64| (next() * n).floor();
            let planes: Vec<JointPlane> = (0..6)
                .map(|k| {
                    let normal = [pick(3.0) - 1.0, pick(3.0) - 1.0, pick(2.0) + 0.0];
                    let normal = if normal == [0.0; 3] {
                        [0.0, 0.0, 1.0]
                    } else {
                        normal
                    };
                    let at = [pick(4.0), pick(3.0), pick(3.0)];
                    let offset = (0..3).map(|i| normal[i] * at[i]).sum();
                    plane(normal, offset, k % 2, k)
                })
                .collect();
            let c = cut(&region, &planes, 0.0).unwrap();
            let mut total = 0.0;
            for (v, f) in &c.blocks {
                let shape =
                    polyhedron::validate(v, f).unwrap_or_else(|e| panic!("{e}: {planes:?}"));
                let signed: f64 = f
                    .iter()
                    .map(|face| {
                        (1..face.len() - 1)
                            .map(|k| {
                                v[face[0]]
                                    .coords
                                    .dot(&v[face[k]].coords.cross(&v[face[k + 1]].coords))
                            })
                            .sum::<f64>()
                    })
                    .sum::<f64>()
                    / 6.0;
                assert!(
                    (signed - shape.volume()).abs() < 1e-9,
                    "inside out: {planes:?}"
                );
                total += shape.volume();
            }
            assert!(
                (total - 12.0).abs() <= 1e-9 * 12.0,
                "volume {total}: {planes:?}"
            );
        }
    }

    #[test]
    fn bad_planes_and_regions_are_errors() {
        let region = Convex::cuboid(Point3::origin(), Point3::new(1.0, 1.0, 1.0)).unwrap();
        assert_eq!(
            cut(&region, &[plane([0.0; 3], 0.5, 0, 0)], 0.0),
            Err(CutError::BadPlane(0))
        );
        assert!(Convex::cuboid(Point3::origin(), Point3::new(1.0, 0.0, 1.0)).is_err());
        let flat = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ]
        .map(Point3::from);
        assert!(Convex::hull(&flat).is_err());
        // A plane along a face cuts nothing.
        let c = cut(&region, &[plane([0.0, 0.0, 1.0], 1.0, 0, 0)], 0.0).unwrap();
        assert_eq!(c.blocks.len(), 1);
        // A sliver is dropped.
        let c = cut(&region, &[plane([0.0, 0.0, 1.0], 1e-3, 0, 0)], 1e-2).unwrap();
        assert_eq!((c.blocks.len(), c.dropped), (1, 1));
    }
}
