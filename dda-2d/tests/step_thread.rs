//! A step runs on a thread of rayon's pool (`Driver::step`), so its
//! parallel loops split from a worker instead of each handing its work over
//! from the calling thread. A material that notes the thread its stress is
//! asked on (the blocks' terms are assembled on the step's own thread, not
//! in a parallel loop) sees only pool threads, though the steps are asked
//! for from the test's thread.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use dda_2d::{Block, Driver2d, Plane, PlaneElastic, Polygons};
use dda_contact::Coulomb;
use dda_core::{ConstitutiveLaw, Settings};
use nalgebra::{SMatrix, SVector, Vector2};

mod common;
use common::square;

/// Plane elasticity that counts the calls made on a pool thread and off it.
struct Noting {
    elastic: PlaneElastic,
    calls: Arc<[AtomicUsize; 2]>,
}

impl ConstitutiveLaw<3> for Noting {
    fn stress(
        &self,
        committed: &SVector<f64, 3>,
        increment: &SVector<f64, 3>,
    ) -> (SVector<f64, 3>, SMatrix<f64, 3, 3>) {
        let on_pool = rayon::current_thread_index().is_some();
        self.calls[usize::from(on_pool)].fetch_add(1, Ordering::Relaxed);
        self.elastic.stress(committed, increment)
    }

    fn modulus(&self) -> f64 {
        self.elastic.modulus()
    }
}

#[test]
fn a_step_runs_on_a_pool_thread() {
    assert!(
        rayon::current_thread_index().is_none(),
        "the test's own thread"
    );
    let calls = Arc::new([AtomicUsize::new(0), AtomicUsize::new(0)]);
    let material = Noting {
        elastic: PlaneElastic {
            young: 1e10,
            poisson: 0.25,
            plane: Plane::Strain,
        },
        calls: calls.clone(),
    };
    let blocks = vec![
        Block::new(&square(0.0, -0.5, 4.0, 1.0), 0, 2700.0).unwrap(),
        Block::new(&square(0.0, 0.5, 1.0, 1.0), 0, 2700.0).unwrap(),
    ];
    let mut system = Polygons::new(blocks, vec![Box::new(material)]);
    system.gravity = Vector2::new(0.0, -9.81);
    system.fix_block(0);
    let settings = Settings {
        dt: Some(1e-3),
        ..Settings::default()
    };
    let law = Coulomb::frictional(30.0);
    let mut driver = Driver2d::new(system, vec![Box::new(law)], settings).unwrap();
    // What building the driver asked is not a step's.
    calls[0].store(0, Ordering::Relaxed);
    calls[1].store(0, Ordering::Relaxed);
    driver.advance_to(0.01).unwrap();
    let (off, on) = (
        calls[0].load(Ordering::Relaxed),
        calls[1].load(Ordering::Relaxed),
    );
    assert!(on > 0 && off == 0, "on the pool {on}, off it {off}");
}
