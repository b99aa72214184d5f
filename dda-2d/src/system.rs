//! The 2D block set the driver runs: polygons with their materials, loads,
//! fixed points and contact search (the shared shell of `dda-core` over
//! [`Block`]).

use crate::block::Block;

/// A force at a material point, constant or a time history.
pub type Force = dda_core::Force<2>;
/// A point load on a block; the point moves with the block.
pub type PointLoad = dda_core::PointLoad<2>;
/// A fixed or driven point of a block.
pub type FixedPoint = dda_core::FixedPoint<2>;

/// Polygonal blocks in the plane (per unit thickness): 2 dimensions, 6 DOF,
/// one tangent per contact, 3 stress components.
pub type Polygons = dda_core::BlockSet<Block, 2, 6, 1, 3>;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Plane, PlaneElastic};
    use dda_core::{BlockMatrix, BlockSystem, BlockVector};
    use nalgebra::{Point2, Vector2, Vector3};

    #[test]
    fn block_tangent_is_symmetric_psd_and_the_derivative_of_the_residual() {
        let v = [(0.0, 0.0), (2.0, 0.2), (1.6, 1.4), (0.3, 1.1)].map(|(x, y)| Point2::new(x, y));
        let mut block = Block::new(&v, 0, 2500.0).unwrap();
        block.stress = Vector3::new(-1e5, 2e4, 3e4);
        let law = PlaneElastic {
            young: 1e9,
            poisson: 0.3,
            plane: Plane::Stress,
        };
        let mut s = Polygons::new(vec![block], vec![Box::new(law)]);
        s.gravity = Vector2::new(0.0, -9.81);
        s.fixed.push(FixedPoint {
            target: v[1] + Vector2::new(1e-4, 0.0),
            velocity: Vector2::new(0.1, 0.0),
            ..FixedPoint::at(0, v[1])
        });
        s.fixed.push(FixedPoint {
            axis: Some(Vector2::new(0.6, 0.8)),
            ..FixedPoint::at(0, v[3])
        });
        s.loads.push(PointLoad {
            block: 0,
            point: v[2],
            force: Force::Constant(Vector2::new(5.0, -7.0)),
        });
        let terms = |d: &BlockVector<6>| {
            let (mut k, mut r) = (BlockMatrix::<6>::zeros(), BlockVector::<6>::zeros());
            s.block_terms(0, 0.3, d, &mut k, &mut r);
            (k, r)
        };
        let d0 = BlockVector::<6>::new(1e-4, -2e-4, 3e-4, 1e-5, -2e-5, 3e-5);
        let (k, _) = terms(&d0);
        assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
        assert!(k.symmetric_eigenvalues().min() > -1e-9 * k.norm());
        let h = 1e-7;
        for j in 0..6 {
            let mut e = BlockVector::<6>::zeros();
            e[j] = h;
            let column = -(terms(&(d0 + e)).1 - terms(&(d0 - e)).1) / (2.0 * h);
            assert!(
                (column - k.column(j)).norm() < 1e-6 * k.norm(),
                "column {j}"
            );
        }
    }
}
