//! The step's contact search and the matrix pattern: contacts within the
//! step's reach are found afresh each step, and the pattern of block pairs
//! the matrix holds changes only when the contact graph really does, so the
//! solver's symbolic analysis is reused across passes and steps.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use super::{Driver, BOUND_BLOCK_SHARE};
use crate::assembly::BlockSparse;
use crate::contact::ContactState;
use crate::contacts::{
    carry_records, pair_chunks, transfer_records, Contact, EntranceRows, SearchedPairs,
};
use crate::system::BlockSystem;
use crate::CONTACTS_PER_TASK;

/// The least reach of the matrix pattern, as a share of the median block
/// size: open contacts this near enter the pattern whatever the motion.
const PATTERN_REACH_SHARE: f64 = 0.05;

/// How many times the last step's largest displacement an open contact's
/// gap may be and still enter the pattern (both blocks may move toward each
/// other, and the next step may be faster).
const PATTERN_REACH_MOTION: f64 = 4.0;

impl<S: BlockSystem<N, T>, const N: usize, const T: usize> Driver<S, N, T> {
    /// The pattern's reach for the next step, after one whose largest
    /// displacement was `moved` (m): `PATTERN_REACH_MOTION` times it, at
    /// least `PATTERN_REACH_SHARE` of the median block size.
    pub(super) fn reach_pattern(&mut self, moved: f64) {
        self.pattern_reach =
            (PATTERN_REACH_MOTION * moved).max(PATTERN_REACH_SHARE * self.block_size);
    }

    /// Finds the contacts within `range` (broad and narrow phase) and moves
    /// the last step's records onto them.
    pub(super) fn search(&mut self, range: f64) {
        let started = Instant::now();
        let pairs = self.system.near_pairs(range);
        let searched = Instant::now();
        self.stats.times.broad_phase += searched - started;
        let at_start = self.stats.steps == 0;
        let touching = self.settings.contact_tolerance * self.length_scale;
        let laws = &self.laws;
        // A contact with no record to take starts its law's history.
        let begin = |new: &mut [Contact<N, T, S::Entrance>]| {
            for c in new.iter_mut().filter(|c| c.record.history.is_none()) {
                c.record.history = Some(laws[c.law].initial_history(at_start));
                // Joints closed in the initial geometry start locked, so
                // their bonds hold from the first step.
                if at_start && c.entrances.iter().all(|e| e.gap() <= touching) {
                    c.record.state = ContactState::Locked;
                }
            }
        };
        // The last step's records move pair by pair as the contacts are
        // made, on the core that made them, where the last search says
        // where each pair's lie: the walk over both whole lists on one core
        // took 7.6 ms a step on a 10,051-block 3D wall, and the sweep
        // starting histories 0.7-1.6 ms more.
        let counts: Vec<AtomicUsize> = pairs.iter().map(|_| AtomicUsize::new(0)).collect();
        let count = |k: usize, new: &[Contact<N, T, S::Entrance>]| {
            counts[k].store(new.len(), Ordering::Relaxed);
        };
        let fresh = match pair_chunks(&mut self.contacts, &self.searched, &pairs) {
            Some(chunks) => {
                let carry = |k: usize, new: &mut [Contact<N, T, S::Entrance>]| {
                    count(k, new);
                    let mut old = chunks[k].lock().unwrap_or_else(|e| e.into_inner());
                    carry_records(&mut old, new);
                    begin(new);
                };
                self.system.pairs_contacts_carried(&pairs, range, &carry)
            }
            None => {
                let carry = |k: usize, new: &mut [Contact<N, T, S::Entrance>]| count(k, new);
                let mut fresh = self.system.pairs_contacts_carried(&pairs, range, &carry);
                transfer_records(&mut self.contacts, &mut fresh);
                (fresh.par_chunks_mut(CONTACTS_PER_TASK)).for_each(begin);
                fresh
            }
        };
        let counts = counts.into_iter().map(AtomicUsize::into_inner);
        self.searched = SearchedPairs::of(pairs, counts);
        // Freeing the last step's contacts (a heap block or two each: 4.6
        // ms at ten thousand blocks) is left to a thread that would idle.
        let last = std::mem::replace(&mut self.contacts, fresh);
        self.chosen.clear();
        rayon::spawn(move || drop(last));
        self.stats.times.narrow_phase += searched.elapsed();
    }

    /// How far a point may move in a step (m); the contact search reaches
    /// 2.5 times as far, so no contact the step can close is missed. Shi's
    /// g2·w0, but in a model many blocks wide no more than a tenth of the
    /// median block size ([`BOUND_BLOCK_SHARE`]) or twice the last step's
    /// motion, whichever is larger: a step that moves farther is cut like
    /// one beyond g2·w0.
    pub(super) fn displacement_bound(&self) -> f64 {
        let shi = self.settings.max_displacement_ratio * self.length_scale;
        shi.min((BOUND_BLOCK_SHARE * self.block_size).max(2.0 * self.last_moved))
    }

    /// Keeps the matrix pattern to the block pairs whose contacts can close
    /// in the step: closed ones, and open ones within the pattern's reach.
    /// The pattern changes (and the solver analyses it again) only when a
    /// pair within reach is missing, or when more than an eighth of its
    /// pairs have moved beyond twice the reach, so a standing wall keeps
    /// one analysis for thousands of steps.
    pub(super) fn update_pattern(&mut self) {
        let reach = self.pattern_reach;
        self.find_slots();
        let mut missing = self.matrix.block_count() == 0;
        let mut held = vec![false; self.matrix.pairs().len()];
        // Read off the contacts on every core (a contact is some 200 bytes
        // in 3D: one core took 1.2 ms at 10,051 blocks), entered in order.
        let wants: Vec<(bool, bool)> = (self.contacts.par_iter())
            .with_min_len(CONTACTS_PER_TASK)
            .map(|c| pattern_wants(c, reach))
            .collect();
        for (&(wanted, kept), slot) in wants.iter().zip(&self.slots) {
            match slot {
                None => missing |= wanted,
                Some(s) => held[*s] |= kept,
            }
        }
        let stale = held.iter().filter(|h| !**h).count();
        if missing || 8 * stale > held.len() {
            let kept: Vec<(usize, usize)> = (self.contacts.iter().zip(&wants))
                .filter(|(_, w)| w.1)
                .map(|(c, _)| (c.blocks[0], c.blocks[1]))
                .collect();
            self.rebuild_pattern(kept);
            self.find_slots();
        }
    }

    /// A new matrix pattern with these block pairs.
    pub(super) fn rebuild_pattern(&mut self, pairs: Vec<(usize, usize)>) {
        let dofs = (0..self.system.block_count())
            .map(|i| self.system.dofs(i))
            .collect();
        self.matrix = BlockSparse::new(dofs, pairs);
        self.factored = None;
        self.analysed = false;
    }

    pub(super) fn find_slots(&mut self) {
        self.slots.clear();
        let matrix = &self.matrix;
        self.slots.par_extend(
            (self.contacts.par_iter())
                .with_min_len(CONTACTS_PER_TASK)
                .map(|c| matrix.slot(c.blocks[0], c.blocks[1])),
        );
        // Read from the slots alone: listing only the loaded contacts read
        // each contact's load (256 bytes in 3D) twice on one core, 2-4 ms
        // a tangent at 10,051 blocks in 3D.
        let slots = self.slots.iter().copied();
        self.slot_contacts.fill(matrix.pairs().len(), slots);
    }

    /// Adds to the pattern the pairs of closed contacts it misses (a contact
    /// that closed from beyond the pattern's reach in this step).
    pub(super) fn cover_closed(&mut self, states: &[ContactState]) {
        let missing: Vec<(usize, usize)> = self
            .contacts
            .iter()
            .zip(states)
            .zip(&self.slots)
            .filter(|((_, s), slot)| s.is_closed() && slot.is_none())
            .map(|((c, _), _)| (c.blocks[0], c.blocks[1]))
            .collect();
        if missing.is_empty() {
            return;
        }
        let started = Instant::now();
        let mut pairs = self.matrix.pairs().to_vec();
        pairs.extend(missing);
        self.rebuild_pattern(pairs);
        self.find_slots();
        self.stats.times.pattern += started.elapsed();
    }
}

/// Whether a contact's block pair must be in the matrix pattern (closed,
/// or open within `reach`), and whether a pattern holding it may keep it
/// (closed, or open within twice the reach).
fn pattern_wants<const N: usize, const T: usize, E: EntranceRows<N, T>>(
    c: &Contact<N, T, E>,
    reach: f64,
) -> (bool, bool) {
    // A closed contact's entrances are not read (each in its own
    // allocation, on one thread, every step).
    if c.record.state.is_closed() {
        return (true, true);
    }
    // Shi's contact closes through its widest entrance, so it is as far
    // from closing as that entrance's gap.
    let (_, gap) = c.widest_at_start();
    (gap <= reach, gap <= 2.0 * reach)
}
