//! Shi's 12-DOF uniform-strain kinematics in 3D: the T-matrix, the mass
//! matrix and the end-of-step motion.
//!
//! DOF order: (u0, v0, w0, rx, ry, rz, εx, εy, εz, γyz, γzx, γxy) about the
//! block centroid, engineering shears.

use std::sync::OnceLock;

use nalgebra::{Matrix3, Point3, Rotation3, SMatrix, SVector, Vector3, Vector6};

use crate::polyhedron::CentralMoments;

/// The 12×12 block matrix type.
pub type Matrix12 = SMatrix<f64, 12, 12>;
/// One block's DOF vector.
pub type Vector12 = SVector<f64, 12>;
/// The 3×12 T-matrix type.
pub type TMatrix = SMatrix<f64, 3, 12>;

/// Displacement of point `p` of a block with centroid `c` is `t_matrix(p, c)·D`
/// (A9.1): translation, r × X, and ε·X with the engineering shears halved.
pub fn t_matrix(p: &Point3<f64>, c: &Point3<f64>) -> TMatrix {
    let (x, y, z) = (p.x - c.x, p.y - c.y, p.z - c.z);
    #[rustfmt::skip]
    let t = TMatrix::from_row_slice(&[
        1.0, 0.0, 0.0, 0.0, z, -y, x, 0.0, 0.0, 0.0, z / 2.0, y / 2.0,
        0.0, 1.0, 0.0, -z, 0.0, x, 0.0, y, 0.0, z / 2.0, 0.0, x / 2.0,
        0.0, 0.0, 1.0, y, -x, 0.0, 0.0, 0.0, z, y / 2.0, x / 2.0, 0.0,
    ]);
    t
}

/// `t_matrix(p, c)ᵀ·v`, the generalised force of a force `v` at `p`,
/// without making the matrix: the narrow phase makes six a contact
/// entrance. Each entry adds the same products in the same order as the
/// product with the matrix, so the two agree to the last bit.
pub fn t_matrix_transpose_times(p: &Point3<f64>, c: &Point3<f64>, v: &Vector3<f64>) -> Vector12 {
    t_matrix_transpose_times_arm(&(p - c), v)
}

/// [`t_matrix_transpose_times`] for the point at `arm` from the centroid
/// (`p − c`, made by the same subtractions).
#[inline]
pub fn t_matrix_transpose_times_arm(arm: &Vector3<f64>, v: &Vector3<f64>) -> Vector12 {
    let (x, y, z) = (arm.x, arm.y, arm.z);
    let [a, b, d] = [v.x, v.y, v.z];
    Vector12::from([
        a,
        b,
        d,
        -z * b + y * d,
        z * a - x * d,
        -y * a + x * b,
        x * a,
        y * b,
        z * d,
        z / 2.0 * b + y / 2.0 * d,
        z / 2.0 * a + x / 2.0 * d,
        y / 2.0 * a + x / 2.0 * b,
    ])
}

/// `t_matrix(p, c)·d`, the displacement of the point at `arm` (`p − c`)
/// from the centroid, without making the matrix: a move reads a contact
/// entrance's gap and shear off two of these, where its rows take six
/// products.
#[inline]
pub fn t_matrix_times_arm(arm: &Vector3<f64>, d: &Vector12) -> Vector3<f64> {
    let (x, y, z) = (arm.x, arm.y, arm.z);
    Vector3::new(
        d[0] + z * d[4] - y * d[5] + x * d[6] + z / 2.0 * d[10] + y / 2.0 * d[11],
        d[1] - z * d[3] + x * d[5] + y * d[7] + z / 2.0 * d[9] + x / 2.0 * d[11],
        d[2] + y * d[3] - x * d[4] + z * d[8] + y / 2.0 * d[9] + x / 2.0 * d[10],
    )
}

/// Mass matrix ρ∫TᵀT dV from the central moments (A9.3). With T = [I | G(X)]
/// and G linear in X, the cross terms vanish about the centroid and the rest
/// is Σ J_ab G_aᵀ G_b.
pub fn mass_matrix(m: &CentralMoments, density: f64) -> Matrix12 {
    let g = axis_products();
    let mut k = Matrix12::zeros();
    let mut translation = k.fixed_view_mut::<3, 3>(0, 0);
    translation += Matrix3::identity() * m.volume;
    let mut rest = k.fixed_view_mut::<9, 9>(3, 3);
    for (a, products) in g.iter().enumerate() {
        for (b, product) in products.iter().enumerate() {
            rest += product * m.second[(a, b)];
        }
    }
    k * density
}

/// G_aᵀ G_b for the unit axes a and b, G_a the T-matrix columns beyond
/// translation at the point a from the centroid: the same for every block,
/// made once (each block's mass matrix, built once a step attempt and once
/// for the energy check, was some 8,000 instructions with them).
fn axis_products() -> &'static [[SMatrix<f64, 9, 9>; 3]; 3] {
    static PRODUCTS: OnceLock<[[SMatrix<f64, 9, 9>; 3]; 3]> = OnceLock::new();
    PRODUCTS.get_or_init(|| {
        let origin = Point3::origin();
        let g: [SMatrix<f64, 3, 9>; 3] = [Vector3::x(), Vector3::y(), Vector3::z()].map(|axis| {
            t_matrix(&Point3::from(axis), &origin)
                .fixed_columns::<9>(3)
                .into_owned()
        });
        std::array::from_fn(|a| std::array::from_fn(|b| g[a].transpose() * g[b]))
    })
}

pub use dda_core::RotationUpdate;

/// The small-strain tensor of the DOF vector.
pub fn strain_tensor(d: &Vector12) -> Matrix3<f64> {
    voigt_strain(&Vector6::new(d[6], d[7], d[8], d[9], d[10], d[11]))
}

/// Tensor of a strain in Voigt order (εx, εy, εz, γyz, γzx, γxy).
pub fn voigt_strain(e: &Vector6<f64>) -> Matrix3<f64> {
    Matrix3::new(
        e[0],
        e[5] / 2.0,
        e[4] / 2.0,
        e[5] / 2.0,
        e[1],
        e[3] / 2.0,
        e[4] / 2.0,
        e[3] / 2.0,
        e[2],
    )
}

/// Voigt strain (engineering shears) of a symmetric tensor.
pub fn strain_voigt(e: &Matrix3<f64>) -> Vector6<f64> {
    Vector6::new(
        e[(0, 0)],
        e[(1, 1)],
        e[(2, 2)],
        2.0 * e[(1, 2)],
        2.0 * e[(0, 2)],
        2.0 * e[(0, 1)],
    )
}

/// Tensor of a stress in Voigt order (σx, σy, σz, τyz, τzx, τxy).
pub fn voigt_stress(s: &Vector6<f64>) -> Matrix3<f64> {
    Matrix3::new(s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2])
}

/// Voigt stress of a symmetric tensor.
pub fn stress_voigt(s: &Matrix3<f64>) -> Vector6<f64> {
    Vector6::new(
        s[(0, 0)],
        s[(1, 1)],
        s[(2, 2)],
        s[(1, 2)],
        s[(0, 2)],
        s[(0, 1)],
    )
}

/// The rotation of the step: Rodrigues of the rotation vector (rx, ry, rz).
pub fn step_rotation(d: &Vector12) -> Rotation3<f64> {
    Rotation3::from_scaled_axis(Vector3::new(d[3], d[4], d[5]))
}

/// Where point `p` goes for step displacement `d` about centroid `c`.
pub fn move_point(
    p: &Point3<f64>,
    c: &Point3<f64>,
    d: &Vector12,
    update: RotationUpdate,
) -> Point3<f64> {
    point_mover(c, d, update)(p)
}

/// [`move_point`] for many points of one block: the step's rotation and
/// strain are made once, not at every point.
pub fn point_mover<'a>(
    c: &'a Point3<f64>,
    d: &'a Vector12,
    update: RotationUpdate,
) -> impl Fn(&Point3<f64>) -> Point3<f64> + 'a {
    let exact = (update == RotationUpdate::Exact).then(|| (step_rotation(d), strain_tensor(d)));
    move |p| match exact {
        None => p + t_matrix(p, c) * d,
        Some((rotation, strain)) => {
            let arm = p - c;
            let strained = arm + strain * arm;
            c + Vector3::new(d[0], d[1], d[2]) + rotation * strained
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polyhedron::{central_moments, cuboid};

    #[test]
    fn the_transpose_product_is_the_t_matrix_products_to_the_last_bit() {
        use proptest::prelude::*;
        let mut runner = crate::seeded_runner(2048);
        let vector = || prop::array::uniform3(-1e3..1e3f64).prop_map(Vector3::from);
        runner
            .run(&(vector(), vector(), vector()), |(p, c, v)| {
                let (p, c) = (Point3::from(p), Point3::from(c));
                let made = t_matrix(&p, &c).transpose() * v;
                let direct = t_matrix_transpose_times(&p, &c, &v);
                for k in 0..12 {
                    prop_assert_eq!(made[k].to_bits(), direct[k].to_bits(), "entry {}", k);
                }
                Ok(())
            })
            .unwrap();
    }

    /// The point's displacement is the T-matrix's product, to round-off.
    #[test]
    fn a_points_displacement_is_the_t_matrix_product() {
        use proptest::prelude::*;
        let mut runner = crate::seeded_runner(2048);
        let vector = || prop::array::uniform3(-1e3..1e3f64).prop_map(Vector3::from);
        let dofs = prop::array::uniform12(-1.0..1.0f64).prop_map(Vector12::from);
        runner
            .run(&(vector(), vector(), dofs), |(p, c, d)| {
                let (p, c) = (Point3::from(p), Point3::from(c));
                let made = t_matrix(&p, &c) * d;
                let direct = t_matrix_times_arm(&(p - c), &d);
                let scale = d.abs().max() * (1.0 + (p - c).abs().max());
                prop_assert!(
                    (made - direct).abs().max() <= 1e-14 * scale,
                    "{made} {direct}"
                );
                Ok(())
            })
            .unwrap();
    }

    /// A skewed, non-convex solid far from the origin.
    fn shape() -> (Vec<Point3<f64>>, Vec<Vec<usize>>) {
        let outline = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.8, 1.3), (0.3, 2.1)]
            .map(|(x, y)| nalgebra::Point2::new(x, y));
        let (v, f) = crate::polyhedron::prism(&outline, -0.4, 1.1);
        let r = Rotation3::from_euler_angles(0.3, -0.5, 1.1);
        let v = v
            .iter()
            .map(|p| Point3::from(r * p.coords) + Vector3::new(10.0, -3.0, 5.0))
            .collect();
        (v, f)
    }

    #[test]
    fn mass_matrix_is_the_integral_of_t_transpose_t() {
        // Compare with ρ∫TᵀT dV by the degree-2 rule on tetrahedra (weights
        // 1/4 at (α, β, β, β), α = 0.5854101966249685) of a fan from a vertex.
        let (v, faces) = shape();
        let m = central_moments(&v, &faces);
        let rho = 2.5;
        let exact = mass_matrix(&m, rho);
        let (alpha, beta) = (0.585_410_196_624_968_5, 0.138_196_601_125_010_5);
        let o = v[0];
        let mut quad = Matrix12::zeros();
        for f in &faces {
            for k in 1..f.len() - 1 {
                let (a, b, c) = (v[f[0]], v[f[k]], v[f[k + 1]]);
                let vol = (a - o).dot(&(b - o).cross(&(c - o))) / 6.0;
                let corners = [o, a, b, c];
                for i in 0..4 {
                    let mut p = Vector3::zeros();
                    for (j, q) in corners.iter().enumerate() {
                        p += q.coords * if i == j { alpha } else { beta };
                    }
                    let t = t_matrix(&Point3::from(p), &m.centroid);
                    quad += t.transpose() * t * (vol / 4.0 * rho);
                }
            }
        }
        assert!(
            (exact - quad).norm() < 1e-12 * exact.norm(),
            "{}",
            (exact - quad).norm()
        );
        assert_eq!(exact, exact.transpose());
        assert!(exact.cholesky().is_some(), "positive definite");
    }

    #[test]
    fn t_matrix_is_the_derivative_of_the_exact_motion() {
        let c = Point3::new(1.0, -2.0, 0.5);
        let p = Point3::new(1.7, -1.4, 1.3);
        let h = 1e-6;
        for base in [Vector12::zeros()] {
            let t = t_matrix(&p, &c);
            for k in 0..12 {
                let mut d = Vector12::zeros();
                d[k] = h;
                let fd = (move_point(&p, &c, &(base + d), RotationUpdate::Exact)
                    - move_point(&p, &c, &(base - d), RotationUpdate::Exact))
                    / (2.0 * h);
                assert!((fd - t.column(k)).norm() < 1e-9, "column {k}");
            }
        }
    }

    #[test]
    fn exact_update_is_rigid_and_linear_update_stretches() {
        let (v, _) = cuboid(
            Point3::origin(),
            Vector3::new(1.0, 2.0, 3.0),
            Rotation3::identity(),
        );
        let c = Point3::origin();
        let mut d = Vector12::zeros();
        d[3] = 0.3;
        d[4] = -0.2;
        d[5] = 0.6;
        let r2: f64 = 0.09 + 0.04 + 0.36;
        for p in &v {
            let q = move_point(p, &c, &d, RotationUpdate::Exact);
            assert!(((q - c).norm() - (p - c).norm()).abs() < 1e-14);
            let l = move_point(p, &c, &d, RotationUpdate::Linear);
            // |X + r × X|² = |X|² + |r × X|²: never shorter, longer unless X ∥ r.
            let expect = ((p - c).norm_squared()
                + d.fixed_rows::<3>(3).cross(&(p - c)).norm_squared())
            .sqrt();
            assert!(((l - c).norm() - expect).abs() < 1e-14);
            assert!((l - c).norm() <= (p - c).norm() * (1.0 + r2).sqrt() + 1e-14);
        }
    }
}
