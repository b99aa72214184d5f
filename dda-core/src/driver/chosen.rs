//! Each contact's chosen entrance, copied side by side at each open-close
//! pass and kept to the step's end: the passes' moves, the penetration
//! check and the commit read it there instead of each through its
//! contact's own allocation (at ten thousand blocks that pointer chase was
//! a third of an assembly; the commit of the 3D wall took 50-65 ms with
//! the copies against 70-85 without).

use rayon::prelude::*;

use crate::contacts::{Contact, Entrance};
use crate::CONTACTS_PER_TASK;

/// The entrance each contact holds in the step, with its index.
#[derive(Debug)]
pub(super) struct Chosen<const N: usize, const T: usize, E = Entrance<N, T>> {
    entrances: Vec<E>,
    of: Vec<usize>,
}

impl<const N: usize, const T: usize, E> Default for Chosen<N, T, E> {
    fn default() -> Self {
        Self {
            entrances: Vec::new(),
            of: Vec::new(),
        }
    }
}

impl<const N: usize, const T: usize, E: Clone + Send + Sync> Chosen<N, T, E> {
    /// Holds entrance `entrances[i]` of each contact `i`, copying only
    /// those not held already. The contacts must be those of the last
    /// update, or the copies cleared since.
    pub fn update(&mut self, contacts: &[Contact<N, T, E>], entrances: &[usize]) {
        if self.of.len() != contacts.len() {
            self.entrances.clear();
            self.entrances.par_extend(
                (contacts.par_iter().zip(entrances))
                    .with_min_len(CONTACTS_PER_TASK)
                    .map(|(c, &e)| c.entrances[e].clone()),
            );
            self.of.clear();
            self.of.extend_from_slice(entrances);
            return;
        }
        (self.entrances.par_iter_mut().zip(&mut self.of))
            .zip(contacts.par_iter().zip(entrances))
            .with_min_len(CONTACTS_PER_TASK)
            .for_each(|((held, of), (c, &e))| {
                if *of != e {
                    held.clone_from(&c.entrances[e]);
                    *of = e;
                }
            });
    }

    /// Forgets the copies (the contacts are replaced).
    pub fn clear(&mut self) {
        self.entrances.clear();
        self.of.clear();
    }

    /// Contact `i`'s entrance `e`, if held.
    pub fn get(&self, i: usize, e: usize) -> Option<&E> {
        (self.of.get(i) == Some(&e)).then(|| &self.entrances[i])
    }

    /// Contact `i`'s entrance `e`: its copy where held, else its own.
    pub fn of<'a>(&'a self, contacts: &'a [Contact<N, T, E>], i: usize, e: usize) -> &'a E {
        self.get(i, e).unwrap_or_else(|| &contacts[i].entrances[e])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contacts::BlockVector;

    fn entrance(gap: f64) -> Entrance<3, 1> {
        Entrance {
            gap,
            normal: [BlockVector::repeat(gap), BlockVector::zeros()],
            tangents: [[BlockVector::zeros(), BlockVector::repeat(-gap)]],
        }
    }

    /// A contact's entrance is given only while the one held is the one
    /// asked for; an update copies what changed; clearing forgets all.
    #[test]
    fn gives_the_held_entrance_only() {
        let contacts: [Contact<3, 1>; 2] = [
            Contact::between_first_two(vec![entrance(1.0), entrance(2.0)]),
            Contact::between_first_two(vec![entrance(3.0)]),
        ];
        let mut chosen = Chosen::default();
        assert!(chosen.get(0, 0).is_none());
        chosen.update(&contacts, &[1, 0]);
        assert_eq!(chosen.get(0, 1), Some(&entrance(2.0)));
        assert!(chosen.get(0, 0).is_none());
        assert_eq!(chosen.get(1, 0), Some(&entrance(3.0)));
        assert!(chosen.get(2, 0).is_none());
        chosen.update(&contacts, &[0, 0]);
        assert_eq!(chosen.get(0, 0), Some(&entrance(1.0)));
        assert!(chosen.get(0, 1).is_none());
        chosen.clear();
        assert!(chosen.get(1, 0).is_none());
    }
}
