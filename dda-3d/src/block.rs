//! A polyhedral block: its geometry, integrals, stress and accumulated motion.

use dda_core::BlockKind;

use nalgebra::{Point3, Rotation3, Vector3, Vector6};

use crate::kinematics::{
    mass_matrix, move_point, point_mover, step_rotation, strain_tensor, strain_voigt, stress_voigt,
    t_matrix, voigt_strain, voigt_stress, Matrix12, RotationUpdate, TMatrix, Vector12,
};
use crate::polyhedron::{self, Polyhedron, PolyhedronError};

/// One polyhedral block (convex or not).
#[derive(Debug, Clone)]
pub struct Block {
    shape: Polyhedron,
    /// Index of the block's material.
    pub material: usize,
    /// Rigid or deformable; deformable unless set.
    pub kind: BlockKind,
    /// Mass; constant while the volume changes with strain.
    pub mass: f64,
    /// Stress (σx, σy, σz, τyz, τzx, τxy), tension positive, global frame.
    pub stress: Vector6<f64>,
    /// Accumulated strain (εx, εy, εz, γyz, γzx, γxy), global frame.
    pub strain: Vector6<f64>,
    /// Accumulated rotation as a rotation vector (axis · angle, angle in
    /// [0, π]), composed exactly step by step.
    pub rotation: Vector3<f64>,
}

impl Block {
    /// Validates the polyhedron and builds the block.
    pub fn new(
        vertices: &[Point3<f64>],
        faces: &[Vec<usize>],
        material: usize,
        density: f64,
    ) -> Result<Self, PolyhedronError> {
        Ok(Self::from_shape(
            polyhedron::validate(vertices, faces)?,
            material,
            density,
        ))
    }

    /// A block of an already validated polyhedron.
    pub fn from_shape(shape: Polyhedron, material: usize, density: f64) -> Self {
        Self {
            mass: density * shape.volume(),
            shape,
            material,
            kind: BlockKind::Deformable,
            stress: Vector6::zeros(),
            strain: Vector6::zeros(),
            rotation: Vector3::zeros(),
        }
    }

    /// The block's polyhedron (faces, edges, normals, convexity).
    pub fn shape(&self) -> &Polyhedron {
        &self.shape
    }

    pub fn vertices(&self) -> &[Point3<f64>] {
        self.shape.vertices()
    }

    pub fn faces(&self) -> &[Vec<usize>] {
        self.shape.faces()
    }

    pub fn centroid(&self) -> Point3<f64> {
        self.shape.centroid()
    }

    pub fn volume(&self) -> f64 {
        self.shape.volume()
    }

    /// Current density: mass over current volume.
    pub fn density(&self) -> f64 {
        self.mass / self.shape.volume()
    }

    /// ∫ρTᵀT dV about the centroid.
    pub fn mass_matrix(&self) -> Matrix12 {
        mass_matrix(self.shape.moments(), self.density())
    }

    /// The T-matrix at a point.
    pub fn t_matrix(&self, p: &Point3<f64>) -> TMatrix {
        t_matrix(p, &self.centroid())
    }

    /// Where a point of this block goes for step displacement `d`.
    pub fn move_point(&self, p: &Point3<f64>, d: &Vector12, update: RotationUpdate) -> Point3<f64> {
        move_point(p, &self.centroid(), d, update)
    }

    /// The accumulated rotation as a rotation.
    pub fn orientation(&self) -> Rotation3<f64> {
        Rotation3::from_scaled_axis(self.rotation)
    }

    /// Applies an accepted step: vertices, stress and strain (co-rotated with
    /// the step's rotation) and the accumulated rotation. `stress` is the
    /// stress after the step's strain increment, in the frame at the start of
    /// the step.
    pub fn commit(&mut self, d: &Vector12, stress: Vector6<f64>, update: RotationUpdate) {
        let c = self.centroid();
        self.shape.move_by(point_mover(&c, d, update));
        let r = step_rotation(d);
        let rotate = |m: nalgebra::Matrix3<f64>| r * m * r.transpose();
        self.stress = stress_voigt(&rotate(voigt_stress(&stress)));
        self.strain = strain_voigt(&rotate(voigt_strain(&self.strain) + strain_tensor(d)));
        self.rotation = (r * self.orientation()).scaled_axis();
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
        self.shape.bounds()
    }

    /// Puts the block back at a checkpointed state.
    pub(crate) fn restore(
        &mut self,
        vertices: Vec<Point3<f64>>,
        stress: Vector6<f64>,
        strain: Vector6<f64>,
        rotation: Vector3<f64>,
    ) {
        self.shape = self.shape.with_vertices(vertices);
        self.stress = stress;
        self.strain = strain;
        self.rotation = rotation;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polyhedron::cuboid;
    use dda_core::Element;

    fn brick() -> Block {
        let (v, f) = cuboid(
            Point3::new(10.0, -3.0, 2.0),
            Vector3::new(2.0, 1.0, 0.5),
            Rotation3::from_euler_angles(0.2, 0.4, -0.3),
        );
        Block::new(&v, &f, 0, 2000.0).unwrap()
    }

    #[test]
    fn t_matrix_is_the_derivative_of_the_committed_motion() {
        let block = brick();
        let p = Point3::new(10.3, -2.7, 2.2);
        let t = Element::t_matrix(&block, &p);
        let h = 1e-6;
        let exact = RotationUpdate::Exact;
        for k in 0..12 {
            let mut d = Vector12::zeros();
            d[k] = h;
            let fd =
                (block.move_point(&p, &d, exact) - block.move_point(&p, &(-d), exact)) / (2.0 * h);
            assert!(
                (fd - t.column(k)).norm() < 1e-8,
                "column {k}: {fd} vs {}",
                t.column(k)
            );
        }
    }

    #[test]
    fn commit_moves_rigidly_and_keeps_the_volume_unless_strained() {
        let mut block = brick();
        let (v0, c0) = (block.volume(), block.centroid());
        let radii: Vec<f64> = block.vertices().iter().map(|v| (v - c0).norm()).collect();
        let mut d = Vector12::zeros();
        d[0] = 0.1;
        d[3] = 0.4;
        d[4] = -0.7;
        d[5] = 0.2;
        block.commit(&d, Vector6::zeros(), RotationUpdate::Exact);
        assert!((block.volume() / v0 - 1.0).abs() < 1e-14);
        let c = block.centroid();
        assert!((c - c0 - Vector3::new(0.1, 0.0, 0.0)).norm() < 1e-12);
        for (v, r) in block.vertices().iter().zip(&radii) {
            assert!(((v - c).norm() - r).abs() < 1e-12);
        }
        assert!((block.rotation - Vector3::new(0.4, -0.7, 0.2)).norm() < 1e-14);
        // A second step about the same axis adds its angle.
        block.commit(&d, Vector6::zeros(), RotationUpdate::Exact);
        assert!((block.rotation - Vector3::new(0.8, -1.4, 0.4)).norm() < 1e-12);
        // Strain changes the volume by det(I + ε).
        let mut s = Vector12::zeros();
        s[6] = 1e-3;
        s[8] = -2e-3;
        s[10] = 4e-4;
        let before = block.volume();
        block.commit(&s, Vector6::zeros(), RotationUpdate::Exact);
        let det = (nalgebra::Matrix3::identity() + strain_tensor(&s)).determinant();
        assert!((block.volume() / before - det).abs() < 1e-13);
    }

    /// A commit moves each vertex where `move_point` takes it, to the last
    /// bit, by either update: its rotation and strain made once are the
    /// per-point ones.
    #[test]
    fn commit_moves_each_vertex_as_move_point_does() {
        let d = Vector12::from_fn(|i, _| ((i as f64) * 0.61 + 0.3).sin() * 1e-2);
        for update in [RotationUpdate::Exact, RotationUpdate::Linear] {
            let mut block = brick();
            let moved: Vec<_> = (block.vertices().iter())
                .map(|v| block.move_point(v, &d, update))
                .collect();
            block.commit(&d, Vector6::zeros(), update);
            assert_eq!(block.vertices(), &moved[..], "{update:?}");
        }
    }

    #[test]
    fn stress_and_strain_turn_with_the_block() {
        let mut block = brick();
        let mut d = Vector12::zeros();
        d[5] = std::f64::consts::FRAC_PI_2; // a quarter turn about z
        d[6] = 1e-3; // εx in the old frame
        let stress = Vector6::new(-5.0, 0.0, 0.0, 0.0, 0.0, 2.0);
        block.commit(&d, stress, RotationUpdate::Exact);
        // x becomes y: σx → σy, εx → εy, τxy changes sign.
        assert!((block.stress - Vector6::new(0.0, -5.0, 0.0, 0.0, 0.0, -2.0)).norm() < 1e-12);
        assert!((block.strain - Vector6::new(0.0, 1e-3, 0.0, 0.0, 0.0, 0.0)).norm() < 1e-15);
    }
}
