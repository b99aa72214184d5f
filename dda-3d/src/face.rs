//! A face's own 2D frame. In it a face is a planar polygon, possibly
//! concave, for the routines of `dda_core::planar` (containment, distances,
//! ear clipping, clipping).

use nalgebra::{Point2, Point3, Vector3};

/// An orthonormal frame in a face's plane: `u` along the face's first edge,
/// `v = n × u`, origin at the face's first vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceFrame {
    pub origin: Point3<f64>,
    pub u: Vector3<f64>,
    pub v: Vector3<f64>,
    pub normal: Vector3<f64>,
}

impl FaceFrame {
    /// The frame of a face with unit normal `normal` whose first two
    /// vertices are `p0`, `p1`. The first edge is projected on the plane so the
    /// frame stays orthonormal for slightly non-planar input.
    pub fn new(p0: Point3<f64>, p1: Point3<f64>, normal: Vector3<f64>) -> Self {
        let edge = p1 - p0;
        let along = edge - normal * normal.dot(&edge);
        let u = along
            .try_normalize(0.0)
            .unwrap_or_else(|| any_perpendicular(&normal));
        Self {
            origin: p0,
            u,
            v: normal.cross(&u),
            normal,
        }
    }

    /// In-plane coordinates of a point (its projection on the plane).
    pub fn to_plane(&self, p: &Point3<f64>) -> Point2<f64> {
        let d = p - self.origin;
        Point2::new(d.dot(&self.u), d.dot(&self.v))
    }

    /// Signed distance of a point from the plane (positive on the normal side).
    pub fn height(&self, p: &Point3<f64>) -> f64 {
        self.normal.dot(&(p - self.origin))
    }
}

/// A unit vector perpendicular to `n`.
pub fn any_perpendicular(n: &Vector3<f64>) -> Vector3<f64> {
    let pick = if n.x.abs() < 0.6 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    (pick - n * n.dot(&pick)).normalize()
}
