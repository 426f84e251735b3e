//! A memory of the reference points the step ladder looked at and put
//! back (method §2.5, "the next reference point"): a point whose element
//! was refused or too poor is met again at the next step, and nothing near
//! it has changed in most cases. Each entry keeps the box of the front its
//! evaluation read; an element committed elsewhere leaves it standing, one
//! that overlaps the box forgets it, and any other change to the mesh or
//! the front forgets everything. Results are the same as without it.

use super::candidate::Chosen;
use crate::front::SlotId;
use crate::geom::Point;

/// One remembered evaluation.
#[derive(Clone, Debug)]
struct Entry {
    slot: SlotId,
    /// The front node at the slot when it was evaluated.
    node: u32,
    lo: Point,
    hi: Point,
    result: Option<Chosen>,
}

/// Remembered evaluations of reference points put back in the queue.
#[derive(Clone, Debug, Default)]
pub(super) struct EvalMemo {
    entries: Vec<Entry>,
}

impl EvalMemo {
    /// The remembered result at `slot` while it holds `node`, if any.
    pub(super) fn get(&self, slot: SlotId, node: u32) -> Option<&Option<Chosen>> {
        self.entries
            .iter()
            .find(|e| e.slot == slot && e.node == node)
            .map(|e| &e.result)
    }

    /// Remembers `result` at `slot` (holding `node`), read from the front
    /// inside the box `lo..hi`.
    pub(super) fn put(
        &mut self,
        slot: SlotId,
        node: u32,
        (lo, hi): (Point, Point),
        result: Option<Chosen>,
    ) {
        self.entries.retain(|e| e.slot != slot);
        self.entries.push(Entry {
            slot,
            node,
            lo,
            hi,
            result,
        });
    }

    /// Forgets the entries whose box meets the box `lo..hi`.
    pub(super) fn changed(&mut self, lo: Point, hi: Point) {
        self.entries
            .retain(|e| e.hi.x < lo.x || e.lo.x > hi.x || e.hi.y < lo.y || e.lo.y > hi.y);
    }

    /// Forgets everything.
    pub(super) fn clear(&mut self) {
        self.entries.clear();
    }
}
