//! The contacts of each block, for gathering a residual block by block.
//!
//! Made once per open-close pass (the contact list stands through a pass),
//! it lets every core sum its blocks' contact forces. Each block adds its
//! contacts in contact order, as the one-thread loop over contacts does,
//! so both give the same residual to the last bit.

use rayon::prelude::*;

use crate::by_block::ByBlock;
use crate::contacts::Contact;
use crate::CONTACTS_PER_TASK;

/// The contacts of each block, in contact order, with the block's side in
/// each (a block-by-block index of the contact list, made for one pass).
/// The side is listed so a block's sum reads its contacts' forces alone:
/// looking it up in each contact took a third of a residual's gathering
/// at ten thousand blocks.
#[derive(Debug, Default)]
pub(super) struct Touching {
    index: ByBlock,
    /// Each contact's two blocks, side by side (kept for its storage).
    blocks: Vec<[usize; 2]>,
}

impl Touching {
    /// Indexes `contacts` among `blocks` blocks.
    pub fn fill<const N: usize, const T: usize, E: Sync>(
        &mut self,
        blocks: usize,
        contacts: &[Contact<N, T, E>],
    ) {
        // The contacts' blocks copied side by side on every core first:
        // the listing reads them twice, on one core, and read in place
        // (a contact is some 200 bytes) that took 0.6-1.2 ms a pass at
        // 10,051 blocks in 2D, 2.8-3.1 ms in 3D.
        let pairs = &mut self.blocks;
        pairs.clear();
        pairs.par_extend(
            (contacts.par_iter())
                .with_min_len(CONTACTS_PER_TASK)
                .map(|c| c.blocks),
        );
        // Item 2i + s is side s of contact i.
        let sides = pairs.iter().flat_map(|blocks| blocks.map(|b| [b]));
        self.index.fill(blocks, sides);
    }

    /// Forgets the index (the pass is over).
    pub fn clear(&mut self) {
        self.index.clear();
    }

    /// Whether a pass's contacts are indexed.
    pub fn is_filled(&self) -> bool {
        self.index.blocks() > 0
    }

    /// The contacts of `block` and its side in each (0 or 1), in contact
    /// order.
    pub fn of(&self, block: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.index
            .of(block)
            .iter()
            .map(|&item| (item / 2, item % 2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contacts::ContactKey;

    fn contact(a: usize, b: usize) -> Contact<3, 1> {
        let key = ContactKey {
            block_a: a as u32,
            feature_a: 0,
            block_b: b as u32,
            feature_b: 0,
        };
        Contact::new(key, 0, (1.0, 1.0), Vec::new())
    }

    /// Each block lists exactly the contacts that touch it, in contact
    /// order, with the side it is on; a block without contacts lists
    /// none; clearing empties the index.
    #[test]
    fn each_block_lists_its_contacts_in_order() {
        let contacts = [(2, 0), (0, 1), (1, 2), (3, 0), (2, 1)].map(|(a, b)| contact(a, b));
        let mut touching = Touching::default();
        assert!(!touching.is_filled());
        touching.fill(5, &contacts);
        assert!(touching.is_filled());
        let of = |b: usize| touching.of(b).collect::<Vec<_>>();
        assert_eq!(of(0), [(0, 1), (1, 0), (3, 1)]);
        assert_eq!(of(1), [(1, 1), (2, 0), (4, 1)]);
        assert_eq!(of(2), [(0, 0), (2, 1), (4, 0)]);
        assert_eq!(of(3), [(3, 0)]);
        assert!(of(4).is_empty());
        touching.clear();
        assert!(!touching.is_filled());
    }
}
