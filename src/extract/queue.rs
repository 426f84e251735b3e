//! The reference-point queue (thesis §5.1, Figure 40): front slots whose
//! angle makes them reference points, sharp corners first; strategy B
//! orders them by the element size wanted there, in bands of [`QueueTuning::band`](super::tuning::QueueTuning::band)
//! from the smallest, then by layer, the newest first within a layer (so a
//! row goes on from its last element); strategy A by recency alone.
//!
//! The size bands make meshing go from fine to coarse: the rows around a
//! finely divided hole spread out, and coarsen, before the coarse rows of
//! the outer boundary move in, so that fronts meet where their spacing is
//! alike (rows counted alike would let the coarse front run up to the
//! hole). A row moving into coarser parts is coarsened by tucks. Where the
//! size is uniform, every slot is in one band and the order is by layer.
//! Entries are versioned: a slot whose angle changed is pushed again and
//! its old entry skipped.
//!
//! A reference point passed over (its element refused or too poor) whose
//! evaluation the memory ([`super::memo`]) keeps is *parked* in its group,
//! by score, instead of going back on the stack: a step reads its group's
//! best parked score in `O(log n)` and walks only the points that are new
//! or whose surroundings changed. The memory hands a parked point back to
//! the stack when it forgets its evaluation, so a front of many loops with
//! long runs of poor reference points (a tube sheet's ligaments) costs a
//! step what a single loop does.

use super::candidate::Chosen;
use super::memo::Eval;
use super::params::Strategy;
use super::session::Mesher;
use crate::front::SlotId;
use std::cmp::Reverse;
use std::collections::BTreeMap;

/// A relink that leaves a loop of at most this many slots makes the
/// memory forget the evaluations at its slots wherever they are: the guard
/// and the candidates read a loop's length where it is short (a four-node
/// loop, a loop too short for a type-1 or 2 element, a snap that would
/// leave a part under four nodes), and a short loop's slots all read it.
/// On a longer loop only the box of the relink is forgotten, as for an
/// element: a remembered element is checked again before it is taken.
const SHORT_LOOP: usize = 16;

/// The queue itself: its entries by group, each slot's current version
/// (an entry of an older version is stale) and the push counter.
///
/// Entries come out greatest first by [`Entry::order`]. A group (sharp
/// or not, band, layer) holds one stack per class: `seq` grows with every
/// push, so a stack is in `seq` order by pushing alone, and the greatest
/// entry is the top of the lowest class's stack of the first group. A pop
/// and a push cost `O(log groups)`, against `O(log entries)` for a heap,
/// and most steps pop and put back a long run of one group.
#[derive(Clone, Debug, Default)]
pub(super) struct RefQueue {
    groups: BTreeMap<GroupKey, Group>,
    /// Emptied groups kept for their stacks' room.
    spare: Vec<Group>,
    pub(super) version: Vec<u32>,
    pub(super) seq: u64,
    /// Per slot, where its parked entry is (its group and key), if any.
    parked_at: Vec<Option<(GroupKey, ParkKey)>>,
}

/// A group's key: not sharp (sharp corners first), band, layer.
pub(super) type GroupKey = (bool, u32, u32);

/// What parking an entry needs: its remembered score (`None`: no
/// element) and a box the memory's entry must widen to, if any.
struct Park {
    score: Option<f64>,
    widen: Option<crate::geom::Aabb>,
}

/// A parked entry's key: its remembered score, best first (no element
/// last), then the latest parked first.
type ParkKey = (Reverse<i64>, Reverse<u64>);

/// The key of a parked entry scoring `score` (`None`: no element).
fn park_key(score: Option<f64>, seq: u64) -> ParkKey {
    // The bits of an f64 as an integer in its total order.
    let bits = score.unwrap_or(f64::NEG_INFINITY).to_bits() as i64;
    (
        Reverse(bits ^ (((bits >> 63) as u64) >> 1) as i64),
        Reverse(seq),
    )
}

/// One group's entries: a stack per class, each in `seq` order, and the
/// parked entries by score.
#[derive(Clone, Debug, Default)]
struct Group {
    by_class: [Vec<Entry>; 3],
    parked: BTreeMap<ParkKey, Entry>,
}

impl Group {
    fn is_empty(&self) -> bool {
        self.by_class.iter().all(Vec::is_empty) && self.parked.is_empty()
    }
}

/// Emptied groups kept for reuse at most.
const SPARE_GROUPS: usize = 8;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Entry {
    pub(super) class: u8,
    pub(super) band: u32,
    pub(super) layer: u32,
    pub(super) seq: u64,
    pub(super) slot: SlotId,
    pub(super) version: u32,
}

impl Entry {
    /// The entry's group.
    fn group(&self) -> GroupKey {
        (self.class > 0, self.band, self.layer)
    }

    /// The queue's order, the first out the least: sharp corners first,
    /// then finer band first, lower layer first, reference points before
    /// wider row ends, newest first.
    #[cfg(test)]
    fn order(&self) -> (GroupKey, u8, std::cmp::Reverse<u64>) {
        (self.group(), self.class, std::cmp::Reverse(self.seq))
    }
}

impl RefQueue {
    /// Adds `e`, whose `seq` is above that of every entry of its group and
    /// class (a new push, or the entry [`RefQueue::pop`] just gave).
    pub(super) fn push_entry(&mut self, e: Entry) {
        let spare = &mut self.spare;
        let stack = &mut self
            .groups
            .entry(e.group())
            .or_insert_with(|| spare.pop().unwrap_or_default())
            .by_class[usize::from(e.class)];
        debug_assert!(stack.last().is_none_or(|l| l.seq < e.seq));
        stack.push(e);
    }

    /// Drops the empty groups at the front, so that the first group holds
    /// the first entry.
    fn drop_empty_front(&mut self) {
        while let Some(first) = self.groups.first_entry() {
            if !first.get().is_empty() {
                return;
            }
            let g = first.remove();
            if self.spare.len() < SPARE_GROUPS {
                self.spare.push(g);
            }
        }
    }

    /// Takes the first entry of the stacks out (parked entries stay).
    #[cfg(test)]
    fn pop(&mut self) -> Option<Entry> {
        self.groups
            .values_mut()
            .find_map(|g| g.by_class.iter_mut().find_map(Vec::pop))
    }

    /// The first entry of the stacks.
    #[cfg(test)]
    fn peek(&self) -> Option<Entry> {
        self.groups.keys().find_map(|&k| self.peek_in(k))
    }

    /// The first entry of group `key`'s stacks.
    fn peek_in(&self, key: GroupKey) -> Option<Entry> {
        let g = self.groups.get(&key)?;
        g.by_class.iter().find_map(|v| v.last().copied())
    }

    /// The key of the first group after `after` (the first of all for
    /// `None`) that holds any entry, on its stacks or parked.
    pub(super) fn group_after(&mut self, after: Option<GroupKey>) -> Option<GroupKey> {
        match after {
            None => {
                self.drop_empty_front();
                self.groups.first_key_value().map(|(k, _)| *k)
            }
            Some(a) => self
                .groups
                .range((std::ops::Bound::Excluded(a), std::ops::Bound::Unbounded))
                .find(|(_, g)| !g.is_empty())
                .map(|(k, _)| *k),
        }
    }

    /// Takes the first entry of group `key`'s stacks out.
    pub(super) fn pop_from(&mut self, key: GroupKey) -> Option<Entry> {
        let g = self.groups.get_mut(&key)?;
        g.by_class.iter_mut().find_map(Vec::pop)
    }

    /// Group `key`'s first parked entry (the best score).
    fn first_parked(&self, key: GroupKey) -> Option<Entry> {
        let g = self.groups.get(&key)?;
        g.parked.first_key_value().map(|(_, e)| *e)
    }

    /// Parks `e`, whose remembered evaluation scores `score` (`None`: no
    /// element); a slot's earlier parked entry is dropped.
    pub(super) fn park(&mut self, e: Entry, score: Option<f64>) {
        self.unpark(e.slot);
        self.seq += 1;
        let e = Entry { seq: self.seq, ..e };
        let key = park_key(score, e.seq);
        let spare = &mut self.spare;
        self.groups
            .entry(e.group())
            .or_insert_with(|| spare.pop().unwrap_or_default())
            .parked
            .insert(key, e);
        let i = e.slot as usize;
        if self.parked_at.len() <= i {
            self.parked_at.resize(i + 1, None);
        }
        self.parked_at[i] = Some((e.group(), key));
    }

    /// Takes slot `s`'s parked entry out, if it has one.
    fn unpark(&mut self, s: SlotId) -> Option<Entry> {
        let (group, key) = self.parked_at.get_mut(s as usize)?.take()?;
        self.groups.get_mut(&group)?.parked.remove(&key)
    }

    /// Puts the parked entries of `slots` back on their stacks, in the
    /// order they were parked (the slots without one are passed over).
    pub(super) fn release(&mut self, slots: &[SlotId]) {
        let mut back: Vec<Entry> = slots.iter().filter_map(|&s| self.unpark(s)).collect();
        back.sort_unstable_by_key(|e| e.seq);
        for e in back {
            self.seq += 1;
            self.push_entry(Entry { seq: self.seq, ..e });
        }
    }

    /// Drops every parked entry.
    pub(super) fn drop_parked(&mut self) {
        for g in self.groups.values_mut() {
            g.parked.clear();
        }
        self.parked_at.clear();
    }
}

impl Mesher {
    /// (Re)queues slot `s` if its angle makes it a reference point.
    pub(super) fn push(&mut self, s: SlotId) {
        let i = s as usize;
        if self.queue.version.len() <= i {
            self.queue.version.resize(i + 1, 0);
        }
        self.queue.version[i] = self.queue.version[i].wrapping_add(1);
        let sl = *self.front.slot(s);
        if !sl.alive {
            return;
        }
        let a = self.front.angle(s, &self.mesh.nodes).to_degrees();
        let [lo, hi] = self.params.reference_angle;
        let class = if a < lo {
            0
        } else if a <= hi {
            1
        } else if a <= self.params.row_angle {
            2
        } else {
            return;
        };
        self.queue.seq += 1;
        let (band, layer) = self.slot_key(s);
        self.queue.push_entry(Entry {
            class,
            band,
            layer,
            seq: self.queue.seq,
            slot: s,
            version: self.queue.version[i],
        });
    }

    /// Puts back entries popped and deferred by a step, after the step.
    /// An entry still current (its slot alive and not pushed since) goes
    /// back with the place [`Mesher::push`] would give it, its kind, band
    /// and layer unchanged, without working them out again (a long group of
    /// poor reference points is popped and put back at every step, and a
    /// band asks the size field); any other is pushed anew.
    ///
    /// An entry whose evaluation the memory keeps is parked instead
    /// ([`Mesher::parkable`]).
    pub(super) fn requeue(&mut self, deferred: Vec<Entry>) {
        for e in deferred {
            if self.front.slot(e.slot).alive && self.queue.version[e.slot as usize] == e.version {
                if let Some(p) = self.parkable(e) {
                    if let Some(bb) = p.widen {
                        self.memo.widen(Eval::Queue, e.slot, bb);
                    }
                    self.queue.park(e, p.score);
                    continue;
                }
                self.queue.seq += 1;
                self.queue.push_entry(Entry {
                    seq: self.queue.seq,
                    ..e
                });
            } else {
                self.push(e.slot);
            }
        }
    }

    /// A slot's place in strategy B's order: its size band and its layer
    /// (both 0 under strategy A).
    pub(super) fn slot_key(&self, s: SlotId) -> (u32, u32) {
        match self.params.strategy {
            Strategy::A => (0, 0),
            Strategy::B => {
                let sl = self.front.slot(s);
                let h = self.size.at(self.mesh.nodes[sl.node as usize]);
                let band = (h / self.size.range()[0]).ln() / self.params.tuning.queue.band.ln();
                (band.max(0.0) as u32, sl.layer)
            }
        }
    }

    /// Whether entry `e` (current) may be parked rather than walked again
    /// at the next step: the memory keeps its evaluation, it is not a
    /// needle nor a sharp corner tried for a seam, and no transition can
    /// be laid out there. Whether it is a needle or a sharp corner is read
    /// within the box the evaluation read; a row's end widens that box to
    /// the front a transition's layout reads. All stay as they are until
    /// the memory forgets the evaluation and the entry goes back on its
    /// stack.
    fn parkable(&self, e: Entry) -> Option<Park> {
        let s = e.slot;
        let r = self.memo.get(Eval::Queue, s, self.front.node(s))?;
        if self.at_needle(s) {
            return None;
        }
        let score = r.as_ref().map(|c| c.score);
        if e.class == 0 {
            let seam = self
                .front
                .angle_below(s, &self.mesh.nodes, &self.angles.seam);
            return (!seam).then_some(Park { score, widen: None });
        }
        if self.params.transition_ratio.is_none() || self.row_at(s).is_none() {
            return Some(Park { score, widen: None });
        }
        // A row's end: parked while no transition can be laid out there,
        // its evaluation kept as long as the front a layout reads stands.
        if self.transition_laid(s) {
            return None;
        }
        Some(Park {
            score,
            widen: Some(self.transition_extent(s)?),
        })
    }

    /// Keeps in `best` the best parked element of group `key` if it beats
    /// `best` ([`Chosen::keep_if_best`]); stale parked entries met on the
    /// way are dropped.
    pub(super) fn best_parked(&mut self, key: GroupKey, best: &mut Option<Chosen>) {
        while let Some(e) = self.queue.first_parked(key) {
            let s = e.slot;
            let live = self.front.slot(s).alive && self.queue.version[s as usize] == e.version;
            match self.memo.get(Eval::Queue, s, self.front.node(s)) {
                Some(r) if live => {
                    if let Some(c) = r.as_ref().filter(|c| Chosen::would_keep(c.score, best)) {
                        *best = Some(c.clone());
                    }
                    return;
                }
                _ => {
                    self.queue.unpark(s);
                    if live {
                        // Its evaluation is gone: looked at afresh.
                        self.push(s);
                    }
                }
            }
        }
    }

    /// The memory forgets its evaluations whose box meets `within`, or
    /// all of them for `None`, and those at the slots of the short loops
    /// ([`SHORT_LOOP`]) relinks formed since it last looked (such a loop's
    /// length changed all along it); the parked entries of the slots
    /// forgotten go back on the stacks.
    pub(super) fn forget(&mut self, within: Option<crate::geom::Aabb>) {
        let mut relinked = Vec::new();
        self.front.take_relinked(&mut relinked);
        relinked.retain(|&l| {
            let l = &self.front.loops[l as usize];
            l.alive && l.len <= SHORT_LOOP
        });
        match within {
            Some(bb) => {
                self.memo.changed(bb.min, bb.max);
                if !relinked.is_empty() {
                    let front = &self.front;
                    self.memo.forget_slots(|s| {
                        front.slots.get(s as usize).is_some_and(|slot| {
                            slot.alive && relinked.binary_search(&slot.loop_id).is_ok()
                        })
                    });
                }
            }
            None => self.memo.clear(),
        }
        self.queue.release(&self.memo.forgotten);
        self.memo.forgotten.clear();
    }

    /// Band and layer of the first live entry of the queue, on a stack or
    /// parked (stale entries dropped).
    pub(super) fn queue_top(&mut self) -> Option<(u32, u32)> {
        let mut after = None;
        while let Some(key) = self.queue.group_after(after) {
            after = Some(key);
            let live = |m: &Mesher, e: &Entry| {
                m.front.slot(e.slot).alive && m.queue.version[e.slot as usize] == e.version
            };
            while let Some(e) = self.queue.peek_in(key) {
                if live(self, &e) {
                    return Some((e.band, e.layer));
                }
                self.queue.pop_from(key);
            }
            let g = &self.queue.groups[&key];
            if let Some(e) = g.parked.values().find(|e| live(self, e)) {
                return Some((e.band, e.layer));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;

    /// Pops come out in [`Entry::order`], as from a heap of all entries,
    /// through pushes of new entries, the put-back of a popped one and
    /// pops that empty groups.
    #[test]
    fn pops_in_heap_order() {
        let mut q = RefQueue::default();
        let mut heap = BinaryHeap::new();
        let mut state: u64 = 12345;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let mut seq = 0;
        for round in 0..2000 {
            match next(5) {
                0..=2 => {
                    seq += 1;
                    let e = Entry {
                        class: next(3) as u8,
                        band: next(3) as u32,
                        layer: next(4) as u32,
                        seq,
                        slot: round,
                        version: 0,
                    };
                    q.push_entry(e);
                    heap.push(Reverse((e.order(), e.slot)));
                }
                3 => {
                    let want = heap.pop().map(|Reverse((_, s))| s);
                    assert_eq!(q.pop().map(|e| e.slot), want);
                }
                _ => {
                    let peeked = q.peek();
                    if let Some(e) = q.pop() {
                        assert_eq!(Some(e), peeked);
                        q.push_entry(e);
                    }
                }
            }
        }
        while let Some(Reverse((_, s))) = heap.pop() {
            assert_eq!(q.pop().map(|e| e.slot), Some(s));
        }
        assert_eq!(q.pop(), None);
    }

    /// Parked entries come out best score first (no element last); a
    /// group holding only parked entries is still walked; a slot parked
    /// again keeps only its newest entry; released entries go back on
    /// their stacks in the order they were parked, above the entries
    /// already there.
    #[test]
    fn parked_entries_by_score_and_released_in_order() {
        let mut q = RefQueue::default();
        let entry = |slot: u32, layer: u32| Entry {
            class: 1,
            band: 0,
            layer,
            seq: 0,
            slot,
            version: 0,
        };
        q.seq = 10;
        q.push_entry(Entry {
            seq: 10,
            ..entry(9, 0)
        });
        q.park(entry(1, 0), Some(0.4));
        q.park(entry(2, 0), None);
        q.park(entry(3, 0), Some(0.7));
        q.park(entry(4, 1), Some(0.9));
        let g0 = entry(0, 0).group();
        let g1 = entry(0, 1).group();
        assert_eq!(q.first_parked(g0).map(|e| e.slot), Some(3));
        q.park(entry(3, 0), Some(0.1));
        assert_eq!(q.first_parked(g0).map(|e| e.slot), Some(1));
        // Group 0's stack runs dry, its parked entries keep it; group 1
        // holds parked entries alone.
        assert_eq!(q.group_after(None), Some(g0));
        assert_eq!(q.pop_from(g0).map(|e| e.slot), Some(9));
        assert_eq!(q.pop_from(g0), None);
        assert_eq!(q.group_after(None), Some(g0));
        assert_eq!(q.group_after(Some(g0)), Some(g1));
        assert_eq!(q.group_after(Some(g1)), None);
        // Slots 2 and 3 were parked after 1: 3 is on top once released.
        q.release(&[3, 7, 1, 2]);
        let out: Vec<u32> = std::iter::from_fn(|| q.pop_from(g0))
            .map(|e| e.slot)
            .collect();
        assert_eq!(out, vec![3, 2, 1]);
        assert_eq!(q.first_parked(g0), None);
        q.drop_parked();
        assert_eq!(q.first_parked(g1), None);
        assert_eq!(q.group_after(None), None);
    }
}
