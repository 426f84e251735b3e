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

use super::params::Strategy;
use super::session::Mesher;
use crate::front::SlotId;
use std::collections::BTreeMap;

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
}

/// A group's key: not sharp (sharp corners first), band, layer.
type GroupKey = (bool, u32, u32);

/// One group's entries: a stack per class, each in `seq` order.
#[derive(Clone, Debug, Default)]
struct Group {
    by_class: [Vec<Entry>; 3],
}

impl Group {
    fn is_empty(&self) -> bool {
        self.by_class.iter().all(Vec::is_empty)
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

    /// Takes the first entry out.
    pub(super) fn pop(&mut self) -> Option<Entry> {
        self.drop_empty_front();
        let mut first = self.groups.first_entry()?;
        first.get_mut().by_class.iter_mut().find_map(Vec::pop)
    }

    /// The first entry.
    fn peek(&mut self) -> Option<Entry> {
        self.drop_empty_front();
        let (_, g) = self.groups.first_key_value()?;
        g.by_class.iter().find_map(|v| v.last().copied())
    }

    /// Empties the queue.
    pub(super) fn clear(&mut self) {
        self.groups.clear();
        self.version.clear();
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
    pub(super) fn requeue(&mut self, deferred: Vec<Entry>) {
        for e in deferred {
            if self.front.slot(e.slot).alive && self.queue.version[e.slot as usize] == e.version {
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

    /// Band and layer of the first live entry of the queue (stale entries
    /// dropped).
    pub(super) fn queue_top(&mut self) -> Option<(u32, u32)> {
        while let Some(e) = self.queue.peek() {
            if self.front.slot(e.slot).alive && self.queue.version[e.slot as usize] == e.version {
                return Some((e.band, e.layer));
            }
            self.queue.pop();
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
}
