//! The step ladder: what one automatic step tries, in order (method §2,
//! thesis §5.1): a first row on a loop without reference points, closing
//! small loops, mapped grids on narrow logical rectangles, the fill inside
//! the first layers, the reference points in queue order, seams, chord
//! splits, a square cut, a relaxed rule-based element, relaxation, a
//! bridge across a gap, rip-up, and the fill as the last resort.

use super::candidate::Chosen;
use super::guard::Limits;
use super::memo::Eval;
use super::params::Strategy;
use super::queue::Entry;

use super::repair::Squares;
use super::report::{MeshError, Remedy, StepReport};
use super::session::{Mesher, PROGRESS_WINDOW};
use crate::front::SlotId;
use std::f64::consts::PI;

/// Rip-ups a run may take, plus one per [`RIP_UP_QUADS`] quads made: a
/// large domain has fronts meet in many places, each of which may need one.
const RIP_UPS: usize = 64;
/// See [`RIP_UPS`].
const RIP_UP_QUADS: usize = 4096;
/// Relaxations a run may take, plus one per [`RELAX_QUADS`] quads made.
const RELAXES: usize = 400;
/// See [`RELAXES`].
const RELAX_QUADS: usize = 512;

/// Loops up to this many nodes are split along a chord before a square is
/// cut on them.
const SMALL_LOOP: usize = 48;

/// A stretch of the given boundary this long (nodes) that no row has
/// reached when the queue moves on gets a row start.
const ROW_RUN: usize = 4;
/// A loop about to start a row first looks for a bridge of at least this
/// scaled Jacobian across a gap at most [`ROW_BRIDGE_GAP`] times as high
/// as the edges it joins are long: a gap a row would not fit.
const ROW_BRIDGE_SJ: f64 = 0.5;
/// See [`ROW_BRIDGE_SJ`].
const ROW_BRIDGE_GAP: f64 = 1.0;
/// A stuck front takes a bridge of any shape across a gap at most this
/// many times as high as the edges it joins are long (the slanted quads
/// of a gap between offset nodes have a scaled Jacobian of about 0.1, and
/// no quad there does better).
const BRIDGE_GAP: f64 = 0.5;
/// Front nodes looked at first, sharpest first, for the best rule-based
/// element anywhere (step 7 of the ladder).
const SHARPEST: usize = 32;

impl Mesher {
    pub(super) fn auto_step(&mut self) -> Result<StepReport, MeshError> {
        if self.params.fill && self.history.len() >= self.fill_after {
            if let Some(r) = self.fill_rest() {
                return Ok(r);
            }
            if !self.replaying {
                return Err(MeshError::StepLimit {
                    limit: self.fill_after,
                    remaining: self.front.len(),
                });
            }
        }
        if self.params.fill && self.stalled() {
            if let Some(r) = self.fill_rest() {
                return Ok(r);
            }
            if !self.replaying && !self.rewound {
                return Err(MeshError::Stalled {
                    steps: PROGRESS_WINDOW,
                    remaining: self.front.len(),
                });
            }
        }
        let limits = self.limits();
        // 0. A loop with no reference point starts a row with a square:
        //    a new loop, or (strategy B) a loop left behind the band or
        //    layer the queue has moved on to.
        self.queue_rows_behind();
        while let Some(lid) = self.row_start.pop() {
            if self.front.loops[lid as usize].alive
                && self.front.loops[lid as usize].len > 6
                && !self.loop_has_reference(lid)
            {
                if let Some(r) = self.bridge(Some(lid), ROW_BRIDGE_SJ, ROW_BRIDGE_GAP) {
                    return Ok(r);
                }
                if let Some(r) = self.square_cut(Squares::Loop(lid), limits) {
                    return Ok(r);
                }
            }
        }
        let hi = self.params.row_angle.to_radians();
        while let Some(s) = self.row_edges.pop() {
            let t = self.front.next(s);
            if self.front.slot(s).alive
                && self.front.loop_len(s) > 6
                && self.front.angle(s, &self.mesh.nodes) > hi
                && self.front.angle(t, &self.mesh.nodes) > hi
            {
                if let Some(r) = self.square_on(s, limits, 0.0) {
                    return Ok(r);
                }
            }
        }
        // 1. Small loops close first.
        let small: Vec<u32> = self
            .front
            .live_loops()
            .filter(|&l| self.front.loops[l as usize].len <= 6)
            .collect();
        for lid in small {
            let key = self.small_loop_key(lid);
            if self.small_stuck.get(lid as usize) == Some(&key) {
                continue;
            }
            if let Some(r) = self.close_small(lid) {
                return Ok(r);
            }
            if self.settle_small(lid) {
                if let Some(r) = self.close_small(lid) {
                    return Ok(r);
                }
            } else {
                if self.small_stuck.len() <= lid as usize {
                    self.small_stuck.resize(lid as usize + 1, 0);
                }
                self.small_stuck[lid as usize] = key;
            }
        }
        // 1b. Narrow logical rectangles close by a mapped grid.
        if self.params.mapped_rows.is_some() {
            for lid in 0..self.front.loops.len() as u32 {
                if self.front.loops[lid as usize].alive {
                    if let Some(r) = self.close_mapped(lid) {
                        return Ok(r);
                    }
                }
            }
        }
        // 2. The region inside the first layers is filled directly.
        if let Some(k) = self.params.fill_after_layers {
            // Strategy B's queue is ordered by layer; strategy A's is not,
            // so there the front's reference points are looked at.
            let layer = match self.params.strategy {
                Strategy::B => self.queue_top().map(|(_, l)| l),
                Strategy::A => {
                    let row = self.params.row_angle.to_radians();
                    self.front
                        .live_loops()
                        .flat_map(|l| self.front.loop_slots(l))
                        .filter(|&s| self.front.angle(s, &self.mesh.nodes) <= row)
                        .map(|s| self.front.slot(s).layer)
                        .min()
                }
            };
            if self.params.fill && layer.is_some_and(|l| l >= k) {
                if let Some(r) = self.fill_rest() {
                    return Ok(r);
                }
            }
        }
        // 3. Reference points in queue order; poor elements wait while a
        //    better reference point of the same kind, band and layer
        //    exists (the "next reference point" remedy): the best of the
        //    group is taken before the queue moves on to the next group.
        let mut skipped = 0;
        let mut deferred: Vec<Entry> = Vec::new();
        let mut best: Option<Chosen> = None;
        let mut chosen = None;
        let mut group = None;
        while let Some(e) = self.queue.pop() {
            let i = e.slot as usize;
            if !self.front.slot(e.slot).alive || self.version[i] != e.version {
                continue;
            }
            let key = (e.class > 0, e.band, e.layer);
            if best.is_some() && group.is_some_and(|g| g != key) {
                self.queue.push(e);
                break;
            }
            group = Some(key);
            if e.class == 0
                && self.front.angle(e.slot, &self.mesh.nodes) < self.params.seam_angle.to_radians()
            {
                if let Some(mut r) = self.try_seam(e.slot) {
                    r.skipped = skipped;
                    self.requeue(deferred);
                    return Ok(r);
                }
            }
            if e.class > 0 {
                if let Some(mut r) = self.try_transition(e.slot, limits) {
                    r.skipped = skipped;
                    self.requeue(deferred);
                    return Ok(r);
                }
            }
            let node = self.front.node(e.slot);
            let result = match self.memo.get(Eval::Queue, e.slot, node) {
                // A remembered element is copied out only when it may be
                // taken or kept as the best so far: most are neither, at
                // every step they wait through.
                Some(Some(c))
                    if c.score >= self.params.defer_score
                        || Chosen::would_keep(c.score, &best)
                        || self.at_needle(e.slot) =>
                {
                    Some(c.clone())
                }
                Some(_) => None,
                None => {
                    let r = self.evaluate(e.slot, limits, false)?;
                    if r.as_ref().is_none_or(|c| c.score < self.params.defer_score) {
                        self.memo
                            .put(Eval::Queue, e.slot, node, self.evaluated, r.clone());
                    }
                    r
                }
            };
            match result {
                Some(c) if c.score >= self.params.defer_score || self.at_needle(e.slot) => {
                    chosen = Some(c);
                    break;
                }
                Some(c) => c.keep_if_best(&mut best),
                None => {}
            }
            deferred.push(e);
            skipped += 1;
        }
        // A remembered element is checked again before it is taken (its
        // box was read with room to spare, but a guard is a guard).
        let best = self.confirmed(best, limits, false)?;
        if let Some(c) = chosen.or(best) {
            let mut r = self.commit_chosen(c);
            r.skipped = skipped;
            self.requeue(deferred);
            return Ok(r);
        }
        // 4. A seam at any sharp corner.
        let sharp: Vec<SlotId> = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .filter(|&s| {
                self.front.angle(s, &self.mesh.nodes) < self.params.reference_angle[0].to_radians()
            })
            .collect();
        for s in sharp {
            if let Some(r) = self.try_seam(s) {
                return Ok(r);
            }
        }
        // 5. A small loop without a usable reference point is split along
        //    its best chord (a ring becomes two halves with square corners).
        let mut loops: Vec<u32> = self.front.live_loops().collect();
        loops.sort_by_key(|&l| self.front.loops[l as usize].len);
        for &lid in &loops {
            if self.front.loops[lid as usize].len <= SMALL_LOOP {
                if let Some(r) = self.chord_split(lid) {
                    return Ok(r);
                }
            }
        }
        // 6. No reference point: a square on the shortest front edge.
        if let Some(mut r) = self.square_cut(Squares::Any, limits) {
            r.skipped = skipped;
            return Ok(r);
        }
        // 7. The best rule-based element with relaxed limits, anywhere.
        let relaxed = Limits {
            min_corner: 10f64.to_radians(),
            max_corner: 170f64.to_radians(),
            min_front: 5f64.to_radians(),
        };
        //    The sharpest front nodes are looked at first, the rest only
        //    when none of them gives an element (a ring with no corner
        //    left is long, and its row may start at any of them).
        let mut all: Vec<(f64, SlotId)> = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .map(|s| (self.front.angle(s, &self.mesh.nodes), s))
            .filter(|&(a, _)| a < PI)
            .collect();
        all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut best: Option<Chosen> = None;
        for part in [
            &all[..all.len().min(SHARPEST)],
            &all[all.len().min(SHARPEST)..],
        ] {
            for &(_, s) in part {
                if let Some(c) = self.evaluate_relaxed(s, relaxed)? {
                    c.keep_if_best(&mut best);
                }
            }
            if best.is_some() {
                break;
            }
        }
        let best = self.confirmed(best, relaxed, true)?;
        if let Some(c) = best {
            let mut r = self.commit_chosen(c);
            r.remedy = Remedy::RuleBased;
            r.skipped = skipped;
            return Ok(r);
        }
        // 7b. Start a row around a small hole no front has reached.
        if let Some(mut r) = self.square_cut(Squares::SmallHoles, limits) {
            r.skipped = skipped;
            return Ok(r);
        }
        // 8. Split a loop along a chord.
        for &lid in &loops {
            if let Some(r) = self.chord_split(lid) {
                return Ok(r);
            }
        }
        // 9. Straighten the smallest stuck loop, moving its interior nodes.
        if let Some(&lid) = loops.first() {
            if self.relaxes < RELAXES + self.mesh.quads.len() / RELAX_QUADS && self.relax_streak < 3
            {
                if let Some(r) = self.relax_loop(lid) {
                    self.relaxes += 1;
                    self.relax_streak += 1;
                    return Ok(r);
                }
            }
        }
        // 9b. A strip no step could take, closed by its best mapped grid.
        for &lid in &loops {
            if let Some(r) = self.close_strip(lid) {
                return Ok(r);
            }
        }
        // 9c. Two facing front edges joined across a gap.
        if let Some(r) = self.bridge(None, 0.0, BRIDGE_GAP) {
            return Ok(r);
        }
        // 10. Give the smallest stuck loop room: remove the elements around it.
        if let Some(&lid) = loops.first() {
            if self.rip_ups < RIP_UPS + self.mesh.quads.len() / RIP_UP_QUADS {
                let r = self.rip_up(lid, 1 + self.rip_ups % 4);
                self.rip_ups += 1;
                if r.removed > 0 || !r.quads.is_empty() {
                    return Ok(r);
                }
                // Nothing around the loop to remove and no split: rip-ups
                // cannot help any more.
                self.rip_ups = usize::MAX / 2;
            }
        }
        // 11. Fill the region left.
        if self.params.fill {
            if let Some(r) = self.fill_rest() {
                return Ok(r);
            }
        }
        let lid = self.front.live_loops().next().unwrap_or(0);
        let head = self.front.loops[lid as usize].head;
        Err(MeshError::Stuck {
            loop_index: lid,
            node: self.front.node(head),
        })
    }

    /// A remembered element checked again before it is taken (its box was
    /// read with room to spare, but a guard is a guard): if the guard now
    /// refuses it, the memory is dropped and its slot evaluated afresh.
    fn confirmed(
        &mut self,
        best: Option<Chosen>,
        limits: Limits,
        rules: bool,
    ) -> Result<Option<Chosen>, MeshError> {
        Ok(match best {
            Some(c) if self.check(c.cand, limits).is_none() => {
                self.memo.clear();
                match c.cand.slot() {
                    s if self.front.slot(s).alive => self.evaluate(s, limits, rules)?,
                    _ => None,
                }
            }
            b => b,
        })
    }

    /// The relaxed rung's evaluation of slot `s` (the rule model under
    /// `limits`), remembered.
    fn evaluate_relaxed(&mut self, s: SlotId, limits: Limits) -> Result<Option<Chosen>, MeshError> {
        let node = self.front.node(s);
        if let Some(r) = self.memo.get(Eval::Relaxed, s, node) {
            return Ok(r.clone());
        }
        let r = self.evaluate(s, limits, true)?;
        self.memo
            .put(Eval::Relaxed, s, node, self.evaluated, r.clone());
        Ok(r)
    }

    /// Strategy B: when the queue moves on to a coarser band or deeper
    /// layer, every loop left behind without a reference point (the front
    /// around a hole after a full ring, all its angles reflex) is queued
    /// for a row start, and so is every stretch of the given boundary no
    /// row has reached, so that every part of the front keeps up.
    fn queue_rows_behind(&mut self) {
        if self.params.strategy != super::params::Strategy::B {
            return;
        }
        let Some(top) = self.queue_top() else {
            return;
        };
        if top <= self.row_key {
            return;
        }
        self.row_key = top;
        let hi = self.params.row_angle.to_radians();
        let loops: Vec<u32> = self.front.live_loops().collect();
        for lid in loops {
            let slots = self.front.loop_slots(lid);
            let n = slots.len();
            if n <= 6 || !slots.iter().any(|&s| self.slot_key(s) < top) {
                continue;
            }
            let open: Vec<bool> = slots
                .iter()
                .map(|&s| self.front.angle(s, &self.mesh.nodes) > hi)
                .collect();
            if open.iter().all(|&o| o) {
                self.row_start.push(lid);
                continue;
            }
            // Stretches of the given boundary no row has reached yet (the
            // far side of a hole): a row start on each one's shortest edge.
            let untouched = |k: usize| open[k] && self.mesh.is_boundary(self.front.node(slots[k]));
            let first = (0..n).find(|&k| !untouched(k)).unwrap_or(0);
            let mut run: Vec<SlotId> = Vec::new();
            for k in 1..=n {
                let i = (first + k) % n;
                if untouched(i) && k < n {
                    run.push(slots[i]);
                    continue;
                }
                if run.len() >= ROW_RUN {
                    let best = run
                        .windows(2)
                        .map(|w| (self.world(w[0]).distance(self.world(w[1])), w[0]))
                        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                    if let Some((_, s)) = best {
                        self.row_edges.push(s);
                    }
                }
                run.clear();
            }
        }
    }

    /// True when some slot of the loop is a reference point or sharp corner.
    pub(super) fn loop_has_reference(&self, lid: u32) -> bool {
        let hi = self.params.reference_angle[1].to_radians();
        self.front
            .loop_slots(lid)
            .into_iter()
            .any(|s| self.front.angle(s, &self.mesh.nodes) <= hi)
    }
}
