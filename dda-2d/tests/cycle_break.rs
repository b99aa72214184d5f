//! Open-close passes that cycle between two sets of states are detected
//! and broken: a law that always answers "the other state" for a closed
//! contact (locked ↔ sliding) makes every step cycle where locking changes
//! the forces (with contact damping, locking adds the shear dashpot). The
//! driver keeps the sliding state after two passes, counts the break, and
//! neither cuts the step nor accepts it unconverged; without the break every
//! step would be cut down to the floor. Without damping a sliding contact
//! that asks to lock already carried the locked force (the return map), so
//! it costs no pass and commits locked: no cycle at all.

use dda_2d::{Block, Driver2d, Plane, PlaneElastic, Polygons};
use dda_contact::Coulomb;
use dda_core::{ContactLaw, ContactResponse, ContactState, LocalKinematics, Settings};
use nalgebra::Vector2;

/// Coulomb, except that a closed contact always asks for the other of
/// locked and sliding.
struct Flipping(Coulomb);

impl ContactLaw for Flipping {
    type History = <Coulomb as ContactLaw>::History;

    fn initial_history(&self, at_start: bool) -> Self::History {
        self.0.initial_history(at_start)
    }
    fn response(&self, s: ContactState, k: &LocalKinematics, h: &Self::History) -> ContactResponse {
        self.0.response(s, k, h)
    }
    fn next_state(&self, s: ContactState, k: &LocalKinematics, h: &Self::History) -> ContactState {
        match self.0.next_state(s, k, h) {
            ContactState::Open => ContactState::Open,
            _ if s == ContactState::Locked => ContactState::Sliding,
            _ => ContactState::Locked,
        }
    }
    fn commit(&self, s: ContactState, k: &LocalKinematics, h: &mut Self::History) {
        self.0.commit(s, k, h)
    }
}

mod common;
use common::square;

fn flipping_driver(contact_damping: f64) -> Driver2d {
    let blocks = vec![
        Block::new(&square(0.0, -0.5, 4.0, 1.0), 0, 2700.0).unwrap(),
        Block::new(&square(0.0, 0.5, 1.0, 1.0), 0, 2700.0).unwrap(),
    ];
    let material = PlaneElastic {
        young: 1e10,
        poisson: 0.25,
        plane: Plane::Strain,
    };
    let mut system = Polygons::new(blocks, vec![Box::new(material)]);
    system.gravity = Vector2::new(0.0, -9.81);
    system.fix_block(0);
    let settings = Settings {
        dt: Some(1e-3),
        contact_damping,
        ..Settings::default()
    };
    let law = Flipping(Coulomb::frictional(30.0));
    Driver2d::new(system, vec![Box::new(law)], settings).unwrap()
}

fn closed_states(driver: &Driver2d) -> Vec<ContactState> {
    let closed: Vec<ContactState> = driver
        .contacts()
        .iter()
        .map(|c| c.record.state)
        .filter(|s| s.is_closed())
        .collect();
    assert!(!closed.is_empty());
    closed
}

#[test]
fn a_two_state_cycle_is_broken_by_sliding_and_counted() {
    let mut driver = flipping_driver(1.0);
    driver.advance_to(0.05).unwrap();
    let stats = driver.statistics();
    assert!(stats.cycle_breaks > 0, "{stats:?}");
    // The cycling contacts are named: the block's corners on the base,
    // with the states they alternated between and the one kept.
    assert!(
        !stats.cycles.is_empty() && stats.cycles.len() <= 20,
        "{stats:?}"
    );
    for c in &stats.cycles {
        assert_eq!([c.key.block_a, c.key.block_b], [1, 0], "{c:?}");
        assert_ne!(c.between[0], c.between[1], "{c:?}");
        assert!(c.between.contains(&c.kept), "{c:?}");
        assert!(c.time > 0.0 && c.time <= 0.05 + 1e-12, "{c:?}");
    }
    assert_eq!(stats.unconverged_steps, 0, "{stats:?}");
    assert_eq!(stats.open_close_cuts, 0, "{stats:?}");
    let closed = closed_states(&driver);
    assert!(
        closed.iter().all(|&s| s == ContactState::Sliding),
        "the cycling contacts kept sliding: {closed:?}"
    );
}

#[test]
fn without_damping_a_sliding_contact_within_its_strength_locks_at_no_cost() {
    let mut driver = flipping_driver(0.0);
    driver.advance_to(0.05).unwrap();
    let stats = driver.statistics();
    assert_eq!(stats.cycle_breaks, 0, "{stats:?}");
    assert_eq!(stats.unconverged_steps, 0, "{stats:?}");
    assert_eq!(stats.open_close_cuts, 0, "{stats:?}");
    // Each step: the pass that unlocks them, and the one that finds them
    // within their strength; and, rarely, one that turns back a foreseen
    // opening (the block rocks on its springs by about the open-close
    // tolerance).
    assert!(
        stats.open_close_iterations <= 2 * stats.steps + stats.foresight_misses,
        "{} passes in {} steps",
        stats.open_close_iterations,
        stats.steps
    );
    assert!(10 * stats.foresight_misses < stats.steps, "{stats:?}");
    let closed = closed_states(&driver);
    assert!(
        closed.iter().all(|&s| s == ContactState::Locked),
        "they commit locked: {closed:?}"
    );
}
