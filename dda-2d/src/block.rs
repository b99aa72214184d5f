//! A Shi polygon block: its geometry, integrals, stress and accumulated motion.

use dda_core::BlockKind;
use nalgebra::{Matrix2, Point2, Rotation2, Vector2, Vector3, Vector6};

use crate::kinematics::{mass_matrix, move_point, strain_tensor, Matrix6, RotationUpdate};
use crate::polygon::{self, central_moments, CentralMoments, PolygonError};

/// One polygonal block (convex or concave, counter-clockwise vertices).
#[derive(Debug, Clone)]
pub struct Block {
    vertices: Vec<Point2<f64>>,
    moments: CentralMoments,
    angles: Vec<f64>,
    edges: Vec<Edge>,
    /// Index of the block's material.
    pub material: usize,
    /// Rigid or deformable; deformable unless set.
    pub kind: BlockKind,
    /// Mass per unit thickness; constant while the area changes with strain.
    pub mass: f64,
    /// Stress (σx, σy, τxy), tension positive.
    pub stress: Vector3<f64>,
    /// Accumulated strain (εx, εy, γxy) in the global frame.
    pub strain: Vector3<f64>,
    /// Accumulated rotation in radians (counter-clockwise positive).
    pub rotation: f64,
}

impl Block {
    /// Validates the polygon and builds the block.
    pub fn new(
        vertices: &[Point2<f64>],
        material: usize,
        density: f64,
    ) -> Result<Self, PolygonError> {
        let vertices = polygon::validate(vertices)?;
        let moments = central_moments(&vertices);
        let angles = polygon::interior_angles(&vertices);
        let edges = edges(&vertices);
        Ok(Self {
            mass: density * moments.area,
            vertices,
            moments,
            angles,
            edges,
            material,
            kind: BlockKind::Deformable,
            stress: Vector3::zeros(),
            strain: Vector3::zeros(),
            rotation: 0.0,
        })
    }

    pub fn vertices(&self) -> &[Point2<f64>] {
        &self.vertices
    }

    /// Interior angle at each vertex (radians; above π at reflex vertices).
    pub fn angles(&self) -> &[f64] {
        &self.angles
    }

    /// Each edge's frame, edge k running from vertex k to the next.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    pub fn centroid(&self) -> Point2<f64> {
        self.moments.centroid
    }

    pub fn area(&self) -> f64 {
        self.moments.area
    }

    /// Current density: mass over current area.
    pub fn density(&self) -> f64 {
        self.mass / self.moments.area
    }

    /// ∫ρTᵀT dA about the centroid.
    pub fn mass_matrix(&self) -> Matrix6 {
        mass_matrix(&self.moments, self.density())
    }

    /// Where a point of this block goes for step displacement `d`.
    pub fn move_point(
        &self,
        p: &Point2<f64>,
        d: &Vector6<f64>,
        update: RotationUpdate,
    ) -> Point2<f64> {
        move_point(p, &self.moments.centroid, d, update)
    }

    /// Applies an accepted step: vertices, stress (co-rotated), strain and
    /// rotation. `stress` is the stress after the step's strain increment, in
    /// the frame at the start of the step.
    pub fn commit(&mut self, d: &Vector6<f64>, stress: Vector3<f64>, update: RotationUpdate) {
        let c = self.moments.centroid;
        for v in &mut self.vertices {
            *v = move_point(v, &c, d, update);
        }
        self.moments = central_moments(&self.vertices);
        self.angles = polygon::interior_angles(&self.vertices);
        self.edges = edges(&self.vertices);
        let rotate = |s: Matrix2<f64>| {
            let r = Rotation2::new(d[2]).into_inner();
            r * s * r.transpose()
        };
        let s = rotate(Matrix2::new(stress.x, stress.z, stress.z, stress.y));
        self.stress = Vector3::new(s[(0, 0)], s[(1, 1)], s[(0, 1)]);
        let e = self.strain;
        let e = rotate(Matrix2::new(e.x, e.z / 2.0, e.z / 2.0, e.y) + strain_tensor(d));
        self.strain = Vector3::new(e[(0, 0)], e[(1, 1)], 2.0 * e[(0, 1)]);
        self.rotation += d[2];
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (Point2<f64>, Point2<f64>) {
        dda_core::planar::bounds(&self.vertices)
    }

    /// Puts the block back at a checkpointed state (its integrals derived
    /// as `commit` derives them, so a restored run goes on bit for bit).
    pub(crate) fn restore(
        &mut self,
        vertices: Vec<Point2<f64>>,
        stress: Vector3<f64>,
        strain: Vector3<f64>,
        rotation: f64,
    ) {
        self.moments = central_moments(&vertices);
        self.angles = polygon::interior_angles(&vertices);
        self.edges = edges(&vertices);
        self.vertices = vertices;
        self.stress = stress;
        self.strain = strain;
        self.rotation = rotation;
    }
}

/// An edge's length and frame, kept with the block: the narrow phase
/// measures every vertex near a block against each of its edges.
#[derive(Debug, Clone, Copy)]
pub struct Edge {
    pub length: f64,
    /// Unit vector along the edge, counter-clockwise round the block.
    pub tangent: Vector2<f64>,
    /// Outward unit normal.
    pub normal: Vector2<f64>,
}

fn edges(vertices: &[Point2<f64>]) -> Vec<Edge> {
    let n = vertices.len();
    (0..n)
        .map(|k| {
            let edge = vertices[(k + 1) % n] - vertices[k];
            let length = edge.norm();
            let tangent = edge / length;
            Edge {
                length,
                tangent,
                // Outward normal of a counter-clockwise polygon's edge.
                normal: Vector2::new(tangent.y, -tangent.x),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use dda_core::Element;

    /// The kept edge frames follow the vertices through a step and a
    /// restore: each edge's length, its unit tangent from one vertex to the
    /// next, and the normal pointing away from the centroid.
    #[test]
    fn edges_follow_the_vertices() {
        let v = [(0.0, 0.0), (2.0, -0.3), (2.6, 1.1), (1.1, 2.0)].map(|(x, y)| Point2::new(x, y));
        let mut block = Block::new(&v, 0, 2000.0).unwrap();
        let check = |b: &Block| {
            let n = b.vertices().len();
            assert_eq!(b.edges().len(), n);
            for (k, e) in b.edges().iter().enumerate() {
                let (p, q) = (b.vertices()[k], b.vertices()[(k + 1) % n]);
                assert!((e.length - (q - p).norm()).abs() < 1e-14);
                assert!((e.tangent * e.length - (q - p)).norm() < 1e-14);
                assert!(e.normal.dot(&e.tangent).abs() < 1e-15);
                assert!(
                    e.normal.dot(&(p - b.centroid())) > 0.0,
                    "edge {k} faces out"
                );
            }
        };
        check(&block);
        let d = Vector6::new(0.3, -0.2, 0.9, 1e-3, -2e-3, 5e-4);
        block.commit(&d, Vector3::zeros(), RotationUpdate::Exact);
        check(&block);
        let moved = v.map(|p| p + Vector2::new(5.0, 1.0));
        block.restore(moved.to_vec(), Vector3::zeros(), Vector3::zeros(), 0.0);
        check(&block);
        assert!((block.edges()[0].tangent - Vector2::new(2.0, -0.3).normalize()).norm() < 1e-15);
    }

    #[test]
    fn t_matrix_is_the_derivative_of_the_committed_motion() {
        let v = [(0.0, 0.0), (2.0, -0.3), (2.6, 1.1), (1.1, 2.0), (-0.4, 1.2)]
            .map(|(x, y)| Point2::new(x + 10.0, y - 3.0));
        let block = Block::new(&v, 0, 2000.0).unwrap();
        let p = Point2::new(11.3, -1.7);
        let t = Element::t_matrix(&block, &p);
        let h = 1e-6;
        let exact = RotationUpdate::Exact;
        for k in 0..6 {
            let mut d = Vector6::zeros();
            d[k] = h;
            let fd =
                (block.move_point(&p, &d, exact) - block.move_point(&p, &(-d), exact)) / (2.0 * h);
            assert!(
                (fd - t.column(k)).norm() < 1e-8,
                "column {k}: {fd} vs {}",
                t.column(k)
            );
        }
        // Rigid-body DOF move the centroid as a translation only.
        let c = block.centroid();
        let d = Vector6::new(0.1, 0.2, 0.7, 0.0, 0.0, 0.0);
        assert!((block.move_point(&c, &d, exact) - c - Vector2::new(0.1, 0.2)).norm() < 1e-14);
    }
}
