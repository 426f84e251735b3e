//! A memory of the reference points the step ladder looked at and put
//! back (method §2.5, "the next reference point"): a point whose element
//! was refused or too poor is met again at the next step, and nothing near
//! it has changed in most cases. Each entry keeps the box of the front its
//! evaluation read; an element committed elsewhere leaves it standing, one
//! that overlaps the box forgets it, and any other change to the mesh or
//! the front forgets everything. Results are the same as without it.
//!
//! The ladder's relaxed rung (a rule-based element anywhere) evaluates
//! every convex front node when nothing else moves the front; its results
//! are remembered apart from the queue's (other limits, the rule model).

use super::candidate::Chosen;
use crate::front::SlotId;
use crate::geom::Point;
use std::collections::BTreeMap;

/// One remembered evaluation.
#[derive(Clone, Debug)]
struct Entry {
    /// The front node at the slot when it was evaluated.
    node: u32,
    lo: Point,
    hi: Point,
    result: Option<Chosen>,
}

/// Which evaluation a result belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Eval {
    /// A reference point from the queue, under the guard's limits.
    Queue,
    /// The relaxed rung: the rule model under relaxed limits.
    Relaxed,
}

/// Remembered evaluations of front slots, by kind and slot.
#[derive(Clone, Debug, Default)]
pub(super) struct EvalMemo {
    entries: BTreeMap<(Eval, SlotId), Entry>,
    /// The box of the front the last [`super::session::Mesher::evaluate`]
    /// read: what [`EvalMemo::put`] is given for it.
    pub(super) read_box: (Point, Point),
    /// The box of the front the last seam changed (its corner, the edges
    /// beside it and the mesh edges at the merged node), forgotten after
    /// the step.
    pub(super) seam_box: Option<crate::geom::Aabb>,
}

impl EvalMemo {
    /// The remembered result of kind `eval` at `slot` while it holds
    /// `node`, if any.
    pub(super) fn get(&self, eval: Eval, slot: SlotId, node: u32) -> Option<&Option<Chosen>> {
        self.entries
            .get(&(eval, slot))
            .filter(|e| e.node == node)
            .map(|e| &e.result)
    }

    /// Remembers `result` of kind `eval` at `slot` (holding `node`), read
    /// from the front inside the box `lo..hi`.
    pub(super) fn put(
        &mut self,
        eval: Eval,
        slot: SlotId,
        node: u32,
        (lo, hi): (Point, Point),
        result: Option<Chosen>,
    ) {
        self.entries.insert(
            (eval, slot),
            Entry {
                node,
                lo,
                hi,
                result,
            },
        );
    }

    /// Forgets the entries whose box meets the box `lo..hi`.
    pub(super) fn changed(&mut self, lo: Point, hi: Point) {
        self.entries
            .retain(|_, e| e.hi.x < lo.x || e.lo.x > hi.x || e.hi.y < lo.y || e.lo.y > hi.y);
    }

    /// Forgets everything.
    pub(super) fn clear(&mut self) {
        self.entries.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The queue's and the relaxed rung's results at one slot are kept
    /// apart; a result is for the node the slot held; a change forgets
    /// exactly the entries whose box it meets.
    #[test]
    fn entries_are_kept_by_kind_node_and_box() {
        let mut m = EvalMemo::default();
        let near = (Point::new(0.0, 0.0), Point::new(1.0, 1.0));
        let far = (Point::new(5.0, 5.0), Point::new(6.0, 6.0));
        m.put(Eval::Queue, 3, 7, near, None);
        m.put(Eval::Relaxed, 3, 7, far, None);
        m.put(Eval::Relaxed, 4, 8, near, None);
        assert!(m.get(Eval::Queue, 3, 7).is_some());
        assert!(m.get(Eval::Relaxed, 3, 7).is_some());
        assert!(
            m.get(Eval::Queue, 3, 9).is_none(),
            "another node at the slot"
        );
        assert!(
            m.get(Eval::Queue, 4, 8).is_none(),
            "only the relaxed rung's"
        );
        m.changed(Point::new(0.5, 0.5), Point::new(0.6, 0.6));
        assert!(m.get(Eval::Queue, 3, 7).is_none());
        assert!(m.get(Eval::Relaxed, 4, 8).is_none());
        assert!(m.get(Eval::Relaxed, 3, 7).is_some(), "its box is far away");
        m.clear();
        assert!(m.get(Eval::Relaxed, 3, 7).is_none());
    }
}
