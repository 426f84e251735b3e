//! The reference-point queue (thesis §5.1, Figure 40): front slots whose
//! angle makes them reference points, sharp corners first; strategy B
//! orders them by layer, the newest first within a layer (so a row goes on
//! from its last element), strategy A by recency alone. Entries are
//! versioned: a slot whose angle changed is pushed again and its old entry
//! skipped.

use super::params::Strategy;
use super::session::Mesher;
use crate::front::SlotId;
use std::cmp::Ordering;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Entry {
    pub(super) class: u8,
    pub(super) layer: u32,
    pub(super) seq: u64,
    pub(super) slot: SlotId,
    pub(super) version: u32,
}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        // Max-heap: sharp class first, lower layer first, newest first.
        o.class
            .cmp(&self.class)
            .then(o.layer.cmp(&self.layer))
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
        if self.version.len() <= i {
            self.version.resize(i + 1, 0);
        }
        self.version[i] = self.version[i].wrapping_add(1);
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
        } else {
            return;
        };
        self.seq += 1;
        let layer = match self.params.strategy {
            Strategy::A => 0,
            Strategy::B => sl.layer,
        };
        self.queue.push(Entry {
            class,
            layer,
            seq: self.seq,
            slot: s,
            version: self.version[i],
        });
    }

    /// Layer of the first live entry of the queue (stale entries dropped).
    pub(super) fn queue_layer(&mut self) -> Option<u32> {
        while let Some(e) = self.queue.peek() {
            if self.front.slot(e.slot).alive && self.version[e.slot as usize] == e.version {
                return Some(e.layer);
            }
            self.queue.pop();
        }
        None
    }
}
