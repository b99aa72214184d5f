//! The block set both dimensions share: blocks with their materials, joint
//! laws, gravity, point loads, fixed or driven points and measured points,
//! written once over an [`Element`] that a dimension crate implements with
//! its geometry, T-matrix, integrals, narrow phase and end-of-step motion.

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use nalgebra::{Point, SMatrix, SVector};
use rayon::prelude::*;

use crate::by_block::ByBlock;
use crate::constitutive::ConstitutiveLaw;
use crate::contacts::{BlockVector, Contact, EntranceRows};
use crate::error::DdaError;
use crate::loads::{held_energy, FixedPoint, MeasuredPoint, PointLoad};
use crate::system::{each_pair_contacts, Carry};
use crate::system::{BlockKind, BlockMatrix, BlockState, BlockSystem, SystemState};
use crate::{BLOCKS_PER_TASK, PAIRS_PER_TASK};

/// Angle tolerance for parallel edges and faces and for wedge tests (Shi's
/// h1 = 3°), in radians.
pub const ANGLE_TOLERANCE: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// Deepest penetration a contact candidate may have, as a share of the
/// search range (Shi's d9 = 0.3·d0).
pub const PENETRATION_SHARE: f64 = 0.3;

/// Where a block's contacts can lie: its axis-aligned bounds grown by twice
/// the search range. A vertex or edge makes a contact with a block only
/// within the range of its edges, faces or corners, and past an edge's end
/// or beside a reflex edge that is within √2 × the range of the block, so a
/// feature outside the other block's reach makes none and need not be
/// examined.
#[derive(Debug, Clone, Copy)]
pub struct Reach<const D: usize> {
    lo: Point<f64, D>,
    hi: Point<f64, D>,
}

impl<const D: usize> Reach<D> {
    /// The reach of a block with these bounds (min, max) at this range.
    pub fn new((lo, hi): (Point<f64, D>, Point<f64, D>), range: f64) -> Self {
        let grow = SVector::<f64, D>::repeat(2.0 * range);
        Self {
            lo: lo - grow,
            hi: hi + grow,
        }
    }

    /// A reach holding every point (every feature examined).
    pub fn everywhere() -> Self {
        Self {
            lo: Point::from(SVector::repeat(f64::NEG_INFINITY)),
            hi: Point::from(SVector::repeat(f64::INFINITY)),
        }
    }

    /// Whether the point lies within the reach.
    pub fn holds(&self, p: &Point<f64, D>) -> bool {
        (0..D).all(|k| p[k] >= self.lo[k] && p[k] <= self.hi[k])
    }

    /// Whether the bounds of the segment from `u` to `v` meet the reach.
    pub fn meets(&self, u: &Point<f64, D>, v: &Point<f64, D>) -> bool {
        (0..D).all(|k| u[k].min(v[k]) <= self.hi[k] && u[k].max(v[k]) >= self.lo[k])
    }
}

/// How vertices move at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum RotationUpdate {
    /// Strain first, then the exact rotation of the step (Rodrigues in 3D):
    /// no false growth of the area or volume.
    #[default]
    Exact,
    /// Shi's original linear update x + T·D, which inflates the block by
    /// (1 + |r|²) each step; kept for comparison.
    Linear,
}

/// One block of a dimension: a body in `D` dimensions with `N` DOF about its
/// centroid (translation and rotation first, the `S` strains last), meeting
/// others through contacts with `T` tangential directions.
pub trait Element<const D: usize, const N: usize, const T: usize, const S: usize>:
    Sized + Send + Sync
{
    fn vertices(&self) -> &[Point<f64, D>];
    fn centroid(&self) -> Point<f64, D>;
    /// Area (2D, per unit thickness) or volume (3D).
    fn measure(&self) -> f64;
    /// A typical length: the square root of the area or the cube root of
    /// the volume.
    fn size(&self) -> f64;
    /// Axis-aligned bounds (min, max).
    fn bounds(&self) -> (Point<f64, D>, Point<f64, D>);
    /// Mass (per unit thickness in 2D); constant while the block strains.
    fn mass(&self) -> f64;
    /// Index of the block's material.
    fn material(&self) -> usize;
    fn kind(&self) -> BlockKind;
    /// Stress, tension positive, engineering order of the strains.
    fn stress(&self) -> &SVector<f64, S>;
    /// Accumulated strain.
    fn strain(&self) -> &SVector<f64, S>;
    /// ∫ρTᵀT over the block.
    fn mass_matrix(&self) -> SMatrix<f64, N, N>;
    /// The T-matrix: the displacement of point `p` is `T(p)·d` to first
    /// order.
    fn t_matrix(&self, p: &Point<f64, D>) -> SMatrix<f64, D, N>;
    /// Where point `p` of the block goes when step `d` is committed; its
    /// derivative at `d = 0` is the T-matrix.
    fn move_point(
        &self,
        p: &Point<f64, D>,
        d: &SVector<f64, N>,
        update: RotationUpdate,
    ) -> Point<f64, D>;
    /// Accumulated rotation: the angle (2D) or the rotation vector (3D).
    fn rotation_state(&self) -> Vec<f64>;
    /// Puts the block where a checkpoint found it: these vertices (same
    /// count and order as now), stress, strain and accumulated rotation.
    fn restore(
        &mut self,
        vertices: Vec<Point<f64, D>>,
        stress: SVector<f64, S>,
        strain: SVector<f64, S>,
        rotation: &[f64],
    );
    /// Applies an accepted step: vertices, stress (`stress` is the stress
    /// after the step's strain, in the frame at the start of the step),
    /// strain and rotation.
    fn commit(&mut self, d: &SVector<f64, N>, stress: SVector<f64, S>, update: RotationUpdate);
    /// How the blocks' contacts keep their entrances' rows.
    type Entrance: EntranceRows<N, T>;
    /// Pairs (i, j), i < j, of blocks close enough to touch within `range`.
    fn near_pairs(blocks: &[Self], range: f64) -> Vec<(usize, usize)>;
    /// The contacts between blocks `i` and `j` within `range`, with law
    /// index `law`.
    fn pair_contacts(
        blocks: &[Self],
        i: usize,
        j: usize,
        range: f64,
        law: usize,
    ) -> Vec<Contact<N, T, Self::Entrance>>;
    /// Which features of a pair of blocks may make contacts, where the set
    /// keeps them between searches (`KEEPS_FEATURES`); `()` where not.
    type Features: Default + Send + Sync;
    /// Whether the set keeps each pair's features, found at a range wider
    /// by `FEATURE_SKIN`, and has later searches test only those while no
    /// point has moved by more than half the difference.
    const KEEPS_FEATURES: bool = false;
    /// The features of blocks `i` and `j` that may make contacts in a
    /// search within `range` or wider, found at `wide`, while no point has
    /// moved by more than half of `wide` less the range searched and
    /// [`Element::feature_kinds`] stay the same.
    fn pair_features(blocks: &[Self], i: usize, j: usize, range: f64, wide: f64) -> Self::Features {
        let _ = (blocks, i, j, range, wide);
        Self::Features::default()
    }
    /// What kept features' tests read of the block besides distances (in
    /// 3D, which vertices are convex and each edge's kind), one byte each,
    /// appended to `out`.
    fn feature_kinds(&self, out: &mut Vec<u8>) {
        let _ = out;
    }
    /// [`Element::pair_contacts`] among `features`, found by
    /// [`Element::pair_features`] while they serve: the same contacts, to
    /// the last bit.
    fn pair_contacts_among(
        blocks: &[Self],
        i: usize,
        j: usize,
        range: f64,
        law: usize,
        features: &Self::Features,
    ) -> Vec<Contact<N, T, Self::Entrance>> {
        let _ = features;
        Self::pair_contacts(blocks, i, j, range, law)
    }
}

/// Blocks of one dimension with what acts on them: the [`BlockSystem`] the
/// driver runs.
pub struct BlockSet<B, const D: usize, const N: usize, const T: usize, const S: usize>
where
    B: Element<D, N, T, S>,
{
    pub blocks: Vec<B>,
    /// Constitutive law of each material.
    pub materials: Vec<Box<dyn ConstitutiveLaw<S>>>,
    /// Contact law index for each pair of materials (symmetric).
    pub joint_laws: Vec<Vec<usize>>,
    /// Contact law index for particular pairs of blocks (a joint set),
    /// keyed (lower index, higher index); overrides `joint_laws`.
    pub pair_laws: HashMap<(usize, usize), usize>,
    /// Body force per unit mass (m/s²).
    pub gravity: SVector<f64, D>,
    /// Point loads. The set lists each block's loads and fixed points at
    /// its first block terms: change the lists, not a point's block, after
    /// that (a set whose lists changed length filters them again).
    pub loads: Vec<PointLoad<D>>,
    pub fixed: Vec<FixedPoint<D>>,
    /// Points whose motion is an output only.
    pub measured: Vec<MeasuredPoint<D>>,
    /// Stiffness of the fixed-point springs (force per length); scenes take
    /// ten times the contact penalty unless they set it.
    pub fixed_penalty: f64,
    pub rotation_update: RotationUpdate,
    /// Model length scale; `None` takes half the diagonal of the model's bounds.
    pub length_scale: Option<f64>,
    /// The last broad phase, reused while the blocks stay near where it
    /// found them.
    near: Mutex<Option<NearPairs<D>>>,
    /// The near pairs' features, where the blocks keep them
    /// (`Element::KEEPS_FEATURES`).
    features: Mutex<FeatureStore<B::Features, D>>,
    /// Which loads and fixed points act on each block.
    points_of: OnceLock<PointsOf>,
}

/// Which point loads and fixed points act on each block (indices into
/// `loads` and `fixed`, in their order), with the lists' lengths when made.
/// A block's terms read its own: filtering every point for every block at
/// every move took half the run of a 3,030-block wall on a fixed base of
/// 1,010 blocks (4,040 fixed points).
#[derive(Debug)]
struct PointsOf {
    lengths: (usize, usize),
    loads: ByBlock,
    fixed: ByBlock,
}

/// How much wider than asked a broad phase searches, as a share of the
/// range: later steps reuse its pairs until the blocks' bounds have moved
/// by half the difference (a standing wall, for thousands of steps).
const NEAR_SKIN: f64 = 0.25;

/// Block pairs found by a broad phase, with the range it searched and the
/// blocks' bounds then.
#[derive(Debug)]
struct NearPairs<const D: usize> {
    bounds: Vec<(Point<f64, D>, Point<f64, D>)>,
    range: f64,
    pairs: Vec<(usize, usize)>,
}

impl<const D: usize> NearPairs<D> {
    /// The pairs, if they hold every pair within `range` of blocks with
    /// these bounds: each bound has moved by at most δ since the search,
    /// so two blocks within `range` now were within `range` + 2δ then.
    fn reach(
        &self,
        bounds: &[(Point<f64, D>, Point<f64, D>)],
        range: f64,
    ) -> Option<&[(usize, usize)]> {
        if bounds.len() != self.bounds.len() {
            return None;
        }
        let mut moved = 0.0_f64;
        for ((lo, hi), (lo0, hi0)) in bounds.iter().zip(&self.bounds) {
            for k in 0..D {
                moved = moved
                    .max((lo[k] - lo0[k]).abs())
                    .max((hi[k] - hi0[k]).abs());
            }
        }
        (range + 2.0 * moved <= self.range).then_some(&self.pairs[..])
    }
}

/// How much wider than asked a search for the pairs' features reaches, as
/// a share of the range: later searches test the same features until a
/// point has moved by half the difference (each distance tested, between
/// two points of two blocks, changes by at most twice what a point moved).
/// A standing wall's blocks move by far less than the eighth of the range
/// this allows (the range is a quarter of a block's size).
const FEATURE_SKIN: f64 = 0.25;

/// Searches that examine every feature, kept nowhere, after a kept list
/// served no search: where the blocks move out of the skin at every step
/// (a falling block, the 3D 40-course wall at its automatic step), a list
/// found 1.25 times as wide costs more than it saves.
const PLAIN_SEARCHES: usize = 8;

/// The features of each near pair, with the range searched, every block's
/// vertices then and how many later searches they served.
#[derive(Debug)]
struct KeptFeatures<F, const D: usize> {
    /// The range asked and the range searched.
    asked: f64,
    range: f64,
    /// Every block's `Element::feature_kinds` then, block after block.
    kinds: Vec<u8>,
    /// Block after block.
    vertices: Vec<Point<f64, D>>,
    pairs: Vec<(usize, usize)>,
    features: Vec<F>,
    served: usize,
}

/// The kept features, if any, and the plain searches still to make before
/// features are kept again.
#[derive(Debug)]
struct FeatureStore<F, const D: usize> {
    kept: Option<KeptFeatures<F, D>>,
    plain: usize,
}

impl<F, const D: usize> Default for FeatureStore<F, D> {
    fn default() -> Self {
        Self {
            kept: None,
            plain: 0,
        }
    }
}

/// How a search finds its pairs' contacts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Search {
    /// Among the kept features.
    Kept,
    /// Keeping the features found at a wider range.
    Keeping,
    /// Examining every feature, keeping none.
    Plain,
}

impl<F, const D: usize> FeatureStore<F, D> {
    /// The next search, given whether the kept features serve it.
    fn plan(&mut self, serve: bool) -> Search {
        if serve {
            if let Some(k) = &mut self.kept {
                k.served += 1;
                return Search::Kept;
            }
        }
        if self.kept.take().is_some_and(|k| k.served == 0) {
            self.plain = PLAIN_SEARCHES;
        }
        if self.plain > 0 {
            self.plain -= 1;
            Search::Plain
        } else {
            Search::Keeping
        }
    }
}

impl<F, const D: usize> KeptFeatures<F, D> {
    /// Whether the features serve a search of `pairs` within `range` of
    /// blocks with these vertices and feature kinds: the same pairs and
    /// kinds, the range no shorter than the one asked then (the features a
    /// near corner ruled out stay ruled out only so), and each point moved
    /// by δ at most, with `range` + 2δ within the range searched: two
    /// points within `range` now were within `range` + 2δ then. A block's
    /// features are its vertices, edges and faces, so vertices that moved
    /// as far show any change of them.
    /// `vertices`: each block's, in block order.
    fn serve(
        &self,
        vertices: &[&[Point<f64, D>]],
        kinds: &[u8],
        pairs: &[(usize, usize)],
        range: f64,
    ) -> bool {
        if pairs != self.pairs || kinds != self.kinds || range < self.asked {
            return false;
        }
        // Where each block's vertices start among the kept ones.
        let mut starts = Vec::with_capacity(vertices.len());
        let mut count = 0;
        for v in vertices {
            starts.push(count);
            count += v.len();
        }
        if count != self.vertices.len() {
            return false;
        }
        // Each block's on any core (80,000 vertices in the 10,051-block 3D
        // wall): the farthest is the same in any order.
        let then = &self.vertices;
        let moved = (vertices.par_iter().zip(&starts))
            .with_min_len(BLOCKS_PER_TASK)
            .map(|(now, &start)| {
                (now.iter().zip(&then[start..start + now.len()]))
                    .map(|(now, then)| (now - then).norm())
                    .fold(0.0_f64, f64::max)
            })
            .reduce(|| 0.0, f64::max);
        range + 2.0 * moved <= self.range
    }
}

impl<B, const D: usize, const N: usize, const T: usize, const S: usize> BlockSet<B, D, N, T, S>
where
    B: Element<D, N, T, S>,
{
    /// Blocks with one material law each, all joints using law 0, no loads.
    pub fn new(blocks: Vec<B>, materials: Vec<Box<dyn ConstitutiveLaw<S>>>) -> Self {
        let n = materials.len();
        let stiffest = materials.iter().map(|m| m.modulus()).fold(0.0, f64::max);
        Self {
            blocks,
            materials,
            joint_laws: vec![vec![0; n]; n],
            pair_laws: HashMap::new(),
            gravity: SVector::zeros(),
            loads: Vec::new(),
            fixed: Vec::new(),
            measured: Vec::new(),
            fixed_penalty: stiffest,
            rotation_update: RotationUpdate::Exact,
            length_scale: None,
            near: Mutex::new(None),
            features: Mutex::new(FeatureStore::default()),
            points_of: OnceLock::new(),
        }
    }

    /// The point loads and fixed points on block `i`, in their lists'
    /// order: from the listing made at the first call, or, where the lists
    /// have changed length since, by filtering them.
    fn points_on(
        &self,
        i: usize,
    ) -> (
        impl Iterator<Item = &PointLoad<D>>,
        impl Iterator<Item = &FixedPoint<D>>,
    ) {
        let lengths = (self.loads.len(), self.fixed.len());
        let blocks = self.blocks.len();
        let points = self.points_of.get_or_init(|| {
            let (mut loads, mut fixed) = (ByBlock::default(), ByBlock::default());
            loads.fill(blocks, self.loads.iter().map(|l| [l.block]));
            fixed.fill(blocks, self.fixed.iter().map(|f| [f.block]));
            PointsOf {
                lengths,
                loads,
                fixed,
            }
        });
        let listed =
            (points.lengths == lengths && points.loads.blocks() == blocks).then_some(points);
        let loads = listed.map(|p| p.loads.of(i).iter().map(|&k| &self.loads[k]));
        let fixed = listed.map(|p| p.fixed.of(i).iter().map(|&k| &self.fixed[k]));
        // Where the listing stands, nothing is left to filter.
        let (all_loads, all_fixed) = match listed {
            Some(_) => (&[][..], &[][..]),
            None => (&self.loads[..], &self.fixed[..]),
        };
        (
            (loads.into_iter().flatten()).chain(all_loads.iter().filter(move |l| l.block == i)),
            (fixed.into_iter().flatten()).chain(all_fixed.iter().filter(move |f| f.block == i)),
        )
    }

    /// Holds every vertex of a block in place.
    pub fn fix_block(&mut self, block: usize) {
        for v in self.blocks[block].vertices().to_vec() {
            self.fixed.push(FixedPoint::at(block, v));
        }
    }

    /// The contact law of the joints between blocks `i` < `j`: their joint
    /// set's, or their materials'.
    pub fn law(&self, i: usize, j: usize) -> usize {
        self.pair_laws.get(&(i, j)).copied().unwrap_or_else(|| {
            self.joint_laws[self.blocks[i].material()][self.blocks[j].material()]
        })
    }

    /// Stress after the strain of step `d`, and its tangent.
    fn stress_after(
        &self,
        block: &B,
        d: &SVector<f64, N>,
    ) -> (SVector<f64, S>, SMatrix<f64, S, S>) {
        stress_after(&self.materials, block, d)
    }
}

/// [`BlockSet::stress_after`] with the materials alone borrowed.
fn stress_after<
    B: Element<D, N, T, S>,
    const D: usize,
    const N: usize,
    const T: usize,
    const S: usize,
>(
    materials: &[Box<dyn ConstitutiveLaw<S>>],
    block: &B,
    d: &SVector<f64, N>,
) -> (SVector<f64, S>, SMatrix<f64, S, S>) {
    let increment = d.fixed_rows::<S>(N - S).into_owned();
    materials[block.material()].stress(block.stress(), &increment)
}

impl<B, const D: usize, const N: usize, const T: usize, const S: usize> BlockSystem<N, T>
    for BlockSet<B, D, N, T, S>
where
    B: Element<D, N, T, S>,
{
    type Entrance = B::Entrance;

    fn block_count(&self) -> usize {
        self.blocks.len()
    }

    fn length_scale(&self) -> f64 {
        if let Some(w) = self.length_scale {
            return w;
        }
        let mut lo = Point::from(SVector::<f64, D>::repeat(f64::INFINITY));
        let mut hi = Point::from(SVector::<f64, D>::repeat(f64::NEG_INFINITY));
        for b in &self.blocks {
            let (l, h) = b.bounds();
            lo = lo.inf(&l);
            hi = hi.sup(&h);
        }
        ((hi - lo).norm() / 2.0).max(f64::MIN_POSITIVE)
    }

    fn block_size(&self) -> f64 {
        let mut sizes: Vec<f64> = self.blocks.iter().map(|b| b.size()).collect();
        sizes.sort_by(f64::total_cmp);
        sizes
            .get(sizes.len().saturating_sub(1) / 2)
            .copied()
            .unwrap_or(1.0)
    }

    fn motion_time(&self) -> Option<f64> {
        let g = self.gravity.norm();
        (g > 0.0).then(|| (self.block_size() / g).sqrt())
    }

    fn stiffness_scale(&self) -> f64 {
        self.materials
            .iter()
            .map(|m| m.modulus())
            .fold(0.0, f64::max)
    }

    fn dofs(&self, block: usize) -> usize {
        self.blocks[block].kind().dofs(N)
    }

    fn mass(&self, block: usize) -> BlockMatrix<N> {
        self.blocks[block].mass_matrix()
    }

    fn block_terms(
        &self,
        i: usize,
        time: f64,
        d: &BlockVector<N>,
        k: &mut BlockMatrix<N>,
        r: &mut BlockVector<N>,
    ) {
        let block = &self.blocks[i];
        if block.kind() == BlockKind::Deformable {
            // A rigid block keeps no strain rows, so its (zero) stress is
            // not asked for: a law call a block a move.
            let measure = block.measure();
            let (stress, tangent) = self.stress_after(block, d);
            let mut elastic = k.fixed_view_mut::<S, S>(N - S, N - S);
            elastic += tangent * measure;
            let mut strain_rows = r.fixed_rows_mut::<S>(N - S);
            strain_rows -= stress * measure;
        }
        for axis in 0..D {
            r[axis] += block.mass() * self.gravity[axis];
        }
        let (loads, fixed) = self.points_on(i);
        for load in loads {
            *r += block.t_matrix(&load.point).transpose() * load.force.at(time);
        }
        for fp in fixed {
            let t = block.t_matrix(&fp.point);
            let held = fp.held() * self.fixed_penalty;
            let drift = fp.target_at(time) - fp.point;
            *k += t.transpose() * held * t;
            *r += t.transpose() * held * (drift - t * d);
        }
    }

    fn near_pairs(&self, range: f64) -> Vec<(usize, usize)> {
        let bounds: Vec<_> = self.blocks.iter().map(|b| b.bounds()).collect();
        let mut near = self.near.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(pairs) = near.as_ref().and_then(|n| n.reach(&bounds, range)) {
            return pairs.to_vec();
        }
        let wide = range * (1.0 + NEAR_SKIN);
        let pairs = B::near_pairs(&self.blocks, wide);
        *near = Some(NearPairs {
            bounds,
            range: wide,
            pairs: pairs.clone(),
        });
        pairs
    }

    fn pair_contacts(&self, i: usize, j: usize, range: f64) -> Vec<Contact<N, T, B::Entrance>> {
        B::pair_contacts(&self.blocks, i, j, range, self.law(i, j))
    }

    fn pairs_contacts_carried(
        &self,
        pairs: &[(usize, usize)],
        range: f64,
        carry: &Carry<'_, N, T, B::Entrance>,
    ) -> Vec<Contact<N, T, B::Entrance>> {
        if !B::KEEPS_FEATURES {
            return each_pair_contacts(self, pairs, range, carry);
        }
        let blocks = &self.blocks;
        let vertices: Vec<&[Point<f64, D>]> = blocks.iter().map(|b| b.vertices()).collect();
        // Each block's kinds on any core, a list a task (not a block),
        // joined in block order.
        let kinds: Vec<u8> = (blocks.par_iter())
            .with_min_len(BLOCKS_PER_TASK)
            .fold(Vec::new, |mut kinds, b| {
                b.feature_kinds(&mut kinds);
                kinds
            })
            .collect::<Vec<Vec<u8>>>()
            .concat();
        let mut store = self.features.lock().unwrap_or_else(|e| e.into_inner());
        let serve = (store.kept.as_ref()).is_some_and(|k| k.serve(&vertices, &kinds, pairs, range));
        match store.plan(serve) {
            Search::Kept => {}
            Search::Plain => return each_pair_contacts(self, pairs, range, carry),
            Search::Keeping => {
                let wide = range * (1.0 + FEATURE_SKIN);
                store.kept = Some(KeptFeatures {
                    asked: range,
                    range: wide,
                    kinds,
                    vertices: vertices.iter().flat_map(|v| v.iter().copied()).collect(),
                    pairs: pairs.to_vec(),
                    features: (pairs.par_iter().with_min_len(PAIRS_PER_TASK))
                        .map(|&(i, j)| B::pair_features(blocks, i, j, range, wide))
                        .collect(),
                    served: 0,
                });
            }
        }
        let features = &store.kept.as_ref().expect("kept above").features;
        (pairs.par_iter().zip(features).enumerate())
            .with_min_len(PAIRS_PER_TASK)
            .flat_map_iter(|(k, (&(i, j), f))| {
                let mut found = B::pair_contacts_among(blocks, i, j, range, self.law(i, j), f);
                carry(k, &mut found);
                found
            })
            .collect()
    }

    fn supports(&self, start: f64, end: f64) -> Vec<crate::loads::Support<N>> {
        crate::loads::supports(&self.fixed, self.fixed_penalty, (start, end), |f| {
            self.blocks[f.block].t_matrix(&f.point)
        })
    }

    fn potential_energy(&self) -> Option<f64> {
        let held = held_energy(&self.fixed, self.fixed_penalty)?;
        if !self.loads.is_empty() {
            return None;
        }
        let gravity: f64 = self
            .blocks
            .iter()
            .map(|b| -b.mass() * self.gravity.dot(&b.centroid().coords))
            .sum();
        // ½ V σ·ε, with engineering shear strains.
        let strain: f64 = self
            .blocks
            .iter()
            .map(|b| 0.5 * b.measure() * b.stress().dot(b.strain()))
            .sum();
        Some(gravity + strain + held)
    }

    fn max_displacement(&self, d: &[BlockVector<N>]) -> f64 {
        // On every core: the largest of the same values in any order.
        (self.blocks.par_iter().zip(d))
            .with_min_len(BLOCKS_PER_TASK)
            .map(|(b, di)| {
                (b.vertices().iter())
                    .map(|v| (b.t_matrix(v) * di).norm())
                    .fold(0.0, f64::max)
            })
            .reduce(|| 0.0, f64::max)
    }

    fn max_own_motion(&self, d: &[BlockVector<N>], whole: &[bool]) -> f64 {
        (self.blocks.par_iter().zip(d).zip(whole))
            .with_min_len(BLOCKS_PER_TASK)
            .map(|((b, di), &whole)| {
                let centroid = if whole {
                    SVector::zeros()
                } else {
                    b.t_matrix(&b.centroid()) * di
                };
                let about = (b.vertices().iter())
                    .map(|v| (b.t_matrix(v) * di - centroid).norm())
                    .fold(0.0, f64::max);
                if whole {
                    about
                } else {
                    2.0 * about
                }
            })
            .reduce(|| 0.0, f64::max)
    }

    fn save_state(&self) -> Result<SystemState, DdaError> {
        let coordinates = |p: &Point<f64, D>| p.coords.iter().copied().collect::<Vec<f64>>();
        Ok(SystemState {
            blocks: self
                .blocks
                .iter()
                .map(|b| BlockState {
                    vertices: b.vertices().iter().flat_map(coordinates).collect(),
                    stress: b.stress().iter().copied().collect(),
                    strain: b.strain().iter().copied().collect(),
                    rotation: b.rotation_state(),
                })
                .collect(),
            fixed_points: self.fixed.iter().map(|f| coordinates(&f.point)).collect(),
            load_points: self.loads.iter().map(|l| coordinates(&l.point)).collect(),
            measured_points: self
                .measured
                .iter()
                .map(|m| coordinates(&m.point))
                .collect(),
        })
    }

    fn restore_state(&mut self, state: &SystemState) -> Result<(), DdaError> {
        let mismatch = |what: &str| {
            DdaError::Checkpoint(format!(
                "the checkpoint's {what} do not match the scene's: it was saved from another scene"
            ))
        };
        if state.blocks.len() != self.blocks.len() {
            return Err(mismatch("blocks"));
        }
        if state.fixed_points.len() != self.fixed.len()
            || state.load_points.len() != self.loads.len()
            || state.measured_points.len() != self.measured.len()
        {
            return Err(mismatch("fixed, load or measured points"));
        }
        let point = |c: &[f64]| Point::from(SVector::<f64, D>::from_column_slice(c));
        for (b, s) in self.blocks.iter().zip(&state.blocks) {
            let fits = s.vertices.len() == D * b.vertices().len()
                && s.stress.len() == S
                && s.strain.len() == S
                && s.rotation.len() == b.rotation_state().len();
            if !fits {
                return Err(mismatch("block shapes"));
            }
        }
        if state
            .fixed_points
            .iter()
            .chain(&state.load_points)
            .chain(&state.measured_points)
            .any(|p| p.len() != D)
        {
            return Err(mismatch("points"));
        }
        for (b, s) in self.blocks.iter_mut().zip(&state.blocks) {
            b.restore(
                s.vertices.chunks(D).map(point).collect(),
                SVector::from_column_slice(&s.stress),
                SVector::from_column_slice(&s.strain),
                &s.rotation,
            );
        }
        let saved = state
            .fixed_points
            .iter()
            .chain(&state.load_points)
            .chain(&state.measured_points);
        let points = carried(&mut self.fixed, &mut self.loads, &mut self.measured);
        for ((_, p), s) in points.zip(saved) {
            *p = point(s);
        }
        Ok(())
    }

    fn commit(&mut self, d: &[BlockVector<N>], _dt: f64, _time: f64) {
        let update = self.rotation_update;
        for (block, point) in carried(&mut self.fixed, &mut self.loads, &mut self.measured) {
            *point = self.blocks[block].move_point(point, &d[block], update);
        }
        // Each block moves by its own displacement alone: on every core
        // (a pool thread's work, as the driver's step runs there).
        let materials = &self.materials;
        self.blocks
            .par_iter_mut()
            .with_min_len(BLOCKS_PER_TASK)
            .zip(d)
            .for_each(|(block, di)| {
                let stress = stress_after(materials, block, di).0;
                block.commit(di, stress, update);
            });
    }
}

/// The points that move with their blocks (fixed, load and measured, in
/// that order), each with its block: one path for commit and restore.
fn carried<'a, const D: usize>(
    fixed: &'a mut [FixedPoint<D>],
    loads: &'a mut [PointLoad<D>],
    measured: &'a mut [MeasuredPoint<D>],
) -> impl Iterator<Item = (usize, &'a mut Point<f64, D>)> {
    let fixed = fixed.iter_mut().map(|f| (f.block, &mut f.point));
    let loads = loads.iter_mut().map(|l| (l.block, &mut l.point));
    let measured = measured.iter_mut().map(|m| (m.block, &mut m.point));
    fixed.chain(loads).chain(measured)
}

#[cfg(test)]
mod reach_tests {
    use super::Reach;
    use nalgebra::Point2;

    /// The bounds grow by twice the range on every side; a segment meets
    /// the reach where its own bounds do.
    #[test]
    fn a_reach_is_the_bounds_grown_by_twice_the_range() {
        let reach = Reach::new((Point2::new(0.0, 0.0), Point2::new(2.0, 1.0)), 0.1);
        assert!(reach.holds(&Point2::new(-0.2, 1.2)));
        assert!(!reach.holds(&Point2::new(-0.21, 0.5)));
        assert!(!reach.holds(&Point2::new(1.0, 1.21)));
        assert!(reach.meets(&Point2::new(-1.0, 0.5), &Point2::new(3.0, 0.5)));
        assert!(!reach.meets(&Point2::new(-1.0, 1.3), &Point2::new(3.0, 1.4)));
        assert!(Reach::<2>::everywhere().holds(&Point2::new(1e300, -1e300)));
    }
}

#[cfg(test)]
mod near_tests {
    use super::NearPairs;
    use nalgebra::Point2;

    fn unit(x: f64, y: f64) -> (Point2<f64>, Point2<f64>) {
        (Point2::new(x, y), Point2::new(x + 1.0, y + 1.0))
    }

    /// A search at range 0.125 holds the pairs of any range up to it, less
    /// twice how far any block's bounds have moved since; beyond that, or
    /// with another block count, it must be searched again.
    #[test]
    fn pairs_are_reused_while_the_blocks_stay_within_the_skin() {
        let then = vec![unit(0.0, 0.0), unit(1.05, 0.0)];
        let near = NearPairs {
            bounds: then.clone(),
            range: 0.125,
            pairs: vec![(0, 1)],
        };
        assert_eq!(near.reach(&then, 0.125), Some(&[(0, 1)][..]));
        assert_eq!(near.reach(&then, 0.15), None);
        let moved = vec![unit(0.0, 0.0), unit(1.04, 0.005)];
        assert!(near.reach(&moved, 0.1).is_some());
        assert!(near.reach(&moved, 0.11).is_none());
        assert!(near.reach(&then[..1], 0.1).is_none());
    }
}

#[cfg(test)]
mod kept_features_tests {
    use super::{FeatureStore, KeptFeatures, Search, PLAIN_SEARCHES};
    use nalgebra::Point2;

    /// Features asked at range 0.1 and found at 0.125 serve a search of the
    /// same pairs at any range from 0.1 up to 0.125 less twice the farthest
    /// any vertex has moved since, while the blocks' feature kinds stay the
    /// same; not at a shorter range, not another pair list, vertex count
    /// or kind.
    #[test]
    fn features_serve_while_no_point_has_moved_beyond_the_skin() {
        let then = [Point2::new(0.0, 0.0), Point2::new(1.0, 0.5)];
        let kinds = [1, 0, 2];
        let kept = KeptFeatures {
            asked: 0.1,
            range: 0.125,
            kinds: kinds.to_vec(),
            vertices: then.to_vec(),
            pairs: vec![(0, 1)],
            features: vec![()],
            served: 0,
        };
        let serve = |at: &[Point2<f64>], pairs: &[(usize, usize)], range| {
            kept.serve(&[at], &kinds, pairs, range)
        };
        assert!(serve(&then, &[(0, 1)], 0.125));
        assert!(serve(&then, &[(0, 1)], 0.1));
        assert!(!serve(&then, &[(0, 1)], 0.099));
        assert!(!serve(&then, &[(0, 1)], 0.126));
        assert!(!serve(&then, &[(0, 2)], 0.1));
        assert!(!serve(&then[..1], &[(0, 1)], 0.1));
        assert!(!serve(&[then[0], then[1], then[1]], &[(0, 1)], 0.1));
        assert!(!kept.serve(&[&then], &[1, 1, 2], &[(0, 1)], 0.1));
        // The second vertex moved by 0.01 (a turn, say, that left the
        // first in place).
        let moved = [then[0], Point2::new(1.006, 0.508)];
        assert!(serve(&moved, &[(0, 1)], 0.1));
        assert!(!serve(&moved, &[(0, 1)], 0.11));
        // The same as two blocks' vertices: each read against its own.
        let blocks: [&[Point2<f64>]; 2] = [&moved[..1], &moved[1..]];
        assert!(kept.serve(&blocks, &kinds, &[(0, 1)], 0.1));
        assert!(!kept.serve(&blocks, &kinds, &[(0, 1)], 0.11));
        let swapped = [moved[1], moved[0]];
        assert!(!kept.serve(&[&swapped[..1], &swapped[1..]], &kinds, &[(0, 1)], 0.1));
    }

    /// Features are kept where they serve later searches; a kept list that
    /// served none gives way to `PLAIN_SEARCHES` plain searches, then
    /// features are kept again.
    #[test]
    fn a_kept_list_that_served_no_search_gives_way_to_plain_searches() {
        let kept = |served| KeptFeatures::<(), 2> {
            asked: 0.08,
            range: 0.1,
            kinds: Vec::new(),
            vertices: Vec::new(),
            pairs: Vec::new(),
            features: Vec::new(),
            served,
        };
        let mut store = FeatureStore::default();
        assert_eq!(store.plan(false), Search::Keeping);
        store.kept = Some(kept(0));
        assert_eq!(store.plan(true), Search::Kept);
        assert_eq!(store.plan(true), Search::Kept);
        // It served two searches: found again.
        assert_eq!(store.plan(false), Search::Keeping);
        store.kept = Some(kept(0));
        // It served none.
        for _ in 0..PLAIN_SEARCHES {
            assert_eq!(store.plan(false), Search::Plain);
        }
        assert_eq!(store.plan(false), Search::Keeping);
    }
}
