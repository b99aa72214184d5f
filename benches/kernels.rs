//! Criterion benches of the kernels a step spends its time in, on the walls
//! `dda bench` times (running bond, 0.5 m × 0.25 m bricks, dt 1 ms, penalty
//! 1e9), so a regression shows in the benches' output:
//!
//! * a block's integrals: a 2D brick (polygon moments, mass matrix, elastic
//!   stiffness) and a 3D one (a 0.5 × 0.25 × 0.25 m box);
//! * contact search (broad and narrow phase) on the 32 × 32 walls, 1,041
//!   blocks, 2D and 3D, at the range the driver asks of a wall at rest;
//!   and the 3D one as a step makes it, on both cores, the pairs' features
//!   kept from the last search;
//! * every block's own terms on the 40 × 40 wall with a fixed point on
//!   each block: a block reads its own points, so this grows with the
//!   blocks, not with blocks × points;
//! * one assembly of the 40 × 40 wall (1,621 blocks) after its first step:
//!   each block's inertia and own terms and each closed contact's normal and
//!   shear springs into the driver's block-sparse matrix (`BlockSparse`);
//! * one numeric factorisation (sparse Cholesky) of that matrix, analysed
//!   beforehand as the driver does once per pattern;
//! * one forward and back substitution with that factor, split between two
//!   cores (its default at this size) and on one, each on a task of rayon's
//!   pool as in a step.
//!
//! `cargo bench --bench kernels` runs them; `-- --quick` gives a quick
//! estimate (well under a minute), as CI runs them.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Point2, Point3};

use dda::bench::{wall, Stepping};
use dda::scene::BlockKind;
use dda_core::assembly::BlockSparse;
use dda_core::driver::BOUND_BLOCK_SHARE;
use dda_core::solve::{LinearSolver, SparseCholesky};
use dda_core::{BlockMatrix, BlockSystem, BlockVector, FixedPoint};

const DENSITY: f64 = 1800.0;

fn integrals(c: &mut Criterion) {
    let model = wall(1, 2, Stepping::Fixed, BlockKind::Deformable)
        .unwrap()
        .build()
        .unwrap();
    let system = &model.driver.system;
    let brick: Vec<Point2<f64>> = system.blocks[1].vertices().to_vec();
    c.bench_function(
        "block integrals 2D (brick: moments, mass, stiffness)",
        |b| {
            b.iter(|| {
                let block = dda_2d::Block::new(black_box(&brick), 0, DENSITY).unwrap();
                let mass = block.mass_matrix();
                let (mut k, mut r) = (BlockMatrix::<6>::zeros(), BlockVector::<6>::zeros());
                system.block_terms(1, 0.0, &BlockVector::<6>::zeros(), &mut k, &mut r);
                black_box((mass, k, r))
            })
        },
    );

    let model = wall(1, 3, Stepping::Fixed, BlockKind::Deformable)
        .unwrap()
        .build_3d()
        .unwrap();
    let system = &model.driver.system;
    let brick: Vec<Point3<f64>> = system.blocks[1].vertices().to_vec();
    let faces = system.blocks[1].faces().to_vec();
    c.bench_function("block integrals 3D (box: moments, mass, stiffness)", |b| {
        b.iter(|| {
            let block = dda_3d::Block::new(black_box(&brick), &faces, 0, DENSITY).unwrap();
            let mass = block.mass_matrix();
            let (mut k, mut r) = (BlockMatrix::<12>::zeros(), BlockVector::<12>::zeros());
            system.block_terms(1, 0.0, &BlockVector::<12>::zeros(), &mut k, &mut r);
            black_box((mass, k, r))
        })
    });
}

fn contact_search(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact search");
    group.sample_size(20);
    let model = wall(32, 2, Stepping::Fixed, BlockKind::Deformable)
        .unwrap()
        .build()
        .unwrap();
    time_search(&mut group, "wall", &model.settings, &model.driver);
    // The 3D wall, one brick thick: its bricks meet corner to corner and
    // corner to edge, so its contacts are vertex-vertex and vertex-edge
    // groups, each weighing several planes and crossings (which, meeting
    // square, coincide and are kept once).
    let model = wall(32, 3, Stepping::Fixed, BlockKind::Rigid)
        .unwrap()
        .build_3d()
        .unwrap();
    time_search(&mut group, "3D wall", &model.settings, &model.driver);
    // The search a step of a standing 3D wall makes: each pair's features
    // kept from the last search and tested again, on both cores.
    let system = &model.driver.system;
    let range = search_range(&model.settings, &model.driver);
    let name = format!(
        "3D wall 32 x 32, features kept, {} blocks",
        system.block_count()
    );
    group.bench_function(name, |b| {
        b.iter(|| {
            let pairs = system.near_pairs(black_box(range));
            black_box(system.pairs_contacts(&pairs, range)).len()
        })
    });
    group.finish();
}

/// The range the driver searches a wall at rest at: 2.5 × the step's
/// displacement bound, Shi's g2·w0 but at most a share of the median block
/// size.
fn search_range<S: BlockSystem<N, T>, const N: usize, const T: usize>(
    settings: &dda_core::Settings,
    driver: &dda_core::Driver<S, N, T>,
) -> f64 {
    let bound = (settings.max_displacement_ratio * driver.length_scale())
        .min(BOUND_BLOCK_SHARE * driver.system.block_size());
    2.5 * bound
}

/// One search of a 32 × 32 wall's contacts, broad and narrow phase, every
/// pair's features examined, on one core, at [`search_range`].
fn time_search<S: BlockSystem<N, T>, const N: usize, const T: usize>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    label: &str,
    settings: &dda_core::Settings,
    driver: &dda_core::Driver<S, N, T>,
) {
    let system = &driver.system;
    let range = search_range(settings, driver);
    let name = format!("{label} 32 x 32, {} blocks", system.block_count());
    group.bench_function(name, |b| {
        b.iter(|| black_box(system.find_contacts(black_box(range))).len())
    });
}

/// The 40 × 40 wall after one step, with its matrix pattern (blocks and the
/// pairs of closed contacts) and an assembly into it.
fn own_terms(c: &mut Criterion) {
    let mut model = wall(40, 2, Stepping::Fixed, BlockKind::Rigid)
        .unwrap()
        .build()
        .unwrap();
    let system = &mut model.driver.system;
    let n = system.blocks.len();
    for i in 0..n {
        let at = system.blocks[i].centroid();
        system.fixed.push(FixedPoint::at(i, at));
    }
    let system = &model.driver.system;
    c.bench_function(
        &format!("own terms, {n} blocks, {} fixed points", system.fixed.len()),
        |b| {
            b.iter(|| {
                let mut r = BlockVector::<6>::zeros();
                for i in 0..n {
                    let mut k = BlockMatrix::<6>::zeros();
                    system.block_terms(i, 0.0, &BlockVector::<6>::zeros(), &mut k, &mut r);
                }
                black_box(r)
            })
        },
    );
}

struct Assembly {
    model: dda::scene::Model,
    matrix: BlockSparse<6>,
    masses: Vec<BlockMatrix<6>>,
    dt: f64,
}

impl Assembly {
    fn new() -> Self {
        let mut model = wall(40, 2, Stepping::Fixed, BlockKind::Deformable)
            .unwrap()
            .build()
            .unwrap();
        let dt = model.driver.dt();
        model.driver.step(dt).unwrap();
        let system = &model.driver.system;
        let n = system.blocks.len();
        let pairs: Vec<(usize, usize)> =
            closed(&model).map(|c| (c.blocks[0], c.blocks[1])).collect();
        let matrix = BlockSparse::new((0..n).map(|i| system.dofs(i)).collect(), pairs);
        let masses = (0..n).map(|i| system.mass(i)).collect();
        Self {
            model,
            matrix,
            masses,
            dt,
        }
    }

    /// Fills the matrix: inertia (Newmark, 2M/dt²) and each block's own
    /// terms on the diagonal, each closed contact's springs (penalty ×
    /// spring length along its normal and tangent rows) in its block pair.
    fn assemble(&mut self) {
        let m = &mut self.matrix;
        m.clear();
        let system = &self.model.driver.system;
        let zero = BlockVector::<6>::zeros();
        for (i, mass) in self.masses.iter().enumerate() {
            let mut k = mass * (2.0 / (self.dt * self.dt));
            let mut r = zero;
            system.block_terms(i, self.dt, &zero, &mut k, &mut r);
            m.add(i, i, &k);
        }
        let penalty = self.model.driver.penalty();
        for c in closed(&self.model) {
            let e = &c.entrances[c.record.entrance];
            let k = penalty * c.spring_length;
            let [a, b] = c.blocks;
            let slot = m.slot(a, b).expect("closed pairs are in the pattern");
            for rows in std::iter::once(&e.normal).chain(e.tangents.iter()) {
                m.add(a, a, &(rows[0] * rows[0].transpose() * k));
                m.add(b, b, &(rows[1] * rows[1].transpose() * k));
                m.add_at(slot, a, b, &(rows[0] * rows[1].transpose() * k));
            }
        }
    }
}

fn closed(model: &dda::scene::Model) -> impl Iterator<Item = &dda_core::Contact<6, 1>> {
    model
        .driver
        .contacts()
        .iter()
        .filter(|c| c.record.state.is_closed())
}

fn assembly_and_factorisation(c: &mut Criterion) {
    let mut a = Assembly::new();
    let blocks = a.model.driver.system.blocks.len();
    let mut group = c.benchmark_group("wall 40 x 40");
    group.sample_size(10);
    group.bench_function(format!("assembly, {blocks} blocks"), |b| {
        b.iter(|| {
            a.assemble();
            black_box(&a.matrix);
        })
    });
    a.assemble();
    let mut values = Vec::new();
    a.matrix.values_into(&mut values);
    let mut solver = SparseCholesky::default();
    solver.analyse(&a.matrix.pattern()).unwrap();
    group.bench_function(
        format!("numeric factorisation, {} unknowns", a.matrix.dim()),
        |b| b.iter(|| solver.factorize(black_box(&values)).unwrap()),
    );
    solver.factorize(&values).unwrap();
    let mut one_core = SparseCholesky::default();
    one_core.split_from = usize::MAX;
    one_core.analyse(&a.matrix.pattern()).unwrap();
    one_core.factorize(&values).unwrap();
    let rhs: Vec<f64> = (0..a.matrix.dim()).map(|i| (i as f64).sin()).collect();
    for (cores, s) in [("two cores", solver), ("one core", one_core)] {
        // Solved on a task of rayon's pool, as a step is.
        let s = std::sync::Mutex::new(s);
        group.bench_function(format!("solve on {cores}, {} unknowns", rhs.len()), |b| {
            b.iter(|| {
                let mut x = rhs.clone();
                rayon::scope(|_| s.lock().unwrap().solve(&mut x));
                black_box(x)
            })
        });
    }
    group.finish();
}

criterion_group!(
    kernels,
    integrals,
    own_terms,
    contact_search,
    assembly_and_factorisation
);
criterion_main!(kernels);
