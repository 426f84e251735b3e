//! A memory of the reference points the step ladder looked at and put
//! back (method §2.5, "the next reference point"): a point whose element
//! was refused or too poor is met again at the next step, and nothing near
//! it has changed in most cases. Each entry keeps the box of the front its
//! evaluation read; a step that changes the front elsewhere leaves it
//! standing, one that changes it inside the box forgets it (the box of the
//! quads a step made, or [`EvalMemo::changed_box`] for a seam, a chord
//! split, a relaxation or a rip-up), a relink that leaves a short loop
//! forgets that loop's entries, and a fill forgets everything. An entry
//! can outlive a change to its loop's parity far away (a snap across the
//! loop reads the odd holes it takes in): what it refused may have become
//! possible, and a remembered element is checked again before it is
//! taken.
//!
//! The ladder's relaxed rung (a rule-based element anywhere) evaluates
//! every convex front node when nothing else moves the front; its results
//! are remembered apart from the queue's (other limits, the rule model).

use super::candidate::Chosen;
use crate::front::SlotId;
use crate::geom::Point;

/// One remembered evaluation's key and the box of front it read: what
/// [`EvalMemo::changed`] walks, kept apart from the results so that the
/// walk reads little.
#[derive(Clone, Copy, Debug)]
struct Keyed {
    eval: Eval,
    slot: SlotId,
    lo: Point,
    hi: Point,
}

/// One remembered evaluation's result.
#[derive(Clone, Debug)]
struct Stored {
    /// The front node at the slot when it was evaluated.
    node: u32,
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

/// No entry at a slot.
const NONE: u32 = u32::MAX;

/// Remembered evaluations of front slots, by kind and slot: entries in
/// no particular order (the keys and boxes in one list, the results in
/// another beside it), found by kind and slot through a table of
/// positions.
#[derive(Clone, Debug, Default)]
pub(super) struct EvalMemo {
    /// Per kind and slot, the position of its entry ([`NONE`]: none).
    at: [Vec<u32>; 2],
    keyed: Vec<Keyed>,
    stored: Vec<Stored>,
    /// The box of the front the last [`super::session::Mesher::evaluate`]
    /// read: what [`EvalMemo::put`] is given for it.
    pub(super) read_box: (Point, Point),
    /// The box of the front the step changed where it is not the box of
    /// the quads it made: a seam's corner, the edges beside it and the mesh
    /// edges at the merged node; a chord split's chord; the nodes a
    /// relaxed loop moved; the region a removal took. Taken after the step.
    pub(super) changed_box: Option<crate::geom::Aabb>,
    /// The slots whose queue evaluation was forgotten since this was last
    /// emptied ([`super::session::Mesher::forget`] hands their parked
    /// reference points back to the queue).
    pub(super) forgotten: Vec<SlotId>,
}

impl EvalMemo {
    /// The position of the entry of kind `eval` at `slot`, if any.
    fn position(&self, eval: Eval, slot: SlotId) -> Option<usize> {
        match self.at[eval as usize].get(slot as usize) {
            Some(&i) if i != NONE => Some(i as usize),
            _ => None,
        }
    }

    /// The remembered result of kind `eval` at `slot` while it holds
    /// `node`, if any.
    pub(super) fn get(&self, eval: Eval, slot: SlotId, node: u32) -> Option<&Option<Chosen>> {
        let e = &self.stored[self.position(eval, slot)?];
        (e.node == node).then_some(&e.result)
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
        let keyed = Keyed { eval, slot, lo, hi };
        let stored = Stored { node, result };
        if let Some(i) = self.position(eval, slot) {
            self.keyed[i] = keyed;
            self.stored[i] = stored;
            return;
        }
        let at = &mut self.at[eval as usize];
        if at.len() <= slot as usize {
            at.resize(slot as usize + 1, NONE);
        }
        at[slot as usize] = self.keyed.len() as u32;
        self.keyed.push(keyed);
        self.stored.push(stored);
    }

    /// Widens the box of the entry of kind `eval` at `slot`, if any, to
    /// take in `bb`: a result that also stands on what lies there.
    pub(super) fn widen(&mut self, eval: Eval, slot: SlotId, bb: crate::geom::Aabb) {
        if let Some(i) = self.position(eval, slot) {
            let k = &mut self.keyed[i];
            k.lo = k.lo.min(bb.min);
            k.hi = k.hi.max(bb.max);
        }
    }

    /// Widens [`EvalMemo::changed_box`] to take in `bb`.
    pub(super) fn widen_changed(&mut self, bb: Option<crate::geom::Aabb>) {
        let corners = self.changed_box.into_iter().chain(bb);
        self.changed_box = crate::geom::Aabb::of(corners.flat_map(|b| [b.min, b.max]));
    }

    /// Forgets the entries at the slots `on` marks (by slot id).
    pub(super) fn forget_slots(&mut self, on: impl Fn(SlotId) -> bool) {
        self.forget_where(|e| on(e.slot));
    }

    /// Forgets the entries `gone` picks.
    fn forget_where(&mut self, gone: impl Fn(&Keyed) -> bool) {
        let mut i = 0;
        while i < self.keyed.len() {
            if gone(&self.keyed[i]) {
                self.remove(i);
            } else {
                i += 1;
            }
        }
    }

    /// Removes entry `i` (the last takes its place).
    fn remove(&mut self, i: usize) {
        let e = self.keyed[i];
        self.at[e.eval as usize][e.slot as usize] = NONE;
        if e.eval == Eval::Queue {
            self.forgotten.push(e.slot);
        }
        self.keyed.swap_remove(i);
        self.stored.swap_remove(i);
        if let Some(moved) = self.keyed.get(i) {
            self.at[moved.eval as usize][moved.slot as usize] = i as u32;
        }
    }

    /// Forgets the entries whose box meets the box `lo..hi`.
    pub(super) fn changed(&mut self, lo: Point, hi: Point) {
        self.forget_where(|e| !(e.hi.x < lo.x || e.lo.x > hi.x || e.hi.y < lo.y || e.lo.y > hi.y));
    }

    /// Number of evaluations remembered.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.keyed.len()
    }

    /// Forgets everything.
    pub(super) fn clear(&mut self) {
        for e in &self.keyed {
            self.at[e.eval as usize][e.slot as usize] = NONE;
            if e.eval == Eval::Queue {
                self.forgotten.push(e.slot);
            }
        }
        self.keyed.clear();
        self.stored.clear();
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
