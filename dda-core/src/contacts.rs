//! Contacts as the driver sees them: linearised gap and tangential
//! displacement in terms of the two blocks' step DOF, plus the record a
//! contact carries from step to step.
//!
//! `N` is the number of DOF per block, `T` the number of tangential directions
//! of the contact frame. The dimension crates fill these in; nothing here knows
//! what they are.

use nalgebra::SVector;
use std::sync::Mutex;

use crate::contact::{ContactState, History};

/// One block's step displacement (or any per-block DOF vector).
pub type BlockVector<const N: usize> = SVector<f64, N>;

/// Identifies a contact across steps so its state can be carried over.
///
/// `block_a`/`feature_a` is the entering feature (a vertex), `block_b`/`feature_b`
/// the feature it enters through (an edge or a face; for a contact with several
/// candidate entrances, a vertex). Meaning of the features is up to the
/// dimension crate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ContactKey {
    pub block_a: u32,
    pub feature_a: u32,
    pub block_b: u32,
    pub feature_b: u32,
}

impl ContactKey {
    /// The key without the entered feature, used when a vertex has moved onto
    /// a neighbouring edge or face: the contact keeps its state.
    fn coarse(&self) -> (u32, u32, u32) {
        (self.block_a, self.feature_a, self.block_b)
    }
}

/// A reference line (2D) or face (3D) through which the entering feature may
/// enter block `b`, linearised about the start of the step, kept as its
/// rows (the 2D form; a dimension may keep fewer numbers, see
/// [`EntranceRows`]):
///
/// `gap(D) = gap + normal[0]·D_a + normal[1]·D_b`
/// `shear_k(D) = tangents[k][0]·D_a + tangents[k][1]·D_b` (this step's part)
#[derive(Debug, Clone, PartialEq)]
pub struct Entrance<const N: usize, const T: usize> {
    pub gap: f64,
    pub normal: [BlockVector<N>; 2],
    pub tangents: [[BlockVector<N>; 2]; T],
}

/// An entrance as the driver reads it: its gap at the step's start and
/// its rows, which a dimension may keep as they are ([`Entrance`]) or
/// rebuild from fewer numbers when read. Rows read twice are the same to
/// the last bit.
pub trait EntranceRows<const N: usize, const T: usize>:
    Clone + PartialEq + std::fmt::Debug + Send + Sync + 'static
{
    /// Gap at the start of the step (negative: penetration).
    fn gap(&self) -> f64;

    /// The gap's rows for the contact's two blocks.
    fn normal(&self) -> [BlockVector<N>; 2];

    /// Tangent `k`'s rows for the contact's two blocks.
    fn tangent(&self, k: usize) -> [BlockVector<N>; 2];

    /// The gap's row for the contact's block `side` (0 or 1) alone.
    #[inline]
    fn normal_of(&self, side: usize) -> BlockVector<N> {
        self.normal()[side]
    }

    /// Tangent `k`'s row for the contact's block `side` alone.
    #[inline]
    fn tangent_of(&self, k: usize, side: usize) -> BlockVector<N> {
        self.tangent(k)[side]
    }

    /// Linearised gap at the step displacements of the two blocks.
    fn gap_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> f64 {
        let [na, nb] = self.normal();
        self.gap() + na.dot(da) + nb.dot(db)
    }

    /// This step's relative tangential displacement.
    fn shear_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> SVector<f64, T> {
        SVector::<f64, T>::from_fn(|k, _| {
            let [ta, tb] = self.tangent(k);
            ta.dot(da) + tb.dot(db)
        })
    }

    /// The step's gap and relative tangential displacement together: a
    /// dimension that keeps points reads their motion once for both.
    fn gap_and_shear_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> (f64, SVector<f64, T>) {
        (self.gap_at(da, db), self.shear_at(da, db))
    }

    /// The two blocks' generalised forces of a contact force `normal`
    /// along the normal and `shear` along the tangents: the rows times
    /// the forces, summed normal first.
    fn spread(&self, normal: f64, shear: &SVector<f64, T>) -> [BlockVector<N>; 2] {
        let [na, nb] = self.normal();
        let mut force = [na * normal, nb * normal];
        for k in 0..T {
            let [ta, tb] = self.tangent(k);
            force[0] += ta * shear[k];
            force[1] += tb * shear[k];
        }
        force
    }

    /// `f` of the entrance with all its rows made, for a reader of them
    /// all: made once, not at each read.
    fn with_rows<R>(&self, f: impl FnOnce(&Entrance<N, T>) -> R) -> R {
        f(&Entrance {
            gap: self.gap(),
            normal: self.normal(),
            tangents: std::array::from_fn(|k| self.tangent(k)),
        })
    }
}

impl<const N: usize, const T: usize> EntranceRows<N, T> for Entrance<N, T> {
    #[inline]
    fn gap(&self) -> f64 {
        self.gap
    }

    #[inline]
    fn normal(&self) -> [BlockVector<N>; 2] {
        self.normal
    }

    #[inline]
    fn tangent(&self, k: usize) -> [BlockVector<N>; 2] {
        self.tangents[k]
    }

    #[inline]
    fn gap_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> f64 {
        Entrance::gap_at(self, da, db)
    }

    #[inline]
    fn shear_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> SVector<f64, T> {
        Entrance::shear_at(self, da, db)
    }

    /// The rows are kept: `f` reads them in place.
    #[inline]
    fn with_rows<R>(&self, f: impl FnOnce(&Entrance<N, T>) -> R) -> R {
        f(self)
    }
}

impl<const N: usize, const T: usize> Entrance<N, T> {
    /// Linearised gap at the step displacements of the two blocks.
    #[inline]
    pub fn gap_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> f64 {
        self.gap + self.normal[0].dot(da) + self.normal[1].dot(db)
    }

    /// This step's relative tangential displacement.
    #[inline]
    pub fn shear_at(&self, da: &BlockVector<N>, db: &BlockVector<N>) -> SVector<f64, T> {
        SVector::<f64, T>::from_fn(|k, _| self.tangents[k][0].dot(da) + self.tangents[k][1].dot(db))
    }
}

/// What a contact remembers between steps. Owned by the driver; the dimension
/// crates only create contacts with a fresh record.
pub struct ContactRecord<const T: usize> {
    pub state: ContactState,
    /// Elastic shear displacement from the lock point, in the entrance's
    /// tangent basis (zero unless locked).
    pub shear: SVector<f64, T>,
    /// Unit slip direction of the last sliding step (zero if none).
    pub slip_direction: SVector<f64, T>,
    pub slip_path: f64,
    pub slip_rate: f64,
    /// Index of the entrance used in the last accepted step.
    pub entrance: usize,
    /// Normal and shear forces of the last accepted step (for output).
    pub normal_force: f64,
    pub shear_force: f64,
    /// The law's own history; `None` until the driver first sees the contact.
    pub history: Option<History>,
}

impl<const T: usize> Default for ContactRecord<T> {
    fn default() -> Self {
        Self {
            state: ContactState::Open,
            shear: SVector::zeros(),
            slip_direction: SVector::zeros(),
            slip_path: 0.0,
            slip_rate: 0.0,
            entrance: 0,
            normal_force: 0.0,
            shear_force: 0.0,
            history: None,
        }
    }
}

impl<const T: usize> std::fmt::Debug for ContactRecord<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactRecord")
            .field("state", &self.state)
            .field("shear", &self.shear)
            .field("slip_path", &self.slip_path)
            .finish_non_exhaustive()
    }
}

/// A contact candidate for one step: which blocks, which law, its entrances
/// (at least one; with several, the one with the largest gap at the trial
/// displacement is used: Shi's entrance-line choice), and its record.
#[derive(Debug)]
pub struct Contact<const N: usize, const T: usize, E = Entrance<N, T>> {
    pub key: ContactKey,
    pub blocks: [usize; 2],
    /// Index into the driver's law table.
    pub law: usize,
    /// Boundary length (2D) or area (3D) the contact stands for: what its
    /// cohesion and tensile strength act over (zero for a point contact).
    pub length: f64,
    /// Boundary length (2D, per unit thickness) or area (3D) the contact's
    /// springs stand for: `length` where the contact has one; for a corner
    /// touching a face (a rocking block's pivot), the entering vertex's share
    /// of its side that most nearly faces the entered one. Never zero, so the
    /// springs of every closed contact are the penalty times this.
    pub spring_length: f64,
    pub entrances: Vec<E>,
    pub record: ContactRecord<T>,
    /// The widest of `entrances` at the step's start, read as they are made
    /// ([`Contact::new`]; they do not change after), while they are at
    /// hand: a step's trial at rest and its pattern read it instead of
    /// every entrance again (5–8 ms a step on the 10,051-block 3D wall,
    /// whose contacts keep some 320,000).
    pub(crate) widest: Widest,
}

/// The largest gap at the step's start among a contact's entrances, and
/// the first entrance with it (`None` where no gap exceeds −∞).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Widest {
    pub first: Option<u32>,
    pub gap: f64,
}

impl Widest {
    fn of<const N: usize, const T: usize, E: EntranceRows<N, T>>(entrances: &[E]) -> Self {
        let mut widest = Self {
            first: None,
            gap: f64::NEG_INFINITY,
        };
        for (i, e) in entrances.iter().enumerate() {
            let gap = e.gap();
            if gap > widest.gap {
                widest = Self {
                    first: Some(i as u32),
                    gap,
                };
            }
        }
        widest
    }
}

impl<const N: usize, const T: usize, E: EntranceRows<N, T>> Contact<N, T, E> {
    /// The contact of `key`'s two blocks (entering first) through
    /// `entrances`, with law `law`, its (length, spring length) and a fresh
    /// record.
    pub fn new(
        key: ContactKey,
        law: usize,
        (length, spring_length): (f64, f64),
        entrances: Vec<E>,
    ) -> Self {
        Self {
            key,
            blocks: [key.block_a as usize, key.block_b as usize],
            law,
            length,
            spring_length,
            widest: Widest::of(&entrances),
            entrances,
            record: ContactRecord::default(),
        }
    }

    /// The largest of the entrances' gaps at the step's start, and the
    /// first entrance with it (`None` where there is none above −∞).
    pub fn widest_at_start(&self) -> (Option<usize>, f64) {
        (self.widest.first.map(|i| i as usize), self.widest.gap)
    }
}

#[cfg(test)]
impl<const N: usize, const T: usize, E: EntranceRows<N, T>> Contact<N, T, E> {
    /// Vertex 0 of block 0 against block 1 through these entrances, law 0,
    /// unit lengths and a fresh record: the driver's tests' contact.
    pub(crate) fn between_first_two(entrances: Vec<E>) -> Self {
        let key = ContactKey {
            block_a: 0,
            feature_a: 0,
            block_b: 1,
            feature_b: 0,
        };
        Self::new(key, 0, (1.0, 1.0), entrances)
    }
}

/// Whether two narrow phases found the same contacts: the same keys,
/// entrances and lengths, in the same order (their records aside).
pub fn same_contacts<const N: usize, const T: usize, E: PartialEq>(
    a: &[Contact<N, T, E>],
    b: &[Contact<N, T, E>],
) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.key == y.key
                && x.entrances == y.entrances
                && (x.length, x.spring_length) == (y.length, y.spring_length)
        })
}

/// Moves the records of last step's contacts onto this step's, matching by
/// key, then by the coarse key (same vertex against the same block) when the
/// vertex has moved onto a neighbouring edge or face. A record only moves
/// between contacts of the same law.
///
/// Both keys name the contact's block pair, so matches are looked for
/// within each pair's contacts: the two lists are walked together in
/// block-pair order (the order the search finds them in; a list out of it
/// is sorted first), with no hashing.
pub fn transfer_records<const N: usize, const T: usize, E>(
    old: &mut [Contact<N, T, E>],
    new: &mut [Contact<N, T, E>],
) {
    for list in [&mut *old, &mut *new] {
        if !list.is_sorted_by_key(pair) {
            list.sort_by_key(pair);
        }
    }
    let mut taken = vec![false; old.len()];
    let (mut o, mut n) = (0, 0);
    while o < old.len() && n < new.len() {
        let (po, pn) = (pair(&old[o]), pair(&new[n]));
        let o_end = o + old[o..].iter().take_while(|c| pair(c) == po).count();
        let n_end = n + new[n..].iter().take_while(|c| pair(c) == pn).count();
        match po.cmp(&pn) {
            std::cmp::Ordering::Less => o = o_end,
            std::cmp::Ordering::Greater => n = n_end,
            std::cmp::Ordering::Equal => {
                transfer_within(&mut old[o..o_end], &mut new[n..n_end], &mut taken[o..o_end]);
                (o, n) = (o_end, n_end);
            }
        }
    }
}

/// The ordered block pair a contact belongs to.
fn pair<const N: usize, const T: usize, E>(c: &Contact<N, T, E>) -> (usize, usize) {
    let [a, b] = c.blocks;
    (a.min(b), a.max(b))
}

/// [`transfer_records`] between one block pair's contacts.
fn transfer_within<const N: usize, const T: usize, E>(
    old: &mut [Contact<N, T, E>],
    new: &mut [Contact<N, T, E>],
    taken: &mut [bool],
) {
    // Exact matches first so a coarse match never steals an exact one.
    for c in new.iter_mut() {
        // The last of equal keys, as a map built in order would hold.
        if let Some(i) = old.iter().rposition(|o| o.key == c.key) {
            if !taken[i] && old[i].law == c.law {
                taken[i] = true;
                c.record = std::mem::take(&mut old[i].record);
            }
        }
    }
    for c in new.iter_mut().filter(|c| c.record.history.is_none()) {
        // Among the old contacts of the coarse key, the first closed one,
        // else the last.
        let coarse = c.key.coarse();
        let mut found = None;
        for (i, o) in old.iter().enumerate() {
            if o.key.coarse() == coarse {
                let closed = found.is_some_and(|j: usize| old[j].record.state.is_closed());
                if !closed {
                    found = Some(i);
                }
            }
        }
        if let Some(i) = found {
            if !taken[i] && old[i].law == c.law && old[i].record.state.is_closed() {
                taken[i] = true;
                let mut record = std::mem::take(&mut old[i].record);
                // Another entrance set: its own indexing and tangent basis.
                record.entrance = 0;
                record.shear = SVector::zeros();
                c.record = record;
            }
        }
    }
}

/// Where a search's contacts lie in its list: each block pair searched
/// (i < j, increasing) and the end of its contacts.
#[derive(Clone, Debug, Default)]
pub struct SearchedPairs {
    pairs: Vec<(usize, usize)>,
    ends: Vec<usize>,
}

impl SearchedPairs {
    /// The pairs searched and how many contacts each made, if the pairs
    /// increase (as the broad phase gives them); none otherwise.
    pub fn of(pairs: Vec<(usize, usize)>, counts: impl IntoIterator<Item = usize>) -> Self {
        if !increasing(&pairs) {
            return Self::default();
        }
        let mut end = 0;
        let ends = counts.into_iter().map(|n| {
            end += n;
            end
        });
        Self {
            pairs,
            ends: ends.collect(),
        }
    }
}

/// Whether each pair is (i, j) with i < j and the pairs increase.
fn increasing(pairs: &[(usize, usize)]) -> bool {
    pairs.windows(2).all(|w| w[0] < w[1]) && pairs.iter().all(|&(i, j)| i < j)
}

/// `old`, the contacts of the search `searched` describes, cut into each
/// of `pairs`' own (empty where a pair is new), to move their records pair
/// by pair as this search makes its contacts ([`carry_records`]); `None`
/// where `searched` does not describe `old` or `pairs` do not increase,
/// and [`transfer_records`] must walk the two lists.
pub fn pair_chunks<'a, const N: usize, const T: usize, E>(
    old: &'a mut [Contact<N, T, E>],
    searched: &SearchedPairs,
    pairs: &[(usize, usize)],
) -> Option<Vec<Mutex<&'a mut [Contact<N, T, E>]>>> {
    if !increasing(pairs) || searched.ends.last().copied().unwrap_or(0) != old.len() {
        return None;
    }
    let mut chunks = Vec::with_capacity(pairs.len());
    let (mut rest, mut start, mut k) = (old, 0, 0);
    for pair in pairs {
        while k < searched.pairs.len() && searched.pairs[k] < *pair {
            let (_, tail) = std::mem::take(&mut rest).split_at_mut(searched.ends[k] - start);
            rest = tail;
            start = searched.ends[k];
            k += 1;
        }
        let chunk = if searched.pairs.get(k) == Some(pair) {
            let (head, tail) = std::mem::take(&mut rest).split_at_mut(searched.ends[k] - start);
            rest = tail;
            start = searched.ends[k];
            k += 1;
            head
        } else {
            &mut []
        };
        chunks.push(Mutex::new(chunk));
    }
    Some(chunks)
}

/// [`transfer_records`] between one block pair's contacts, `old` of the
/// last search and `new` of this one: the same records move.
pub fn carry_records<const N: usize, const T: usize, E>(
    old: &mut [Contact<N, T, E>],
    new: &mut [Contact<N, T, E>],
) {
    if old.is_empty() || new.is_empty() {
        return;
    }
    let mut few = [false; 32];
    let mut many = Vec::new();
    let taken = if old.len() <= few.len() {
        &mut few[..old.len()]
    } else {
        many.resize(old.len(), false);
        &mut many[..]
    };
    transfer_within(old, new, taken);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A contact of vertex `fa` of block `a` against feature `fb` of block
    /// `b`, its record marked by `slip_path` and closed or not.
    fn contact(
        a: u32,
        fa: u32,
        b: u32,
        fb: u32,
        law: usize,
        mark: Option<(f64, bool)>,
    ) -> Contact<2, 1> {
        let mut record = ContactRecord::default();
        if let Some((m, closed)) = mark {
            record.slip_path = m;
            record.entrance = 1;
            record.shear = SVector::from_element(m);
            record.history = Some(Box::new(()));
            if closed {
                record.state = ContactState::Locked;
            }
        }
        let key = ContactKey {
            block_a: a,
            feature_a: fa,
            block_b: b,
            feature_b: fb,
        };
        Contact {
            record,
            ..Contact::new(key, law, (0.0, 1.0), Vec::new())
        }
    }

    fn marks(list: &[Contact<2, 1>]) -> Vec<Option<(f64, usize)>> {
        list.iter()
            .map(|c| {
                c.record
                    .history
                    .as_ref()
                    .map(|_| (c.record.slip_path, c.record.entrance))
            })
            .collect()
    }

    #[test]
    fn records_move_by_key_then_by_vertex_within_each_pair() {
        let mut old = vec![
            contact(0, 1, 1, 2, 0, Some((1.0, true))),
            // Vertex 3 of block 0 touched two edges of block 1: the closed
            // one is the coarse match.
            contact(0, 3, 1, 0, 0, Some((2.0, false))),
            contact(0, 3, 1, 1, 0, Some((3.0, true))),
            contact(1, 0, 2, 0, 0, Some((4.0, true))),
            // Another law's record never moves.
            contact(2, 0, 3, 1, 1, Some((5.0, true))),
            contact(3, 2, 4, 0, 0, Some((6.0, true))),
        ];
        let mut new = vec![
            contact(0, 1, 1, 2, 0, None),
            contact(0, 3, 1, 5, 0, None),
            // A pair the old list does not have.
            contact(0, 2, 2, 0, 0, None),
            contact(1, 0, 2, 0, 0, None),
            contact(2, 0, 3, 1, 0, None),
            // Listed before its pair's turn: sorted first.
            contact(4, 1, 3, 0, 0, None),
        ];
        transfer_records(&mut old, &mut new);
        let got: Vec<_> = new
            .iter()
            .map(|c| (c.key, c.record.history.is_some()))
            .collect();
        assert_eq!(got.len(), 6);
        let by_key = |a, fa, b, fb| {
            let i = new
                .iter()
                .position(|c| {
                    c.key
                        == ContactKey {
                            block_a: a,
                            feature_a: fa,
                            block_b: b,
                            feature_b: fb,
                        }
                })
                .unwrap();
            marks(&new)[i]
        };
        assert_eq!(
            by_key(0, 1, 1, 2),
            Some((1.0, 1)),
            "exact match keeps its entrance"
        );
        assert_eq!(
            by_key(0, 3, 1, 5),
            Some((3.0, 0)),
            "the closed coarse match, on entrance 0"
        );
        assert_eq!(by_key(0, 2, 2, 0), None);
        assert_eq!(by_key(1, 0, 2, 0), Some((4.0, 1)));
        assert_eq!(by_key(2, 0, 3, 1), None, "another law's record");
        assert_eq!(
            by_key(4, 1, 3, 0),
            None,
            "vertex 1 of block 4 had no record"
        );
        let shear: Vec<f64> = new.iter().map(|c| c.record.shear[0]).collect();
        assert_eq!(
            shear.iter().filter(|s| **s != 0.0).count(),
            2,
            "coarse matches drop their shear"
        );
    }

    /// A search's contacts of the pairs of blocks 0-7 that `keep` keeps,
    /// each pair's made from `seed`: vertices 0-3 of either block against
    /// features 0-2 (some keys twice), law 0 or 1, their records marked
    /// (some closed) where `marked`.
    fn search(seed: u64, keep: u64, marked: bool) -> (Vec<(usize, usize)>, Vec<Contact<2, 1>>) {
        let mut state = seed;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let (mut pairs, mut list) = (Vec::new(), Vec::new());
        for (i, j) in (0..8).flat_map(|i| (i + 1..8).map(move |j| (i, j))) {
            if next(4) >= keep {
                continue;
            }
            pairs.push((i, j));
            for _ in 0..next(6) {
                let (a, b) = if next(2) == 0 { (i, j) } else { (j, i) };
                let mark = marked.then(|| (list.len() as f64 + 1.0, next(2) == 0));
                let law = usize::from(next(5) == 0);
                list.push(contact(
                    a as u32,
                    next(4) as u32,
                    b as u32,
                    next(3) as u32,
                    law,
                    mark,
                ));
            }
        }
        (pairs, list)
    }

    /// Records moved pair by pair as a search makes its contacts land where
    /// the walk over the two whole lists puts them.
    #[test]
    fn records_carried_pair_by_pair_are_those_the_whole_walk_moves() {
        for seed in 0..200 {
            let (old_pairs, mut old) = search(seed, 3, true);
            let (pairs, mut new) = search(seed + 1000, 3, false);
            let (_, mut walked_old) = search(seed, 3, true);
            let (_, mut walked) = search(seed + 1000, 3, false);
            transfer_records(&mut walked_old, &mut walked);
            let count = |p: &(usize, usize)| new.iter().filter(|c| pair(c) == *p).count();
            let counts: Vec<usize> = pairs.iter().map(count).collect();
            let old_counts = old_pairs
                .iter()
                .map(|p| old.iter().filter(|c| pair(c) == *p).count());
            let old_counts: Vec<usize> = old_counts.collect();
            let searched = SearchedPairs::of(old_pairs, old_counts);
            let chunks = pair_chunks(&mut old, &searched, &pairs).expect("increasing pairs");
            let mut start = 0;
            for (k, n) in counts.iter().enumerate() {
                let mut chunk = chunks[k].lock().unwrap();
                carry_records(&mut chunk, &mut new[start..start + n]);
                start += n;
            }
            assert_eq!(marks(&new), marks(&walked), "seed {seed}");
            let shear =
                |l: &[Contact<2, 1>]| l.iter().map(|c| c.record.shear[0]).collect::<Vec<_>>();
            assert_eq!(shear(&new), shear(&walked), "seed {seed}");
        }
    }

    /// Contacts the last search did not make (a checkpoint's) are walked.
    #[test]
    fn contacts_of_another_search_are_not_cut_by_its_pairs() {
        let (pairs, mut old) = search(7, 4, true);
        let searched = SearchedPairs::of(pairs.clone(), [old.len() - 1]);
        assert!(pair_chunks(&mut old, &searched, &pairs).is_none());
        assert!(pair_chunks(&mut old, &SearchedPairs::default(), &pairs).is_none());
        let backwards: Vec<_> = pairs.iter().rev().copied().collect();
        let all = SearchedPairs::of(pairs.clone(), [old.len()]);
        assert!(pair_chunks(&mut old, &all, &backwards).is_none());
    }
}
