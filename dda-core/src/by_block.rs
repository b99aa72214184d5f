//! Items grouped by the blocks they act on: each block's in item order, so
//! a sum over a block's items is the one a loop over all items makes.

/// Items `0..` listed under the blocks each names: block b's are
/// `items[starts[b]..starts[b + 1]]`.
#[derive(Debug, Default, Clone)]
pub(crate) struct ByBlock {
    starts: Vec<usize>,
    items: Vec<usize>,
}

impl ByBlock {
    /// Lists items `0..` among `blocks` blocks, item k under each block
    /// `blocks_of` gives for it; a block past the last lists nothing, as no
    /// block's filter would find it. The buffers are kept for the next fill.
    pub fn fill<B: IntoIterator<Item = usize>>(
        &mut self,
        blocks: usize,
        blocks_of: impl Iterator<Item = B> + Clone,
    ) {
        self.starts.clear();
        self.starts.resize(blocks + 1, 0);
        for b in blocks_of.clone().flatten().filter(|&b| b < blocks) {
            self.starts[b + 1] += 1;
        }
        for b in 0..blocks {
            self.starts[b + 1] += self.starts[b];
        }
        let mut next = self.starts.clone();
        self.items.clear();
        self.items.resize(self.starts[blocks], 0);
        for (k, of) in blocks_of.enumerate() {
            for b in of.into_iter().filter(|&b| b < blocks) {
                self.items[next[b]] = k;
                next[b] += 1;
            }
        }
    }

    /// Forgets the lists.
    pub fn clear(&mut self) {
        self.starts.clear();
        self.items.clear();
    }

    /// How many blocks are listed (0 before a fill or after a clear).
    pub fn blocks(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// The items of `block`, in item order.
    pub fn of(&self, block: usize) -> &[usize] {
        &self.items[self.starts[block]..self.starts[block + 1]]
    }
}
