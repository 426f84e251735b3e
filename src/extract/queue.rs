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
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The queue itself: a max-heap of [`Entry`], each slot's current version
/// (an entry of an older version is stale) and the push counter.
#[derive(Clone, Debug, Default)]
pub(super) struct RefQueue {
    pub(super) heap: BinaryHeap<Entry>,
    pub(super) version: Vec<u32>,
    pub(super) seq: u64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Entry {
    pub(super) class: u8,
    pub(super) band: u32,
    pub(super) layer: u32,
    pub(super) seq: u64,
    pub(super) slot: SlotId,
    pub(super) version: u32,
}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        // Max-heap: sharp corners first, then finer band first, lower
        // layer first, reference points before wider row ends, newest
        // first.
        (o.class > 0)
            .cmp(&(self.class > 0))
            .then(o.band.cmp(&self.band))
            .then(o.layer.cmp(&self.layer))
            .then(o.class.cmp(&self.class))
            .then(self.seq.cmp(&o.seq))
    }
}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
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
        self.queue.heap.push(Entry {
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
                self.queue.heap.push(Entry {
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
        while let Some(e) = self.queue.heap.peek() {
            if self.front.slot(e.slot).alive && self.queue.version[e.slot as usize] == e.version {
                return Some((e.band, e.layer));
            }
            self.queue.heap.pop();
        }
        None
    }
}
