//! Trial and commit are kept apart: open-close passes and cut steps call a
//! law's `response` and `next_state` many times, but its history changes
//! only in `commit`, once per contact per accepted step.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use dda_2d::{Block, Driver2d, Plane, PlaneElastic, Polygons};
use dda_contact::Coulomb;
use dda_core::{ContactLaw, ContactResponse, ContactState, LocalKinematics, Settings};
use nalgebra::Vector2;

/// Coulomb, counting commits globally and in each contact's history.
struct Counting {
    inner: Coulomb,
    commits: Arc<AtomicUsize>,
}

impl ContactLaw for Counting {
    type History = (<Coulomb as ContactLaw>::History, usize);

    fn initial_history(&self, at_start: bool) -> Self::History {
        (self.inner.initial_history(at_start), 0)
    }
    fn response(&self, s: ContactState, k: &LocalKinematics, h: &Self::History) -> ContactResponse {
        self.inner.response(s, k, &h.0)
    }
    fn next_state(&self, s: ContactState, k: &LocalKinematics, h: &Self::History) -> ContactState {
        self.inner.next_state(s, k, &h.0)
    }
    fn commit(&self, s: ContactState, k: &LocalKinematics, h: &mut Self::History) {
        self.inner.commit(s, k, &mut h.0);
        h.1 += 1;
        self.commits.fetch_add(1, Ordering::Relaxed);
    }
}

mod common;
use common::square;

#[test]
fn histories_change_once_per_accepted_step_even_when_steps_are_cut() {
    let blocks = vec![
        Block::new(&square(0.0, -0.5, 4.0, 1.0), 0, 2700.0).unwrap(),
        Block::new(&square(0.0, 0.52, 1.0, 1.0), 0, 2700.0).unwrap(),
    ];
    let law = PlaneElastic {
        young: 1e10,
        poisson: 0.25,
        plane: Plane::Strain,
    };
    let mut system = Polygons::new(blocks, vec![Box::new(law)]);
    system.gravity = Vector2::new(0.0, -9.81);
    system.fix_block(0);
    let commits = Arc::new(AtomicUsize::new(0));
    let counting = Counting {
        inner: Coulomb::frictional(30.0),
        commits: commits.clone(),
    };
    // One pass at most: steps in which a contact changes state are cut.
    let settings = Settings {
        dt: Some(0.01),
        penalty: Some(2e10),
        open_close_limit: 1,
        ..Settings::default()
    };
    let mut driver = Driver2d::new(system, vec![Box::new(counting)], settings).unwrap();
    let mut expected = 0;
    while driver.time() < 0.2 {
        driver.step(0.2 - driver.time()).unwrap();
        expected += driver.contacts().len();
    }
    let stats = driver.statistics();
    assert!(
        stats.open_close_iterations > stats.steps,
        "passes were repeated: {stats:?}"
    );
    assert!(stats.open_close_cuts > 0, "a step was cut: {stats:?}");
    assert_eq!(commits.load(Ordering::Relaxed), expected);
    assert!(
        driver.contacts().iter().any(|c| c.record.state.is_closed()),
        "the block landed"
    );
}
