//! The 3D block system the driver runs: blocks, materials, loads, fixed
//! points and contact search.

use std::collections::HashMap;

use dda_core::{BlockMatrix, BlockSystem, BlockVector, ConstitutiveLaw};
use nalgebra::{Matrix6, Point3, Vector3, Vector6};

use crate::block::Block;
use crate::broad_phase::near_pairs;
use crate::contact::{pair_contacts, Contact3};
use crate::kinematics::{t_matrix, RotationUpdate, Vector12};

/// A force at a material point, constant or a time history.
pub type Force = dda_core::Force<3>;
/// A point load on a block; the point moves with the block.
pub type PointLoad = dda_core::PointLoad<3>;
/// A fixed or driven point of a block.
pub type FixedPoint = dda_core::FixedPoint<3>;

/// Polyhedral blocks in space.
pub struct Polyhedra {
    pub blocks: Vec<Block>,
    /// Constitutive law of each material.
    pub materials: Vec<Box<dyn ConstitutiveLaw<6>>>,
    /// Contact law index for each pair of materials (symmetric).
    pub joint_laws: Vec<Vec<usize>>,
    /// Contact law index for particular pairs of blocks (a joint set),
    /// keyed (lower index, higher index); overrides `joint_laws`.
    pub pair_laws: HashMap<(usize, usize), usize>,
    pub gravity: Vector3<f64>,
    pub loads: Vec<PointLoad>,
    pub fixed: Vec<FixedPoint>,
    /// Stiffness of the fixed-point springs (force per length); scenes take
    /// ten times the contact penalty unless they set it.
    pub fixed_penalty: f64,
    pub rotation_update: RotationUpdate,
    /// Model length scale; `None` takes half the diagonal of the model's bounds.
    pub length_scale: Option<f64>,
}

impl Polyhedra {
    /// Blocks with one material law each, all joints using law 0, no loads.
    pub fn new(blocks: Vec<Block>, materials: Vec<Box<dyn ConstitutiveLaw<6>>>) -> Self {
        let n = materials.len();
        let stiffest = materials.iter().map(|m| m.modulus()).fold(0.0, f64::max);
        Self {
            blocks,
            materials,
            joint_laws: vec![vec![0; n]; n],
            pair_laws: HashMap::new(),
            gravity: Vector3::zeros(),
            loads: Vec::new(),
            fixed: Vec::new(),
            fixed_penalty: stiffest,
            rotation_update: RotationUpdate::Exact,
            length_scale: None,
        }
    }

    /// Holds every vertex of a block in place.
    pub fn fix_block(&mut self, block: usize) {
        for v in self.blocks[block].vertices().to_vec() {
            self.fixed.push(FixedPoint::at(block, v));
        }
    }

    fn stress_after(&self, block: &Block, d: &Vector12) -> (Vector6<f64>, Matrix6<f64>) {
        let increment = d.fixed_rows::<6>(6).into_owned();
        self.materials[block.material].stress(&block.stress, &increment)
    }
}

impl BlockSystem<12, 2> for Polyhedra {
    fn block_count(&self) -> usize {
        self.blocks.len()
    }

    fn length_scale(&self) -> f64 {
        if let Some(w) = self.length_scale {
            return w;
        }
        let mut lo = Point3::from(Vector3::repeat(f64::INFINITY));
        let mut hi = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
        for b in &self.blocks {
            let (l, h) = b.bounds();
            lo = lo.inf(&l);
            hi = hi.sup(&h);
        }
        ((hi - lo).norm() / 2.0).max(f64::MIN_POSITIVE)
    }

    fn block_size(&self) -> f64 {
        let mut sizes: Vec<f64> = self
            .blocks
            .iter()
            .map(|b| b.volume().abs().cbrt())
            .collect();
        sizes.sort_by(f64::total_cmp);
        sizes
            .get(sizes.len().saturating_sub(1) / 2)
            .copied()
            .unwrap_or(1.0)
    }

    fn stiffness_scale(&self) -> f64 {
        self.materials
            .iter()
            .map(|m| m.modulus())
            .fold(0.0, f64::max)
    }

    fn dofs(&self, block: usize) -> usize {
        self.blocks[block].kind.dofs(12)
    }

    fn mass(&self, block: usize) -> BlockMatrix<12> {
        self.blocks[block].mass_matrix()
    }

    fn block_terms(
        &self,
        i: usize,
        time: f64,
        d: &BlockVector<12>,
        k: &mut BlockMatrix<12>,
        r: &mut BlockVector<12>,
    ) {
        let block = &self.blocks[i];
        let volume = block.volume();
        let (stress, tangent) = self.stress_after(block, d);
        let mut elastic = k.fixed_view_mut::<6, 6>(6, 6);
        elastic += tangent * volume;
        let mut strain_rows = r.fixed_rows_mut::<6>(6);
        strain_rows -= stress * volume;
        let mut translation = r.fixed_rows_mut::<3>(0);
        translation += self.gravity * block.mass;
        let c = block.centroid();
        for load in self.loads.iter().filter(|l| l.block == i) {
            *r += t_matrix(&load.point, &c).transpose() * load.force.at(time);
        }
        for fp in self.fixed.iter().filter(|f| f.block == i) {
            let t = t_matrix(&fp.point, &c);
            let held = fp.held() * self.fixed_penalty;
            let drift = fp.target_at(time) - fp.point;
            *k += t.transpose() * held * t;
            *r += t.transpose() * held * (drift - t * d);
        }
    }

    fn find_contacts(&self, range: f64) -> Vec<Contact3> {
        let points: Vec<&[Point3<f64>]> = self.blocks.iter().map(|b| b.vertices()).collect();
        let mut contacts = Vec::new();
        for (i, j) in near_pairs(&points, range) {
            let law = self.pair_laws.get(&(i, j)).copied().unwrap_or_else(|| {
                self.joint_laws[self.blocks[i].material][self.blocks[j].material]
            });
            contacts.extend(pair_contacts(&self.blocks, i, j, range, law));
        }
        contacts
    }

    fn potential_energy(&self) -> Option<f64> {
        let held = dda_core::loads::held_energy(&self.fixed, self.fixed_penalty)?;
        if !self.loads.is_empty() {
            return None;
        }
        let gravity: f64 = self
            .blocks
            .iter()
            .map(|b| -b.mass * self.gravity.dot(&b.centroid().coords))
            .sum();
        // ½ V σ·ε, with engineering shear strains.
        let strain: f64 = self
            .blocks
            .iter()
            .map(|b| 0.5 * b.volume() * b.stress.dot(&b.strain))
            .sum();
        Some(gravity + strain + held)
    }

    fn max_displacement(&self, d: &[BlockVector<12>]) -> f64 {
        self.blocks
            .iter()
            .zip(d)
            .flat_map(|(b, di)| {
                let c = b.centroid();
                b.vertices()
                    .iter()
                    .map(move |v| (t_matrix(v, &c) * di).norm())
            })
            .fold(0.0, f64::max)
    }

    fn commit(&mut self, d: &[BlockVector<12>], _dt: f64, _time: f64) {
        let update = self.rotation_update;
        for fp in &mut self.fixed {
            fp.point = self.blocks[fp.block].move_point(&fp.point, &d[fp.block], update);
        }
        for load in &mut self.loads {
            load.point = self.blocks[load.block].move_point(&load.point, &d[load.block], update);
        }
        let stresses: Vec<Vector6<f64>> = self
            .blocks
            .iter()
            .zip(d)
            .map(|(b, di)| self.stress_after(b, di).0)
            .collect();
        for ((block, di), stress) in self.blocks.iter_mut().zip(d).zip(stresses) {
            block.commit(di, stress, update);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::IsotropicElastic;
    use crate::polyhedron::cuboid;
    use nalgebra::Rotation3;

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
}
