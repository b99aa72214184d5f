//! The 3D block set the driver runs: polyhedra with their materials, loads,
//! fixed points and contact search (the shared shell of `dda-core` over
//! [`Block`]).

use dda_core::{BlockKind, Element};
use nalgebra::{Point3, Vector3, Vector6};

use crate::block::Block;
use crate::broad_phase::near_pairs;
use crate::contact::{pair_contacts, pair_contacts_among, Contact3, Feature};
use crate::entrance::PointEntrance;
use crate::features::pair_features;
use crate::kinematics::{Matrix12, RotationUpdate, TMatrix, Vector12};

/// A force at a material point, constant or a time history.
pub type Force = dda_core::Force<3>;
/// A point load on a block; the point moves with the block.
pub type PointLoad = dda_core::PointLoad<3>;
/// A fixed or driven point of a block.
pub type FixedPoint = dda_core::FixedPoint<3>;

/// Polyhedral blocks in space: 3 dimensions, 12 DOF, two tangents per
/// contact, 6 stress components.
pub type Polyhedra = dda_core::BlockSet<Block, 3, 12, 2, 6>;

/// Shi's 12-DOF polyhedron: the 3D element of the shared block set.
impl Element<3, 12, 2, 6> for Block {
    fn vertices(&self) -> &[Point3<f64>] {
        Block::vertices(self)
    }

    fn centroid(&self) -> Point3<f64> {
        Block::centroid(self)
    }

    fn measure(&self) -> f64 {
        Block::volume(self)
    }

    fn size(&self) -> f64 {
        Block::volume(self).abs().cbrt()
    }

    fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
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

    fn stress(&self) -> &Vector6<f64> {
        &self.stress
    }

    fn strain(&self) -> &Vector6<f64> {
        &self.strain
    }

    fn mass_matrix(&self) -> Matrix12 {
        Block::mass_matrix(self)
    }

    fn t_matrix(&self, p: &Point3<f64>) -> TMatrix {
        Block::t_matrix(self, p)
    }

    fn move_point(&self, p: &Point3<f64>, d: &Vector12, update: RotationUpdate) -> Point3<f64> {
        Block::move_point(self, p, d, update)
    }

    fn commit(&mut self, d: &Vector12, stress: Vector6<f64>, update: RotationUpdate) {
        Block::commit(self, d, stress, update)
    }

    fn rotation_state(&self) -> Vec<f64> {
        self.rotation.iter().copied().collect()
    }

    fn restore(
        &mut self,
        vertices: Vec<Point3<f64>>,
        stress: Vector6<f64>,
        strain: Vector6<f64>,
        rotation: &[f64],
    ) {
        Block::restore(
            self,
            vertices,
            stress,
            strain,
            Vector3::from_column_slice(rotation),
        )
    }

    type Entrance = PointEntrance;

    fn near_pairs(blocks: &[Self], range: f64) -> Vec<(usize, usize)> {
        let points: Vec<&[Point3<f64>]> = blocks.iter().map(|b| b.vertices()).collect();
        near_pairs(&points, range)
    }

    fn pair_contacts(blocks: &[Self], i: usize, j: usize, range: f64, law: usize) -> Vec<Contact3> {
        pair_contacts(blocks, i, j, range, law)
    }

    /// The vertex, edge and face pairs that may touch (`features.rs`).
    type Features = Vec<Feature>;

    const KEEPS_FEATURES: bool = true;

    fn pair_features(blocks: &[Self], i: usize, j: usize, range: f64, wide: f64) -> Vec<Feature> {
        pair_features(blocks, i, j, range, wide)
    }

    fn feature_kinds(&self, out: &mut Vec<u8>) {
        let s = self.shape();
        out.extend((0..s.vertices().len()).map(|v| u8::from(s.is_convex_vertex(v))));
        out.extend((0..s.edges().len()).map(|e| s.edge_kind(e) as u8));
    }

    fn pair_contacts_among(
        blocks: &[Self],
        i: usize,
        j: usize,
        range: f64,
        law: usize,
        features: &Vec<Feature>,
    ) -> Vec<Contact3> {
        pair_contacts_among(blocks, i, j, range, law, features)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::IsotropicElastic;
    use crate::polyhedron::cuboid;
    use dda_core::contacts::same_contacts;
    use dda_core::{BlockMatrix, BlockSystem, BlockVector};
    use nalgebra::Rotation3;
    use nalgebra::{Point3, Vector3, Vector6};

    #[test]
    fn block_tangent_is_symmetric_psd_and_the_derivative_of_the_residual() {
        let (v, f) = cuboid(
            Point3::new(1.0, 2.0, 3.0),
            Vector3::new(2.0, 1.0, 1.5),
            Rotation3::from_euler_angles(0.3, 0.1, -0.4),
        );
        let mut block = Block::new(&v, &f, 0, 2500.0).unwrap();
        block.stress = Vector6::new(-1e5, 2e4, 3e4, -1e4, 5e3, 7e3);
        let law = IsotropicElastic {
            young: 1e9,
            poisson: 0.3,
        };
        let mut s = Polyhedra::new(vec![block], vec![Box::new(law)]);
        s.gravity = Vector3::new(0.0, 0.0, -9.81);
        s.fixed.push(FixedPoint {
            target: v[1] + Vector3::new(1e-4, 0.0, -2e-4),
            velocity: Vector3::new(0.1, 0.0, 0.05),
            ..FixedPoint::at(0, v[1])
        });
        s.fixed.push(FixedPoint {
            axis: Some(Vector3::new(0.6, 0.0, 0.8)),
            ..FixedPoint::at(0, v[6])
        });
        s.loads.push(PointLoad {
            block: 0,
            point: v[3],
            force: Force::Constant(Vector3::new(5.0, -7.0, 3.0)),
        });
        let terms = |d: &BlockVector<12>| {
            let (mut k, mut r) = (BlockMatrix::<12>::zeros(), BlockVector::<12>::zeros());
            s.block_terms(0, 0.3, d, &mut k, &mut r);
            (k, r)
        };
        let d0 = BlockVector::<12>::from_fn(|i, _| 1e-4 * (i as f64 - 5.5) / 5.5);
        let (k, _) = terms(&d0);
        assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
        assert!(k.symmetric_eigenvalues().min() > -1e-9 * k.norm());
        let h = 1e-7;
        for j in 0..12 {
            let mut e = BlockVector::<12>::zeros();
            e[j] = h;
            let column = -(terms(&(d0 + e)).1 - terms(&(d0 - e)).1) / (2.0 * h);
            assert!(
                (column - k.column(j)).norm() < 1e-6 * k.norm(),
                "column {j}"
            );
        }
        // Gravity loads only the translation of the centroid.
        let mut s2 = Polyhedra::new(vec![s.blocks[0].clone()], vec![Box::new(law)]);
        s2.gravity = Vector3::new(0.0, 0.0, -9.81);
        s2.blocks[0].stress = Vector6::zeros();
        let (mut k2, mut r2) = (BlockMatrix::<12>::zeros(), BlockVector::<12>::zeros());
        s2.block_terms(0, 0.0, &BlockVector::<12>::zeros(), &mut k2, &mut r2);
        let w = -9.81 * s2.blocks[0].mass;
        assert!(
            (r2 - BlockVector::<12>::from_fn(|i, _| if i == 2 { w } else { 0.0 })).norm() < 1e-9
        );
    }

    /// Runs `steps` steps of the blocks' motion, `d(step, block)`, checking
    /// at each that the set's narrow phase on kept features finds the
    /// contacts a search of every feature finds; returns their keys.
    fn kept_as_searched(
        blocks: Vec<Block>,
        steps: usize,
        d: impl Fn(usize, usize) -> BlockVector<12>,
    ) -> Vec<Vec<dda_core::ContactKey>> {
        let law = IsotropicElastic {
            young: 1e9,
            poisson: 0.3,
        };
        let mut s = Polyhedra::new(blocks, vec![Box::new(law)]);
        let range = 0.06;
        let mut keys = Vec::new();
        for step in 0..steps {
            let pairs = s.near_pairs(range);
            let kept = s.pairs_contacts(&pairs, range);
            let searched: Vec<_> = (pairs.iter())
                .flat_map(|&(i, j)| s.pair_contacts(i, j, range))
                .collect();
            assert!(same_contacts(&kept, &searched), "step {step}");
            keys.push(kept.iter().map(|c| c.key).collect());
            let d: Vec<_> = (0..s.blocks.len()).map(|i| d(step, i)).collect();
            s.commit(&d, 1e-3, 1e-3 * step as f64);
        }
        keys
    }

    fn brick(center: Point3<f64>, size: Vector3<f64>) -> Block {
        let (v, f) = cuboid(center, size, Rotation3::identity());
        Block::new(&v, &f, 0, 2000.0).unwrap()
    }

    /// The set's narrow phase on kept features finds, step after step, what
    /// a search of every feature finds: on a wall whose bricks creep (the
    /// features kept), and on a cube that slides to the edge of its base in
    /// one step (found again: kept, its corners would miss the edge they
    /// now come near; the same pair of blocks throughout).
    #[test]
    fn kept_features_find_what_a_search_finds_as_blocks_move() {
        let wall = (0..9)
            .map(|k| {
                let (course, x) = (k / 3, 0.5 * (k % 3) as f64);
                let x = x + if course == 1 { 0.25 } else { 0.0 };
                let z = 0.125 + 0.25 * course as f64;
                brick(Point3::new(x, 0.0, z), Vector3::new(0.5, 0.25, 0.25))
            })
            .collect();
        let creep = |step: usize, i: usize| {
            let c = 1e-5 * (1.0 + (i + step) as f64);
            let mut d = BlockVector::<12>::zeros();
            (d[0], d[1], d[2], d[4], d[5]) = (c, 0.3 * c, -c / 2.0, c, -c);
            d
        };
        let keys = kept_as_searched(wall, 8, creep);
        assert_eq!(keys[0].len(), 64);
        let base = brick(Point3::new(0.0, 0.0, -0.5), Vector3::new(2.0, 2.0, 1.0));
        let cube = brick(Point3::new(0.5, 0.0, 0.25), Vector3::new(0.5, 0.5, 0.5));
        let slide = |step: usize, i: usize| {
            let mut d = creep(step, i) * 0.1;
            if step == 2 && i == 1 {
                d[0] += 0.23;
            }
            d
        };
        let keys = kept_as_searched(vec![base, cube], 5, slide);
        // Its corners left the face for the edge.
        assert_ne!(keys[2], keys[3]);
    }
}
