//! The 2D block set the driver runs: polygons with their materials, loads,
//! fixed points and contact search (the shared shell of `dda-core` over
//! [`Block`]).

use dda_core::{BlockKind, Element};
use nalgebra::{Matrix2x6, Point2, Vector3, Vector6};

use crate::block::Block;
use crate::broad_phase::near_pairs;
use crate::contact::{pair_contacts, Contact2};
use crate::kinematics::{t_matrix, Matrix6, RotationUpdate};

/// A force at a material point, constant or a time history.
pub type Force = dda_core::Force<2>;
/// A point load on a block; the point moves with the block.
pub type PointLoad = dda_core::PointLoad<2>;
/// A fixed or driven point of a block.
pub type FixedPoint = dda_core::FixedPoint<2>;

/// Polygonal blocks in the plane (per unit thickness): 2 dimensions, 6 DOF,
/// one tangent per contact, 3 stress components.
pub type Polygons = dda_core::BlockSet<Block, 2, 6, 1, 3>;

/// Shi's 6-DOF polygon: the 2D element of the shared block set.
impl Element<2, 6, 1, 3> for Block {
    fn vertices(&self) -> &[Point2<f64>] {
        Block::vertices(self)
    }

    fn centroid(&self) -> Point2<f64> {
        Block::centroid(self)
    }

    fn measure(&self) -> f64 {
        Block::area(self)
    }

    fn size(&self) -> f64 {
        Block::area(self).abs().sqrt()
    }

    fn bounds(&self) -> (Point2<f64>, Point2<f64>) {
        Block::bounds(self)
    }

    fn mass(&self) -> f64 {
        self.mass
    }

    fn material(&self) -> usize {
        self.material
    }

    fn kind(&self) -> BlockKind {
        self.kind
    }

    fn stress(&self) -> &Vector3<f64> {
        &self.stress
    }

    fn strain(&self) -> &Vector3<f64> {
        &self.strain
    }

    fn mass_matrix(&self) -> Matrix6 {
        Block::mass_matrix(self)
    }

    fn t_matrix(&self, p: &Point2<f64>) -> Matrix2x6<f64> {
        t_matrix(p, &Block::centroid(self))
    }

    fn move_point(&self, p: &Point2<f64>, d: &Vector6<f64>, update: RotationUpdate) -> Point2<f64> {
        Block::move_point(self, p, d, update)
    }

    fn commit(&mut self, d: &Vector6<f64>, stress: Vector3<f64>, update: RotationUpdate) {
        Block::commit(self, d, stress, update)
    }

    fn rotation_state(&self) -> Vec<f64> {
        vec![self.rotation]
    }

    fn restore(
        &mut self,
        vertices: Vec<Point2<f64>>,
        stress: Vector3<f64>,
        strain: Vector3<f64>,
        rotation: &[f64],
    ) {
        Block::restore(self, vertices, stress, strain, rotation[0])
    }

    type Entrance = dda_core::Entrance<6, 1>;

    fn near_pairs(blocks: &[Self], range: f64) -> Vec<(usize, usize)> {
        let outlines: Vec<&[Point2<f64>]> = blocks.iter().map(|b| b.vertices()).collect();
        near_pairs(&outlines, range)
    }

    fn pair_contacts(blocks: &[Self], i: usize, j: usize, range: f64, law: usize) -> Vec<Contact2> {
        pair_contacts(blocks, i, j, range, law)
    }

    type Features = ();
}

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

    /// A block's own motion leaves out its translation and bounds how far
    /// its points move against each other: a column turning about a
    /// corner (a rocking column's pivot) reaches its far corner's whole
    /// motion, a stretch the stretch across the block; a block counted
    /// whole moves as far as its farthest point.
    #[test]
    fn a_blocks_own_motion_leaves_out_its_translation() {
        let law = || -> Box<dyn dda_core::ConstitutiveLaw<3>> {
            Box::new(PlaneElastic {
                young: 1e9,
                poisson: 0.3,
                plane: Plane::Stress,
            })
        };
        let column =
            [(0.0, 0.0), (1.0, 0.0), (1.0, 4.0), (0.0, 4.0)].map(|(x, y)| Point2::new(x, y));
        let s = Polygons::new(vec![Block::new(&column, 0, 2500.0).unwrap()], vec![law()]);
        let own = |d: BlockVector<6>| s.max_own_motion(&[d], &[false]);
        let whole = |d: BlockVector<6>| s.max_own_motion(&[d], &[true]);
        let shift = BlockVector::<6>::new(0.3, -0.2, 0.0, 0.0, 0.0, 0.0);
        assert!(own(shift) < 1e-15, "{}", own(shift));
        assert!((whole(shift) - 0.13f64.sqrt()).abs() < 1e-15);
        // A turn θ about the corner (0, 0): the centroid (0.5, 2) moves
        // θ × (−2, 0.5).
        let theta = 1e-4;
        let pivot = BlockVector::<6>::new(-2.0 * theta, 0.5 * theta, theta, 0.0, 0.0, 0.0);
        let far = theta * 17f64.sqrt();
        assert!((own(pivot) - far).abs() < 1e-12 * far, "{}", own(pivot));
        assert!((s.max_displacement(&[pivot]) - far).abs() < 1e-12 * far);
        let stretch = BlockVector::<6>::new(0.0, 0.0, 0.0, 1e-5, 0.0, 0.0);
        assert!((own(stretch) - 1e-5).abs() < 1e-17, "{}", own(stretch));
        // Two blocks: each counted its own way.
        let shifted = column.map(|p| p + Vector2::new(3.0, 0.0));
        let blocks = vec![
            Block::new(&column, 0, 2500.0).unwrap(),
            Block::new(&shifted, 0, 2500.0).unwrap(),
        ];
        let two = Polygons::new(blocks, vec![law()]);
        assert_eq!(
            two.max_own_motion(&[shift, stretch], &[false, false]),
            own(stretch)
        );
        assert_eq!(
            two.max_own_motion(&[shift, stretch], &[true, false]),
            whole(shift)
        );
    }

    /// Each block's loads and fixed points, read from the set's listing,
    /// give the block terms that filtering the whole lists gives (the path
    /// of a set whose lists changed after the listing), to the last bit;
    /// points on no block act on none.
    #[test]
    fn listed_points_give_the_terms_of_the_filtered_lists() {
        let square = |x: f64| [(x, 0.0), (x + 1.0, 0.0), (x + 1.0, 1.0), (x, 1.0)];
        let law = || -> Box<dyn dda_core::ConstitutiveLaw<3>> {
            Box::new(PlaneElastic {
                young: 1e9,
                poisson: 0.3,
                plane: Plane::Stress,
            })
        };
        let set = || {
            let blocks = (0..4)
                .map(|b| {
                    let v = square(2.0 * b as f64).map(|(x, y)| Point2::new(x, y));
                    Block::new(&v, 0, 2500.0).unwrap()
                })
                .collect();
            let mut s = Polygons::new(blocks, vec![law()]);
            // Interleaved over the blocks, two on block 2, one on none.
            for (k, b) in [2, 0, 3, 2, 7].into_iter().enumerate() {
                let at = Point2::new(2.0 * b as f64 + 0.3, 0.1 * k as f64);
                s.fixed.push(FixedPoint {
                    target: at + Vector2::new(1e-4 * k as f64, -2e-5),
                    ..FixedPoint::at(b, at)
                });
                s.loads.push(PointLoad {
                    block: (b + 1) % 5,
                    point: at,
                    force: Force::Constant(Vector2::new(3.0 + k as f64, -7.0)),
                });
            }
            s
        };
        let terms = |s: &Polygons, i: usize| {
            let d = BlockVector::<6>::new(1e-4, -2e-4, 3e-4, 1e-5, -2e-5, 3e-5) * (i + 1) as f64;
            let (mut k, mut r) = (BlockMatrix::<6>::zeros(), BlockVector::<6>::zeros());
            s.block_terms(i, 0.3, &d, &mut k, &mut r);
            (k, r)
        };
        let listed = set();
        let mut filtered = set();
        terms(&filtered, 0);
        // Listed at the first terms; a load on no block makes the listing
        // stale without changing any block's terms.
        filtered.loads.push(PointLoad {
            block: 9,
            point: Point2::new(0.5, 0.5),
            force: Force::Constant(Vector2::new(1.0, 1.0)),
        });
        let bare = Polygons::new(set().blocks, vec![law()]);
        for i in 0..4 {
            assert_eq!(terms(&listed, i), terms(&filtered, i), "block {i}");
            // Every block but 1 has a fixed point, and every one a load.
            assert_ne!(terms(&listed, i).1, terms(&bare, i).1, "block {i}");
        }
    }
}
